"""Extraction of T, A, eps from sampled series: a reference trajectory sampled like an engine
dump must give back the reference values: exactly where the bodies fly freely (the start, the x0
end, a clipped force's exit velocity), to fourth order in the sampling step elsewhere."""

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

from records.collision_metrics import ExtractionError, collision_metrics
from records.dump_file import DumpError, read_dump, write_dump
from reference import collision_trajectory, solve_collision


def sampled_reference(K, steps_per_tau=1000 / 2.943, tail=0.3, gap=0.01, clip=False):
    """The dimensionless reference trajectory (V = delta_e = 1, so t = tau) resampled at a
    uniform step, starting `gap` before contact, continuing `tail` after x = 0 in free flight.
    With clip=True the force is cut at zero and the bodies fly apart from the F0 point on."""
    tr = collision_trajectory(K, points_per_phase=3000)
    tau, x, v, F = tr["tau"], tr["x"], tr["v"], tr["force"]
    keep = np.concatenate([[True], np.diff(tau) > 0])
    spline_x = CubicHermiteSpline(tau[keep], x[keep], v[keep])
    spline_v = CubicHermiteSpline(tau[keep], v[keep], -F[keep])
    dt = 1 / steps_per_tau
    t = np.arange(-gap, tau[-1] + tail, dt)
    inside = (t >= 0) & (t <= tau[-1])
    xs = np.where(inside, spline_x(np.clip(t, 0, tau[-1])), 0.0)
    vs = np.where(inside, spline_v(np.clip(t, 0, tau[-1])), 0.0)
    xs = np.where(t < 0, t, np.where(t > tau[-1], v[-1] * (t - tau[-1]), xs))
    vs = np.where(t < 0, 1.0, np.where(t > tau[-1], v[-1], vs))
    fs = np.where(xs > 0, np.sqrt(np.maximum(xs, 0)) * (1.25 * xs + K * vs), 0.0)
    if clip:
        r = solve_collision(K)
        after = t > r["tau_f"]
        x_f = spline_x(r["tau_f"])
        xs = np.where(after, x_f - r["eps_F0"] * (t - r["tau_f"]), xs)
        vs = np.where(after, -r["eps_F0"], vs)
        fs = np.where(after, 0.0, fs)
    return t, xs, vs, fs


STEPS = 1000 / 2.943  # the study's default step T_e/1000, in units of delta_e/V
DT2 = (1 / STEPS) ** 2  # second-order interpolation: errors of order dt^2 ~ 9e-6


@pytest.mark.parametrize("K", [0.1, 0.5])
def test_reference_trajectory_round_trip(K):
    r = solve_collision(K)
    m = collision_metrics(*sampled_reference(K), impact_velocity=1.0)
    assert m.t_start == pytest.approx(0.0, abs=DT2)
    assert m.delta_max == pytest.approx(r["x_max"], abs=DT2)
    assert m.T_x0 == pytest.approx(r["tau_0"], abs=DT2)
    assert m.eps_x0 == pytest.approx(r["eps_x0"], abs=DT2)
    assert m.T_F0 == pytest.approx(r["tau_f"], abs=DT2)
    assert m.eps_F0 == pytest.approx(r["eps_F0"], abs=DT2)
    assert m.samples_in_contact > 900


def test_clipped_force_gives_F0_and_a_different_x0():
    K = 0.5
    r = solve_collision(K)
    m = collision_metrics(*sampled_reference(K, clip=True), impact_velocity=1.0)
    assert m.T_F0 == pytest.approx(r["tau_f"], abs=2 * DT2)
    assert m.eps_F0 == pytest.approx(r["eps_F0"], abs=2 * DT2)
    assert m.eps_x0 == pytest.approx(r["eps_F0"], abs=2 * DT2)  # free flight after F0
    assert m.T_x0 > r["tau_f"] + 0.1


def test_elastic_contact_ends_together():
    m = collision_metrics(*sampled_reference(0.0), impact_velocity=1.0)
    assert m.T_F0 == m.T_x0 == pytest.approx(2.94327518432470, abs=DT2)
    assert m.eps_x0 == pytest.approx(1.0, abs=DT2)


