"""`python -m contact_model.viscosity_for_k`: the eta that gives a case's contact a target K."""

import subprocess
import sys
from pathlib import Path

import pytest

from contact_model import ContactPair, load_case
from contact_model.viscosity_for_k import viscosity_table

ROOT = Path(__file__).resolve().parents[1]


def test_the_viscosity_gives_back_the_target_dissipation_in_each_geometry():
    case = load_case(ROOT / "cases" / "steel.yaml")
    rows = viscosity_table(case, [0.05, 0.5], [0.3, 1.0, 4.0])
    assert len(rows) == 2 * 3 * 2
    for r in rows:
        p = case.pair(r["geometry"])
        tuned = ContactPair(p.geometry, p.body_1, p.body_2, p.E, r["eta_Pa_s"])
        assert tuned.dissipation_parameter(r["V"]) == pytest.approx(r["K"], rel=1e-12)
        assert r["eta_P"] == pytest.approx(10 * r["eta_Pa_s"], rel=1e-15)
    # K ~ eta V^{1/5}: the eta for one K falls as V^{-1/5}
    at = {(r["geometry"], r["V"], r["K"]): r["eta_Pa_s"] for r in rows}
    assert at[("sphere-plane", 4.0, 0.5)] / at[("sphere-plane", 1.0, 0.5)] == pytest.approx(4 ** -0.2, rel=1e-12)


def run(*args):
    return subprocess.run([sys.executable, "-m", "contact_model.viscosity_for_k", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_the_command_prints_the_table_and_refuses_a_bad_unit_naming_it():
    ok = run("cases/steel.yaml", "--K", "0.1", "--velocity", "2 m/s")
    assert ok.returncode == 0, ok.stderr
    assert " sphere-sphere          2      0.1    6.703e+04    6.703e+05" in ok.stdout
    bad = run("cases/steel.yaml", "--K", "0.1", "--velocity", "2 km/hr/s")
    assert bad.returncode == 2 and "--velocity: field 'velocity'" in bad.stderr
    assert "expected a [length] / [time]" in bad.stderr
    assert run("cases/steel.yaml", "--K", "-1").returncode == 2
