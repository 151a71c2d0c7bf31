"""Extraction of T, A, eps from sampled series: a reference trajectory sampled like an engine
dump must give back the reference values, to the interpolation error of the sampling step."""

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

from postprocess.collision_metrics import ExtractionError, collision_metrics
from postprocess.dump_file import DumpError, read_dump, write_dump
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
def test_sampling_error_is_second_order(clip):
    """|error| <= 2 dt^2 (in units of delta_e/V) for the crossings, at two step sizes."""
    K = 0.3
    r = solve_collision(K)
    for n in (100, 400):
        m = collision_metrics(*sampled_reference(K, steps_per_tau=n, clip=clip), impact_velocity=1.0)
        dt2 = 2 * (1 / n) ** 2
        assert abs(m.T_F0 - r["tau_f"]) < dt2
        assert abs(m.eps_F0 - r["eps_F0"]) < dt2
        if not clip:
            assert abs(m.T_x0 - r["tau_0"]) < dt2
            assert abs(m.eps_x0 - r["eps_x0"]) < dt2
        assert abs(m.delta_max - r["x_max"]) < dt2


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


def test_clipped_zero_falls_back_to_linear_extrapolation_then_to_the_next_sample():
    """Branches of the F0 time of a clipped force that no engine run reaches (coverage showed it):
    a quadratic with no zero before the clipped sample, then no decrease at all."""
    from postprocess.collision_metrics import _extrapolated_zero

    t = np.array([0.0, 1.0, 2.0])
    # Three falling samples on a convex parabola with no real zero; the last two fall with slope -0.25.
    y = np.array([3.0, 2.5, 2.25])
    assert _extrapolated_zero(t, y, 20.0) == pytest.approx(2.0 + 2.25 / 0.25)
    assert _extrapolated_zero(t, y, 5.0) == 5.0  # never past the clipped sample
    assert _extrapolated_zero(t, np.array([1.0, 1.0, 1.0]), 3.0) == 3.0  # flat: the clipped sample
    # A genuine quadratic zero inside the interval: y = 4 - t^2 crosses at t = 2 (t0 = 1).
    assert _extrapolated_zero(np.array([-1.0, 0.0, 1.0]), 4 - np.array([-1.0, 0.0, 1.0]) ** 2, 3.0) == \
        pytest.approx(2.0)


def test_parabola_vertex_at_the_ends_and_on_a_flat_or_convex_top():
    from postprocess.collision_metrics import _parabola_vertex

    t = np.array([0.0, 1.0, 2.0])
    assert _parabola_vertex(t, np.array([3.0, 2.0, 1.0]), 0) == (0.0, 3.0)
    assert _parabola_vertex(t, np.array([1.0, 2.0, 3.0]), 2) == (2.0, 3.0)
    assert _parabola_vertex(t, np.array([2.0, 2.0, 2.0]), 1) == (1.0, 2.0)  # c = 0: no vertex to find
    tv, yv = _parabola_vertex(t, np.array([0.0, 1.0, 0.5]), 1)  # -0.75 t^2 + 1.75 t
    assert tv == pytest.approx(1.75 / 1.5) and yv == pytest.approx(1.75**2 / 3)
