"""The one way tests start processes that may outlive a moment (Snakemake, make, a README command,
the engines' wrappers): each in a session of its own, killed with its whole session however the
test run ends.

- `start` and `run` (subprocess.Popen and subprocess.run with the same arguments) put the process
  in a new session and give it SIGKILL when the test process dies, even by SIGKILL
  (PR_SET_PDEATHSIG, `engines.engine_process.dies_with`); a `run` that times out or is
  interrupted (Ctrl-C, a failing assertion in another thread) kills the session before it raises.
- `stop_all` kills every process `start` or `run` started that is still running, with its process
  group and session; conftest.py calls it when pytest or an xdist worker is told to stop
  (SIGTERM, SIGHUP, `timeout`, a killed `make test`) and when it exits. A worker dies with pytest
  (conftest.py), so its processes die with it too.

What a killed Snakemake leaves (its jobs' engines) dies with it: the engines' guard
(`engines.engine_process.engine_guard`) kills each job whose workflow is gone.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading

from engines.engine_process import kill_all

_started: dict[int, subprocess.Popen] = {}
_lock = threading.Lock()


def _die_with_this_process():
    from engines.engine_process import dies_with

    return dies_with(os.getpid())


def start(cmd, **kwargs) -> subprocess.Popen:
    """subprocess.Popen(cmd, **kwargs) in a session of its own, dying with this process; `stop`
    or `stop_all` kill it with its session."""
    if "start_new_session" in kwargs or "preexec_fn" in kwargs or "process_group" in kwargs:
        raise ValueError("tests/processes.py sets the session and the death signal itself")
    proc = subprocess.Popen(cmd, start_new_session=True, preexec_fn=_die_with_this_process(), **kwargs)
    with _lock:
        for pid in [p for p, q in _started.items() if q.poll() is not None]:
            del _started[pid]
        _started[proc.pid] = proc
    return proc


def stop(proc: subprocess.Popen, sig: int = signal.SIGKILL) -> None:
    """`sig` to the process group and session of `proc` (a process of `start`)."""
    kill_all(proc.pid, sig)


def stop_all() -> list[int]:
    """SIGKILL every process of `start` and `run` with its session; the pids of those that were
    still running."""
    with _lock:
        running = [p for p in _started.values() if p.poll() is None]
    for proc in running:
        stop(proc)
    with _lock:
        _started.clear()
    return [p.pid for p in running]


def run(cmd, *, input=None, capture_output=False, timeout=None, check=False, **kwargs):
    """subprocess.run with `start`: its process (and its session) is killed when it times out
    (subprocess.TimeoutExpired, as subprocess.run raises) or the test is interrupted."""
    if capture_output:
        kwargs["stdout"] = kwargs["stderr"] = subprocess.PIPE
    if input is not None:
        kwargs["stdin"] = subprocess.PIPE
    with start(cmd, **kwargs) as proc:
        try:
            stdout, stderr = proc.communicate(input, timeout=timeout)
        except BaseException:  # TimeoutExpired, KeyboardInterrupt, ...: nothing of it is left running
            stop(proc)
            try:
                proc.communicate(timeout=30)
            except (subprocess.SubprocessError, OSError, ValueError):
                pass
            raise
        finally:
            stop(proc)  # what it left in its session (a shell's background job, a daemon that did not detach)
    done = subprocess.CompletedProcess(proc.args, proc.returncode, stdout, stderr)
    if check:
        done.check_returncode()
    return done
