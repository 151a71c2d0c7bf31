"""Speed changed no result: a reduced study (steel, K = 0.01, 0.1, 0.2, both geometries, every law,
LAMMPS) against a stored copy made before the speed work (commit 0c17100: scipy DOP853 solver,
the ODE solved per run).

- The engines' output is bit-identical for the viscoelastic laws: the data section of every dump
  has the stored sha256. The out-of-the-box law is given the reference eps at K = 0.1 as its
  restitution coefficient, a solver output: the new solver's differs from the old one's by ~1e-13
  (the new one agrees with mpmath to 1e-15, the old one to 5e-14), so those runs differ in the last
  bits of their input, and must agree to 1e-12 in the summary.
- The reference solution handed on by the plan agrees with the old solver's to 1e-12 relative.
- summary.csv's engine columns are the same text.

tests/data/speed_baseline/ holds the copy: baseline.json (dump data hashes, the old solver's rows
at each run's exact K) and summary.csv (the old summary without its absolute dump paths).
"""

import hashlib
import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from engine_cases import require_engine
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
BASELINE = Path(__file__).parent / "data" / "speed_baseline"
# One reduced study serves the three tests: keep them on one pytest-xdist worker.
pytestmark = pytest.mark.xdist_group("speed_baseline")
ENGINE_COLUMNS = ["V", "K", "dt", "T_e", "A_e", "samples_in_contact", "T", "A", "eps", "Q1", "Q2"]
KEY = ["engine", "law", "geometry", "criterion", "K"]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    require_engine("lmp", "lammps")
    root = copy_workflow(tmp_path_factory.mktemp("speed"))
    out = subprocess.run([sys.executable, "-m", "snakemake", "-j2", "results/steel/summary.csv", "--config",
                          "cases=cases/steel.yaml", "K_grid=[0.01,0.1,0.2]", "builds=[{id: lammps, code: lammps, executable: lmp}]",
                          "laws=[viscoelastic, viscoelastic_clipped, default]"],  # the laws of the stored copy
                         cwd=root, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return root / "results" / "steel"


def test_engine_output_is_bit_identical(study):
    stored = json.loads((BASELINE / "baseline.json").read_text())["dump_data_sha256"]
    runs = study / "lammps" / "runs"
    found = {}
    for dump in sorted(runs.glob("*.csv")):
        text = dump.read_text()
        found[dump.stem] = hashlib.sha256(text[text.index("time,overlap,"):].encode()).hexdigest()
    assert set(found) == set(stored)
    viscoelastic = [run for run in stored if "-default-" not in run]
    assert len(viscoelastic) == 12
    assert {run: found[run] for run in viscoelastic} == {run: stored[run] for run in viscoelastic}
    for dump in runs.glob("lammps-default-*.csv"):  # its input: the solver's eps at K = 0.1
        header = dict(line[2:].split(": ", 1) for line in dump.read_text().splitlines() if line.startswith("# "))
        assert float(header["matched_restitution"]) == pytest.approx(0.9048857834919442, rel=1e-12)


def test_reference_handed_on_by_the_plan_agrees_with_the_old_solver(study):
    old = json.loads((BASELINE / "baseline.json").read_text())["reference"]
    plan = {r["name"]: r["reference"] for r in json.loads((study / "plan.json").read_text())["runs"]}
    assert set(plan) == set(old)
    worst = 0.0
    for run, row in plan.items():
        for field, value in old[run].items():
            if field == "energy_residual":
                continue  # a round-off figure (~1e-15), not a result
            worst = max(worst, abs(row[field] / value - 1))
    assert worst <= 1e-12


def test_summary_engine_columns_are_unchanged(study):
    before = pd.read_csv(BASELINE / "summary.csv", dtype=str).sort_values(KEY).reset_index(drop=True)
    after = pd.read_csv(study / "summary.csv", dtype=str).sort_values(KEY).reset_index(drop=True)
    pd.testing.assert_frame_equal(after[KEY + ENGINE_COLUMNS], before[KEY + ENGINE_COLUMNS])
    for q in ("T", "A", "eps", "Q1", "Q2"):  # printed with 12 digits, so equal to ~1e-12
        assert after[f"{q}_ref"].astype(float).to_numpy() == pytest.approx(
            before[f"{q}_ref"].astype(float).to_numpy(), rel=2e-12, abs=0)
