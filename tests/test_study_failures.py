"""The study's failure paths, end to end through Snakemake with a real engine (LAMMPS).

Each test runs the workflow on a copy of the project with one small case (steel spheres, K = 0.1)
and, where it needs a faulty engine, a wrapper named `lmp` put first on PATH: it runs the real
LAMMPS and then spoils what it wrote (a collision 1 % slower: times x 1.01, velocities / 1.01;
the out-of-the-box records deleted), or crashes, or hangs. The tests check what a user and a CI see: the exit \
status, the verdict at the
top of the report, the JUnit XML, and that nothing saying PASS survives a failed or killed rerun.
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pandas as pd
import pytest

import processes
from engine_cases import missing, require_engine
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
CASE = """name: steel
effective_modulus: 109 GPa
radius: 0.635 cm
viscosity: 6.7e5 P
density: 7800 kg/m^3
geometries: [sphere-sphere]
impact:
  K: [0.1]
"""
SMALL = ["builds=[{id: lammps, code: lammps, executable: lmp}]", "laws=[viscoelastic,default]", "extras=[]"]
WRAPPER = '''#!{python}
"""A faulty LAMMPS for the tests: mode {mode!r}."""
import glob, os, subprocess, sys, time
args = sys.argv[1:]
sweep = "-in" in args
if sweep and {mode!r} == "crash":
    sys.exit(139)
if sweep and {mode!r} == "hang":
    open("hang.pid", "w").write(str(os.getpid()))
    time.sleep(600)
if sweep and {mode!r} == "hog":  # 3 GiB, every page touched, held until killed
    block = bytearray(3 * 2**30)
    block[::4096] = b"1" * len(block[::4096])
    time.sleep(600)
if sweep and {mode!r} == "hold":  # waits while the file HOLD_FILE exists, then runs LAMMPS
    while os.path.exists(os.environ["HOLD_FILE"]):
        time.sleep(0.2)
if sweep and {mode!r} == "scale-e":  # the keyword's e (LAMMPS tsuji, LIGGGHTS's), a dashpot's eta_n x (1 + 1e-4)
    import re
    script = args[args.index("-in") + 1]
    text = open(script).read()
    scale = lambda m: m.group(1) + repr(float(m.group(2)) * (1 + 1e-4)) + m.group(3)
    text = re.sub(r"(hertz/material \\S+ )(\\S+)( 0\\.0 damping (?:tsuji|velocity|mass_velocity) )", scale, text)
    text = re.sub(r'(variable restitution index ")([^"]+)(")', scale, text)
    open(script, "w").write(text)
rc = subprocess.call([{real!r}, *args])
for raw in glob.glob("*.lammps.txt") if sweep else []:
    if "slow" in {mode!r} and "-viscoelastic" in raw:
        # the same collision 1 % slower, consistently: t -> 1.01 t, d(delta)/dt -> / 1.01
        lines = open(raw).read().splitlines()
        rows = [" ".join([repr(float(w[0]) * 1.01), w[1], repr(float(w[2]) / 1.01), w[3]])
                for w in (line.split() for line in lines[1:])]
        open(raw, "w").write("\\n".join([lines[0]] + rows) + "\\n")
    if "drop-default" in {mode!r} and "-default-" in raw:
        os.remove(raw)
sys.exit(rc)
'''


@pytest.fixture
def project(tmp_path, runs_workflow):
    require_engine("lmp", "lammps")
    return copy_workflow(tmp_path / "study", CASE)


def faulty_lammps(tmp_path, mode, name="lmp") -> dict:
    """The environment with a wrapper `lmp` first on PATH. Modes: slow (the viscoelastic runs'
    collisions 1 % slower: times x 1.01, velocities / 1.01), drop-default (the out-of-the-box
    records deleted), both joined by '+', crash (exit 139 at once), hang (sleep 600 s before
    running), hog (take 3 GiB and hold it), hold (wait while the file $HOLD_FILE exists)."""
    real = shutil.which(name)
    bin_dir = tmp_path / f"bin-{mode}"
    bin_dir.mkdir()
    wrapper = bin_dir / name
    wrapper.write_text(WRAPPER.format(python=sys.executable, mode=mode, real=real))
    wrapper.chmod(0o755)
    return {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}


def wait_for_the_hung_engine(pid_file: Path, proc) -> None:
    """Until the 'hang' wrapper wrote its pid (the engine job is running), at most 300 s."""
    deadline = time.monotonic() + 300
    while not pid_file.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.2)
    assert pid_file.exists(), "the engine job never started"


def kill_the_hung_engine(pid_file: Path) -> None:
    """SIGKILL the 'hang' wrapper, wherever the test ended (it would sleep 600 s)."""
    for pid in [int(pid_file.read_text())] if pid_file.exists() else []:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def study(project, *config, env=None, target="all", extra=()):
    return processes.run([sys.executable, "-m", "snakemake", "-j2", target, *extra, "--config", *SMALL, *config],
                         cwd=project, capture_output=True, text=True, timeout=600, env=env)


def verdict_files(project):
    return sorted(p.name for p in (project / "results").glob("*") if p.name in
                  ("gate.txt", "verdict.json", "junit.xml", "report.md", "report.html"))


def junit(project):
    root = ET.parse(project / "results" / "junit.xml").getroot()
    cases = root.findall(".//testcase")
    failing = {f"{c.get('classname')}.{c.get('name')}" for c in cases if c.find("failure") is not None}
    return len(cases), failing


def report_head(project) -> str:
    return (project / "results" / "report.md").read_text().split("## Engines")[0]


@pytest.mark.parametrize("law", ["viscoelastic", "elastic"])
def test_a_study_of_one_build_one_case_one_geometry_and_one_law_passes_with_every_extra(project, law):
    """The minima a user gating their own build meets: one build (no pair of builds to spread or
    compare), one case of one geometry, one law; every extra section on (convergence, paper,
    LAMMPS regressions, calibration). It crashed in the report on a one-byte build_spread.csv."""
    for path in (ROOT / "cases").rglob("*"):  # the paper's and the calibration's cases, for those extras
        target = project / "cases" / path.relative_to(ROOT / "cases")
        if path.is_file() and not target.exists():
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(path, target)
    out = processes.run([sys.executable, "-m", "snakemake", "-j2", "all", "--config", "cases=cases/steel.yaml",
                         "builds=[{id: lammps-mine, code: lammps, executable: lmp}]", f"laws=[{law}]"],
                        cwd=project, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    checks = 2 if law == "viscoelastic" else 1  # criteria x0 and F0, or x0 alone; x one geometry
    assert (project / "results" / "gate.txt").read_text().startswith(f"PASS: {checks * 3} ")
    head = report_head(project)
    assert f"**Verdict: PASS** — {checks * 3} of {checks * 3} gated checks" in head
    assert pd.read_csv(project / "results" / "convergence" / "build_spread.csv").empty  # its header, no rows
    assert junit(project) == (checks * 3 + 3 * 2, set())  # and the reported-only regression checks, skipped


def test_an_elastic_case_says_in_its_plan_and_its_reports_that_only_the_elastic_law_runs(project):
    (project / "cases" / "steel.yaml").write_text(CASE.replace("6.7e5 P", "0 P").replace("K: [0.1]",
                                                                                         "velocity: [1 m/s]"))
    out = study(project, "laws=[viscoelastic,elastic,default]")  # the later laws= of --config holds
    assert out.returncode == 0, out.stderr[-3000:]
    note = ("steel: the viscosity is 0, an elastic contact: only the law 'elastic' runs; viscoelastic, default left "
            "out (give a positive `viscosity:` to run them)")
    assert f"Note: {note}" in out.stderr
    assert note in json.loads((project / "results" / "steel" / "plan.json").read_text())["notes"]
    for report in (project / "results" / "report.md", project / "results" / "steel" / "report.md"):
        assert f"## What the plans say\n\n- {note}\n" in report.read_text(), report
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 3 ")


def test_a_case_of_restitutions_runs_each_at_its_own_viscosity_and_passes(project):
    """impact: {restitution: [0.8, 0.5], velocity: [1 m/s]} through the workflow with real LAMMPS:
    two ladders per law, each at the eta that restitutes its eps (F0), which LAMMPS reproduces;
    the out-of-the-box law told 0.8 and 0.5."""
    (project / "cases" / "steel.yaml").write_text(CASE.replace("viscosity: 6.7e5 P\n", "").replace(
        "  K: [0.1]", "  restitution: [0.8, 0.5]\n  velocity: [1 m/s]"))
    out = study(project)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "Note: steel: restitution 0.8 under F0 at V = 1 m/s: sphere-sphere eta = " in out.stderr
    summary = pd.read_csv(project / "results" / "summary.csv")
    limits = summary[(summary.law == "viscoelastic") & (summary.dt == 0) & (summary.criterion == "F0")]
    assert sorted(limits.eps_ref.round(9)) == [0.5, 0.8] and (limits.err_eps.abs() < 1e-6).all()
    plan = json.loads((project / "results" / "steel" / "plan.json").read_text())
    assert sorted({r["matched_restitution"] for r in plan["runs"] if r["law"] == "default"}) == [0.5, 0.8]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 9 ")  # the keyword's x0 too


@pytest.mark.parametrize("code, executable", [("lammps", "lmp"), ("liggghts", "liggghts")])
def test_a_keyword_told_a_restitution_1e_4_off_fails_its_own_checks(project, tmp_path, code, executable):
    """LAMMPS's tsuji and LIGGGHTS's coefficientRestitution with the e of the generated deck scaled by
    (1 + 1e-4): the keyword's checks against its own equation fail, named; the viscoelastic law's pass."""
    require_engine(executable, code)
    out = study(project, f"builds=[{{id: {code}, code: {code}, executable: {executable}}}]",
                env=faulty_lammps(tmp_path, "scale-e", executable))
    assert out.returncode != 0
    n, failing = junit(project)
    assert n == 9  # viscoelastic x0, F0 and the keyword's x0, each T, A, eps
    assert f"{code}.default.sphere-sphere.x0.eps" in failing
    assert not any(".viscoelastic." in f for f in failing)
    assert f"{code} default sphere-sphere x0 eps: " in out.stdout + out.stderr


def test_a_dashpot_whose_coefficient_is_1e_4_off_fails_its_own_checks(project, tmp_path):
    """LAMMPS's damping velocity and mass_velocity (laws of their own) with the eta_n of the generated
    deck scaled by (1 + 1e-4): each law's checks against its own equation fail, named; the
    viscoelastic law's pass. Unscaled, the same study passes."""
    laws = "laws=[viscoelastic,velocity,mass_velocity]"
    ok = study(project, laws)
    assert ok.returncode == 0, ok.stderr[-3000:]
    out = study(project, laws, env=faulty_lammps(tmp_path, "scale-e"), extra=("--forceall",))
    assert out.returncode != 0
    n, failing = junit(project)
    assert n == 12  # viscoelastic x0, F0 and each dashpot's x0, each T, A, eps
    for law in ("velocity", "mass_velocity"):
        assert f"lammps.{law}.sphere-sphere.x0.eps" in failing
        assert f"lammps {law} sphere-sphere x0 eps: " in out.stdout + out.stderr
    assert not any(".viscoelastic." in f for f in failing)


