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
- dies with the job that started it, however the job ends, and with the job's workflow: a
  `kill -9` of Snakemake, or of the job's script, must not leave an engine running (nor a script
  that writes its manifest after the workflow is gone). The engine gets SIGKILL when the job's
  process dies (PR_SET_PDEATHSIG), and the job's guard (`engine_guard`), a small process beside
  it, kills the engine's whole session (mpirun's ranks, the real `lmp` under PyPI's Python
  wrapper) when the job's process is gone, and the job itself with its engines when the
  Snakemake that runs it is gone;
- sees none of the variables of a SLURM job step or of a PMI server (`engine_environment`);
- keeps Open MPI's session directory in a folder of its own (`OMPI_SESSION_VARIABLE`).
"""

from __future__ import annotations

import ctypes
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
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


#: prctl(2)'s option: the signal a process gets when the thread that started it ends (Linux).
PR_SET_PDEATHSIG = 1


def _linux_prctl():
    """libc's prctl, or None where there is none (not Linux)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None


_PRCTL = _linux_prctl()


def dies_with(parent: int, sig: int = signal.SIGKILL):
    """A `preexec_fn` for a child of process `parent`: `sig` when `parent` dies (PR_SET_PDEATHSIG),
    and at once when it has already died between the fork and this call. (The signal follows the
    thread that forks: every caller waits for its engine in that thread.) Called in a process,
    `dies_with(os.getppid(), sig)()` gives that process `sig` when its parent dies."""
    def preexec():
        if _PRCTL is not None:
            _PRCTL(PR_SET_PDEATHSIG, int(sig))
        if os.getppid() != parent:
            os.kill(os.getpid(), sig)
    return preexec


