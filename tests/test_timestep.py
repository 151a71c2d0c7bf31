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

import processes
from contact_model import load_case
from analysis import timestep
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]
STEEL = str(ROOT / "cases" / "steel.yaml")
KEYS = {"law", "geometry", "quantity", "tolerance", "dt_max_s", "dt_max_over_T_R", "dt_max_over_T_e", "err_min",
        "err_median", "err_max", "note"}
COMMAND = [sys.executable, "-m", "analysis.timestep"]


def advisor(*args) -> subprocess.CompletedProcess:
    """The advisor's command line (`timestep.main`) run in this process, as a user runs it: its exit
    status, stdout and stderr (the unit tier starts no process; `test_the_module_runs_as_a_command`
    runs it as one)."""
    import contextlib
    import io
    import os

    out, err = io.StringIO(), io.StringIO()
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = timestep.main([str(a) for a in args])
            except SystemExit as stop:  # argparse's usage errors, and sys.exit
                status = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
                if isinstance(stop.code, str):
                    print(stop.code, file=sys.stderr)
    finally:
        os.chdir(cwd)
    return subprocess.CompletedProcess([*COMMAND, *args], status, out.getvalue(), err.getvalue())


def both(*args, timeout=120) -> tuple[subprocess.CompletedProcess, subprocess.CompletedProcess]:
    """The advisor run with `args` as text and with --json: (plain, json)."""
    return advisor(*args), advisor(*args, "--json")


