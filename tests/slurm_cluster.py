"""The local SLURM cluster the cluster-path tests run on (profiles/slurm/local_cluster.sh), and
Snakemake with the SLURM executor plugin (.venv-slurm, `make slurm-venv`).

`require_slurm()` starts the cluster when SLURM's packages are installed (idempotent: a running
cluster is used as it is) and skips the test, saying how to install them, where they are not.
In CI (HERTZ_CI=1, set by .ci/run) a missing cluster fails the test instead: CI never skips
(engine_cases.missing).
"""

import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

from engine_cases import missing

ROOT = Path(__file__).resolve().parents[1]
CLUSTER = ROOT / "profiles" / "slurm" / "local_cluster.sh"
SLURM_SNAKEMAKE = ROOT / ".venv-slurm" / "bin" / "snakemake"
SLURM_CONF = ROOT / ".slurm" / "etc" / "slurm.conf"
DAEMONS = ("slurmctld", "slurmd", "slurmdbd", "munged", "mariadbd", "sbatch", "sacct")
#: No test of the cluster path may hang: every workflow it starts is killed after this [s].
WORKFLOW_TIMEOUT_S = 600


def require_slurm() -> dict:
    """The environment for SLURM's clients (SLURM_CONF) once the local cluster is up."""
    absent = [exe for exe in DAEMONS if shutil.which(exe) is None]
    if absent:
        missing(f"SLURM is not installed ({', '.join(absent)} missing); install and start the local "
                 "cluster with: make slurm-up (apt-get install slurm-wlm slurmdbd munge mariadb-server)")
    if not SLURM_SNAKEMAKE.exists():
        missing("Snakemake's SLURM executor plugin is not installed; install it with: make slurm-venv")
    up = subprocess.run([str(CLUSTER), "up"], capture_output=True, text=True, timeout=180)
    if up.returncode != 0:
        pytest.fail(f"the local SLURM cluster did not start:\n{up.stdout}{up.stderr}")
    return {**os.environ, "SLURM_CONF": str(SLURM_CONF)}


def slurm(*cmd, env=None, check=True) -> str:
    out = subprocess.run(list(cmd), capture_output=True, text=True, timeout=60, env=env)
    if check and out.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} failed: {out.stderr}")
    return out.stdout


def start_workflow(project: Path, *args, env=None) -> subprocess.Popen:
    """`snakemake --profile profiles/slurm ...` in `project`, in a process group of its own."""
    return subprocess.Popen([str(SLURM_SNAKEMAKE), "--profile", "profiles/slurm", *args], cwd=project, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)


def finish(proc: subprocess.Popen, timeout_s: float = WORKFLOW_TIMEOUT_S) -> tuple[int, str]:
    """Wait for a workflow of `start_workflow`; one that outlives `timeout_s` is SIGKILLed with its
    whole process group (SIGTERM only asks Snakemake to wait for its jobs) and fails the test."""
    try:
        out, _ = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
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