def test_too_tight_tolerance_fails_and_no_earlier_pass_survives(project):
    ok = study(project)
    assert ok.returncode == 0, ok.stderr[-3000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 9 ")
    # Tolerances through --config arrive as strings in a mapping: accepted as numbers. 1e-8 is below
    # the ladders' resolution (~1e-7): T and A cannot be judged at it, and their checks fail (the
    # model's and LAMMPS's tsuji keyword's).
    tight = study(project, "tolerance={T: 1e-8, A: 1.0e-8, eps: 1e-6}")
    assert tight.returncode != 0
    assert not (project / "results" / "gate.txt").exists()
    head = report_head(project)
    assert "**Verdict: FAIL** — 3 of 9 gated checks" in head
    assert "not resolved at this tolerance" in head
    expected = ({f"lammps.viscoelastic.sphere-sphere.{c}.{q}" for c in ("x0", "F0") for q in ("T", "A")}
                | {f"lammps.default.sphere-sphere.x0.{q}" for q in ("T", "A")})
    assert junit(project) == (9, expected)
    for name in expected:
        law, rest = name.split(".", 2)[1:]
        line = f"lammps {law} " + rest.replace(".", " ")
        assert f"- {line}: " in head and line in tight.stdout + tight.stderr
    verdict = json.loads((project / "results" / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and verdict["failed"] == 6 and verdict["tolerance"]["T"] == 1e-8


def test_engine_one_percent_slow_fails_its_time_and_restitution_checks_and_a_keyword_with_no_record_fails_its_own(
        project, tmp_path):
    out = study(project, env=faulty_lammps(tmp_path, "slow+drop-default"))
    assert out.returncode != 0
    summary = pd.read_csv(project / "results" / "summary.csv")
    gated = summary[(summary.law == "viscoelastic") & (summary.dt == 0)]
    # 1 % slower on top of the engine's own ~1e-9 at dt -> 0: err_T = 1.01 (1 + e) - 1 and
    # err_eps = (1 + e) / 1.01 - 1; the overlap, hence A, is the engine's.
    assert len(gated) == 2 and gated.err_T.to_numpy() == pytest.approx(0.01, abs=1e-7)
    assert gated.err_eps.to_numpy() == pytest.approx(1 / 1.01 - 1, abs=1e-7)
    assert (gated.err_A.abs() < 1e-7).all() and (gated.problem.isna() | (gated.problem == "")).all()
    # The T and eps checks fail, A passes; the keyword's runs left no record: its checks fail, naming them.
    keyword = {f"lammps.default.sphere-sphere.x0.{q}" for q in ("T", "A", "eps")}
    assert junit(project) == (9, {f"lammps.viscoelastic.sphere-sphere.{c}.{q}" for c in ("x0", "F0")
                                  for q in ("T", "eps")} | keyword)
    assert "**Verdict: FAIL** — 2 of 9 gated checks" in report_head(project)
    assert "lammps viscoelastic sphere-sphere x0 T: 1.000e-02 > 1e-06" in out.stdout + out.stderr
    report = (project / "results" / "report.md").read_text()
    section = report.split("## Runs not made or not completed")[1]
    assert "| steel | lammps | default | lammps-default-sphere-sphere-K0.1-" in section
    assert "unreadable engine record" in section
    failures = "".join(json.loads((project / "results" / "verdict.json").read_text())["failures"])
    assert "lammps default sphere-sphere x0 T: " in failures and "unreadable engine record" in failures


def test_crashed_engine_fails_every_check_naming_the_run(project, tmp_path):
    out = study(project, env=faulty_lammps(tmp_path, "crash"))
    assert out.returncode != 0
    n, failing = junit(project)
    assert n == 9 and len(failing) == 9
    head = report_head(project)
    assert "**Verdict: FAIL** — 0 of 9 gated checks" in head
    assert "1 of 1 ladders have a failed run; first: lammps-viscoelastic-sphere-sphere-K0.1-" in head
    assert "139" in head and "1 of 1 ladders have a failed run" in out.stdout + out.stderr
    # The runs the engine did not complete: one table row per run, its log's last lines in a
    # collapsed block below the table (never as rows of their own), in report.md and report.html.
    report = (project / "results" / "report.md").read_text()
    section = report.split("Runs the engine did not complete")[1].split("\n## ")[0]
    table = [line for line in section.splitlines() if line.startswith("|")]
    runs = table[2:]  # the crashed rung, the ladder's three others and the keyword's four, not run after it
    assert len(runs) == 8 and all(line.count(" | ") == 5 for line in runs), table
    assert "\\|" not in section
    assert section.count("<details><summary>") == 1 and "<pre>(the log is empty)</pre>" in section
    page = (project / "results" / "report.html").read_text()
    html_section = page.split("Runs the engine did not complete")[1].split("<h2")[0]
    assert html_section.count("<tr>") == 9 and html_section.count("<details>") == 1  # the header and eight runs


def test_hung_engine_is_stopped_and_fails_every_check(project, tmp_path):
    started = time.monotonic()
    out = study(project, "engine_timeout_floor_s=1", env=faulty_lammps(tmp_path, "hang"))
    assert out.returncode != 0
    assert time.monotonic() - started < 100  # the wrapper would sleep 600 s; the limit here is ~11 s
    n, failing = junit(project)
    assert n == 9 and len(failing) == 9
    head = report_head(project)
    assert "**Verdict: FAIL** — 0 of 9 gated checks" in head and "did not finish within" in head


def test_copied_results_read_their_own_dumps_and_an_edited_dump_is_refused(project, tmp_path):
    out = study(project)
    assert out.returncode == 0, out.stderr[-3000:]
    manifest = json.loads((project / "results" / "steel" / "lammps" / "manifest.json").read_text())
    assert all(not Path(d["path"]).is_absolute() and d["path"].startswith("runs/") for d in manifest["dumps"])
    summary = (project / "results" / "summary.csv").read_bytes()
    assert b"steel/lammps/runs/lammps-viscoelastic" in summary and str(project).encode() not in summary

    copy = tmp_path / "copy"
    shutil.copytree(project, copy, symlinks=True)  # the engines stay links (.yade-2025 holds /dev nodes)
    shutil.rmtree(project)  # the copy must not need the original
    again = study(copy, extra=["--forcerun", "case_summary"])
    assert again.returncode == 0, again.stderr[-3000:]
    assert (copy / "results" / "summary.csv").read_bytes() == summary

    dump = next((copy / "results" / "steel" / "lammps" / "runs").glob("lammps-viscoelastic-*.csv"))
    lines = dump.read_text().splitlines()
    row = next(i for i, line in enumerate(lines) if line and line[0].isdigit() and float(line.split(",")[1]) > 0)
    t, x, v, f = lines[row].split(",")
    lines[row] = ",".join([t, repr(float(x) * 1.0002), v, f])
    dump.write_text("\n".join(lines) + "\n")
    edited = study(copy, extra=["--forcerun", "case_summary"])
    assert edited.returncode != 0
    assert f"{dump.relative_to(copy)}: the dump changed after the engine job wrote it" in edited.stderr
    # The rerun withdrew the old PASS before it failed, and the failed job is the verdict: FAIL naming it.
    assert verdict_files(copy) == ["junit.xml", "report.html", "report.md", "verdict.json"]
    verdict = json.loads((copy / "results" / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and [f["job"] for f in verdict["failed_jobs"]] == ["case_summary (case steel)"]
    assert verdict["failed_jobs"][0]["reason"].startswith(f"DumpError: {dump.relative_to(copy)}: the dump changed")
    assert junit(copy) == (1, {"workflow.case_summary.case=steel"})
    assert "## The workflow did not finish: FAIL" in (copy / "results" / "report.md").read_text()
    assert "FAIL: 1 job(s) did not finish" in edited.stderr


def test_killed_run_leaves_no_verdict_and_the_documented_recovery_works(project, tmp_path):
    # The verdict files of an earlier study, all saying PASS; the engine job must withdraw them.
    (project / "results").mkdir()
    for name in ("gate.txt", "verdict.json", "junit.xml", "report.md", "report.html"):
        (project / "results" / name).write_text("PASS\n")
    env = faulty_lammps(tmp_path, "hang")
    proc = processes.start([sys.executable, "-m", "snakemake", "-j2", "all", "--config", *SMALL], cwd=project,
                           env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    pid_file = project / "results" / "steel" / "lammps" / "runs" / "hang.pid"
    try:
        wait_for_the_hung_engine(pid_file, proc)
        os.killpg(proc.pid, signal.SIGKILL)  # kill -9 the workflow mid-run
        proc.wait(timeout=30)
    finally:
        kill_the_hung_engine(pid_file)
    # Nothing says PASS: the gate's stamp is gone, the verdict says STALE, the reports open with it.
    assert verdict_files(project) == ["junit.xml", "report.html", "report.md", "verdict.json"]
    assert json.loads((project / "results" / "verdict.json").read_text())["verdict"] == "STALE"
    assert "**STALE**" in (project / "results" / "report.md").read_text()

    # What a user meets next: the killed run's outputs are incomplete, and its lock is still there.
    incomplete = study(project)
    assert incomplete.returncode != 0 and "IncompleteFilesException" in incomplete.stderr
    locked = study(project, extra=["--rerun-incomplete"])
    assert locked.returncode != 0 and "LockException" in locked.stderr
    # The README's recovery: unlock, then rerun what was left incomplete.
    unlock = processes.run([sys.executable, "-m", "snakemake", "--unlock"], cwd=project, capture_output=True,
                           text=True, timeout=120)
    assert unlock.returncode == 0, unlock.stderr
    again = study(project, extra=["--rerun-incomplete"])
    assert again.returncode == 0, again.stderr[-3000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: 9 ")


def test_an_interrupted_case_run_is_no_failure_and_continues_to_pass(project, tmp_path):
    """Ctrl-C (SIGINT to the workflow's process group) during `snakemake -j2 steel`: the case's
    verdict says INTERRUPTED with the job and the command that continues, the study's report stays
    readable and is only marked stale, no report holds a traceback, the unfinished engine outputs
    are gone; the continuing command passes the case, and `all` the study."""
    ok = study(project)
    assert ok.returncode == 0, ok.stderr[-3000:]
    results = project / "results"
    matrix = (results / "report.md").read_text().split("## Engines")[1]
    proc = processes.start([sys.executable, "-m", "snakemake", "-j2", "steel", "--forcerun", "run_engine",
                             "--config", *SMALL], cwd=project, env=faulty_lammps(tmp_path, "hang"),
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    pid_file = results / "steel" / "lammps" / "runs" / "hang.pid"
    try:
        wait_for_the_hung_engine(pid_file, proc)
        hung = int(pid_file.read_text())
        os.killpg(proc.pid, signal.SIGINT)  # what Ctrl-C in the terminal does
        said, _ = proc.communicate(timeout=120)
    finally:
        kill_the_hung_engine(pid_file)
    assert proc.returncode != 0
    command = ("snakemake -j2 steel --forcerun run_engine --config " + " ".join(f"'{c}'" if " " in c or "[" in c
                                                                                 else c for c in SMALL)
               + " --rerun-incomplete")
    assert "INTERRUPTED: run_engine (case steel, build lammps) did not finish" in said
    assert f"Continue with:\n  {command}" in said and "FAIL" not in said
    case_verdict = json.loads((results / "steel" / "verdict.json").read_text())
    assert case_verdict["verdict"] == "INTERRUPTED" and case_verdict["continue"] == command
    assert [j["job"] for j in case_verdict["interrupted_jobs"]] == ["run_engine (case steel, build lammps)"]
    assert not (results / "steel" / "lammps" / "runs").exists()  # the unfinished dumps and the engine's scratch
    study_verdict = json.loads((results / "verdict.json").read_text())
    assert study_verdict["verdict"] == "STALE" and study_verdict["stale"]["was"] == "PASS"
    assert "interrupted in run_engine (case steel, build lammps)" in study_verdict["stale"]["by"]
    assert not (results / "gate.txt").exists()
    report = (results / "report.md").read_text()
    assert "**STALE**" in report and report.split("## Engines")[1] == matrix  # the study's report is kept
    for path in [*results.rglob("report.md"), *results.rglob("report.html"), *results.rglob("*.json"),
                 *results.rglob("junit.xml")]:
        assert "Traceback" not in path.read_text() and "KeyboardInterrupt" not in path.read_text(), path
    try:
        os.kill(hung, 0)
        alive = True
    except ProcessLookupError:
        alive = False
    assert not alive, "the interrupted engine process outlived the workflow"

    again = processes.run(command.replace("snakemake", f"{sys.executable} -m snakemake", 1), shell=True,
                          cwd=project, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr[-3000:]
    assert (results / "steel" / "gate.txt").read_text().startswith("PASS: 9 ")
    assert json.loads((results / "verdict.json").read_text())["verdict"] == "STALE"  # a case target leaves it so
    whole = study(project)
    assert whole.returncode == 0, whole.stderr[-3000:]
    assert (results / "gate.txt").read_text().startswith("PASS: 9 ")
    assert "STALE" not in (results / "report.md").read_text()


def test_compare_target_names_the_regressions_of_a_faulty_build_and_the_reverse_as_fixes(project, tmp_path):
    baseline = tmp_path / "baseline"
    shutil.copytree(project, baseline, symlinks=True)
    ok = study(baseline)
    assert ok.returncode == 0, ok.stderr[-3000:]
    # The candidate: the same study with an engine whose collisions are 1 % slow, compared through the workflow.
    out = study(project, f"compare_baseline={baseline / 'results'}", env=faulty_lammps(tmp_path, "slow"),
                target="compare")
    assert out.returncode != 0 and "4 regressions against the baseline" in out.stdout + out.stderr
    comparison = pd.read_csv(project / "results" / "compare" / "compare.csv")
    regressions = comparison[comparison.status == "regression"]
    assert sorted(regressions.criterion + " " + regressions.quantity) == ["F0 T", "F0 eps", "x0 T", "x0 eps"]
    assert (comparison[comparison.quantity == "A"].status == "unchanged").all()
    assert regressions.change.min() > 1e5  # ~1e-9 -> 1e-2
    assert not (project / "results" / "compare" / "gate.txt").exists()
    # The other way round (baseline: the faulty build) the same checks are fixes, and it passes.
    back = processes.run([sys.executable, "-m", "verdict.compare", str(project / "results"),
                           str(baseline / "results"), "--out", str(tmp_path / "back")], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert back.returncode == 0 and "0 regressions, 4 fixes" in back.stdout


YADE_SCALING_WRAPPER = '''#!{python}
"""YADE 2025 with the number {key!r} of every run of its job file that has one scaled by (1 + {scale!r}):
c (the native law's beta is computed from it), en (what YADE's en + vn is told; cases/decks/yade/collisions.py)."""
import json, os, sys
args = sys.argv[1:]
for a in args:
    if a.startswith("job="):
        path = a[4:]
        job = json.load(open(path))
        for run in job["runs"]:
            if {key!r} in run:
                run[{key!r}] = run[{key!r}] * (1 + {scale!r})
        json.dump(job, open(path, "w"))
os.execv({real!r}, [{real!r}, *args])
'''


def test_yade_2025s_own_law_passes_and_its_coefficient_1e_5_off_fails(tmp_path):
    """YADE 2025.2.0 runs the viscoelastic law clipped with its own Brilliantov force (MindlinPhys.beta,
    set from the study's c): unmodified it passes the gate at K = 1; with c scaled by (1 + 1e-5) in
    the job file YADE reads, eps (F0) moves by -6.8e-6 and the gate FAILs, naming the build, law and eps."""
    real = ROOT / ".yade-2025" / "yade"
    if not real.exists():
        missing("YADE 2025 is not installed; install it with: make yade-2025")
    # ten times the viscosity: K = 1 at the velocity of K = 0.1 (K ~ eta V^(-1/5))
    project = copy_workflow(tmp_path / "study", CASE.replace("6.7e5 P", "6.7e6 P").replace("K: [0.1]", "K: [1.0]"))
    wrapper = tmp_path / "yade-scaled"
    wrapper.write_text(YADE_SCALING_WRAPPER.format(python=sys.executable, key="c", scale=1e-5, real=str(real)))
    wrapper.chmod(0o755)
    settings = ["laws=[viscoelastic_clipped]", "compare_builds=[]"]
    ok = study(project, "builds=[{id: yade-2025, code: yade, executable: .yade-2025/yade}]", *settings)
    assert ok.returncode == 0, ok.stderr[-3000:]
    assert junit(project) == (3, set())  # T, A and eps (F0), each within 1e-6 with its resolution
    out = study(project, f"builds=[{{id: yade-2025, code: yade, executable: {wrapper}}}]", *settings,
                extra=("--forceall",))
    assert out.returncode != 0
    n, failing = junit(project)
    assert n == 3 and "yade-2025.viscoelastic_clipped.sphere-sphere.F0.eps" in failing
    assert "yade-2025 viscoelastic_clipped sphere-sphere F0 eps: " in out.stdout + out.stderr


def test_yade_2025s_en_vn_passes_and_told_an_en_1e_4_off_fails_its_own_checks(tmp_path):
    """The law en_vn (YADE's en + vn, Brilliantov's law at the K of its Pade): unmodified, YADE 2025
    meets its own equation (T, A, eps under F0); with the en of the job file YADE reads scaled by
    (1 + 1e-4), K moves, eps with it (~1e-4), and the gate FAILs, naming yade-2025 en_vn F0 eps."""
    real = ROOT / ".yade-2025" / "yade"
    if not real.exists():
        missing("YADE 2025 is not installed; install it with: make yade-2025")
    project = copy_workflow(tmp_path / "study", CASE)
    wrapper = tmp_path / "yade-scaled"
    wrapper.write_text(YADE_SCALING_WRAPPER.format(python=sys.executable, key="en", scale=1e-4, real=str(real)))
    wrapper.chmod(0o755)
    settings = ["laws=[en_vn]", "compare_builds=[]"]
    ok = study(project, "builds=[{id: yade-2025, code: yade, executable: .yade-2025/yade}]", *settings)
    assert ok.returncode == 0, ok.stderr[-3000:]
    assert junit(project) == (3, set())
    out = study(project, f"builds=[{{id: yade-2025, code: yade, executable: {wrapper}}}]", *settings,
                extra=("--forceall",))
    assert out.returncode != 0
    n, failing = junit(project)
    assert n == 3 and "yade-2025.en_vn.sphere-sphere.F0.eps" in failing
    assert "yade-2025 en_vn sphere-sphere F0 eps: " in out.stdout + out.stderr


def case_verdict_files(project, case="steel"):
    return sorted(p.name for p in (project / "results" / case).glob("*") if p.name in
                  ("gate.txt", "verdict.json", "junit.xml", "checks.csv", "report.md", "report.html"))


def test_a_case_verdict_that_fails_leaves_no_pass_of_its_case(project):
    """The audit's case: the case passes; then its plots folder is read-only (a read-only bind mount,
    bwrap) and a new tolerance reruns case_verdict, which fails writing its first figure. Its
    gate.txt (the case gate's output, which Snakemake does not remove) went when case_verdict
    started, and its verdict says FAIL naming the job and the file; the old figure is whole, no
    temporary file is left; with the folder writable again the case passes."""
    if shutil.which("bwrap") is None:
        missing("bwrap is not installed; install it with: sudo apt-get install bubblewrap (make yade-2025 does this)")
    ok = study(project, target="steel")
    assert ok.returncode == 0, ok.stderr[-3000:]
    case = project / "results" / "steel"
    assert (case / "gate.txt").read_text().startswith("PASS: 9 ")
    plots = case / "plots"
    figure = (plots / "timestep.png").read_bytes()
    read_only = ["bwrap", "--bind", "/", "/", "--dev-bind", "/dev", "/dev", "--ro-bind", str(plots), str(plots)]
    out = processes.run([*read_only, sys.executable, "-m", "snakemake", "-j2", "steel", "--config", *SMALL,
                          "tolerance={T: 1e-9, A: 1e-6, eps: 1e-6}"], cwd=project, capture_output=True, text=True,
                        timeout=600)
    assert out.returncode != 0
    said = "OSError: [Errno 30] Read-only file system: 'results/steel/plots/timestep.png'"
    assert f"case_verdict (case steel): {said}" in out.stderr
    assert case_verdict_files(project) == ["junit.xml", "report.html", "report.md", "verdict.json"]  # no gate.txt
    verdict = json.loads((case / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and verdict["failures"] == [f"case_verdict (case steel) did not finish: {said}"]
    assert junit(project) == (1, {"workflow.case_verdict.case=steel"})  # the study's verdict says it too
    assert "## The workflow did not finish: FAIL" in (case / "report.md").read_text()
    assert "withdrew results/steel/gate.txt: the case's verdict is being made anew" in \
        (project / "logs" / "steel" / "verdict.log").read_text()
    assert sorted(p.name for p in plots.iterdir()) == sorted(p.name for p in plots.iterdir() if p.suffix == ".png")
    assert (plots / "timestep.png").read_bytes() == figure
    again = study(project, target="steel")
    assert again.returncode == 0, again.stderr[-3000:]
    assert (case / "gate.txt").read_text().startswith("PASS: 9 ")


def test_a_dump_changed_by_hand_fails_the_next_run_naming_it_without_being_told(project):
    """A dump truncated by hand after a PASS: the next plain `snakemake -j2 steel` reruns the case's
    summary (a param of it lists the dumps that no longer match their manifest), which refuses the
    dump by name: FAIL, no gate.txt. The documented repair (--forcerun run_engine) passes, and the
    run after it has nothing to do. A dump edited in place with Snakemake told to look at mtimes
    alone (no params trigger) is caught by the gate, which checks every dump before a PASS."""
    ok = study(project, target="steel")
    assert ok.returncode == 0, ok.stderr[-3000:]
    case = project / "results" / "steel"
    dump = next((case / "lammps" / "runs").glob("lammps-viscoelastic-*.csv"))
    text = dump.read_text()
    dump.write_text(text[: len(text) // 2])
    out = study(project, target="steel")
    assert out.returncode != 0
    named = f"DumpError: {dump.relative_to(project)}: the dump changed after the engine job wrote it (sha256 "
    assert f"case_summary (case steel): {named}" in out.stderr
    assert "reason: Params have changed since last execution" in out.stdout + out.stderr
    assert not (case / "gate.txt").exists()
    verdict = json.loads((case / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and verdict["failed_jobs"][0]["reason"].startswith(named)
    assert json.loads((project / "results" / "verdict.json").read_text())["verdict"] == "FAIL"

    repaired = study(project, target="steel", extra=("--forcerun", "run_engine"))
    assert repaired.returncode == 0, repaired.stderr[-3000:]
    assert (case / "gate.txt").read_text().startswith("PASS: 9 ")
    idle = study(project, target="steel")
    assert idle.returncode == 0 and "Nothing to be done" in idle.stdout + idle.stderr

    other = next((case / "lammps" / "runs").glob("lammps-default-*.csv"))
    other.write_text(other.read_text()[:-3] + "9\n")  # the last digit of the last force
    gate = study(project, target="steel", extra=("--rerun-triggers", "mtime", "--forcerun", "case_gate"))
    assert gate.returncode != 0
    assert ("FAIL: 1 dump(s) are not the ones their engine jobs wrote; the verdict of results/steel is withdrawn "
            f"(STALE):\n  {other.relative_to(project)}: the dump changed after the engine job wrote it") in gate.stderr
    assert case_verdict_files(project) == ["junit.xml", "report.html", "report.md", "verdict.json"]
    stale = json.loads((case / "verdict.json").read_text())
    assert stale["verdict"] == "STALE" and stale["stale"]["was"] == "PASS"
    assert stale["stale"]["rerun"] == "snakemake -j2 steel --forcerun run_engine"
    assert "**STALE**: results changed since this verdict (PASS) was written: 1 dump(s) changed after their engine " \
           f"job wrote them (first: {other.relative_to(project)})" in (case / "report.md").read_text()


def test_a_tolerance_of_1_or_more_is_refused_naming_it_and_a_loose_one_is_stated_and_warned(project):
    """tolerance.T = 10 (and = 1) is refused before any job, by the config schema, naming the key; at
    0.05 the study passes, and gate.txt, verdict.json, the report and the logs say what the PASS was
    judged against and warn that it is loose."""
    for T in ("10", "1"):
        refused = study(project, f"tolerance={{T: {T}, A: 1e-6, eps: 1e-6}}")
        assert refused.returncode != 0 and not (project / "results").exists()
        said = refused.stdout + refused.stderr
        assert f"config 'tolerance.T': {T} is greater than or equal to the maximum of 1" in said
        assert "Traceback" not in said
    out = study(project, "tolerance={T: 0.05, A: 1e-6, eps: 1e-6}")
    assert out.returncode == 0, out.stderr[-3000:]
    warning = "tolerance.T = 0.05 is above 1e-2: a PASS at it allows T to be off by 5 %"
    assert f"Warning: {warning}" in out.stderr
    gate = (project / "results" / "gate.txt").read_text().splitlines()
    assert gate[0].startswith("PASS: 9 engine build x law x geometry x criterion x quantity checks within tolerance "
                              "(relative: T 0.05, A 1e-06, eps 1e-06; summary sha256 ")
    assert gate[1:] == [f"Warning: {warning}"]
    verdict = json.loads((project / "results" / "verdict.json").read_text())
    assert verdict["tolerance"] == {"T": 0.05, "A": 1e-6, "eps": 1e-6} and verdict["warnings"] == [warning]
    assert f"**Warning**: {warning}." in report_head(project)
    assert warning in (project / "logs" / "checks.log").read_text()
    assert warning in (project / "logs" / "gate.log").read_text()