@pytest.mark.parametrize("clip", [False, True])
@pytest.mark.parametrize("K", [0.05, 0.3, 1.0])
def test_free_flight_events_are_exact_and_the_others_fourth_order(K, clip):
    """The start and the x0 end are zeros of free-flight lines (exact to rounding, whatever the
    step); a clipped force's eps_F0 is its exit velocity (exact); T_F0, eps_F0 (tail kept) and
    delta_max come from cubic and quartic stencils: |error| <= 5 dt^4 (in units of delta_e/V),
    measured at most 2 dt^4, at four step sizes."""
    r = solve_collision(K)
    for n in (50, 100, 200, 400):
        m = collision_metrics(*sampled_reference(K, steps_per_tau=n, clip=clip), impact_velocity=1.0)
        dt4 = 5 * (1 / n) ** 4
        assert abs(m.t_start) < 1e-14
        assert abs(m.T_F0 - r["tau_f"]) < dt4
        assert abs(m.delta_max - r["x_max"]) < dt4
        if clip:
            assert m.eps_F0 == pytest.approx(r["eps_F0"], abs=1e-12)
        else:
            assert abs(m.eps_F0 - r["eps_F0"]) < 10 * dt4
            assert abs(m.T_x0 - r["tau_0"]) < 1e-12
            assert abs(m.eps_x0 - r["eps_x0"]) < 1e-12


def test_start_phase_and_end_phase_on_the_step_grid():
    """A contact that starts 0.3 steps after a sample reports start_phase 0.3; its x0 end, at
    tau_0 later, reports the fraction of a step tau_0 / dt + 0.3 leaves."""
    K, n = 0.2, 100
    r = solve_collision(K)
    t, x, v, f = sampled_reference(K, steps_per_tau=n, gap=2.3 / n)  # samples at -2.3, -1.3, -0.3, 0.7 steps
    m = collision_metrics(t, x, v, f, impact_velocity=1.0)
    assert m.start_phase == pytest.approx(0.3, abs=1e-9)
    expected = (0.3 + r["tau_0"] * n) % 1.0
    assert m.end_phase == pytest.approx(expected, abs=1e-9)


def test_a_clip_that_leaves_rounding_is_still_a_clip():
    """An engine that clips by adding -F_el to F may leave 1e-20 N instead of 0: still clipped
    (the force stays within CLIPPED of zero while the bodies overlap), so eps_F0 is the exit
    velocity and T_F0 the extrapolated zero, as for an exact zero."""
    K = 0.5
    t, x, v, f = sampled_reference(K, clip=True)
    exact = collision_metrics(t, x, v, f, impact_velocity=1.0)
    noisy = np.where((f == 0) & (x > 0), 1e-20 * np.sign(np.sin(np.arange(len(f)))), f)
    m = collision_metrics(t, x, v, noisy, impact_velocity=1.0)
    assert (m.T_F0, m.eps_F0) == (exact.T_F0, exact.eps_F0)


def test_F0_in_the_last_step_before_x0():
    """At K = 0.01 and a coarse step the force's zero lies in the last step before the x0 end: no
    in-contact sample has a negative force, and the zero is extrapolated from the last four. T_F0
    keeps its fourth order; eps_F0 is off by up to K dt^{3/2} (measured up to 0.6 K dt^{3/2}: the
    velocity is not smooth at the x0 end, a step away, where it changes as K (t_x0 - t)^{3/2}),
    and back at fourth order once a sample falls between F0 and x0 (measured 2.9e-7 at 60 steps
    per delta_e/V, 6.2e-8 at 120)."""
    K = 0.01
    r = solve_collision(K)
    for n in (23, 30, 37):  # steps whose last in-contact sample still has a positive force
        t, x, v, f = sampled_reference(K, steps_per_tau=n)
        last = np.nonzero(x > 0)[0][-1]
        assert f[last] > 0  # the case this test is about
        m = collision_metrics(t, x, v, f, impact_velocity=1.0)
        assert abs(m.T_F0 - r["tau_f"]) < 5 * (1 / n) ** 4
        assert abs(m.eps_F0 - r["eps_F0"]) < K * (1 / n) ** 1.5


