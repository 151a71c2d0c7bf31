"""The time-step ladders (engines/ladder.py, analysis/extrapolation.py), measured on the
engines' own discrete map (reference/engine_map.py) rather than taken on trust:

- the powers of the error expansion, from the orders of successive differences over eight
  halvings of dt: 1, then 3/2, then 2 with damping; 2, then 5/2 for Hertz alone;
- the extrapolation: a series of known limit is recovered, and its error estimate holds on
  random series of the expansion's form as often as engines/ladder.py says;
- an aligned ladder of the map extrapolates to the reference within its resolution at every K;
- a ladder whose contact starts at another phase at one rung is caught (and why it must be);
- the round-off floor bounds what positions stored at their magnitude do to T, A and eps.
"""

import math

import numpy as np
import pandas as pd
import pytest

from engines.ladder import (DISSIPATIVE_POWERS, ELASTIC_POWERS, START_PHASE, aligned_time_step, extrapolate,
                            phase_offset, powers_of, richardson_weights, rung_factor)
from records.collision_metrics import collision_metrics
from analysis.comparison import comparison_rows
from analysis.extrapolation import extrapolated_rows
from reference import HERTZ_TAU, solve_collision
from reference.engine_map import replay

KEYS = {"T_x0": ("T_x0", "tau_0"), "A": ("delta_max", "x_max"), "eps_x0": ("eps_x0", "eps_x0"),
        "T_F0": ("T_F0", "tau_f"), "eps_F0": ("eps_F0", "eps_F0")}


#: The reference at K = 0: Hertz alone (x0 and F0 end together, eps = 1).
HERTZ = {"tau_0": HERTZ_TAU, "tau_f": HERTZ_TAU, "x_max": 1.0, "eps_x0": 1.0, "eps_F0": 1.0}


def map_run(K, factor, clipped=False, start_phase=START_PHASE, position_scale=0.0):
    """The map's collision at dt ~ T_e / factor, aligned like a rung of the study (the x0 end, or
    the F0 end when clipped, a whole number of steps after the start), and its metrics, in the
    reference's units (V = delta_e = 1)."""
    r = solve_collision(K) if K > 0 else HERTZ
    h = aligned_time_step(r["tau_f"] if clipped else r["tau_0"], HERTZ_TAU, factor)
    end = r["tau_f"] + 0.8 * K if clipped else r["tau_0"]
    steps = int(20 + 1.25 * end / h + 30)
    d = replay(K, h, steps, start_phase=start_phase, clipped=clipped, position_scale=position_scale)
    return collision_metrics(*d.T, impact_velocity=1.0), h, steps


def errors(K, factors, clipped=False):
    """{quantity: relative errors at each rung}, and the rungs' h = dt / T_e."""
    ref = solve_collision(K) if K > 0 else HERTZ
    runs = [map_run(K, f, clipped) for f in factors]
    h = np.array([r[1] / HERTZ_TAU for r in runs])
    return {q: np.array([getattr(m, attr) for m, _, _ in runs]) / ref[key] - 1 for q, (attr, key) in KEYS.items()}, h


def orders(h, y, eliminated):
    """The order of the next term after the `eliminated` powers: log of the ratio of successive
    differences of y over rungs that halve h, after one Richardson step per eliminated power."""
    for p in eliminated:
        r = (h[:-1] / h[1:]) ** p
        y = (r * y[1:] - y[:-1]) / (r - 1)
        h = h[1:]
    d = np.diff(y)
    return np.log(d[:-1] / d[1:]) / np.log(h[:-2] / h[1:-1])


LONG = 250 * 2.0 ** np.arange(8)  # T_e/250 ... T_e/32000


@pytest.mark.parametrize("K", [0.1, 0.5])
def test_powers_of_the_maps_expansion_with_damping_are_1_then_3_halves_then_2(K):
    """Measured on the finest differences of eight halvings: T and A first order (within 0.02),
    eps_x0's next power 3/2 (within 0.02: the damping force's s^{1/2} where contact ends), and
    after 1 and 3/2 are removed T and A go as dt^2 (within 0.05)."""
    e, h = errors(K, LONG)
    for q in ("T_x0", "A", "T_F0"):
        assert orders(h, e[q], [])[-1] == pytest.approx(1.0, abs=0.02), q
        assert orders(h, e[q], [1.0, 1.5])[-2] == pytest.approx(2.0, abs=0.05), q
    assert orders(h, e["eps_x0"], [1.0])[-1] == pytest.approx(1.5, abs=0.02)


