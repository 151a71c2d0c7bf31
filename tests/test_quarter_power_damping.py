"""The Tsuji-type collision x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 in closed form
(reference.quarter_power_damping) against Hertz's closed forms, an independent ODE solution
(scipy's DOP853 with x^{1/4} as the variable near the ends) and its own inverse."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from reference import HERTZ_TAU
from reference.quarter_power_damping import (damping_for_restitution_quarter_power, restitution_quarter_power,
                                             solve_quarter_power)

TOL = dict(rtol=1e-13, atol=1e-15)


def ode_solution(b: float) -> dict:
    """x_max, tau_max, tau_0, eps_x0, tau_f, eps_F0 of (1) by DOP853, with w = x^{1/4} as the
    independent variable near x = 0 (where x^{1/4} is singular) and tau in between."""
    w_s = 0.3 ** 0.25

    def near(w, y):  # y = (v, tau): dv/dw = (dv/dtau) / (dw/dtau), dw/dtau = v / (4 w^3)
        return [-4.0 * b * w**4 - 5.0 * w**9 / y[0], 4.0 * w**3 / y[0]]

    a = solve_ivp(near, (0.0, w_s), [1.0, 0.0], method="DOP853", **TOL)
    v1, t1 = a.y[:, -1]

    def middle(t, y):
        return [y[1], -(b * y[0] ** 0.25 * y[1] + 1.25 * y[0] ** 1.5)]

    top = lambda t, y: y[1]  # noqa: E731
    top.direction = -1
    back = lambda t, y: y[0] - 0.3  # noqa: E731
    back.terminal, back.direction = True, -1
    force = lambda t, y: 1.25 * y[0] ** 1.25 + b * y[1]  # noqa: E731  (F / x^{1/4})
    force.direction = -1
    m = solve_ivp(middle, (t1, t1 + 30.0), [0.3, v1], method="DOP853", events=[top, back, force], **TOL)
    out = {"x_max": float(m.y_events[0][0][0]), "tau_max": float(m.t_events[0][0])}
    if len(m.t_events[2]):
        out.update(tau_f=float(m.t_events[2][0]), eps_F0=float(-m.y_events[2][0][1]))
    t2, v2 = float(m.t_events[1][0]), float(m.y_events[1][0][1])
    c = solve_ivp(near, (w_s, 0.0), [v2, t2], method="DOP853", **TOL,
                  events=[lambda w, y: 1.25 * w**5 + b * y[0]])
    if "tau_f" not in out:
        out.update(tau_f=float(c.y_events[0][0][1]), eps_F0=float(-c.y_events[0][0][0]))
    out.update(eps_x0=float(-c.y[0, -1]), tau_0=float(c.y[1, -1]))
    return out


def test_without_damping_it_is_hertz():
    r = solve_quarter_power(0.0)
    assert r["tau_0"] == pytest.approx(HERTZ_TAU, rel=1e-13) and r["tau_f"] == pytest.approx(HERTZ_TAU, rel=1e-13)
    assert r["tau_max"] == pytest.approx(HERTZ_TAU / 2, rel=1e-13)
    assert r["x_max"] == pytest.approx(1.0, rel=1e-14) and r["eps_x0"] == 1.0 and r["eps_F0"] == pytest.approx(1.0)
    assert r["force_max"] == pytest.approx(1.25, rel=1e-12)  # (5/4) x_max^{3/2}


@pytest.mark.parametrize("b", [0.01, 0.1, 0.3, 0.638, 1.2])
def test_agrees_with_an_independent_ode_solution(b):
    closed, ode = solve_quarter_power(b), ode_solution(b)
    for key in ("x_max", "tau_max", "tau_0", "eps_x0", "tau_f", "eps_F0"):
        assert closed[key] == pytest.approx(ode[key], rel=1e-10, abs=1e-12), key


@pytest.mark.parametrize("e", [0.05, 0.3, 0.5, 0.8, 0.95, 0.99])
def test_the_beta_map_restitutes_e_exactly_without_the_clip(e):
    """b = (5/2) |ln e| / sqrt(ln^2 e + pi^2) (LIGGGHTS's coefficientRestitution, LAMMPS's
    coeff_restitution): eps_x0 = e to round-off, by the linear oscillator of the same zeta."""
    b = 2.5 * -math.log(e) / math.hypot(math.log(e), math.pi)
    assert restitution_quarter_power(b, "x0") == pytest.approx(e, rel=1e-14)
    assert solve_quarter_power(b)["eps_x0"] == pytest.approx(e, rel=1e-14)
    assert damping_for_restitution_quarter_power(e, "x0") == pytest.approx(b, rel=1e-14)


@pytest.mark.parametrize("e", [0.05, 0.2, 0.5, 0.8, 0.97])
def test_the_clipped_inverse_round_trips(e):
    b = damping_for_restitution_quarter_power(e, "F0")
    assert restitution_quarter_power(b, "F0") == pytest.approx(e, rel=1e-12)
    assert b > damping_for_restitution_quarter_power(e, "x0")  # clipping loses less: it needs more damping


def test_an_overdamped_contact_separates_only_where_the_force_vanishes():
    """zeta = 2b/5 > 1 (YADE's en = 0.05 gives b = 4.87): no rebound through x = 0, a finite
    one where the clipped force vanishes, continuous in b across zeta = 1."""
    r = solve_quarter_power(4.8656)
    assert math.isnan(r["eps_x0"]) and r["tau_0"] == math.inf and 0.0 < r["eps_F0"] < 0.1
    near = [restitution_quarter_power(b, "F0") for b in (2.5 - 1e-7, 2.5, 2.5 + 1e-7)]
    assert np.ptp(near) < 1e-6


def test_a_negative_or_unknown_input_is_refused():
    with pytest.raises(ValueError, match="b must be a finite number >= 0"):
        solve_quarter_power(-0.1)
    with pytest.raises(ValueError, match="must lie in \\(0, 1\\]"):
        damping_for_restitution_quarter_power(1.2)
    with pytest.raises(ValueError, match="unknown criterion"):
        restitution_quarter_power(0.1, "F1")
