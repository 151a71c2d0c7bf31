"""Engine builds: which executable runs which code, as configuration (config `builds:`).

A build is an id (`lammps-2021`), a code (`liggghts`, `yade`, `lammps`: which driver runs it)
and an executable (a path, or a name on PATH; a relative path is relative to the project
folder). Adding a build is one config entry: what is known about a code (its version banner,
where it comes from) is its entry in `engines.codes`.

`find_executable` refuses a missing executable when the workflow starts (a look-up: nothing is
started, so a dry run or ``--unlock`` runs no engine). `check_build` asks the executable for its
version (the workflow's ``engine_version`` job, results/engine_versions/<build>.json) and refuses,
with the build named and what to do, one that is another engine or cannot say which version it is.
"""

from __future__ import annotations

import difflib
import os
import re
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .engine_process import line_buffered, run_logged
from .codes import CODES
from .errors import not_found

#: Time limit of a version query [s]: the engine only starts and reads an empty input (~0.4 s).
VERSION_TIMEOUT_S = 60.0
ID_PATTERN = re.compile(r"[a-z][a-z0-9_.-]*")


class BuildError(ValueError):
    """A build that cannot run; the message names the build and what to do."""


@dataclass(frozen=True)
class Build:
    """One engine build: `id` names its runs and results folder, `code` picks the driver,
    `executable` is what is started (an absolute path once loaded, or a name on PATH)."""

    id: str
    code: str
    executable: str

    def __post_init__(self):
        if self.code not in CODES:
            close = difflib.get_close_matches(self.code.lower(), list(CODES), n=1, cutoff=0.6)
            guess = f" (did you mean {close[0]!r}?)" if close else ""
            raise BuildError(f"build {self.id!r}: unknown code {self.code!r}{guess}; known: {', '.join(CODES)}")
        if not ID_PATTERN.fullmatch(self.id):
            raise BuildError(f"build id {self.id!r}: use lower-case letters, digits and . _ -, starting with a letter")


def load_builds(config_list, project_dir) -> list[Build]:
    """The builds of config `builds:` (a list of {id, code, executable}), in order. A relative
    executable path (one with a '/') is made absolute against `project_dir`; a bare name is
    looked up on PATH when it runs. Two builds with one id are refused."""
    builds, seen = [], set()
    for entry in config_list:
        exe = str(entry["executable"])
        if os.sep in exe and not os.path.isabs(exe):
            exe = str(Path(project_dir, exe).absolute())
        build = Build(str(entry["id"]), str(entry["code"]), exe)
        if build.id in seen:
            raise BuildError(f"config 'builds': two builds have the id {build.id!r}; give each build its own id "
                             "(it names the build's runs and its results folder results/<case>/<id>/)")
        seen.add(build.id)
        builds.append(build)
    return builds


def query_version(executable: str, code: str, timeout_s: float = VERSION_TIMEOUT_S) -> str:
    """What the executable prints when asked for its version the way `code` is (empty input)."""
    with tempfile.TemporaryDirectory() as scratch:  # LIGGGHTS writes log.liggghts before reading -log
        out = Path(scratch) / "version.txt"
        done = run_logged(line_buffered([executable, *CODES[code].version_args]), out, timeout_s, cwd=scratch,
                          env=CODES[code].process_environment())
        text = out.read_text(errors="replace")
    if done.timed_out:
        tail = "\n".join(f"    | {line}" for line in text.strip().splitlines()[-10:]) or "    | (nothing)"
        raise TimeoutError(f"did not exit within {timeout_s:g} s when asked for its version and was killed; "
                           f"it printed:\n{tail}")
    return text


def find_executable(build: Build) -> str:
    """The absolute path of the build's executable, looked up (PATH for a bare name), not started.

    Raises
    ------
    BuildError
        When it is not there: the message names what was looked up (PATH's folders, or the
        path), then how to install the code.
    """
    exe = shutil.which(build.executable)
    if exe is None:
        raise BuildError(f"build {build.id!r} ({build.code}): {not_found(build.executable)}; "
                         f"{CODES[build.code].install_hint}, or point the build's `executable` at your own build")
    return exe


def executable_identity(build: Build) -> dict:
    """Where the build's executable is and which file it is (resolved path, size [bytes],
    modification time [ns]), read by ``stat`` alone: the ``engine_version`` job's parameter, so
    that an engine installed anew at the same path is asked its version again (and its runs rerun),
    and an unchanged one is not. BuildError when it is missing (`find_executable`)."""
    exe = Path(find_executable(build)).resolve()
    st = exe.stat()
    return {"path": str(exe), "size": st.st_size, "mtime_ns": st.st_mtime_ns}


def check_build(build: Build, timeout_s: float = VERSION_TIMEOUT_S) -> str:
    """The build's version banner (e.g. 'LAMMPS (22 Jul 2025 - Update 4)'), read from the
    executable; BuildError when it is missing, is another engine, or prints no version."""
    exe = find_executable(build)
    try:
        text = query_version(exe, build.code, timeout_s)
    except (OSError, TimeoutError) as err:
        raise BuildError(f"build {build.id!r} ({build.code}): {exe} cannot report its version ({err}); "
                         f"check that it is a {build.code} executable") from err
    banner = CODES[build.code].banner.search(text)
    if banner:
        return banner.group(0).strip()
    others = [name for name, c in CODES.items() if name != build.code and c.banner.search(text)]
    if others:
        raise BuildError(f"build {build.id!r}: {exe} is not {build.code}, its version banner says "
                         f"{CODES[others[0]].banner.search(text).group(0).strip()!r}; set the build's code to "
                         f"{others[0]!r} or point its executable at a {build.code} build")
    tail = " | ".join(text.strip().splitlines()[-3:]) or "nothing"
    raise BuildError(f"build {build.id!r} ({build.code}): {exe} cannot report its version (no line matching "
                     f"{CODES[build.code].banner.pattern!r}; it printed: {tail}); check that it is a {build.code} "
                     "executable that starts")
