"""One engine process: its time limit, its log streamed to disk, and a clean kill.

A hung engine must not keep the study silent for many minutes, and what it printed must be on
disk when it is killed. So every engine process

- gets a time limit scaled to its sweep (`time_limit`), never below a floor (`timeout_floor_s`
  of the runners and of `engines.run_sweep`, default `DEFAULT_TIMEOUT_FLOOR_S`);
- writes its output (stdout and stderr) straight into its log file: the file is the process's
  stdout, and the engine's C stdio is made line-buffered with coreutils' `stdbuf -oL -eL` (YADE:
  PYTHONUNBUFFERED=1), so that lines land as they are printed, not when a 4 KiB buffer fills;
- runs in a session of its own, and the whole process group is killed when it times out, and
  after it exits (MPI helpers, a `shell` command's children or a wrapper's engine must not linger);
  so is every other process of its session: mpirun puts each rank in a process group of its own;
- sees none of the variables of a SLURM job step or of a PMI server (`engine_environment`);
- keeps Open MPI's session directory in a folder of its own (`OMPI_SESSION_VARIABLE`).
"""

from __future__ import annotations

import math
import os
import shutil
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from .codes import code

#: The floor of every engine process's time limit [s] (`timeout_floor_s`).
DEFAULT_TIMEOUT_FLOOR_S = 60.0
#: The limit is this many times the sweep's expected length (shared machines, slow CI).
SAFETY_FACTOR = 10.0
#: Time given to a process group between SIGTERM and SIGKILL [s].
KILL_GRACE_S = 3.0
#: Last log lines quoted in the error of a timed-out or crashed engine.
TAIL_LINES = 10


#: Prefixes of the environment variables an engine process does not see: a SLURM job step's
#: (SLURM_*) and a process manager's (PMI_*, PMIX_*). Debian's liggghts, lmp and esysparticle are
#: linked against Open MPI 4.1, which takes SLURM_STEP_ID as "this process was launched by srun as
#: one rank of an MPI job": it skips its singleton start-up and asks srun's PMI server for its rank.
#: A step started without one (MpiDefault=none, SLURM's default, under the Snakemake plugin's
#: `srun -n1`) has none, and the engine aborts before MPI_Init completes ("OPAL ERROR: Unreachable
#: in file ext3x_client.c", "Local abort before MPI_INIT completed"). Every engine process is one
#: process of its job whatever the cluster's MPI set-up, and ESyS starts its own mpirun; so none
#: of these variables is theirs to read.
HIDDEN_ENV_PREFIXES = ("SLURM_", "PMI_", "PMIX_")


#: Open MPI 4.1 (Debian's liggghts, lmp and esysparticle) keeps each process's session directory
#: in one tree per user and host, /tmp/ompi.<host>.<uid>. Processes that start together race on
#: it: one's clean-up removes the tree while another creates its directory there, and that one
#: aborts before MPI_Init completes ("orte_session_dir failed ... Local abort before MPI_INIT
#: completed"). Measured on this project's 2-core VM: 3 of 400 version queries of five builds,
#: six at a time, failed so; none of 1 250 with a tree of each process's own. It broke the
#: workflow's start at random (every start asks all builds for their version at once), on a
#: SLURM cluster more often, where every job starts its own Snakemake. So every engine process
#: gets a fresh folder for this tree, removed when it ends.
OMPI_SESSION_VARIABLE = "OMPI_MCA_orte_tmpdir_base"


def engine_environment(extra: dict | None = None) -> dict:
    """This process's environment without the HIDDEN_ENV_PREFIXES variables, updated by `extra`."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(HIDDEN_ENV_PREFIXES)}
    return {**env, **(extra or {})}


def time_limit(engine: str, specs, floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> float:
    """The time limit [s] of one `engine` process running `specs`: SAFETY_FACTOR times the
    sweep's expected length (the code's `engines.codes.EngineCost`), at least `floor_s`:

        limit = max(floor, SAFETY_FACTOR * (start_s + runs * per_run_s + sum(steps) * per_step_s))

    e.g. a LIGGGHTS sweep of 36 runs of 2 600 steps: 10 * (1 + 0.07 + 1.4) = 25 s -> the 60 s floor."""
    if not (floor_s > 0 and math.isfinite(floor_s)):
        raise ValueError(f"the engine time-limit floor must be a positive number of seconds, got {floor_s}")
    expected = code(engine).expected_seconds(len(specs), sum(s.steps() for s in specs))
    return max(float(floor_s), SAFETY_FACTOR * expected)


def line_buffered(cmd: list[str]) -> list[str]:
    """`cmd` with its C stdio line-buffered (stdbuf), when coreutils' stdbuf is there."""
    stdbuf = shutil.which("stdbuf")
    return [stdbuf, "-oL", "-eL", *cmd] if stdbuf else list(cmd)


