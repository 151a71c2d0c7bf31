"""The local SLURM cluster the cluster-path tests run on (profiles/slurm/local_cluster.sh), and
Snakemake with the SLURM executor plugin (.venv-slurm, `make slurm-venv`).

`require_slurm()` starts the cluster when SLURM's packages are installed (idempotent: a running
cluster is used as it is) and skips the test, saying how to install them, where they are not.
In CI (HERTZ_CI=1, set by .ci/run) a missing cluster fails the test instead: CI never skips
(engine_cases.missing).

A test run stops the cluster it started, and only that (`release_cluster`, from conftest.py when
the run ends or is stopped): a cluster that was up when the run first needed it (`make slurm-up`,
.ci/run's) is left as it was, even where a test stops and restarts it. Each run that uses the cluster
holds a lease, `.slurm/tests/run-<pid>-<start>` ("started" or "found"); a run that started it and
ends while another still holds a lease hands the cluster over, and the last one stops it. The
lease of a run that was killed outright (SIGKILL) passes its claim to the next run that uses the
cluster; `local_cluster.sh up` run by anyone else (`make slurm-up`) takes the cluster over from
the tests.
"""

import fcntl
import os
import shutil
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path

import pytest

import processes

ROOT = Path(__file__).resolve().parents[1]
CLUSTER = ROOT / "profiles" / "slurm" / "local_cluster.sh"
SLURM_SNAKEMAKE = ROOT / ".venv-slurm" / "bin" / "snakemake"
SLURM_CONF = ROOT / ".slurm" / "etc" / "slurm.conf"
DAEMONS = ("slurmctld", "slurmd", "slurmdbd", "munged", "mariadbd", "sbatch", "sacct")
#: No test of the cluster path may hang: every workflow it starts is killed after this [s].
WORKFLOW_TIMEOUT_S = 600


def require_slurm() -> dict:
    """The environment for SLURM's clients (SLURM_CONF) once the local cluster is up."""
    from engine_cases import missing  # (here: conftest.py imports this module, at every start of pytest)

    absent = [exe for exe in DAEMONS if shutil.which(exe) is None]
    if absent:
        missing(f"SLURM is not installed ({', '.join(absent)} missing); install and start the local "
                 "cluster with: make slurm-up (apt-get install slurm-wlm slurmdbd munge mariadb-server)")
    if not SLURM_SNAKEMAKE.exists():
        missing("Snakemake's SLURM executor plugin is not installed; install it with: make slurm-venv")
    with leases() as folder:  # one test run starts the cluster at a time
        take_lease(folder)
        # Not through processes.run: the daemons it starts stay in its session.
        up = subprocess.run([str(CLUSTER), "up"], capture_output=True, text=True, timeout=180)
    if up.returncode != 0:
        pytest.fail(f"the local SLURM cluster did not start:\n{up.stdout}{up.stderr}")
    return {**os.environ, "SLURM_CONF": str(SLURM_CONF)}


#: The environment variable naming the test run (conftest.py sets it in pytest's own process; its
#: xdist workers inherit it): '<pid>-<start time>' of that process.
TEST_RUN = "HERTZ_TEST_RUN"
#: The daemons of local_cluster.sh, each with its pid file `<state>/run/<name>.pid`.
CLUSTER_DAEMONS = ("munged", "mariadbd", "slurmdbd", "slurmctld", "slurmd")


def state_dir() -> Path:
    return Path(os.environ.get("SLURM_LOCAL_DIR") or ROOT / ".slurm")


