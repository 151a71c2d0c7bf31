"""The time-step advisor (python -m postprocess.timestep): its interface as users and CI call it,
its dt_max is the largest step that holds the tolerance at every start phase, and every request
it cannot answer is refused naming the argument or the case's field."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contact_model import load_case
from postprocess import timestep
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]
STEEL = str(ROOT / "cases" / "steel.yaml")
KEYS = {"law", "geometry", "quantity", "tolerance", "dt_max_s", "dt_max_over_T_R", "dt_max_over_T_e", "err_min",
        "err_median", "err_max"}


def advisor(*args):
    return subprocess.run([sys.executable, "-m", "postprocess.timestep", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


def test_the_json_answers_each_geometry_and_quantity_with_the_issues_keys():
    out = advisor(STEEL, "--law", "viscoelastic", "--velocity", "1 m/s", "--tolerance", "1e-3", "--dt", "0.2T_R",
                  "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    assert [(r["geometry"], r["quantity"]) for r in rows] == [
        (g, q) for g in ("sphere-sphere", "sphere-plane") for q in ("T", "A", "delta_max", "F_max", "eps")]
    for r in rows:
        assert KEYS <= set(r) and r["law"] == "viscoelastic" and r["tolerance"] == 1e-3
        assert r["dt_s"] == pytest.approx(0.2 * r["T_R_s"], rel=1e-15)  # the user's dt
        assert r["dt_max_s"] == pytest.approx(r["dt_max_over_T_R"] * r["T_R_s"], rel=1e-12)
        assert r["dt_max_s"] == pytest.approx(r["dt_max_over_T_e"] * r["T_e_s"], rel=1e-12)
        assert r["err_min"] <= r["err_median"] <= r["err_max"]
    # T_R of steel (Y = 2 E* = 218 GPa, nu = 0, rho = 7800, R = 6.35 mm): pi R sqrt(rho/G) / 0.8766
    assert rows[0]["T_R_s"] == pytest.approx(math.pi * 0.635e-2 * math.sqrt(7800 / 109e9) / 0.8766, rel=1e-12)
    text = advisor(STEEL, "--law", "viscoelastic", "--velocity", "1", "--dt", "0.2T_R").stdout
    assert "0.1631 nu + 0.8766" in text and "min / median / max over the start phases" in text


@pytest.mark.parametrize("law, code, tolerance", [("viscoelastic", None, 1e-3), ("default", "liggghts", 1e-3),
                                                  ("lammps:velocity", None, 1e-2)])
def test_dt_max_holds_the_tolerance_at_every_phase_and_a_tenth_more_does_not(law, code, tolerance):
    case = load_case(STEEL)
    c = timestep.collisions(case, law, code, 0.8 if law != "viscoelastic" else None, None, 1.0)[0]
    largest = timestep.largest_step(c, tolerance)
    to_h = c.T_R * c.V / c.delta_e
    for q in ("T", "eps"):
        at = timestep.errors_at(c, largest[q] * to_h)[q]
        assert np.all(np.abs(at) <= tolerance), (q, at)
        above = timestep.errors_at(c, 1.1 * largest[q] * to_h)[q]
        assert np.nanmax(np.abs(above)) > tolerance or np.isnan(above).any(), q


def test_the_map_converges_to_the_reference_and_spreads_over_the_phases():
    """At a tiny step every phase meets the ODE's solution; at the issue's 0.2 T_R, LIGGGHTS told
    e = 0.8 restitutes with a phase band that straddles zero (the issue's user measured -0.27 % to
    +0.19 % over 40 phases on their case; here -0.28 % to +0.30 % on steel spheres)."""
    case = load_case(STEEL)
    c = timestep.collisions(case, "viscoelastic", None, None, None, 1.0)[0]
    assert c.K == pytest.approx(case.pair("sphere-sphere").dissipation_parameter(1.0), rel=1e-12)
    assert c.reference == solve_collision(c.K)
    fine, coarse = timestep.errors_at(c, 1e-3), timestep.errors_at(c, 2e-3)
    for q in ("T", "A", "F_max", "eps"):
        assert np.max(np.abs(fine[q])) < 5e-5, q
    for q in ("T", "F_max"):  # first order in dt: halving the step halves the error, at every phase
        assert np.median(coarse[q] / fine[q]) == pytest.approx(2.0, abs=0.1), q
    k = timestep.collisions(case, "default", "liggghts", 0.8, None, 1.0)[0]
    band = timestep.errors_at(k, 0.2 * k.T_R * k.V / k.delta_e)["eps"]
    assert band.min() < -2e-3 and band.max() > 1.5e-3


@pytest.mark.parametrize("args, message", [
    (["--law", "viscoelastik", "--velocity", "1"], "--law 'viscoelastik' is not a law of the study (did you mean "
                                                   "'viscoelastic'?)"),
    (["--law", "default", "--velocity", "1"], "name the code with --code"),
    (["--law", "lammps:tsuji", "--velocity", "1"], "a keyword is told a restitution: give --restitution"),
    (["--law", "default", "--code", "liggghts", "--restitution", "0.03", "--velocity", "1"],
     "liggghts refuses it: e must lie in (0.05, 1]"),
    (["--law", "viscoelastic", "--restitution", "1.2", "--velocity", "1"], "--restitution 1.2: a restitution"),
    (["--law", "viscoelastic", "--velocity", "1", "--dt", "0.2 T_X"], "--dt '0.2 T_X': give a positive step"),
    (["--law", "viscoelastic", "--velocity", "-1"], "--velocity '-1': give the relative impact velocity"),
    (["--law", "viscoelastic", "--velocity", "1", "--tolerance", "2"], "--tolerance 2: give a relative error"),
    (["--law", "viscoelastic"], "no impact velocity: give --velocity"),
])
def test_requests_it_cannot_answer_are_refused_naming_the_argument(args, message):
    out = advisor(STEEL, *args)
    assert out.returncode == 2 and message in out.stderr and "Traceback" not in out.stderr
    assert out.stdout == ""


def test_a_bad_case_file_is_refused_naming_the_file_and_field(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text((ROOT / "cases" / "steel.yaml").read_text().replace("0.635 cm", "0.635 kg"))
    out = advisor(str(bad), "--law", "viscoelastic", "--velocity", "1")
    assert out.returncode == 2 and str(bad) in out.stderr and "radius" in out.stderr
