"""The cluster path, end to end on a real SLURM cluster: the local single-node cluster of
profiles/slurm/local_cluster.sh (slurmctld, slurmd, slurmdbd with MariaDB, munge), the study's
profile profiles/slurm and snakemake-executor-plugin-slurm (.venv-slurm).

Each study is small (steel spheres at K = 0.1, the viscoelastic law, LAMMPS and ESyS, whose two
MPI ranks make it the one engine job of two CPUs). The tests check what a user and a CI see: the
exit status, the rows of summary.csv against the same study run locally, what each job asked
SLURM for (sacct), and the verdict when SLURM kills, cancels or holds a job. Faulty engines are
wrappers of the real LAMMPS put first on PATH (as in test_study_failures), which SLURM's jobs
inherit. They run one at a time (one xdist group): they share the cluster's two CPUs, and one
of them drains its node.
"""

import json
import os
import shutil
import socket
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import processes
from engine_cases import missing, require_engine
from slurm_cluster import (CLUSTER, SLURM_CONF, finish, jobs_of, queued_jobs_of, require_slurm, run_workflow, slurm,
                           start_workflow, wait_for)
from test_study_failures import CASE, faulty_lammps
from workflow_copy import copy_workflow

pytestmark = pytest.mark.xdist_group("slurm")

ROOT = Path(__file__).resolve().parents[1]
#: Where a job's srun finds the cluster's config (profiles/slurm/local_cluster.sh, CLIENT_CONF).
CLIENT_CONF = Path("/run/slurm/conf/slurm.conf")
LAMMPS = "{id: lammps, code: lammps, executable: lmp}"
ESYS = "{id: esys, code: esys, executable: esysparticle}"
SMALL = ["laws=[viscoelastic]", "extras=[]", "compare_builds=[]"]


def config(*builds, extra=()):
    """--config with these builds; `extra` settings replace SMALL's of the same key."""
    keys = {e.split("=")[0] for e in extra}
    return ["--config", f"builds=[{', '.join(builds)}]", *(s for s in SMALL if s.split("=")[0] not in keys), *extra]


