"""A test run that is stopped leaves nothing running: a pytest (alone, or with xdist workers) whose test
holds a process started with tests/processes.py `start` and, through `run`, a shell with a child of
its own, is stopped as a user, `timeout` or a killed `make test` stops it; then none of those
processes is left (conftest.py: STOP_SIGNALS, the workers' death signal, `processes.stop_all`)."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import processes

ROOT = Path(__file__).resolve().parents[1]
INNER = '''import os
from pathlib import Path

import pytest

import processes

pytestmark = pytest.mark.workflow  # it starts processes: not the unit tier (tests/conftest.py)


def test_holds_processes():
    out = Path({out!r})
    child = processes.start(["sleep", "300"])
    (out / "child.pid").write_text(str(child.pid))
    (out / "worker.pid").write_text(str(os.getpid()))
    processes.run(["bash", "-c", "echo $$ > {out}/shell.pid; sleep 301 & echo $! > {out}/grandchild.tmp; "
                   "mv {out}/grandchild.tmp {out}/grandchild.pid; wait"], timeout=600)
'''
PIDS = ("child", "shell", "grandchild", "worker")


def start_time(pid: int) -> str | None:
    """The start time of a live (not zombie) process, None if it is gone."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return None if fields[0] in ("Z", "X") else fields[19]


@pytest.mark.parametrize("workers, sig, to", [
    (0, signal.SIGTERM, "pytest"),          # kill <pytest>
    (1, signal.SIGTERM, "pytest"),          # kill <pytest>: its worker dies with it
    (1, signal.SIGTERM, "process group"),   # timeout, or a killed make test
    (1, signal.SIGINT, "process group"),    # Ctrl-C
])
def test_a_stopped_test_run_leaves_none_of_its_processes(tmp_path, workers, sig, to, runs_workflow):
    out = tmp_path / "pids"
    out.mkdir()
    (tmp_path / "test_inner.py").write_text(INNER.format(out=str(out)))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), str(ROOT)])}
    inner = processes.start([sys.executable, "-m", "pytest", "-q", "-c", str(ROOT / "pyproject.toml"), "--rootdir",
                             str(tmp_path), "-p", "conftest", "-p", "no:cacheprovider",
                             *(["-n", str(workers)] if workers else []), str(tmp_path / "test_inner.py")],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 240
        while not (out / "grandchild.pid").exists() and inner.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
        assert (out / "grandchild.pid").exists(), inner.communicate(timeout=60)[0][-3000:]
        pids = {name: int((out / f"{name}.pid").read_text()) for name in PIDS}
        started = {name: start_time(pid) for name, pid in pids.items()}
        assert all(started.values()), started
        assert (pids["worker"] == inner.pid) == (workers == 0)
        if to == "pytest":
            os.kill(inner.pid, sig)
        else:
            os.killpg(inner.pid, sig)
        said, _ = inner.communicate(timeout=120)
    finally:
        processes.stop(inner)
    deadline = time.monotonic() + 10  # killed processes are gone (reaped) at once; allow for a loaded machine
    while (left := [n for n, pid in pids.items() if start_time(pid) == started[n]]) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert left == [], f"{left} outlived the stopped test run:\n{said[-3000:]}"


INNER_CLUSTER = '''import time
from pathlib import Path

import pytest

from slurm_cluster import require_slurm

pytestmark = pytest.mark.workflow  # it starts the cluster: not the unit tier (tests/conftest.py)


def test_holds_the_cluster():
    require_slurm()
    Path({ready!r}).write_text("up")
    time.sleep(600)
'''


@pytest.mark.workflow
@pytest.mark.xdist_group("slurm")  # with the cluster tests, one at a time
def test_a_stopped_test_run_stops_the_cluster_it_started_and_leaves_one_it_found(tmp_path):
    """A pytest whose test started the local SLURM cluster (or found it up: `make slurm-up`, .ci/run),
    stopped by SIGTERM mid-test: it stops the cluster if it started it, unless another test run
    (this one) still holds it; one it found is left running."""
    import shutil

    from engine_cases import missing
    from slurm_cluster import DAEMONS, SLURM_SNAKEMAKE, TEST_RUN, cluster_running, state_dir

    if any(shutil.which(exe) is None for exe in DAEMONS) or not SLURM_SNAKEMAKE.exists():
        missing("SLURM or its Snakemake plugin is not installed: make slurm-up slurm-venv")
    was_running = cluster_running()
    (tmp_path / "test_inner.py").write_text(INNER_CLUSTER.format(ready=str(tmp_path / "ready")))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), str(ROOT)])}
    inner = processes.start([sys.executable, "-m", "pytest", "-q", "-c", str(ROOT / "pyproject.toml"), "--rootdir",
                             str(tmp_path), "-p", "conftest", "-p", "no:cacheprovider",
                             str(tmp_path / "test_inner.py")],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 300
        while not (tmp_path / "ready").exists() and inner.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)
        assert (tmp_path / "ready").exists(), inner.communicate(timeout=60)[0][-3000:]
        assert cluster_running()
        (inner_lease,) = (state_dir() / "tests").glob(f"run-{inner.pid}-*")  # (slurm_cluster.take_lease)
        os.kill(inner.pid, signal.SIGTERM)
        said, _ = inner.communicate(timeout=180)
    finally:
        processes.stop(inner)
    assert not inner_lease.exists()
    # This run holds the cluster too when one of its tests used it before: the stopped run hands it over.
    held = (state_dir() / "tests" / f"run-{os.environ[TEST_RUN]}").exists()
    assert cluster_running() == (was_running or held), said[-3000:]