def run_id(pid: int | None = None) -> str | None:
    """'<pid>-<start time>' of process `pid` (this one), None if there is no such process."""
    try:
        fields = Path(f"/proc/{pid or os.getpid()}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return None if fields[0] in ("Z", "X") else f"{pid or os.getpid()}-{fields[19]}"


def cluster_running() -> bool:
    """Every daemon of the local cluster runs (its pid file names a live process of its name)."""
    for name in CLUSTER_DAEMONS:
        try:
            pid = int((state_dir() / "run" / f"{name}.pid").read_text().strip())
            if Path(f"/proc/{pid}/comm").read_text().strip() != name:
                return False
        except (OSError, ValueError):
            return False
    return True


@contextmanager
def leases():
    """The folder of the test runs' leases, locked (flock) while in use."""
    folder = state_dir() / "tests"
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield folder


def _live(lease: Path) -> bool:
    pid = lease.name.removeprefix("run-").split("-")[0]
    return pid.isdigit() and run_id(int(pid)) == lease.name.removeprefix("run-")


def take_lease(folder: Path) -> None:
    """This run's lease, at its first use of the cluster: "started" when the cluster is not up, or
    was started by a run that was killed (its lease says so and it is gone), else "found"."""
    mine = folder / f"run-{os.environ.get(TEST_RUN) or run_id()}"
    if mine.exists():
        return
    dead = [f for f in folder.glob("run-*") if not _live(f)]
    claimed = any(f.read_text().strip() == "started" for f in dead)
    for f in dead:
        f.unlink()
    mine.write_text("started" if claimed or not cluster_running() else "found")


def release_cluster(run: str | None = None) -> str:
    """At the end of test run `run` (this one): drop its lease; stop the cluster if the run started
    it and no other live run holds a lease (it hands the cluster over to those). What it did."""
    folder = state_dir() / "tests"
    mine = folder / f"run-{run or os.environ.get(TEST_RUN) or run_id()}"
    if not mine.exists():
        return "the run did not use the cluster"
    with leases():
        if not mine.exists():
            return "the run did not use the cluster"
        started = mine.read_text().strip() == "started"
        mine.unlink()
        others = [f for f in folder.glob("run-*") if _live(f)]
        if not started:
            return "left running: the run found it running"
        if others:
            for f in others:
                f.write_text("started")
            return f"handed over to {len(others)} other test run(s)"
        down = subprocess.run([str(CLUSTER), "down"], capture_output=True, text=True, timeout=120)
        return f"stopped: {(down.stdout + down.stderr).strip()}"


def slurm(*cmd, env=None, check=True) -> str:
    out = subprocess.run(list(cmd), capture_output=True, text=True, timeout=60, env=env)
    if check and out.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} failed: {out.stderr}")
    return out.stdout


def start_workflow(project: Path, *args, env=None) -> subprocess.Popen:
    """`snakemake --profile profiles/slurm ...` in `project`, in a session of its own that dies
    with the test (tests/processes.py)."""
    return processes.start([str(SLURM_SNAKEMAKE), "--profile", "profiles/slurm", *args], cwd=project, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def finish(proc: subprocess.Popen, timeout_s: float = WORKFLOW_TIMEOUT_S) -> tuple[int, str]:
    """Wait for a workflow of `start_workflow`; one that outlives `timeout_s` is SIGKILLed with its
    whole session (SIGTERM only asks Snakemake to wait for its jobs) and fails the test."""
    try:
        out, _ = proc.communicate(timeout=timeout_s)
    except BaseException as err:
        processes.stop(proc)
        out, _ = proc.communicate()
        if not isinstance(err, subprocess.TimeoutExpired):
            raise
        raise AssertionError(f"the workflow did not end within {timeout_s} s and was killed:\n{out[-4000:]}")
    return proc.returncode, out


def run_workflow(project: Path, *args, env=None, timeout_s: float = WORKFLOW_TIMEOUT_S) -> tuple[int, str]:
    return finish(start_workflow(project, *args, env=env), timeout_s)


def jobs_of(project: Path, env, since: str) -> list[dict]:
    """sacct's allocation rows of the jobs submitted from `project` since `since` (HH:MM:SS)."""
    fields = ("JobID", "State", "Partition", "Account", "AllocCPUS", "ReqMem", "Timelimit", "WorkDir", "Comment")
    out = slurm("sacct", "-X", "-n", "-P", "-S", since, "-o", ",".join(f"{f}%300" for f in fields), env=env)
    rows = [dict(zip(fields, line.split("|"))) for line in out.splitlines()]
    return [r for r in rows if Path(r["WorkDir"]) == project]


def queued_jobs_of(project: Path, env) -> list[dict]:
    """squeue's rows (JobID, State, Reason, Comment) of the jobs submitted from `project` that are
    still queued or running: live, where sacct lags slurmdbd by a few seconds."""
    fields = ("JobID", "State", "Reason", "Comment", "WorkDir")
    out = slurm("squeue", "-h", "-o", "|".join(f"%{c}" for c in "iTrkZ"), env=env)
    rows = [dict(zip(fields, line.split("|"))) for line in out.splitlines()]
    return [r for r in rows if Path(r["WorkDir"]) == project]


def wait_for(predicate, timeout_s: float, what: str, poll_s: float = 1.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(poll_s)
    raise AssertionError(f"waited {timeout_s} s for {what}")