def local_study(project: Path, *args) -> bytes:
    """The same study run locally (`snakemake -j2`): its summary.csv."""
    out = processes.run([sys.executable, "-m", "snakemake", "-j2", "all", *args], cwd=project, capture_output=True,
                        text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return (project / "results" / "summary.csv").read_bytes()


def now() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%S")


def lost_jobs(project: Path) -> dict[str, str]:
    verdict = json.loads((project / "results" / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and not verdict["pass"]
    return {f["job"]: f["reason"] for f in verdict["failed_jobs"]}


@pytest.fixture
def cluster(runs_workflow):
    return require_slurm()


def test_study_through_slurm_gives_the_local_rows_and_each_job_asks_for_what_it_uses(cluster, tmp_path):
    require_engine("lmp", "lammps")
    require_engine("esysparticle", "esys-particle")
    # ESyS runs the viscoelastic law only clipped at zero force (engines.codes).
    args = config(LAMMPS, ESYS, extra=["laws=[viscoelastic, viscoelastic_clipped]"])
    local = local_study(copy_workflow(tmp_path / "local", CASE), *args)
    project = copy_workflow(tmp_path / "slurm", CASE)
    since = now()
    # Partition from the config, account from the environment (as sbatch reads SBATCH_ACCOUNT).
    rc, out = run_workflow(project, "all", *args, "slurm={partition: local}",
                           env={**cluster, "SBATCH_ACCOUNT": "hertz"})
    assert rc == 0, out[-4000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: ")
    assert (project / "results" / "summary.csv").read_bytes() == local  # every row, every digit
    jobs = {j["Comment"]: j for j in jobs_of(project, cluster, since)}
    # Only the engine jobs and the case summary go to the cluster; the bookkeeping stays local.
    assert set(jobs) == {"rule_run_engine_wildcards_steel_lammps", "rule_run_engine_wildcards_steel_esys",
                         "rule_case_summary_wildcards_steel"}, jobs
    assert all(j["State"] == "COMPLETED" and j["Partition"] == "local" and j["Account"] == "hertz"
               for j in jobs.values())
    esys, lammps = jobs["rule_run_engine_wildcards_steel_esys"], jobs["rule_run_engine_wildcards_steel_lammps"]
    assert (esys["AllocCPUS"], lammps["AllocCPUS"]) == ("2", "1")  # ESyS's two MPI ranks, LAMMPS's one
    assert esys["ReqMem"] == lammps["ReqMem"] == "2000M" and esys["Timelimit"] == "00:30:00"
    assert jobs["rule_case_summary_wildcards_steel"]["Timelimit"] == "00:10:00"


def test_jobs_slurm_kills_at_their_time_or_memory_limit_fail_the_gate_naming_each_engine(cluster, tmp_path):
    require_engine("lmp", "lammps")
    hang = faulty_lammps(tmp_path, "hang")["PATH"].split(":")[0] + "/lmp"
    hog = faulty_lammps(tmp_path, "hog")["PATH"].split(":")[0] + "/lmp"
    project = copy_workflow(tmp_path / "study", CASE)
    (project / "results").mkdir()
    (project / "results" / "gate.txt").write_text("PASS: an earlier study\n")
    # One minute and 1 500 MB for every engine job, no retry; the engine's own time limit is longer
    # than SLURM's, so that SLURM stops the hung engine. The healthy LAMMPS finishes within both.
    started = time.monotonic()
    rc, out = run_workflow(project, "all", "--retries", "0", "--keep-going",
                           "--set-resources", "run_engine:runtime=1", "run_engine:mem_mb=1500",
                           *config(LAMMPS, f"{{id: hang, code: lammps, executable: {hang}}}",
                                   f"{{id: hog, code: lammps, executable: {hog}}}",
                                   extra=["engine_timeout_floor_s=3600"]), env=cluster)
    assert rc != 0
    assert time.monotonic() - started < 400
    lost = lost_jobs(project)
    assert set(lost) == {"run_engine (case steel, build hang)", "run_engine (case steel, build hog)"}, lost
    assert "TIMEOUT" in lost["run_engine (case steel, build hang)"]
    assert "killed at its time limit 00:01:00" in lost["run_engine (case steel, build hang)"]
    assert "killed for its memory" in lost["run_engine (case steel, build hog)"]
    assert "over the 1500M it requested" in lost["run_engine (case steel, build hog)"]
    assert (project / "results" / "steel" / "lammps" / "manifest.json").exists()  # the healthy engine's job
    assert not (project / "results" / "gate.txt").exists()
    root = ET.parse(project / "results" / "junit.xml").getroot()
    failing = {(c.get("classname"), c.get("name")) for c in root.iter("testcase") if c.find("failure") is not None}
    assert failing == {("workflow.run_engine", "case=steel, build=hang"),
                       ("workflow.run_engine", "case=steel, build=hog")}
    head = (project / "results" / "report.md").read_text()
    assert "## The workflow did not finish: FAIL" in head and "run_engine (case steel, build hang)" in head
    assert "FAIL: 2 job(s) did not finish" in out


def test_a_cancelled_job_fails_the_run_and_a_rerun_ends_in_the_same_pass_and_rows(cluster, tmp_path):
    require_engine("lmp", "lammps")
    args = config(LAMMPS)
    local = local_study(copy_workflow(tmp_path / "local", CASE), *args)
    project = copy_workflow(tmp_path / "study", CASE)
    hold = tmp_path / "hold"
    hold.write_text("the wrapper waits while this file exists\n")
    env = {**faulty_lammps(tmp_path, "hold"), "SLURM_CONF": cluster["SLURM_CONF"], "HOLD_FILE": str(hold)}
    proc = start_workflow(project, "all", "--retries", "0", *args, env=env)
    try:
        engine_job = wait_for(lambda: [j for j in queued_jobs_of(project, cluster) if j["State"] == "RUNNING"
                                       and j["Comment"] == "rule_run_engine_wildcards_steel_lammps"],
                              240, "the engine job to run")[0]
        slurm("scancel", engine_job["JobID"], env=cluster)
    finally:
        rc, out = finish(proc)
    assert rc != 0
    lost = lost_jobs(project)
    assert list(lost) == ["run_engine (case steel, build lammps)"]
    assert f"SLURM job {engine_job['JobID']}: CANCELLED by " in lost["run_engine (case steel, build lammps)"]
    # The user's rerun, the engine released: the same PASS and the local run's rows.
    hold.unlink()
    rc, out = run_workflow(project, "all", *args, env=env)
    assert rc == 0, out[-4000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 6 ")
    assert (project / "results" / "summary.csv").read_bytes() == local
    assert "failed_jobs" not in json.loads((project / "results" / "verdict.json").read_text())


def test_a_drained_node_holds_the_jobs_until_it_is_resumed(cluster, tmp_path):
    require_engine("lmp", "lammps")
    node = slurm("sinfo", "-h", "-o", "%n", env=cluster).split()[0]
    project = copy_workflow(tmp_path / "study", CASE)
    since = now()
    slurm("scontrol", "update", f"NodeName={node}", "State=DRAIN", "Reason=hertz test: drained", env=cluster)
    try:
        proc = start_workflow(project, "all", *config(LAMMPS), env=cluster)
        try:
            wait_for(lambda: queued_jobs_of(project, cluster), 240, "a job to be queued")
            time.sleep(15)  # the scheduler has had its passes: the job still waits, and so does the workflow
            (job,) = queued_jobs_of(project, cluster)
            state, reason = job["State"], job["Reason"]
            assert state == "PENDING" and proc.poll() is None
            # What a user sees: squeue's reason names the drained node; Snakemake waits without a word.
            assert "ReqNodeNotAvail" in reason or "Nodes required for job are DOWN, DRAINED" in reason, reason
            assert "drain" in slurm("sinfo", "-h", "-n", node, "-o", "%t", env=cluster)
        finally:
            slurm("scontrol", "update", f"NodeName={node}", "State=RESUME", env=cluster, check=False)
        rc, out = finish(proc)
    finally:
        slurm("scontrol", "update", f"NodeName={node}", "State=RESUME", env=cluster, check=False)
    assert rc == 0, out[-4000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 6 ")
    assert all(j["State"] == "COMPLETED" for j in jobs_of(project, cluster, since))


def test_local_cluster_script_is_idempotent_and_refuses_a_second_cluster(cluster, tmp_path):
    again = subprocess.run([str(CLUSTER), "up"], capture_output=True, text=True, timeout=120)
    assert again.returncode == 0 and "already running" in again.stdout
    state = tmp_path / "second"
    env = {**cluster, "SLURM_LOCAL_DIR": str(state)}
    second = subprocess.run([str(CLUSTER), "up"], capture_output=True, text=True, timeout=120, env=env)
    # The running cluster's client link is the first thing it meets; it names the way to stop it.
    assert second.returncode != 0, second.stdout
    assert (f"{CLIENT_CONF} links to {SLURM_CONF}, the config of another local cluster that still runs"
            in second.stderr), second.stderr
    assert f"SLURM_LOCAL_DIR={SLURM_CONF.parents[1]} " in second.stderr
    status = subprocess.run([str(CLUSTER), "status"], capture_output=True, text=True, timeout=60, env=env)
    assert status.stdout.count("not running") == 5
    assert CLIENT_CONF.resolve() == SLURM_CONF  # left as it was
    (state / "run").mkdir(parents=True)
    (state / "run" / "slurmd.pid").write_text("999999\n")
    stale = subprocess.run([str(CLUSTER), "status"], capture_output=True, text=True, timeout=60, env=env)
    assert "stale pid file" in stale.stderr and not (state / "run" / "slurmd.pid").exists()


def cluster_script(*args, env=None) -> subprocess.CompletedProcess:
    return subprocess.run([str(CLUSTER), *args], capture_output=True, text=True, timeout=180, env=env)


def test_what_a_stopped_cluster_left_in_run_is_replaced_and_what_another_owns_is_refused(cluster, tmp_path):
    """/run outlives the daemons: a session or CI job that ended with its cluster up leaves its
    client link behind, pointing at its own clone. The next clone's cluster must replace it (CI on
    a clean clone was refused by exactly that), but never a file it did not write, nor start
    anything where one of its ports is taken."""
    if os.geteuid() != 0:
        missing("writing /run/slurm/conf needs root (CI runs as root); run this test as root")
    down = cluster_script("down")
    assert down.returncode == 0 and not CLIENT_CONF.is_symlink(), down.stdout + down.stderr
    other = tmp_path / "clone" / ".slurm" / "etc" / "slurm.conf"
    other.parent.mkdir(parents=True)
    other.write_text("# Written by profiles/slurm/local_cluster.sh: a single-node cluster for the study's tests.\n"
                     f"SlurmctldPidFile={tmp_path}/clone/.slurm/run/slurmctld.pid\n")
    try:
        # A link to another clone's config whose slurmctld no longer runs, then one whose clone is gone.
        for planted in ("stopped", "deleted"):
            if planted == "deleted":
                shutil.rmtree(tmp_path / "clone")
            CLIENT_CONF.parent.mkdir(parents=True, exist_ok=True)
            CLIENT_CONF.symlink_to(other)
            up = cluster_script("up")
            assert up.returncode == 0, up.stdout + up.stderr
            assert (f"replacing {CLIENT_CONF}, a link to {other} left by a local cluster that no longer runs"
                    in up.stdout), (planted, up.stdout)
            assert Path(os.readlink(CLIENT_CONF)) == SLURM_CONF
            assert cluster_script("down").returncode == 0

        # A file it did not write (a configless slurmd's cache): refused, left alone, nothing started.
        CLIENT_CONF.write_text("ClusterName=elsewhere\n")
        refused = cluster_script("up")
        assert refused.returncode != 0
        assert f"{CLIENT_CONF} exists and is not this cluster's" in refused.stderr, refused.stderr
        assert CLIENT_CONF.read_text() == "ClusterName=elsewhere\n"
        assert cluster_script("status").stdout.count("not running") == 5
        CLIENT_CONF.unlink()

        # slurmd's port taken by another process: refused before any daemon starts (it is checked last).
        with socket.socket() as taken:
            # SO_REUSEADDR: the stopped slurmd's connections may linger in TIME_WAIT on 6818, which
            # blocks a plain bind ('Address already in use') though nothing listens there any more.
            taken.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            taken.bind(("127.0.0.1", 6818))
            taken.listen()
            refused = cluster_script("up")
        assert refused.returncode != 0 and "port 6818 (for slurmd) is in use by another process" in refused.stderr
        assert cluster_script("status").stdout.count("not running") == 5
    finally:
        if CLIENT_CONF.is_symlink() or CLIENT_CONF.exists():
            if Path(os.readlink(CLIENT_CONF) if CLIENT_CONF.is_symlink() else "") != SLURM_CONF:
                CLIENT_CONF.unlink()
        restored = cluster_script("up")
        assert restored.returncode == 0, restored.stdout + restored.stderr