def test_powers_of_the_maps_expansion_without_damping_are_2_then_5_halves():
    """Hertz alone: the map is symmetric, so its smooth error has even powers only (2); the force's
    s^{3/2} where contact starts and ends adds 5/2."""
    e, h = errors(0.0, LONG[:7])
    for q in ("T_x0", "A"):
        assert orders(h, e[q], [])[-1] == pytest.approx(2.0, abs=0.02), q
        assert orders(h, e[q], [2.0])[-1] == pytest.approx(2.5, abs=0.05), q
    assert powers_of(0.0) == ELASTIC_POWERS and powers_of(1e3) == DISSIPATIVE_POWERS


def test_extrapolation_recovers_a_known_limit_and_its_estimate_holds():
    """c0 + c1 h^p + c2 h^(p+1) with p = 1 (both powers eliminated): c0 back to rounding, with a
    positive estimate; with a term beyond the eliminated ones (h^{5/2}), the error stays within
    the estimate."""
    h = 1 / np.array([250.0, 500.0, 1000.0, 2000.0])
    exact = extrapolate(h, 0.3 + 2.0 * h + 5.0 * h**2, DISSIPATIVE_POWERS)
    assert exact.value == pytest.approx(0.3, abs=1e-15) and exact.estimate > 0
    assert exact.order == pytest.approx(1.0, abs=0.05)
    beyond = extrapolate(h, 0.3 + 2.0 * h + 5.0 * h**2 + 40.0 * h**2.5, DISSIPATIVE_POWERS)
    assert 0 < abs(beyond.value - 0.3) < beyond.estimate
    # The weights recover a constant and eliminate every power they are given.
    w = richardson_weights(h, (1.0, 1.5, 2.0))
    assert w.sum() == pytest.approx(1.0, abs=1e-12)
    for p in (1.0, 1.5, 2.0):
        assert w @ h**p == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(ValueError, match="cannot eliminate"):
        richardson_weights(h[:3], (1.0, 1.5, 2.0))
    with pytest.raises(ValueError, match="3 or more rungs"):
        extrapolate(h[:2], h[:2], DISSIPATIVE_POWERS)


def test_the_estimate_holds_on_random_series_as_often_as_documented():
    """engines/ladder.py says: on random series of the expansion's form (coefficients uniform in
    [-1, 1], every power up to h^3) the estimate holds in 97 % of them, median margin 18. Measured
    here on 4000 series with a fixed seed: at least 95 % and a median margin of at least 10."""
    rng = np.random.default_rng(23)
    h = 1 / np.array([250.0, 500.0, 1000.0, 2000.0])
    powers = (1.0, 1.5, 2.0, 2.5, 3.0)
    held, margins = 0, []
    for _ in range(4000):
        c = rng.uniform(-1, 1, len(powers) + 1)
        y = c[0] + sum(ck * h**p for ck, p in zip(c[1:], powers))
        e = extrapolate(h, y, DISSIPATIVE_POWERS)
        error = abs(e.value - c[0])
        held += e.estimate >= error
        margins.append(e.estimate / error)
    assert held / 4000 >= 0.95 and np.median(margins) >= 10


def ladder_rows(K, factors, clipped=False, shifted=None, shift=0.25):
    """summary.csv rows (analysis.comparison) of a ladder of the map at K, its rung
    `shifted` (an index, or None) starting `shift` of a step off the planned phase."""
    law = "viscoelastic_clipped" if clipped else ("elastic" if K == 0 else "viscoelastic")
    represents = ["F0"] if clipped else ["x0"] if K == 0 else ["x0", "F0"]
    rows = []
    for k, f in enumerate(factors):
        phase = START_PHASE + (shift if k == shifted else 0.0)
        m, h, steps = map_run(K, f, clipped, start_phase=phase)
        meta = {"case": "map", "engine": "lammps", "build": "map", "engine_version": "the map", "law": law,
                "geometry": "sphere-plane", "represents": represents, "impact_velocity": 1.0, "K": K,
                "time_step": h, "T_e": HERTZ_TAU, "A_e": math.pi, "delta_e": 1.0, "effective_radius": 1.0,
                "ladder": f"map-{law}-K{K:g}", "time_step_factor": f, "roundoff_floor": 1e-13}
        rows += [{**r, "run": f"{meta['ladder']}-dt{f:g}"} for r in comparison_rows(meta, m)]
    return pd.DataFrame(rows)


