"""Errors of engine runs, each with what the user needs to act on it."""

from __future__ import annotations

import shutil

from .codes import CODES

class EngineMissing(RuntimeError):
    """The engine's executable is not on PATH."""

    def __init__(self, engine: str, executable: str):
        self.engine = engine
        super().__init__(f"{engine}: the executable '{executable}' is not on PATH; "
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