def kill_group(pgid: int, sig: int = signal.SIGKILL) -> None:
    """Send `sig` to process group `pgid`, if any process is left in it."""
    try:
        os.killpg(pgid, sig)
    except (ProcessLookupError, PermissionError):
        pass


def kill_session(sid: int, sig: int = signal.SIGKILL) -> None:
    """Send `sig` to every process of session `sid` (read from /proc; nothing where there is
    no /proc). Reaches what left the leader's process group but not its session, such as
    mpirun's ranks, each in a group of its own, and their children."""
    for stat_file in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat_file.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[3]) == sid:  # state, ppid, pgrp, session
            try:
                os.kill(int(stat_file.parent.name), sig)
            except (ProcessLookupError, PermissionError):
                pass


def kill_all(pgid: int, sig: int = signal.SIGKILL) -> None:
    """`kill_group` and `kill_session` of a process started with start_new_session (its pid is
    both its group and its session)."""
    kill_group(pgid, sig)
    kill_session(pgid, sig)


@dataclass
class Finished:
    """How an engine process ended: its exit status (None if killed for its time limit)."""

    returncode: int | None
    seconds: float

    @property
    def timed_out(self) -> bool:
        return self.returncode is None


def run_logged(cmd: list[str], log: Path, timeout_s: float, cwd=None, env: dict | None = None,
               stdin=subprocess.DEVNULL, mode: str = "w") -> Finished:
    """Run `cmd` with stdout and stderr going straight into `log`, in a new session.

    If it has not exited after `timeout_s`, its process group gets SIGTERM, then its group and
    session SIGKILL after KILL_GRACE_S; they are SIGKILLed after a normal exit too, so that
    nothing it started survives. It runs in `engine_environment(env)`, with an Open MPI session
    folder of its own (OMPI_SESSION_VARIABLE). Returns how it ended."""
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="ompi-session-") as session_dir, open(log, mode) as out:
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT, stdin=stdin,
                                env=engine_environment({OMPI_SESSION_VARIABLE: session_dir, **(env or {})}),
                                start_new_session=True)
        pgid = proc.pid  # start_new_session: the child leads its own group
        try:
            returncode = proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            returncode = None
            kill_group(pgid, signal.SIGTERM)
            try:
                proc.wait(timeout=KILL_GRACE_S)
            except subprocess.TimeoutExpired:
                pass
        except BaseException:  # e.g. KeyboardInterrupt: do not leave the engine running
            kill_all(pgid)
            proc.wait()
            raise
        kill_all(pgid)
        proc.wait()
    return Finished(returncode, time.perf_counter() - started)


def log_tail(log: Path, n: int = TAIL_LINES) -> list[str]:
    """The last `n` non-blank lines of a log (none if it cannot be read)."""
    try:
        lines = Path(log).read_text(errors="replace").splitlines()
    except OSError:
        return []
    return [line.rstrip() for line in lines if line.strip()][-n:]


def describe_exit(returncode: int) -> str:
    """'status 3', or 'signal SIGSEGV (status 139)' for a signal (negative, or a shell's 128+n)."""
    signum = -returncode if returncode < 0 else returncode - 128 if 128 < returncode < 128 + 65 else None
    if signum is not None:
        try:
            return f"signal {signal.Signals(signum).name} (status {returncode})"
        except ValueError:
            pass
    return f"status {returncode}"


def stop_message(engine: str, build: str, case: str, run: str, what: str, log: Path) -> str:
    """The problem of the run an engine process stopped in: engine and build, case, run, what
    happened, and the log's last lines."""
    tail = log_tail(log)
    quoted = "\n".join(f"    | {line}" for line in tail) if tail else "    | (the log is empty)"
    return (f"{engine} {what} (build: {build}), in case {case}, run {run}; "
            f"the last {len(tail)} line(s) of its log follow\n{quoted}")
