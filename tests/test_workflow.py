"""The Snakemake workflow: its DAG, its refusal of bad cases and settings before any engine
starts, a real one-case run, reruns only of what changed, and the SLURM profile (dry run; the
cluster itself in test_slurm)."""

import re
import shutil
import sys
from pathlib import Path

import pytest
import yaml

import processes
from engine_cases import recording_executable, require_default_builds, require_engine
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake"]
SLURM_SNAKEMAKE = ROOT / ".venv-slurm" / "bin" / "snakemake"  # the SLURM executor plugin's venv (make slurm-venv)


def snakemake(*args, cwd=ROOT):
    return processes.run([*SNAKEMAKE, *args], cwd=cwd, capture_output=True, text=True, timeout=600)


@pytest.fixture
def project(tmp_path, runs_workflow):
    """A copy of the workflow (Snakefile, config, scripts, decks, the steel case) in tmp_path.
    Its default builds must be installed: parsing the workflow asks each for its version."""
    require_default_builds()
    return copy_workflow(tmp_path)


def test_dry_run_plans_every_case_and_engine():
    require_default_builds()
    out = snakemake("-n", "all", "--forceall")
    assert out.returncode == 0, out.stderr
    cases = len(list((ROOT / "cases").glob("*.yaml")))
    builds = len(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"])
    assert re.search(rf"^run_engine\s+{builds * cases}$", out.stdout, flags=re.M), out.stdout
    lammps = sum(b["code"] == "lammps" for b in yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"])
    assert re.search(rf"^lammps_regression_runs\s+{lammps}$", out.stdout, flags=re.M), out.stdout  # one per build
    assert "convergence_runs" in out.stdout and "compare_builds" in out.stdout
    for rule in ("paper_reference", "paper_figure_3", "paper_figure_4", "reference_tables"):
        assert rule in out.stdout, rule
    assert "gate" in out.stdout and "report" in out.stdout


def test_an_unknown_engine_code_stops_the_workflow_with_its_message_alone(project):
    out = snakemake("-n", "steel", "--config", "builds=[{id: mine, code: lamps, executable: lmp}]", cwd=project)
    assert out.returncode != 0
    assert ("config 'builds': build 'mine': unknown code 'lamps' (did you mean 'lammps'?); known: liggghts, yade, "
            "lammps, esys, kratos") in out.stderr
    assert "Traceback" not in out.stderr and 'File "' not in out.stderr


def test_malformed_case_stops_before_any_job(project):
    (project / "cases" / "broken.yaml").write_text("name: broken\nradius: 1 cm\nviscosity: 1 P\n"
                                                  "effective_modulus: 1 GPa\n")
    out = snakemake("-j1", "all", cwd=project)
    said = out.stdout + out.stderr
    assert out.returncode != 0
    assert "broken.yaml" in said and "'density'" in said and "missing" in said
    assert not (project / "results").exists()


#: Three case files, one per kind of mistake, each from the steel case.
BROKEN = {"bad_key": ("viscosity: 6.7e5 P", "viscocity: 6.7e5 P"),
          "bad_unit": ("effective_modulus: 109 GPa", "effective_modulus: 109 Mpa"),
          "bad_dim": ("radius: 0.635 cm", "radius: 0.635 kg")}
SAID = {"bad_key": "cases/bad_key.yaml: field 'viscocity': unknown field (did you mean 'viscosity'?",
        "bad_unit": "cases/bad_unit.yaml: field 'effective_modulus': cannot read the unit 'Mpa' of '109 Mpa' "
                    "(UndefinedUnitError: 'Mpa' is not defined in the unit registry) (did you mean 'MPa'?)",
        "bad_dim": "cases/bad_dim.yaml: field 'radius': '0.635 kg' is a [mass], expected a [length] (e.g. m)"}


def test_bad_case_files_block_only_the_targets_that_need_them_each_named_at_once(project):
    steel = (project / "cases" / "steel.yaml").read_text()
    for name, (good, bad) in BROKEN.items():
        text = steel.replace("name: steel", f"name: {name}").replace(good, bad)
        (project / "cases" / f"{name}.yaml").write_text(text)
    # Another case's target runs, and says which files it left out.
    ok = snakemake("-n", "steel", cwd=project)
    assert ok.returncode == 0, ok.stderr
    for text in SAID.values():
        assert f"Left out (not needed by this target): {text}" in ok.stderr
    # `all` needs every case: every bad file at once, each with its field, no traceback.
    study = snakemake("-n", "all", cwd=project)
    assert study.returncode != 0
    assert "3 of the case files this target needs cannot be used (of 4 in all):" in study.stderr
    assert all(text in study.stderr for text in SAID.values())
    assert "run the cases that are fine alone, e.g. snakemake -j2 steel" in study.stderr
    assert "Traceback" not in study.stderr and 'File "' not in study.stderr and "Error in file" not in study.stderr
    # One bad case's own target: its error first, the others after.
    one = snakemake("-n", "bad_unit", cwd=project)
    assert one.returncode != 0
    head, others = one.stderr.split("Also not usable (not needed by this target):")
    assert "1 of the case files this target needs cannot be used" in head and SAID["bad_unit"] in head
    assert SAID["bad_key"] in others and SAID["bad_dim"] in others
    assert not (project / "results").exists()


def test_a_build_list_of_ones_own_just_works_and_a_calibration_engine_outside_it_is_refused_with_the_fix(project):
    shutil.copytree(ROOT / "cases" / "calibration", project / "cases" / "calibration")  # a measured case
    mine = "builds=[{id: yade-mine, code: yade, executable: yade}, {id: lammps-mine, code: lammps, executable: lmp}]"
    out = snakemake("-n", "all", "--config", mine, "extras=[calibration]", cwd=project)
    assert out.returncode == 0, out.stderr
    # The calibration's loop follows the build list: its engine job runs the first build that runs
    # the viscoelastic law (YADE: its deck is the job's input).
    assert re.search(r"rule calibration_dem:\n    input: [^\n]*cases/decks/yade/collisions\.py", out.stdout), out.stdout
    refused = snakemake("-n", "all", "--config", mine, "extras=[calibration]", "calibration={engine: lammps-2021}",
                        cwd=project)
    assert refused.returncode != 0
    assert ("config 'calibration.engine': 'lammps-2021' is not the id of a build of this run; set it to one of "
            "yade-mine, lammps-mine, or to null for the first of them") in refused.stderr


def test_bad_config_is_refused_naming_the_key(project):
    out = snakemake("-n", "all", "--config", "time_step_factor=5", cwd=project)
    assert out.returncode != 0 and "time_step_factor" in out.stdout + out.stderr


def test_slurm_profile_dry_run_gives_every_engine_job_its_limits():
    require_default_builds()
    if not SLURM_SNAKEMAKE.exists():
        pytest.skip("Snakemake's SLURM executor plugin is not installed; install it with: make slurm-venv")
    out = processes.run([str(SLURM_SNAKEMAKE), "-n", "--profile", "profiles/slurm", "all", "--forceall"], cwd=ROOT,
                        capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    jobs = re.split(r"\n(?=\[.*\]\n(?:local)?rule )", out.stdout)
    engine_jobs = [j for j in jobs if "\nrule run_engine:" in j]
    builds = len(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"])
    assert len(engine_jobs) == builds * len(list((ROOT / "cases").glob("*.yaml")))
    # (their CPUs, ESyS's two, are evaluated only when a job is submitted: test_slurm checks them in sacct)
    for job in engine_jobs:
        assert re.search(r"resources: .*mem_mb=2000,.*runtime=30", job), job
    # (which jobs stay local shows only when they run: test_slurm asks sacct which jobs SLURM ran)


def test_one_case_for_real_then_only_changes_rerun(project):
    require_engine("liggghts", "liggghts")
    require_engine("yade", "yade")
    args = ["--config", "K_grid=[0.1]", "laws=[viscoelastic]",
            "builds=[{id: liggghts, code: liggghts, executable: liggghts}, {id: yade, code: yade, executable: yade}]"]
    out = snakemake("-j2", "steel", *args, cwd=project)
    assert out.returncode == 0, out.stderr
    summary = (project / "results" / "steel" / "summary.csv").read_text().splitlines()
    # header + engines x geometries x (4 rungs + the ladder's limit) x criteria
    assert len(summary) == 1 + 2 * 2 * (4 + 1) * 2
    assert (project / "logs" / "steel" / "liggghts.log").exists()
    assert (project / "logs" / "benchmarks" / "run_engine" / "steel" / "yade.tsv").exists()
    again = snakemake("-n", "steel", *args, cwd=project)
    assert "Nothing to be done" in again.stdout, again.stdout
    case = project / "cases" / "steel.yaml"
    case.write_text(case.read_text().replace("density: 7800 kg/m^3", "density: 7850 kg/m^3"))
    changed = snakemake("-n", "steel", *args, "--rerun-triggers", "mtime", cwd=project)
    assert "run_engine" in changed.stdout and "plan" in changed.stdout


@pytest.mark.parametrize("file_name, said", [
    ("steel (v2).yaml", "the file name 'steel (v2)' cannot name a case"),
    ("all.yaml", "the file name 'all' is taken by the workflow's rule 'all'"),
    ("report.yaml", "the file name 'report' is taken by the workflow's rule 'report'"),
])
def test_case_file_name_that_cannot_be_a_target_is_refused(project, file_name, said):
    shutil.copy(project / "cases" / "steel.yaml", project / "cases" / file_name)
    (project / "cases" / file_name).write_text((project / "cases" / "steel.yaml").read_text()
                                               .replace("name: steel", "name: other"))
    out = snakemake("-n", "all", cwd=project)
    assert out.returncode != 0
    assert f"cases/{file_name}: {said}" in out.stdout + out.stderr


def test_two_case_files_claiming_one_name_are_refused(project):
    shutil.copy(project / "cases" / "steel.yaml", project / "cases" / "steel_copy.yaml")
    out = snakemake("-n", "all", cwd=project)
    assert out.returncode != 0
    assert "cases/steel_copy.yaml: field 'name': 'steel' is already the name of cases/steel.yaml" in \
        out.stdout + out.stderr


def test_numbers_given_through_config_inside_lists_and_mappings_are_numbers(project):
    ok = snakemake("-n", "all", "--config", "tolerance={T: 1e-6, A: 2.5E-4, eps: 5e-4}", "K_grid=[1e-2,0.1]",
                   "extras=[]",
                   cwd=project)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    bad = snakemake("-n", "all", "--config", "tolerance={T: 1e-6 s, A: 1e-4, eps: 5e-4}", cwd=project)
    assert bad.returncode != 0 and "tolerance" in bad.stdout + bad.stderr and "1e-6 s" in bad.stdout + bad.stderr


@pytest.mark.parametrize("impact, field, said", [
    ("impact:\n  velocity: [1.0e-12 m/s]\n", "impact.velocity[0]", "too small for double-precision positions"),
    ("impact:\n  K: [9.5]\n", "impact.K", "nothing to run: every velocity is left out"),
])
def test_case_the_engines_cannot_run_honestly_is_refused_before_any_job(project, impact, field, said):
    case = project / "cases" / "steel.yaml"
    case.write_text(case.read_text() + impact)
    out = snakemake("-j1", "all", "--config", "extras=[]", cwd=project)
    told = out.stdout + out.stderr
    assert out.returncode != 0
    assert f"cases/steel.yaml: field '{field}': " in told and said in told, told[-2000:]
    assert not (project / "results").exists()


def test_the_keywords_target_tabulates_each_keywords_promise_against_an_independent_solution(tmp_path):
    """snakemake -j2 keywords with LAMMPS and LIGGGHTS told e = 0.05, 0.5, 0.9: LAMMPS's tsuji delivers
    what its own equation restitutes (checked against scipy's DOP853 of that equation, not the
    project's closed form), +0.116 over what it was told at 0.5; LIGGGHTS delivers e; LIGGGHTS
    refuses 0.05 (its own range), which is said, not run."""
    from contact_model.constant_restitution import restitution_of_damping
    from contact_model.keywords import KEYWORDS

    require_engine("lmp", "lammps")
    require_engine("liggghts", "liggghts")
    project = copy_workflow(tmp_path / "project")
    (project / "cases" / "calibration").mkdir()
    shutil.copy(ROOT / "cases" / "calibration" / "gugan_jaques_on_wood.csv", project / "cases" / "calibration")
    out = snakemake("-j2", "keywords", "--config",
                    "builds=[{id: lammps, code: lammps, executable: lmp}, {id: liggghts, code: liggghts, "
                    "executable: liggghts}]",
                    "keywords={case: cases/steel.yaml, geometry: sphere-sphere, velocity: 1.0, "
                    "restitution: [0.05, 0.5, 0.9]}", cwd=project)
    assert out.returncode == 0, out.stderr[-3000:]
    import pandas as pd

    table = pd.read_csv(project / "results" / "keywords" / "promise.csv").set_index(["build", "e_requested"])
    assert list(table.columns[:4]) == ["code", "keyword", "V", "criterion"]
    for build, name in (("lammps", "lammps:tsuji"), ("liggghts", "liggghts:hertz-coefficientRestitution")):
        for e in (0.5, 0.9):
            row = table.loc[(build, e)]
            independent = restitution_of_damping(KEYWORDS[name].b(e), "x0")
            assert row.eps_own_equation == pytest.approx(independent, abs=1e-9)
            assert abs(row.err_own_equation) + row.resolution <= 1e-6
            assert row.err_promise == pytest.approx(row.eps_delivered - e, abs=1e-11)  # promise.csv keeps 12 digits
    assert table.loc[("lammps", 0.5)].err_promise == pytest.approx(0.116, abs=1e-3)
    assert abs(table.loc[("liggghts", 0.5)].err_promise) < 1e-6
    assert table.loc[("liggghts", 0.05)].problem.startswith("not run: liggghts refuses it")
    assert table.loc[("lammps", 0.05)].err_promise == pytest.approx(0.125, abs=2e-3)
    summary = (project / "results" / "keywords" / "promise.md").read_text()
    assert "| lammps " in summary and (project / "results" / "keywords" / "promise.png").stat().st_size > 0
    # Gugan's eps(V), falling with V: only the viscoelastic law follows it (R^2 >= 0.9 with its trend).
    forms = pd.read_csv(project / "results" / "keywords" / "eps_of_velocity.csv").set_index(["form", "criterion"])
    assert set(forms[forms.follows].index) == {("half", "F0"), ("half", "x0")}
    assert forms.loc[("half", "F0"), "R2"] == pytest.approx(0.949, abs=1e-3)
    assert forms.loc[("quarter", "any"), "value"] == pytest.approx(0.8207, abs=1e-4)  # the data's mean
    assert "Follows: half (F0)" in summary and "neither can follow an eps that falls with V" in summary
    assert not (project / "results" / "verdict.json").exists()  # no verdict of the study is touched


def test_yade_2025s_en_vn_keeps_its_promise_at_vn_and_drifts_as_brilliantov_away_from_it(tmp_path):
    """snakemake -j2 keywords with Debian 13's YADE 2025.2.0 told e = 0.3 and 0.8 at vn = V: en + vn
    delivers Brilliantov's law at the K of its Pade (checked against scipy's DOP853 of that law),
    2.0e-4 short of e = 0.3 and within 1e-6 of 0.8; told 0.8 at vn, it restitutes 0.86672 at V = vn/10
    (its own equation; 0.86672 measured in YADE by hand at en = 0.8, vn = 1, V = 0.1). `measured: null`
    on the command line is YAML's null (no fit), not a file named 'null'."""
    from contact_model.keywords import KEYWORDS
    from engine_cases import missing
    from scipy_solver import solve_collision as scipy_collision

    if not (ROOT / ".yade-2025" / "yade").exists():
        missing("YADE 2025 is not installed; install it with: make yade-2025")
    project = copy_workflow(tmp_path / "project")
    out = snakemake("-j2", "keywords", "--config", "builds=[{id: yade-2025, code: yade, executable: .yade-2025/yade}]",
                    "keywords={case: cases/steel.yaml, geometry: sphere-sphere, velocity: 1.0, "
                    "restitution: [0.3, 0.8], measured: null}", cwd=project)
    assert out.returncode == 0, out.stderr[-3000:]
    import pandas as pd

    table = pd.read_csv(project / "results" / "keywords" / "promise.csv").set_index(["keyword", "e_requested"])
    assert {k for k, _ in table.index} == {"yade:en", "yade:en-vn"}
    for e in (0.3, 0.8):
        row = table.loc[("yade:en-vn", e)]
        assert row.eps_own_equation == pytest.approx(scipy_collision(KEYWORDS["yade:en-vn"].b(e))["eps_F0"], abs=1e-9)
        assert abs(row.err_own_equation) + row.resolution <= 1e-6, row
    assert table.loc[("yade:en-vn", 0.3)].err_promise == pytest.approx(-2.0e-4, abs=1e-5)
    assert abs(table.loc[("yade:en-vn", 0.8)].err_promise) < 1e-6
    over = pd.read_csv(project / "results" / "keywords" / "promise_over_velocity.csv")
    at = over[(over.e_requested == 0.8) & (over.V_over_vn == 0.1)].eps_own_equation.item()
    assert at == pytest.approx(0.86672, abs=2e-5)
    assert "V = 0.1 vn" in (project / "results" / "keywords" / "promise.md").read_text()


def test_a_cluster_job_reads_the_runs_plans_and_no_process_reading_the_workflow_asks_a_build(tmp_path):
    """Reading the workflow starts no engine (the version is the engine_version job's): neither the
    run's own Snakemake nor a job of it (--target-jobs, as a SLURM job is started) starts LAMMPS.
    The run plans every case and keeps the plans by their inputs' key (workflow/rules/setup_cache.smk);
    a job reads them; for other inputs (a case file changed) it plans, and keeps, its own."""
    require_engine("lmp", "lammps")
    project = copy_workflow(tmp_path / "project")
    calls = tmp_path / "calls.txt"
    counting = recording_executable(tmp_path / "lmp", calls, "lmp")
    config = ["--config", f"builds=[{{id: lammps, code: lammps, executable: {counting}}}]", "laws=[viscoelastic]",
              "extras=[]", "compare_builds=[]"]
    kept = project / ".snakemake" / "hertz-setup"

    def asked(*args):
        before = len(calls.read_text().splitlines()) if calls.exists() else 0
        out = snakemake("-n", *args, *config, cwd=project)
        assert out.returncode == 0, out.stderr[-2000:]
        return (len(calls.read_text().splitlines()) if calls.exists() else 0) - before

    assert asked("all") == 0
    assert len(list(kept.glob("*.json"))) == 1
    job = ["--target-jobs", "run_engine:case=steel,build=lammps"]
    assert asked(*job) == 0 and len(list(kept.glob("*.json"))) == 1  # read, not planned again
    case = project / "cases" / "steel.yaml"
    case.write_text(case.read_text() + "\n# another case file: another key\n")
    assert asked(*job) == 0 and len(list(kept.glob("*.json"))) == 2  # planned anew for these inputs
