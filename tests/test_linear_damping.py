"""reference.linear_damping, the Hertz collision with a linear dashpot (LAMMPS's `damping velocity`
and `mass_velocity`), against what is known without it: Hertz's closed form at c = 0, the first
order in c in closed form, the energy balance it integrates separately, and a second solver
(scipy's Radau, in tau alone: another method, another variable)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import beta

from reference import HERTZ_TAU
from reference.linear_damping import (damping_for_restitution_linear, restitution_linear_damping,
                                      solve_linear_damping)


def test_without_a_dashpot_it_is_hertz():
    r = solve_linear_damping(0.0)
    assert r["tau_0"] == pytest.approx(HERTZ_TAU, rel=1e-12)
    assert r["tau_max"] == pytest.approx(HERTZ_TAU / 2, rel=1e-12)
    assert r["x_max"] == pytest.approx(1.0, rel=1e-12) and r["force_max"] == pytest.approx(1.25, rel=1e-12)
    assert r["eps_x0"] == pytest.approx(1.0, abs=1e-12)


def test_a_weak_dashpot_loses_what_the_first_order_says():
    """eps = 1 - c int v^2 dtau + O(c^2) over Hertz's elastic motion, int v^2 dtau = 2 int_0^1
    sqrt(1 - x^(5/2)) dx = (4/5) B(2/5, 3/2)."""
    first = 0.8 * beta(0.4, 1.5)
    for c in (1e-4, 1e-3):
        assert (1 - restitution_linear_damping(c)) / c == pytest.approx(first, rel=5 * c)


def _radau(c):
    """x0 and the maximum by Radau in tau from touching (x^(3/2) is not smooth there: ~1e-9)."""
    def rhs(t, y):
        return [y[1], -(c * y[1] + 1.25 * max(y[0], 0.0) ** 1.5)]

    def back(t, y):
        return y[0] if t > 0.1 else 1.0
    back.terminal, back.direction = True, -1

    def top(t, y):
        return y[1]
    top.direction = -1
    s = solve_ivp(rhs, (0, 50), [0.0, 1.0], "Radau", rtol=1e-12, atol=1e-15, events=[back, top])
    return {"tau_0": s.t_events[0][0], "eps_x0": -s.y_events[0][0][1], "tau_max": s.t_events[1][0],
            "x_max": s.y_events[1][0][0]}


@pytest.mark.parametrize("c", [0.05, 0.3, 1.0])
def test_a_second_solver_agrees(c):
    mine, other = solve_linear_damping(c), _radau(c)
    for key, value in other.items():
        assert mine[key] == pytest.approx(value, rel=1e-8), key
    assert mine["energy_error"] < 1e-11
    assert 0 < mine["tau_f"] < mine["tau_0"] and mine["eps_F0"] > mine["eps_x0"]  # the tail pulls back


def test_a_strong_dashpot_never_lets_go_and_the_inverse_is_exact():
    stuck = solve_linear_damping(2.0)
    assert stuck["eps_x0"] == 0.0 and math.isinf(stuck["tau_0"]) and stuck["energy_error"] < 1e-11
    assert stuck["force_max"] == 2.0 and stuck["tau_force_max"] == 0.0  # the dashpot at touching
    for eps in np.linspace(0.05, 0.95, 7):
        for criterion in ("x0", "F0"):
            c = damping_for_restitution_linear(eps, criterion)
            assert restitution_linear_damping(c, criterion) == pytest.approx(eps, abs=1e-12)
    with pytest.raises(ValueError, match="restitution in"):
        damping_for_restitution_linear(1.0)
    with pytest.raises(ValueError, match="must be finite"):
        solve_linear_damping(-1.0)


def test_the_cache_gives_the_solvers_own_numbers_in_a_fresh_dict():
    """solve_linear_damping caches by c (the inversions ask for the same c again and again): the cached
    answer is the uncached solver's, number for number (==, no tolerance); a caller's change to its dict
    does not reach the next caller; and -0.0 is answered as asked."""
    from reference.linear_damping import _solve_linear_damping

    first = solve_linear_damping(0.7)
    first["eps_x0"] = -1.0
    again = solve_linear_damping(0.7)
    assert again == _solve_linear_damping.__wrapped__(0.7) and 0 < again["eps_x0"] < 1
    assert math.copysign(1.0, solve_linear_damping(-0.0)["c"]) == -1.0