@pytest.mark.parametrize("K,clipped", [(0.0, False), (0.03, False), (0.3, True), (1.0, False), (5.0, True)])
def test_an_aligned_ladder_of_the_map_extrapolates_to_the_reference_within_its_resolution(K, clipped):
    """The map is what every engine computes: its ladder's limit is the reference to within the
    ladder's resolution (measured 1e-10 to 8e-8 against resolutions of 1e-8, the floor, to 3e-7),
    the observed order is the expansion's first power, and no ladder problem is raised."""
    factors = [125, 250, 500] if K == 0 else [rung_factor(f, K) for f in (250, 500, 1000, 2000)]
    limits = extrapolated_rows(ladder_rows(K, factors, clipped))
    assert len(limits) == (1 if clipped or K == 0 else 2) and (limits.dt == 0).all()
    for r in limits.itertuples():
        assert r.problem == "" and r.rungs == len(factors) and abs(r.phase_offset) < 1e-9
        for q in ("T", "A", "eps"):
            error, resolution = abs(getattr(r, f"err_{q}")), getattr(r, f"resolution_{q}")
            assert error <= resolution < 5e-7, (r.criterion, q, error, resolution)
        assert r.order_T == pytest.approx(2.0 if K == 0 else 1.0, abs=0.1)
        assert len(r.rungs_T.split(";")) == len(factors)


def test_a_rung_that_starts_at_another_phase_is_caught():
    """Rung T_e/500 of a K = 0.5 ladder starts a quarter step late: its errors no longer lie on one
    series in dt (the phase-dependent terms of the contact's start change), the limit moves by far
    more than the ladder's own resolution, and the ladder is flagged misaligned, naming the rung."""
    factors = [250, 500, 1000, 2000]
    aligned = extrapolated_rows(ladder_rows(0.5, factors)).set_index("criterion")
    shifted = extrapolated_rows(ladder_rows(0.5, factors, shifted=1)).set_index("criterion")
    assert aligned.loc["x0", "problem"] == ""
    problem = shifted.loc["x0", "problem"]
    assert problem.startswith("misaligned ladder: contact starts +0.25 steps from the planned phase 0.5 at "
                              "dt = T_e/500")
    moved = abs(shifted.loc["x0", "err_eps"] - aligned.loc["x0", "err_eps"])
    assert moved > 10 * aligned.loc["x0", "resolution_eps"]
    assert phase_offset(0.75) == pytest.approx(0.25) and phase_offset(0.2) == pytest.approx(-0.3)
    assert phase_offset(0.0) == pytest.approx(-0.5) and phase_offset(0.999) == pytest.approx(0.499)


@pytest.mark.parametrize("delta_e_over_R,K", [(1.7e-9, 0.01), (3.8e-7, 0.1)])
def test_roundoff_floor_bounds_what_positions_stored_at_their_magnitude_do(delta_e_over_R, K):
    """Positions stored as centres of magnitude R (the engines' way) against the same map on the
    overlap itself: over ten offsets of the centre (a different rounding each), the rms
    difference of T, A and eps lies below sqrt(N) u X / delta_max (RunSpec.roundoff_floor's
    bound) and above a tenth of u X / delta_max (the bound is not vacuous: it is at most ~50
    times the truth). Ice at K = 0.01 (delta_e / R = 1.7e-9) and cork at K = 0.1."""
    r = solve_collision(K)
    exact, h, steps = map_run(K, 1000)
    X = 1.0 / delta_e_over_R
    diffs = []
    for j in range(10):
        m, _, _ = map_run(K, 1000, position_scale=X * (1 + 1e-13 * j))
        diffs.append([m.T_x0 / exact.T_x0 - 1, m.delta_max / exact.delta_max - 1, m.eps_x0 / exact.eps_x0 - 1])
    rms = np.sqrt(np.mean(np.square(diffs), axis=0))
    floor = math.sqrt(steps) * 2.0**-53 * X / r["x_max"]
    assert (rms < floor).all(), (rms, floor)
    assert rms.max() > 0.1 * 2.0**-53 * X / r["x_max"]