@pytest.mark.workflow  # a process of its own, as a user starts it
def test_the_module_runs_as_a_command_and_refuses_as_one():
    ok = processes.run([*COMMAND, STEEL, "--law", "elastic", "--velocity", "1 m/s", "--tolerance", "1e-3", "--json"],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0 and {row["quantity"] for row in strict_json(ok.stdout)} >= {"T", "eps"}, ok.stderr
    bad = processes.run([*COMMAND, STEEL, "--law", "elastic", "--K", "-1", "--json"], cwd=ROOT, capture_output=True,
                        text=True, timeout=300)
    assert bad.returncode == 2 and strict_json(bad.stdout)["error"]["argument"] == "--K"
    assert "Traceback" not in bad.stderr


def strict_json(text: str):
    """json.loads that refuses NaN and Infinity (Python's json reads them; JSON has none)."""
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")

    return json.loads(text, parse_constant=refuse)


def assert_refused(args, argument: str, message: str) -> dict:
    """The advisor refuses `args`, as text and as JSON, naming `argument` with `message`: exit
    status 2, no traceback; the text on stderr alone, the JSON an error object on stdout."""
    plain, as_json = both(*args)
    assert plain.returncode == 2, plain.stdout + plain.stderr
    assert message in plain.stderr and "Traceback" not in plain.stderr, plain.stderr
    assert plain.stdout == ""
    assert as_json.returncode == 2, as_json.stdout + as_json.stderr
    assert "Traceback" not in as_json.stderr, as_json.stderr
    error = strict_json(as_json.stdout)["error"]
    assert error["argument"] == argument and message in error["message"], error
    assert f"error: {error['message']}" in as_json.stderr
    return error


@pytest.fixture(scope="module")
def plane(tmp_path_factory):
    """Steel, a sphere on a plane alone: the answers that scan the grid, in half the time."""
    path = tmp_path_factory.mktemp("cases") / "plane.yaml"
    text = (ROOT / "cases" / "steel.yaml").read_text()
    assert "geometries: [sphere-sphere, sphere-plane]" in text
    path.write_text(text.replace("geometries: [sphere-sphere, sphere-plane]", "geometries: [sphere-plane]"))
    return str(path)


def test_the_json_answers_each_geometry_and_quantity_with_the_issues_keys():
    out = advisor(STEEL, "--law", "viscoelastic", "--velocity", "1 m/s", "--tolerance", "1e-3", "--dt", "0.2T_R",
                  "--json")
    assert out.returncode == 0, out.stderr
    rows = strict_json(out.stdout)
    assert [(r["geometry"], r["quantity"]) for r in rows] == [
        (g, q) for g in ("sphere-sphere", "sphere-plane") for q in ("T", "A", "delta_max", "F_max", "eps")]
    for r in rows:
        assert KEYS <= set(r) and r["law"] == "viscoelastic" and r["tolerance"] == 1e-3
        assert r["dt_s"] == pytest.approx(0.2 * r["T_R_s"], rel=1e-15)  # the user's dt
        assert r["dt_max_s"] == pytest.approx(r["dt_max_over_T_R"] * r["T_R_s"], rel=1e-12)
        assert r["dt_max_s"] == pytest.approx(r["dt_max_over_T_e"] * r["T_e_s"], rel=1e-12)
        assert r["err_min"] <= r["err_median"] <= r["err_max"] and r["note"] is None
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


# The audit "Trust 3": every request the advisor used to answer wrongly, or with a traceback, is
# refused naming the argument (as text and as JSON), or answered honestly.

def test_K_with_velocity_is_refused_naming_both_as_velocity_would_ignore_it():
    """--K picks the velocity at which the case's viscosity gives it; with --velocity it was
    silently ignored (the advisor answered for K = 0.087, steel's K at 1 m/s)."""
    assert_refused([STEEL, "--law", "viscoelastic", "--K", "0.5", "--velocity", "1"], "--K",
                   "--K 0.5 and --velocity 1: give one of them. --K picks the impact velocity at which the case's "
                   "viscosity gives that K")


@pytest.mark.parametrize("K", ["-1", "0", "nan", "inf", "11"])
def test_a_K_outside_the_references_range_is_refused_naming_K(K):
    assert_refused([STEEL, "--law", "viscoelastic", f"--K={K}"], "--K",
                   f"--K {float(K):g}: the dissipation parameter must lie in (0, 10], where the reference solves "
                   "the collision")


def test_a_restitution_the_clipped_law_cannot_reach_is_refused_naming_restitution():
    """The clipped law restitutes at least eps_F0(K = 10) = 0.0307 (no K of the reference reaches less)."""
    least = solve_collision(10.0)["eps_F0"]
    assert least == pytest.approx(0.03073, abs=1e-5)
    assert_refused([STEEL, "--law", "viscoelastic_clipped", "--restitution", "0.01", "--velocity", "1"],
                   "--restitution", f"--restitution 0.01: the law 'viscoelastic_clipped' cannot restitute it: no K in "
                                    f"[0, 10] restitutes 0.01 under F0: the viscoelastic collision restitutes at least "
                                    f"{least:.4g} there")


def test_a_restitution_told_the_elastic_law_is_refused_not_ignored():
    assert_refused([STEEL, "--law", "elastic", "--restitution", "0.8", "--velocity", "1"], "--restitution",
                   "--restitution 0.8: the law 'elastic' has no damping (it restitutes 1)")


@pytest.mark.parametrize("value", ["nan", "inf", "0", "1", "-0.5"])
def test_a_restitution_outside_0_1_is_refused_naming_restitution(value):
    assert_refused([STEEL, "--law", "viscoelastic", f"--restitution={value}", "--velocity", "1"], "--restitution",
                   f"--restitution {float(value):g}: a restitution coefficient lies in (0, 1)")


@pytest.mark.parametrize("value", ["nan", "inf", "0", "-2", "1e999"])
def test_a_velocity_not_positive_and_finite_is_refused_naming_velocity(value):
    assert_refused([STEEL, "--law", "viscoelastic", f"--velocity={value}"], "--velocity",
                   f"--velocity {value!r}: give the relative impact velocity in m/s")


def test_a_velocity_whose_hertz_overlap_exceeds_the_studys_limit_is_refused_as_the_study_does():
    """At 1e5 m/s steel spheres would overlap 41.7 R*; the study leaves out any velocity beyond
    max_overlap_ratio (0.5) R* (engines.plan), and so does the advisor, naming the argument the
    velocity came from."""
    pair = load_case(STEEL).pair("sphere-sphere")
    ratio = pair.scales(1e5)["delta_e"] / pair.R
    assert ratio == pytest.approx(41.7, abs=0.05) and timestep.max_overlap_ratio() == 0.5
    assert_refused([STEEL, "--law", "viscoelastic", "--velocity", "1e5"], "--velocity",
                   f"--velocity 100000: the sphere-sphere Hertz overlap would be {ratio:.3g} R* (> 0.5 R*, "
                   "max_overlap_ratio in config/config.yaml)")
    V = pair.velocity_for_dissipation(10.0)  # K = 10 at steel's viscosity: 2e10 m/s
    ratio = pair.scales(V)["delta_e"] / pair.R
    assert_refused([STEEL, "--law", "viscoelastic", "--K", "10"], "--K",
                   f"--K 10 (V = {V:.3g} m/s): the sphere-sphere Hertz overlap would be {ratio:.3g} R* (> 0.5 R*")


def test_the_overlap_limit_lies_where_the_study_puts_it():
    """delta_e grows as V^{4/5}: just below the velocity of delta_e = 0.5 R* the advisor answers,
    just above it refuses (both geometries checked; the sphere-sphere contact reaches it first)."""
    case = load_case(STEEL)
    pair = case.pair("sphere-sphere")
    limit = 1e5 * (0.5 / (pair.scales(1e5)["delta_e"] / pair.R)) ** 1.25
    assert pair.scales(limit)["delta_e"] / pair.R == pytest.approx(0.5, rel=1e-12)
    cs = timestep.collisions(case, "viscoelastic", None, None, None, 0.99 * limit)
    assert [c.geometry for c in cs] == ["sphere-sphere", "sphere-plane"]
    assert cs[0].delta_e / pair.R == pytest.approx(0.5 * 0.99**0.8, rel=1e-12)
    with pytest.raises(timestep.AdvisorError, match="sphere-sphere Hertz overlap would be 0.504 R") as refused:
        timestep.collisions(case, "viscoelastic", None, None, None, 1.01 * limit)
    assert refused.value.argument == "--velocity"


@pytest.mark.parametrize("value", ["nan", "inf", "0", "-1e-3", "1"])
def test_a_tolerance_outside_0_1_is_refused_naming_tolerance(value):
    assert_refused([STEEL, "--law", "viscoelastic", "--velocity", "1", f"--tolerance={value}"], "--tolerance",
                   f"--tolerance {float(value):g}: give a relative error in (0, 1)")


def test_a_tolerance_below_the_floor_is_refused_with_the_true_reason():
    """--tolerance 1e-12 answered dt_max 0 'fewer than 6 samples in contact'; the reference is
    accurate to about 1e-12, so a tolerance below 1e-10 is refused, saying so."""
    assert timestep.TOLERANCE_FLOOR == 1e-10
    assert_refused([STEEL, "--law", "viscoelastic", "--velocity", "1", "--tolerance", "1e-12"], "--tolerance",
                   "--tolerance 1e-12: below 1e-10, what the advisor answers for: the reference solution is "
                   "integrated to about 1e-12")


def test_a_tolerance_no_step_of_the_grid_holds_is_answered_null_with_the_reason(plane):
    """Above the floor, a tolerance the finest step of the grid (1e-4 T_R) cannot hold gets no
    dt_max (null, not 0) and the errors at that finest step, which exceed it: here T, A and F_max
    (first order, 5e-7 to 7e-7 at 1e-4 T_R) miss 1e-7 and eps (4.8e-8 to 9.8e-8 at its dt_max) holds it."""
    plain, as_json = both(plane, "--law", "viscoelastic", "--velocity", "1", "--tolerance", "1e-7")
    assert plain.returncode == 0 and as_json.returncode == 0, plain.stderr + as_json.stderr
    rows = {r["quantity"]: r for r in strict_json(as_json.stdout)}
    finest = timestep.GRID_OVER_T_R[0]
    assert finest == 1e-4
    for q in ("T", "A", "delta_max", "F_max"):
        r = rows[q]
        assert r["dt_max_s"] is None and r["dt_max_over_T_R"] is None and r["dt_max_over_T_e"] is None, r
        assert r["dt_s"] == pytest.approx(finest * r["T_R_s"], rel=1e-15)
        assert 4e-7 < max(abs(r["err_min"]), abs(r["err_max"])) < 8e-7, r  # above the tolerance: the reason
        assert r["note"] == ("no step of the grid down to 0.0001 T_R (6.09e-10 s) holds the tolerance; the errors "
                             "are at that finest step")
    eps = rows["eps"]
    assert eps["note"] is None and finest < eps["dt_max_over_T_R"] < 1e-3
    assert max(abs(eps["err_min"]), abs(eps["err_max"])) <= 1e-7
    assert "fewer than" not in plain.stdout
    assert "  T                  none        -        -   -5.61e-07 / -5.60e-07 / -5.60e-07; no step of the grid " \
           "down to 0.0001 T_R (6.09e-10 s) holds the tolerance" in plain.stdout


def test_an_unreadable_step_is_null_in_the_json_with_the_extractions_reason(plane):
    """At dt = 0.5 T_e the contact spans a sample or two: the errors do not exist. The JSON said
    NaN (not JSON); now null, with the reason in `note`, and dt_max still answered."""
    plain, as_json = both(plane, "--law", "viscoelastic", "--velocity", "1", "--dt", "0.5T_e")
    assert plain.returncode == 0 and as_json.returncode == 0, plain.stderr + as_json.stderr
    assert "NaN" not in as_json.stdout
    for r in strict_json(as_json.stdout):
        assert r["err_min"] is None and r["err_median"] is None and r["err_max"] is None, r
        assert r["dt_s"] == pytest.approx(0.5 * r["T_e_s"], rel=1e-15)
        assert r["note"].startswith("not readable at that step (the contact spans 1 samples, fewer than 6: the time "
                                    "step is too coarse to resolve it)"), r["note"]
        assert 0.09 < r["dt_max_over_T_R"] < 0.4  # steel at 1 m/s: 0.099 T_R (F_max) to 0.34 T_R (eps)
    assert "not readable at that step (the contact spans 1 samples" in plain.stdout


@pytest.mark.parametrize("dt, message", [
    ("1e-300", "--dt '1e-300': 1e-300 s needs 5.11e+295 steps over the sphere-sphere contact, more than the 2,000,000 "
               "a replay of the map may take"),
    ("1e-14", "--dt '1e-14': 1e-14 s needs 5.11e+09 steps over the sphere-sphere contact, more than the 2,000,000"),
    ("1e-3", "--dt '1e-3': 0.001 s is longer than the whole sphere-sphere contact (T_e = 3.9e-05 s, 6.4 T_R)"),
    ("1e300", "--dt '1e300': 1e+300 s is longer than the whole sphere-sphere contact"),
    ("nan", "--dt 'nan': give a positive step"),
    ("inf", "--dt 'inf': give a positive step"),
    ("1e999", "--dt '1e999': give a positive step"),
    ("0", "--dt '0': give a positive step"),
    ("-1e-7", "--dt '-1e-7': give a positive step"),
    ("1e-320 ns", "--dt '1e-320 ns': give a positive step"),  # 1e-329 s: no float64 but 0
])
def test_a_step_the_map_cannot_replay_is_refused_naming_dt(dt, message):
    """--dt 1e-300 raised OverflowError, 1e-14 MemoryError after asking for ~32 GB: now a step
    needing more than MAX_STEPS over the contact is refused before any replay, naming the finest
    step answered; a step longer than the contact, or not positive and finite, too."""
    error = assert_refused([STEEL, "--law", "viscoelastic", "--velocity", "1", f"--dt={dt}"], "--dt", message)
    if "steps over" in message:
        assert "the finest step answered is 2.56e-11 s (4.2e-06 T_R)" in error["message"]


def test_the_finest_step_answered_is_the_last_within_max_steps():
    case = load_case(STEEL)
    c = timestep.collisions(case, "viscoelastic", None, None, None, 1.0)[0]
    to_h = c.V / c.delta_e
    finest = 1.3 * c.tau_end / (timestep.MAX_STEPS - timestep.GAP_STEPS - 11) / to_h
    assert timestep.MAX_STEPS - 2 <= timestep.steps_for(c, finest * to_h) <= timestep.MAX_STEPS
    timestep.check_dt(c, finest, "finest")  # answered
    with pytest.raises(timestep.AdvisorError, match="more than the 2,000,000") as refused:
        timestep.check_dt(c, 0.999 * finest, "below")
    assert refused.value.argument == "--dt"
    with pytest.raises(timestep.AdvisorError, match="longer than the whole"):
        timestep.check_dt(c, 1.001 * c.T_e, "T_e")
    timestep.check_dt(c, c.T_e, "T_e")
    # The grid scans only steps a replay takes within MAX_STEPS: at steel's 1 m/s all of it.
    assert timestep.finest_step(c) == timestep.GRID_OVER_T_R[0]
    assert timestep.steps_for(c, timestep.GRID_OVER_T_R[0] * c.T_R * to_h) < timestep.MAX_STEPS / 10


@pytest.mark.parametrize("args, argument, message", [
    (["--law", "viscoelastic", "--K", "abc"], "--K", "argument --K: invalid float value: 'abc'"),
    (["--law", "viscoelastic", "--K", "0.1", "--restitution", "0.8"], "--restitution",
     "argument --restitution: not allowed with argument --K"),
    (["--velocity", "1"], "--law", "the following arguments are required: --law"),
])
def test_a_mistake_argparse_finds_is_json_too(args, argument, message):
    assert_refused([STEEL, *args], argument, message)


def test_a_case_file_that_cannot_be_read_is_a_json_error_naming_the_file(tmp_path):
    missing = str(tmp_path / "nope.yaml")
    error = assert_refused([missing, "--law", "viscoelastic", "--velocity", "1"], "case",
                           f"{missing}: field '(file)': cannot read")
    assert error["file"] == missing and error["field"] == "(file)"
