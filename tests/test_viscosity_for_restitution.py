"""`python -m contact_model.viscosity_for_restitution`: eta at full precision for a restitution,
which the reference solver restitutes to round-off; a restitution no eta reaches, refused."""

import subprocess
import sys
from pathlib import Path

import pytest

from contact_model import load_case
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]


def run(*args):
    return subprocess.run([sys.executable, "-m", "contact_model.viscosity_for_restitution", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_it_prints_eta_at_full_precision_and_that_eta_restitutes_the_eps_asked_for():
    out = run("cases/steel.yaml", "--restitution", "0.8", "--velocity", "3.9 m/s", "--criterion", "x0")
    assert out.returncode == 0, out.stderr
    rows = [line.split() for line in out.stdout.splitlines()[2:]]
    assert [r[0] for r in rows] == ["sphere-sphere", "sphere-plane"]
    for geometry, V, eps, K, eta, _ in rows:
        pair = load_case(ROOT / "cases" / "steel.yaml").pair(geometry)
        eta = float(eta)
        assert len(repr(eta)) >= 15  # full precision, to paste
        tuned = type(pair)(pair.geometry, pair.body_1, pair.body_2, pair.E, eta)
        assert solve_collision(tuned.dissipation_parameter(3.9))["eps_x0"] == pytest.approx(0.8, abs=1e-12)
        assert float(K) == pytest.approx(tuned.dissipation_parameter(3.9), rel=1e-12)


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_a_restitution_no_viscosity_reaches_and_a_case_without_velocity_are_refused():
    low = run("cases/steel.yaml", "--restitution", "0.01", "--velocity", "1 m/s")
    assert low.returncode == 2 and "--restitution: no K in [0, 10] restitutes 0.01 under F0" in low.stderr
    none = run("cases/steel.yaml", "--restitution", "0.8")
    assert none.returncode == 2 and none.stderr.startswith("--velocity: cases/steel.yaml gives no impact velocity")
    bad = run("cases/steel.yaml", "--restitution", "0.8", "--velocity", "3 m")
    assert bad.returncode == 2 and "field 'velocity'" in bad.stderr
