"""The benchmarks' own refusals (their figures are printed by `make bench`, never asserted)."""

import pytest
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_reference_solver_benchmark_refuses_an_unknown_baseline_naming_it():
    run = subprocess.run([sys.executable, "-m", "benchmarks.reference_solver", "--baseline", "no-such-rev"],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode != 0
    assert "--baseline no-such-rev: not a git revision" in run.stderr
    assert "Traceback" not in run.stderr


def test_sensitivity_benchmark_writes_the_model_lammps_runs_and_scales_one_parameter():
    """The deck words the sensitivity benchmark gives LAMMPS: the study's kn and eta_n0
    (engines.codes.CODES' contact parameters), one of them scaled by (1 + s)."""
    from benchmarks.sensitivity import ladders, model
    from engines.codes import CODES
    from engines.script_engine import number

    spec = ladders()[(0.1, "eta_n0")]
    p = CODES["lammps"].contact_parameters(spec.pair)
    assert model(spec, "kn", 0.0) == model(spec, "eta_n0", 0.0)
    assert f"hertz {number(p['kn'])} {number(p['eta_n0'] * (1 + 1e-5))} " in model(spec, "eta_n0", 1e-5)
    assert f"hertz {number(p['kn'] * (1 + 1e-5))} {number(p['eta_n0'])} " in model(spec, "kn", 1e-5)