def _stat(pid: int) -> list[str] | None:
    """The fields of /proc/<pid>/stat after the command (state, ppid, pgrp, session, ...; the
    start time is [19]); None if there is no such process."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text.rsplit(")", 1)[1].split()


def is_snakemake(pid: int) -> bool:
    """Whether process `pid` runs Snakemake (`snakemake ...`, `python .../bin/snakemake ...` or
    `python -m snakemake ...`)."""
    try:
        args = Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace").split("\0")
    except OSError:
        return False
    return any(Path(a).name == "snakemake" for a in args[:2]) or any(
        a == "-m" and b == "snakemake" for a, b in zip(args, args[1:]))


def workflow_ancestors(pid: int | None = None) -> list[tuple[int, str]]:
    """The processes of the workflow above process `pid` (this one): its ancestors up to the
    outermost Snakemake among them, as (pid, start time); none when no Snakemake runs it. The
    shell or terminal that started Snakemake is not among them (`nohup snakemake &` outlives it)."""
    chain, outermost = [], 0
    fields = _stat(os.getpid() if pid is None else pid)
    parent = int(fields[1]) if fields else 0
    while parent > 1:
        fields = _stat(parent)
        if fields is None:
            break
        chain.append((parent, fields[19]))
        if is_snakemake(parent):
            outermost = len(chain)
        parent = int(fields[1])
    return chain[:outermost]


#: The guard (`EngineGuard`): a process started with `python -I -S -c GUARD <job pid> <pid:start>...`,
#: the job being the process that runs engines and pid:start the processes of its workflow
#: (`workflow_ancestors`). Its stdin is a pipe from the job: "+<sid>" when an engine session starts,
#: "-<sid>" when it is over. It SIGKILLs every process of the live sessions
#: - when the pipe closes: the job has ended, or was killed (kill -9 included), and
#: - when a process of the workflow has ended (kill -9 of Snakemake): the job and the workflow's
#:   processes between it and the one that ended first, so that nothing of the job writes after
#:   the workflow is gone;
#: then it exits. It polls the workflow five times a second; its own session is its own.
GUARD = r'''# engines/engine_process.py: the engine guard of one job
import os, select, signal, sys, time
signal.signal(signal.SIGINT, signal.SIG_IGN)
job = int(sys.argv[1])
workflow = [tuple(a.split(":")) for a in sys.argv[2:]]


def stat(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            text = f.read()
    except OSError:
        return None
    return text[text.rindex(")") + 2:].split()


def alive(pid, start):
    f = stat(pid)
    return f is not None and f[0] not in ("Z", "X") and f[19] == start


def kill(pid):
    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass


def kill_sessions(sids):
    me = os.getpid()
    for _ in range(50):
        left = False
        for name in os.listdir("/proc"):
            f = stat(int(name)) if name.isdigit() and int(name) != me else None
            if f and f[0] not in ("Z", "X") and (int(f[2]) in sids or int(f[3]) in sids):
                kill(int(name))
                left = True
        if not left:
            return
        time.sleep(0.02)


sessions, pending = set(), b""
job_start = (stat(job) or [""] * 20)[19]
while True:
    if os.getppid() != job:
        kill_sessions(sessions)
        break
    ended = next((i for i, (pid, start) in enumerate(workflow) if not alive(int(pid), start)), None)
    if ended is not None:
        if alive(job, job_start):
            kill(job)
        for pid, start in workflow[:ended]:
            if alive(int(pid), start):
                kill(int(pid))
        kill_sessions(sessions)
        break
    if select.select([0], [], [], 0.2 if workflow else None)[0]:
        data = os.read(0, 4096)
        if not data:
            kill_sessions(sessions)
            break
        *lines, pending = (pending + data).split(b"\n")
        for line in lines:
            (sessions.add if line[:1] == b"+" else sessions.discard)(int(line[1:]))
'''


class EngineGuard:
    """This process's guard (`GUARD`), started with its first engine and told of every engine
    session (`watch`, `forget`). A forked child gets a guard of its own. Where the guard cannot run
    (no /proc), engines still die with this process (`dies_with`), but not with the workflow."""

    def __init__(self):
        self._lock = threading.Lock()
        self._pipe: int | None = None  # the write end of the guard's stdin
        self._owner = 0  # the pid of the process that started the guard
        self._process: subprocess.Popen | None = None
        os.register_at_fork(after_in_child=self._forget_in_child)

    def _forget_in_child(self):
        """In a forked child: the parent's guard is not the child's (and its pipe must close with
        the parent alone). No lock taken: another thread may have held it at the fork."""
        if self._pipe is not None:
            try:
                os.close(self._pipe)
            except OSError:
                pass
        self._lock, self._pipe, self._process = threading.Lock(), None, None

    def _send(self, line: str) -> None:
        with self._lock:
            for _ in range(2):  # a guard that has died is started again once
                if self._pipe is None or self._owner != os.getpid():
                    if not self._start():
                        return
                try:
                    os.write(self._pipe, line.encode() + b"\n")
                    return
                except OSError:  # the guard is gone (EPIPE)
                    os.close(self._pipe)
                    self._pipe = None
                    if self._process is not None:
                        self._process.poll()  # reaped

    def _start(self) -> bool:
        if not sys.executable or not Path("/proc/self/stat").exists():
            return False
        read, write = os.pipe()
        try:
            args = [f"{pid}:{start}" for pid, start in workflow_ancestors()]
            self._process = subprocess.Popen([sys.executable, "-I", "-S", "-c", GUARD, str(os.getpid()), *args],
                                             stdin=read, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                             start_new_session=True)
        except OSError:
            os.close(write)
            return False
        finally:
            os.close(read)
        self._pipe, self._owner = write, os.getpid()
        return True

    def watch(self, sid: int) -> None:
        """Kill session `sid` if this process or its workflow ends before `forget(sid)`."""
        self._send(f"+{sid}")

    def forget(self, sid: int) -> None:
        self._send(f"-{sid}")


#: The guard of this process's engines.
engine_guard = EngineGuard()


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
    nothing it started survives. It dies with this process (`dies_with`) and its session with this
    process or its workflow (`engine_guard`). It runs in `engine_environment(env)`, with an Open
    MPI session folder of its own (OMPI_SESSION_VARIABLE). Returns how it ended."""
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="ompi-session-") as session_dir, open(log, mode) as out:
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT, stdin=stdin,
                                env=engine_environment({OMPI_SESSION_VARIABLE: session_dir, **(env or {})}),
                                start_new_session=True, preexec_fn=dies_with(os.getpid()))
        pgid = proc.pid  # start_new_session: the child leads its own group and session
        try:
            engine_guard.watch(pgid)
            returncode = proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            returncode = None
            kill_group(pgid, signal.SIGTERM)
            try:
                proc.wait(timeout=KILL_GRACE_S)
            except subprocess.TimeoutExpired:
                pass
        finally:  # normally, or on e.g. KeyboardInterrupt: nothing of the engine is left running
            kill_all(pgid)
            proc.wait()
            engine_guard.forget(pgid)
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
