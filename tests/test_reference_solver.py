"""The reference solver against the issue's reference values, closed forms, an independent
mpmath solution, the DOP853 solver it replaced, the Hertz limit and energy conservation."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from reference import (FIRST_ORDER, FIRST_ORDER_INTEGRAL, HERTZ_TAU, K_PREFACTOR, CollisionTable,
                       collision_trajectory, solve_collision, solve_collisions)
import scipy_solver
from independent_solver import solve_high_precision

KEYS = ("x_max", "tau_f", "eps_F0", "tau_0", "eps_x0")
# Reference values of the foundation issue (15 significant digits).
REFERENCE = {
    0.1: (0.961532369910445, 2.89442295753887, 0.905405538032722, 2.97444264691693, 0.904885783491945),
    1.0: (0.727430582889519, 2.55809273346605, 0.433312255905162, 3.40325174621087, 0.380838630487197),
}
ACCURACY = 1e-10  # relative accuracy the study requires of the solver


def test_closed_forms():
    assert HERTZ_TAU == pytest.approx(2.94327518432470, rel=1e-14)
    assert K_PREFACTOR == pytest.approx(1.924034, abs=5e-7)
    assert FIRST_ORDER_INTEGRAL == pytest.approx(0.50445489, abs=5e-9)
    # The paper's prefactor 2.8683 of T_e = 2.8683 (M^2/(R V E^2))^{1/5} is tau_e (15/16)^{2/5}.
    assert HERTZ_TAU * (15 / 16) ** 0.4 == pytest.approx(2.8683, abs=5e-5)


@pytest.mark.parametrize("K", sorted(REFERENCE))
def test_reference_values(K):
    r = solve_collision(K)
    for key, expected in zip(KEYS, REFERENCE[K]):
        assert r[key] == pytest.approx(expected, rel=1e-13), key


@pytest.mark.parametrize("K", ["0.1", "1", "0.37"])
def test_against_independent_high_precision_solution(K):
    """mpmath (Taylor series, 25 digits, tau-time in the middle phase) vs the fast solver."""
    exact = solve_high_precision(K, dps=25)
    fast = solve_collision(float(K))
    for key in ("x_max", "tau_max", "tau_f", "eps_F0", "tau_0", "eps_x0"):
        assert fast[key] == pytest.approx(float(exact[key]), rel=ACCURACY), key


def test_hertz_limit():
    r = solve_collision(0.0)
    assert r["x_max"] == pytest.approx(1.0, rel=1e-12)
    assert r["tau_0"] == pytest.approx(HERTZ_TAU, rel=1e-12)
    assert r["tau_max"] == pytest.approx(HERTZ_TAU / 2, rel=1e-12)
    assert r["eps_x0"] == pytest.approx(1.0, rel=1e-12)
    assert r["tau_f"] == r["tau_0"] and r["eps_F0"] == r["eps_x0"]
    assert r["force_max"] == pytest.approx(1.25, rel=1e-12)  # (5/4) x_max^{3/2}
    assert r["dissipated_x0"] == 0.0


def test_energy_partition_sums_to_one_over_the_whole_range():
    t = solve_collisions(np.linspace(0, 10, 201))
    assert np.all(t.energy_residual < 1e-11)
    # x0 end: x = 0, so the kinetic energy eps^2 and the dissipated energy make up the whole.
    assert np.allclose(t.eps_x0**2 + t.dissipated_x0, 1.0, rtol=0, atol=1e-11)
    # F0 end: the elastic energy x^{5/2} at separation is (4/5 K eps_F0)^{5/2}.
    x_f = 0.8 * t.K * t.eps_F0
    assert np.allclose(t.eps_F0**2 + x_f**2.5 + t.dissipated_F0, 1.0, rtol=0, atol=1e-11)


def test_dissipation_before_and_after_maximum_compression_is_positive_and_ordered():
    t = solve_collisions([0.05, 0.5, 2.0])
    assert np.all(t.dissipated_at_max > 0)
    assert np.all(t.dissipated_F0 > t.dissipated_at_max)
    assert np.all(t.dissipated_x0 > t.dissipated_F0)


def test_first_order_coefficients_by_finite_difference():
    """d/dK at K = 0 by a central difference over [-h, h] (error ~ h^2 c3 ~ 1e-8)."""
    h = 1e-4
    t = solve_collisions([-h, h], allow_negative=True)
    d_eps = (t.eps_x0[1] - t.eps_x0[0]) / (2 * h)
    d_area = (t.x_max[1] - t.x_max[0]) / (2 * h)
    d_time = (t.tau_0[1] - t.tau_0[0]) / (2 * h) / HERTZ_TAU
    assert d_eps == pytest.approx(FIRST_ORDER["eps"], abs=1e-7)
    assert d_area == pytest.approx(FIRST_ORDER["A/A_e"], abs=1e-7)
    assert d_time == pytest.approx(FIRST_ORDER["T/T_e"], abs=1e-7)


def test_maximum_force_is_the_maximum_along_a_plain_integration():
    """Cross-check of force_max against a dense plain tau-integration started off x = 0."""
    K = 0.7
    r = solve_collision(K)
    tau0 = 1e-3  # start on the small-tau series x = tau - (4/15) K tau^{5/2} + ...
    x0, v0 = tau0 - (4 / 15) * K * tau0**2.5, 1 - (2 / 3) * K * tau0**1.5
    sol = solve_ivp(lambda t, y: [y[1], -np.sqrt(max(y[0], 0)) * (K * y[1] + 1.25 * y[0])],
                    (tau0, r["tau_max"]), [x0, v0], rtol=1e-12, atol=1e-14, dense_output=True)
    tau = np.linspace(tau0, r["tau_max"], 20001)
    x, v = sol.sol(tau)
    F = np.sqrt(x) * (1.25 * x + K * v)
    assert F.max() == pytest.approx(r["force_max"], rel=1e-6)
    assert tau[F.argmax()] == pytest.approx(r["tau_force_max"], abs=2e-3)


def test_rejects_K_outside_range():
    with pytest.raises(ValueError, match="K must lie in"):
        solve_collisions([10.5])
    with pytest.raises(ValueError, match="K must lie in"):
        solve_collisions([-0.1])
    with pytest.raises(ValueError, match="finite"):
        solve_collisions([np.nan])


def test_a_failed_integration_is_an_error_naming_its_K_not_a_row_of_numbers():
    """The kernel's failure path: a K whose coefficients are not finite (overflow; the public API
    refuses such K before they get here) ends its integration with STEP_FAILURE, and the batch
    raises naming that K, while the other K of the batch solve as usual."""
    from reference import collision_ode

    kernel = collision_ode._kernel()
    table, status = kernel.solve_batch(np.array([0.1, 1e300]))
    assert list(status) == [kernel.OK, kernel.STEP_FAILURE]
    assert table[0, 6] == pytest.approx(0.904885783491945, rel=1e-13)  # eps_x0(0.1), docs/reference_solver.md table
    with pytest.raises(FloatingPointError, match=r"integration failed for K = \[1\.?e\+300\]"):
        collision_ode._solve_batch(np.array([0.1, 1e300]))


@pytest.mark.parametrize("n", [1, 4, 5, 8, 203])  # scalar path, lanes padded, full groups
def test_lanes_are_bit_identical_to_the_scalar_path(n):
    """solve_batch steps LANES K together (vectorised coefficients); each lane must do exactly
    the scalar integration's arithmetic: same rows to the bit, for any group size, for K = 0
    and negative K, and with a failing K in a group leaving its neighbours untouched."""
    from reference import collision_ode

    kernel = collision_ode._kernel()
    K = np.random.default_rng(n).uniform(-0.5, 10.0, n)
    K[0] = 0.0
    if n >= 8:
        K[3] = 1e300  # fails (STEP_FAILURE) inside a group of lanes
    table, status = kernel.solve_batch(K)
    for i, k in enumerate(K):
        row, st = kernel.solve_one(k)
        assert status[i] == st, k
        assert np.array_equal(table[i], row, equal_nan=True), k
    assert (status == kernel.OK).sum() == n - (n >= 8)


def test_batches_agree_with_single_solutions():
    Ks = np.linspace(0.01, 3, 300)
    batch = solve_collisions(Ks)
    for i in (0, 137, 299):
        single = solve_collision(Ks[i])
        for key in ("x_max", "tau_f", "eps_F0", "tau_0", "eps_x0"):
            assert getattr(batch, key)[i] == pytest.approx(single[key], rel=1e-11)


@pytest.mark.parametrize("K", [0.0, 0.1, 1.0, 4.0])
def test_trajectory_energy_partition(K):
    tr = collision_trajectory(K, points_per_phase=150)
    total = tr["kinetic"] + tr["elastic"] + tr["dissipated"]
    assert np.max(np.abs(total - 1.0)) < 1e-11
    assert np.all(np.diff(tr["tau"]) >= 0)
    assert np.all(np.diff(tr["dissipated"]) >= -1e-15)  # dissipation never decreases
    r = solve_collision(K)
    assert tr["tau"][-1] == pytest.approx(r["tau_0"], rel=1e-13)
    assert tr["x"].max() == pytest.approx(r["x_max"], rel=1e-13)
    assert tr["dissipated"][-1] == pytest.approx(r["dissipated_x0"], rel=1e-12, abs=1e-15)


def test_trajectory_is_the_hertz_solution_at_K_0():
    """At K = 0 energy conservation gives the time in closed form: tau(x) on the approach is
    int_0^x dx / sqrt(1 - x^{5/2}) = x 2F1(1/2, 2/5; 7/5; x^{5/2})."""
    from scipy.special import hyp2f1
    tr = collision_trajectory(0.0, points_per_phase=120)
    up = (tr["v"] > 0.05) & (tr["x"] < 0.9)
    x = tr["x"][up]
    assert tr["tau"][up] == pytest.approx(x * hyp2f1(0.5, 0.4, 1.4, x**2.5), rel=1e-11)


# Every field of CollisionTable but the energy residual, which is a rounding-level number.
COMPARED = [f for f in CollisionTable.__dataclass_fields__ if f not in ("K", "energy_residual")]


@pytest.fixture(scope="module")
def dense_grid():
    """2000 K in [0, 10]: 0, tiny K down to 1e-8, and a uniform grid up to 10."""
    K = np.unique(np.concatenate([np.linspace(0.0, 10.0, 1801), np.logspace(-8, 0, 200)]))
    assert len(K) == 2000 and K[0] == 0.0 and K[1] == 1e-8 and K[-1] == 10.0
    return K


def test_agrees_with_the_dop853_solver_on_a_dense_grid(dense_grid):
    """The compiled Taylor solver against the scipy DOP853 solver it replaced (rtol 1e-13), field
    by field, to 1e-12 relative; fields that are exactly 0 (the dissipation at K = 0) in one
    must be exactly 0 in the other."""
    new = solve_collisions(dense_grid)
    old = scipy_solver.solve_collisions(dense_grid)
    assert np.array_equal(new.K, dense_grid)
    for name in COMPARED:
        a, b = getattr(new, name), getattr(old, name)
        assert np.all(np.isfinite(a)), name
        assert np.array_equal(a == 0, b == 0), name
        rel = np.abs(a - b) / np.where(b == 0, 1.0, np.abs(b))
        assert rel.max() < 1e-12, (name, rel.max(), dense_grid[rel.argmax()])
    assert np.all(new.energy_residual < 1e-13)


def test_agrees_with_the_dop853_solver_for_negative_K():
    """K < 0 (energy gain, used for the Taylor fit around 0): x0 quantities agree, F0 is NaN."""
    K = np.array([-0.5, -0.3, -1e-4])
    new = solve_collisions(K, allow_negative=True)
    old = scipy_solver.solve_collisions(K, allow_negative=True)
    for name in ("x_max", "tau_max", "tau_0", "eps_x0", "dissipated_at_max", "dissipated_x0",
                 "force_max", "tau_force_max", "x_force_max"):
        np.testing.assert_allclose(getattr(new, name), getattr(old, name), rtol=1e-12, err_msg=name)
    for name in ("tau_f", "eps_F0", "dissipated_F0"):
        assert np.all(np.isnan(getattr(new, name))) and np.all(np.isnan(getattr(old, name)))
    assert np.all(new.eps_x0 > 1.0)  # the contact gains energy


def test_batch_size_and_order_do_not_change_results(dense_grid):
    K = dense_grid[::7]
    ref = solve_collisions(K)
    shuffled = np.random.default_rng(1).permutation(len(K))
    other = solve_collisions(K[shuffled], batch=5)
    for name in COMPARED:
        assert np.array_equal(getattr(other, name), getattr(ref, name)[shuffled]), name


def test_trajectory_agrees_with_the_dop853_trajectory():
    """Both solvers sample x(tau) differently (other phase splits); compare the DOP853 samples
    with the new trajectory's Taylor-accurate interpolation: a cubic Hermite interpolant of the
    new samples (x, x' = v) at the old sample times, where the samples are dense."""
    from scipy.interpolate import CubicHermiteSpline
    K = 0.8
    new = collision_trajectory(K, points_per_phase=2000)
    old = scipy_solver.collision_trajectory(K, points_per_phase=200)
    keep = np.concatenate([[True], np.diff(new["tau"]) > 0])
    x_of_tau = CubicHermiteSpline(new["tau"][keep], new["x"][keep], new["v"][keep])
    inside = (old["tau"] > 0.05) & (old["tau"] < new["tau"][-1] - 0.05)
    assert np.abs(x_of_tau(old["tau"][inside]) - old["x"][inside]).max() < 1e-11  # seen: 1.6e-13
    assert new["tau"][-1] == pytest.approx(old["tau"][-1], rel=1e-12)
    assert new["dissipated"][-1] == pytest.approx(old["dissipated"][-1], rel=1e-12)


def test_generated_coefficients_are_current():
    """reference/_coefficients.py is what its generator writes, and reference/_taylor.py records
    its digest (numba's cache of _taylor.py is keyed by that file alone)."""
    from pathlib import Path
    from reference import _coefficients, _generate_coefficients, _taylor
    text = Path(_coefficients.__file__).read_text()
    assert text == _generate_coefficients.source()
    assert _taylor.COEFFICIENTS_SHA256 == _generate_coefficients.digest(text)


@pytest.mark.parametrize("kind", ["u", "t"])
def test_lane_step_sizes_and_step_ends_are_the_scalar_ones_to_the_bit(kind):
    """_steps_lanes and _horner3_lanes compute eight lanes' steps in one vectorised loop; in the
    regular case each lane's step size, step and step-end state must be the scalar
    `_scaled_step_size` / `_horner3`'s to the bit, and a lane outside it must be handed back to
    the scalar path (nan step size) rather than stepped on a guess: K = 0, where D stays 0 (its
    scale is 0, a component the scalar step size skips; at u = 0 v's last coefficients vanish
    too), and a lane whose state is not finite."""
    from reference import collision_ode

    T = collision_ode._kernel()
    rng = np.random.default_rng(11)
    Ks = np.array([0.0, 0.05, 0.3, 1.0, 2.5, 5.0, 9.9, 0.7])
    b = np.zeros(T.S_SIZE)
    states = []
    for l, K in enumerate(Ks):
        if kind == "u":  # (v, tau, D) at u; lane 0 at u = 0, the start of phase A
            w = 0.0 if l == 0 else rng.uniform(0.1, 0.8)
            y = np.array([1.0, 0.0, 0.0]) if l == 0 else np.array([rng.uniform(0.2, 0.9), rng.uniform(0.1, 1.0),
                                                                   rng.uniform(0, 0.3) * K])
        else:  # (x, v, D) at tau
            w, y = rng.uniform(0.5, 2.0), np.array([rng.uniform(0.3, 0.9), rng.uniform(-0.5, 0.5),
                                                    rng.uniform(0, 0.3) * K])
        if l == 7:
            y[1] = np.nan  # a failed lane: its neighbours must not notice
        states.append((w, y))
        b[T.B_W + l], b[T.B_K + l] = w, K
        for i in range(3):
            b[T.B_Y + i * T.LANES + l] = y[i]
        b[T.S_STOP + l], b[T.S_DIR + l], b[T.S_SPAN + l] = (w + 0.05, 1.0, 1.0) if l % 2 else (np.inf, 1.0, 0.0)
    k = T.KIND_U if kind == "u" else T.KIND_T
    (T._coefficients_u_lanes if kind == "u" else T._coefficients_t_lanes)(b)
    T._steps_lanes(b, k)
    T._horner3_lanes(b)
    c = np.empty((3, T.ORDER + 1))
    regular = 0
    for l, ((w, y), K) in enumerate(zip(states, Ks)):
        T._lane_coefficients(b, l, c)
        h = T._scaled_step_size(k, y, K, c)
        if np.isnan(b[T.S_HR + l]):  # handed to the scalar path
            assert l in (0, 7), (kind, l)
            continue
        regular += 1
        assert b[T.S_HR + l] == h and h > 0
        stop = b[T.S_STOP + l]
        last = l % 2 == 1 and h >= abs(stop - w)
        step = stop - w if last else h
        assert b[T.S_H + l] == step and b[T.S_WN + l] == (stop if last else w + step)
        end = np.empty(3)
        T._horner3(c, step, end)
        assert np.array_equal(end, b[T.S_Y + l:T.S_Y + 3 * T.LANES:T.LANES])
    assert regular == 6
