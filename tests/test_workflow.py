"""The Snakemake workflow: its DAG, its refusal of bad cases and settings before any engine
starts, a real one-case run, reruns only of what changed, and the SLURM profile (dry run)."""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from engine_cases import require_engine

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake"]


def snakemake(*args, cwd=ROOT):
    return subprocess.run([*SNAKEMAKE, *args], cwd=cwd, capture_output=True, text=True, timeout=600)


@pytest.fixture
def project(tmp_path):
    """A copy of the workflow (Snakefile, config, scripts, decks, the steel case) in tmp_path."""
    for item in ("Snakefile", "config", "workflow", "profiles"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    (tmp_path / "cases").mkdir()
    shutil.copytree(ROOT / "cases" / "decks", tmp_path / "cases" / "decks")
    shutil.copy(ROOT / "cases" / "steel.yaml", tmp_path / "cases")
    return tmp_path


def test_dry_run_plans_every_case_and_engine():
    out = snakemake("-n", "all", "--forceall")
    assert out.returncode == 0, out.stderr
    cases = len(list((ROOT / "cases").glob("*.yaml")))
    engines = 3  # config/config.yaml: liggghts, yade, lammps
    assert re.search(rf"^run_engine\s+{engines * cases}$", out.stdout, flags=re.M), out.stdout
    assert "convergence_runs" in out.stdout and "lammps_wall_modulus" in out.stdout
    for rule in ("paper_claims", "paper_figure_1", "paper_figure_3", "paper_figure_4", "paper_figure_5"):
        assert rule in out.stdout, rule
    assert "gate" in out.stdout and "report" in out.stdout


def test_malformed_case_stops_before_any_job(project):
    (project / "cases" / "broken.yaml").write_text("name: broken\nradius: 1 cm\nviscosity: 1 P\n"
                                                  "effective_modulus: 1 GPa\n")
    out = snakemake("-j1", "all", cwd=project)
    said = out.stdout + out.stderr
    assert out.returncode != 0
    assert "broken.yaml" in said and "'density'" in said and "missing" in said
    assert not (project / "results").exists()


def test_bad_config_is_refused_naming_the_key(project):
    out = snakemake("-n", "all", "--config", "time_step_factor=5", cwd=project)
    assert out.returncode != 0 and "time_step_factor" in out.stdout + out.stderr


def test_slurm_profile_dry_run():
    out = snakemake("-n", "--profile", "profiles/slurm", "all", "--forceall")
    assert out.returncode == 0, out.stderr
    assert "run_engine" in out.stdout


def test_one_case_for_real_then_only_changes_rerun(project):
    require_engine("liggghts", "liggghts")
    require_engine("yade", "yade")
    args = ["--config", "K_grid=[0.1]", "laws=[viscoelastic]", "engines=[liggghts,yade]"]
    out = snakemake("-j2", "steel", *args, cwd=project)
    assert out.returncode == 0, out.stderr
    summary = (project / "results" / "steel" / "summary.csv").read_text().splitlines()
    assert len(summary) == 1 + 2 * 2 * 2  # header + engines x geometries x criteria
    assert (project / "logs" / "steel" / "liggghts.log").exists()
    assert (project / "benchmarks" / "steel" / "yade.tsv").exists()
    again = snakemake("-n", "steel", *args, cwd=project)
    assert "Nothing to be done" in again.stdout, again.stdout
    case = project / "cases" / "steel.yaml"
    case.write_text(case.read_text().replace("density: 7800 kg/m^3", "density: 7850 kg/m^3"))
    changed = snakemake("-n", "steel", *args, "--rerun-triggers", "mtime", cwd=project)
    assert "run_engine" in changed.stdout and "plan" in changed.stdout
