"""Errors of engine runs, each with what the user needs to act on it."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from .codes import CODES


def not_found(executable: str) -> str:
    """What was looked up for `executable` and not found, as the start of a message: a bare name
    (no '/') is looked up in the directories of PATH, which it names, saying how to write a file
    of the working folder instead; a path (absolute, or relative to the working folder) is
    named as the absolute path that was looked at.

        the executable 'lmp-np2' is not on PATH (looked up in /usr/local/bin:/usr/bin:/bin; ...)
        the executable '/home/me/lammps/lmp' does not exist"""
    if os.sep not in executable:
        path = os.environ.get("PATH", os.defpath)
        here = Path(executable)
        own = (f"; there is a file {str(here.absolute())!r}: write it as a path, './{executable}', to run that"
               if here.exists() else f"; a file of your own is written as a path, './{executable}' or an absolute one")
        return f"the executable {executable!r} is not on PATH (looked up in {path}{own})"
    where = Path(os.path.abspath(executable))  # absolute, '..' taken out
    if not where.exists():
        return f"the executable {str(where)!r} does not exist"
    what = "a folder" if where.is_dir() else "not executable (chmod +x)"
    return f"the executable {str(where)!r} is {what}"


class EngineMissing(RuntimeError):
    """The engine's executable is not there: the message names what was looked up (`not_found`),
    then how to install the code."""

    def __init__(self, engine: str, executable: str):
        self.engine, self.executable = engine, executable
        super().__init__(f"{engine}: {not_found(executable)}; "
                         f"{CODES[engine].install_hint if engine in CODES else ''}")


class EngineRunFailed(RuntimeError):
    """An engine run that produced no valid collision; the message names the run and its log.

    When the engine process itself stopped (timed out or crashed), `engine` and `case` name it
    and `log_tail` holds the log's last lines, which the problem quotes on its following lines.
    """

    def __init__(self, run_name: str, problem: str, log_path, *, engine: str = "", case: str = "",
                 log_tail: tuple[str, ...] = ()):
        self.run_name, self.problem, self.log_path = run_name, problem, str(log_path)
        self.engine, self.case, self.log_tail = engine, case, tuple(log_tail)
        head, _, rest = problem.rstrip("\n").partition("\n")
        super().__init__(f"{run_name}: {head} (engine log: {log_path})" + (f"\n{rest}" if rest else ""))


def require_executable(engine: str, executable: str) -> str:
    """The full path of `executable`, or EngineMissing with the install command."""
    path = shutil.which(executable)
    if path is None:
        raise EngineMissing(engine, executable)
    return path
