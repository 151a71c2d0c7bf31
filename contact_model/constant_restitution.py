r"""The Tsuji-type collision by scipy's DOP853: the independent check of the closed form
(`reference.quarter_power_damping`) and of the keywords' maps (`contact_model.keywords`, which
holds each code's b(e)).

The engines' restitution keywords damp with a coefficient proportional to delta^{1/4}; in the
Hertz units of `reference` (x = delta/delta_e, tau = t V/delta_e) each is

    x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0,

b set by the keyword's map (`contact_model.keywords`; docs/keywords.md): its restitution depends on
b only, not on the impact velocity. This module integrates that equation numerically, apart from
the closed form, so that each can check the other (tests/test_keywords.py,
tests/test_quarter_power_damping.py).

x^{1/4} is singular at x = 0; as in `reference.collision_ode`, the ends are integrated with
w = x^{1/4} as independent variable (dv/dw = -4 b w^4 - 5 w^9 / v, dtau/dw = 4 w^3 / v).
"""

from __future__ import annotations

from scipy.integrate import solve_ivp
from scipy.optimize import brentq

_TOL = dict(rtol=1e-12, atol=1e-14)


def restitution_of_damping(b: float, criterion: str = "x0") -> float:
    """Restitution coefficient of x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 (b >= 0).

    Parameters
    ----------
    b : float
        The damping coefficient of b x^{1/4} x', >= 0 (only eps > 0.3 is supported) [-].
    criterion : str
        'x0': velocity when the overlap returns to zero (attractive tail kept); 'F0': velocity when
        the force 5/4 x^{3/2} + b x^{1/4} x' first vanishes (clipped force) [-].

    Returns
    -------
    float
        The restitution coefficient [-].

    Raises
    ------
    ValueError
        For b < 0, or a b that stops the bodies before x = 0.3.

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    if b < 0:
        raise ValueError(f"b must be non-negative, got {b}")
    w_s = 0.3 ** 0.25  # switch at x = 0.3 < x_max for the b of interest (eps > 0.3)

    def near_ends(w, y):
        v = y[0]
        return [-4 * b * w**4 - 5 * w**9 / v, 4 * w**3 / v]

    approach = solve_ivp(near_ends, (0, w_s), [1.0, 0.0], method="DOP853", **_TOL)
    v1, t1 = approach.y[:, -1]
    if not v1 > 0:
        raise ValueError(f"b = {b} stops the bodies before x = 0.3; only eps > 0.3 is supported")

    def middle(t, y):
        x, v = y
        return [v, -(b * x**0.25 * v + 1.25 * x**1.5)]

    back = lambda t, y: y[0] - w_s**4  # noqa: E731
    back.terminal, back.direction = True, -1
    force = lambda t, y: 1.25 * y[0] ** 1.25 + b * y[1]  # noqa: E731  (force / x^{1/4})
    force.terminal, force.direction = criterion == "F0", -1
    mid = solve_ivp(middle, (t1, t1 + 20), [w_s**4, v1], method="DOP853", events=[back, force], **_TOL)
    if criterion == "F0" and len(mid.t_events[1]):
        return float(-mid.y_events[1][0][1])
    x2, v2 = mid.y_events[0][0]

    separation = solve_ivp(near_ends, (w_s, 0), [v2, 0.0], method="DOP853", **_TOL,
                           events=[lambda w, y: 1.25 * w**5 + b * y[0]])
    if criterion == "F0" and len(separation.t_events[0]):
        return float(-separation.y_events[0][0][0])
    return float(-separation.y[0, -1])


def damping_for_restitution(eps: float, criterion: str = "x0") -> float:
    """The b that gives restitution `eps` (0.3 < eps <= 1).

    Parameters
    ----------
    eps : float
        The restitution coefficient to reach, in (0.3, 1] [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    float
        The damping coefficient b of b x^{1/4} x' [-].

    Raises
    ------
    ValueError
        For eps outside (0.3, 1].

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    if not 0.3 < eps <= 1.0:
        raise ValueError(f"restitution must lie in (0.3, 1], got {eps}")
    if eps == 1.0:
        return 0.0
    return brentq(lambda b: restitution_of_damping(b, criterion) - eps, 0.0, 5.0, xtol=1e-13)


__all__ = ["restitution_of_damping", "damping_for_restitution"]