def test_bad_series():
    t = np.linspace(0, 1, 50)
    with pytest.raises(ExtractionError, match="never touch"):
        collision_metrics(t, -np.ones(50), np.ones(50), np.zeros(50), 1.0)
    with pytest.raises(ExtractionError, match="still open"):
        collision_metrics(t, t - 0.5, np.ones(50), np.ones(50), 1.0)
    with pytest.raises(ExtractionError, match="first sample"):
        collision_metrics(t, np.ones(50), np.ones(50), np.ones(50), 1.0)
    with pytest.raises(ExtractionError, match="NaN"):
        collision_metrics(t, np.full(50, np.nan), np.ones(50), np.ones(50), 1.0)


def test_dump_round_trip_and_errors(tmp_path):
    data = np.column_stack(sampled_reference(0.2))
    meta = {"engine": "test", "case": "x", "time_step": 1e-3, "parameters": {"kn": 1.5}}
    path = tmp_path / "run.csv"
    write_dump(path, meta, data)
    assert not (tmp_path / "run.csv.part").exists()
    got_meta, cols = read_dump(path)
    assert got_meta["engine"] == "test" and got_meta["parameters"] == {"kn": 1.5}
    assert np.array_equal(cols["overlap"], data[:, 1])  # %.17g round-trips doubles exactly
    bad = tmp_path / "bad.csv"
    bad.write_text(path.read_text().replace("\n1", "\nnan", 1) if False else
                   path.read_text().rsplit("\n", 2)[0] + "\nnan,1,1,1\n")
    with pytest.raises(DumpError, match="non-finite"):
        read_dump(bad)
    other = tmp_path / "other.csv"
    other.write_text("time,overlap\n1,2\n")
    with pytest.raises(DumpError, match="not a hertz-dem-dump"):
        read_dump(other)


def test_root_in_keeps_the_root_inside_and_nearest_to_the_start():
    """_root_in: the real root in [lo, hi] nearest to lo (a cubic with three roots), None when the
    polynomial has none there; a root within rounding of an end is clamped onto it."""
    from records.collision_metrics import _root_in

    c = np.poly([1.0, 2.0, 3.0])  # (t - 1)(t - 2)(t - 3), in t - t0 with t0 = 0
    assert _root_in(c, 0.0, 1.5, 3.5) == pytest.approx(2.0)
    assert _root_in(c, 10.0, 11.5, 13.5) == pytest.approx(12.0)  # the same, shifted by t0
    assert _root_in(c, 0.0, 3.5, 9.0) is None
    assert _root_in(np.array([1.0, 0.0, 1.0]), 0.0, -5.0, 5.0) is None  # t^2 + 1: no real root
    assert _root_in(c, 0.0, 1.0 + 1e-12, 1.5) == 1.0 + 1e-12


def test_peak_of_the_quartic_and_a_short_contact():
    """delta_max is the top of the quartic through five samples (exact for a quartic whose top lies
    between samples); a contact of fewer than six samples is refused as too coarse."""
    t = np.arange(-3.0, 12.0)
    top = 4.3
    x = 10.0 - (t - top) ** 2 - 0.01 * (t - top) ** 4
    f = np.where(x > 0, np.sqrt(np.maximum(x, 0)) * 1.25 * x, 0.0)
    v = -2 * (t - top) - 0.04 * (t - top) ** 3
    m = collision_metrics(t, x, v, f, impact_velocity=1.0)
    assert m.delta_max == pytest.approx(10.0, abs=1e-12) and m.t_max == pytest.approx(top, abs=1e-9)
    short = np.array([-2.0, -1.0, 1.0, 2.0, 1.0, -1.0, -2.0])
    with pytest.raises(ExtractionError, match="too coarse"):
        collision_metrics(np.arange(7.0), short, np.ones(7), np.maximum(short, 0), 1.0)