def test_aligned_time_step_puts_a_whole_number_of_steps_into_the_contact():
    T_c, T_e = 2.974, HERTZ_TAU
    dt = aligned_time_step(T_c, T_e, 1000)
    N = T_c / dt
    assert N == pytest.approx(round(N), abs=1e-9) and dt == pytest.approx(T_e / 1000, rel=1e-3)
    assert round(T_c / aligned_time_step(T_c, T_e, 1.0)) == 8  # never fewer than MIN_CONTACT_STEPS
    with pytest.raises(ValueError):
        aligned_time_step(0.0, T_e, 1000)
    assert rung_factor(250, 0.5) == 250 and rung_factor(250, 5.0) == 559


@pytest.mark.parametrize("law,K", [("viscoelastic", 0.3), ("viscoelastic_clipped", 2.0), ("elastic", 0.0)])
def test_the_maps_own_record_in_physical_units_is_on_the_map(law, K):
    """analysis.map_reference replays the map at a run's dt from its dump header: the map's
    own record, put in a run's physical units (delta_e = 2e-6 m, V = 0.5 m/s), differs from it by
    rounding alone (1e-13); replayed as an engine keyword's run, its force is another and the
    differences are the laws' (a keyword's map: tests/test_engine_timestep.py)."""
    from analysis.map_reference import map_errors

    delta_e, V = 2e-6, 0.5
    clipped = law == "viscoelastic_clipped"
    r = solve_collision(K) if K > 0 else HERTZ
    h = aligned_time_step(r["tau_f"] if clipped else r["tau_0"], HERTZ_TAU, 700)
    d = replay(K, h, int(20 + 1.25 * (r["tau_f"] + 0.8 * K if clipped else r["tau_0"]) / h + 30), clipped=clipped)
    t, x, v, f = d[:, 0] * delta_e / V, d[:, 1] * delta_e, d[:, 2] * V, d[:, 3] * 3.0  # any force unit
    m = collision_metrics(t, x, v, f, impact_velocity=V)
    represents = ["F0"] if clipped else ["x0"] if K == 0 else ["x0", "F0"]
    meta = {"law": law, "engine": "lammps", "K": K, "time_step": h * delta_e / V, "impact_velocity": V,
            "delta_e": delta_e, "start_phase": START_PHASE, "represents": represents}
    errors = map_errors(meta, m, len(t) - 1)
    assert set(errors) == set(represents)
    for criterion in represents:
        for q, e in errors[criterion].items():
            assert abs(e) < 1e-13, (criterion, q, e)
    if K > 0:  # LAMMPS's tsuji told what the model restitutes: another force, another collision
        keyword = map_errors({**meta, "law": "default", "matched_restitution": r["eps_x0"], "represents": ["x0"]}, m,
                             len(t) - 1)
        assert abs(keyword["x0"]["T"]) > 1e-4


def test_richardson_weights_cached_are_the_uncached_weights_bit_for_bit_and_a_copy():
    """The cache (engines.ladder._richardson_weights) returns what the pseudo-inverse gives for the
    same steps and powers, bit for bit; a caller that changes its array leaves the next caller's
    weights alone. Three rungs eliminating dt^1 and dt^2 at h = 1, 1/2, 1/4: the closed form
    w = (1/3, -2, 8/3) (Richardson's table), to 1e-12."""
    h = np.array([1.0, 0.5, 0.25])
    scale = h.max()
    direct = np.linalg.pinv(np.column_stack([np.ones_like(h), h / scale, (h / scale) ** 2]))[0]
    first = richardson_weights(h, (1.0, 2.0))
    assert first.tobytes() == direct.tobytes()
    np.testing.assert_allclose(first, [1 / 3, -2.0, 8 / 3], rtol=0, atol=1e-12)
    first[:] = 0.0
    assert richardson_weights(h, (1.0, 2.0)).tobytes() == direct.tobytes()
