r"""The Hertz collision with a velocity-proportional (linear) dashpot, solved to ~1e-12.

LAMMPS's ``hertz/material`` with ``damping velocity`` (F_d = -eta_n d(delta)/dt, eta_n in N s/m)
or ``damping mass_velocity`` (F_d = -eta_n M* d(delta)/dt, eta_n in 1/s) keeps the Hertz force
and damps with a constant coefficient. In the Hertz units of `reference` (x = delta/delta_e,
tau = t V/delta_e, forces of M* V^2/delta_e)::

    x'' + c x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,                          (1)

with c = eta_n delta_e / (M* V) (velocity) or eta_n delta_e / V (mass_velocity). Since
delta_e ~ V^{4/5}, c falls as V^{-1/5}: at a fixed eta_n the restitution *rises* with the impact
velocity, where the viscoelastic law's falls (K ~ V^{1/5}) and the x^{1/4} keywords' stays put.

The force F = (5/4) x^{3/2} + c x' jumps to c at touching (the dashpot acts at once), and the
tail is kept: LAMMPS clips only with ``limit_damping``. With the tail kept a strong dashpot never
lets go: x creeps to zero as tau^{-2} (x' ~ -(5/4c) x^{3/2}), and eps_x0 = 0 with T infinite;
`solve_linear_damping` says so (eps_x0 = 0, tau_0 = inf) where the overlap has not returned by
RETURN_LIMIT.

How it is solved
----------------
(1) has no closed form. x^{3/2} is not smooth at x = 0, so, as in `reference.collision_ode`, the
ends are integrated in u = sqrt(x) (dx = 2u du), where the motion is smooth::

    dv/du = 2u (-c v - (5/4) u^3) / v,   dtau/du = 2u / v,   dD/du = 4 c u v,

and the middle (where v passes through zero at the maximum compression) in tau::

    dx/dtau = v,   dv/dtau = -(c v + (5/4) x^{3/2}),   dD/dtau = 2 c v^2,

each phase by scipy's DOP853 at rtol 1e-13. The phase ends (v = 1/2 on the way in, x = x_in/4 on
the way out) and the events (the maximum compression v = 0, the force zero F0, the force maximum
dF/dtau = 0) are located on the dense output. D, the energy dissipated (a fraction of
(1/2) M* V^2), is integrated on its own, so that v^2 + x^{5/2} + D = 1 checks the integration.
tests/test_linear_damping.py checks it against a second solver (Radau in tau alone), Hertz's
closed form at c = 0 and the energy balance.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

#: The 5/4 of (5/4) x^{3/2}: the elastic coefficient in Hertz units.
ELASTIC = 1.25
RTOL, ATOL = 1e-13, 1e-16
#: The time [delta_e / V] by which an overlap that has not returned is taken as never returning.
RETURN_LIMIT = 200.0
#: Where the first phase (in u) hands over to the second (in tau): at this velocity on the way in.
V_HANDOVER = 0.5


def _force(x, v, c):
    return c * v + ELASTIC * max(x, 0.0) ** 1.5


def _in_u(u, y, c):
    """d(v, tau, D)/du with u = sqrt(x)."""
    v = y[0]
    return [2.0 * u * (-c * v - ELASTIC * u**3) / v, 2.0 * u / v, 4.0 * c * u * v]


def _in_tau(t, y, c):
    """d(x, v, D)/dtau."""
    x, v = y[0], y[1]
    return [v, -(c * v + ELASTIC * max(x, 0.0) ** 1.5), 2.0 * c * v * v]


def _event(fun, terminal=False, direction=0.0):
    fun.terminal, fun.direction = terminal, direction
    return fun


def solve_linear_damping(c: float) -> dict:
    """The collision (1) at dashpot coefficient c >= 0 (Hertz units).

    Parameters
    ----------
    c : float
        The dashpot coefficient of (1), eta_n delta_e / (M* V) (velocity) or eta_n delta_e / V
        (mass_velocity), finite and >= 0 [-].

    Returns
    -------
    dict
        c; x_max [delta_e], tau_max [delta_e/V] (maximum compression); eps_F0 [-], tau_f (the
        force's zero after the maximum: where a clipped force would let go); eps_x0 [-], tau_0
        (the overlap's return: 0 and inf where it does not return); force_max [M* V^2/delta_e],
        tau_force_max (the force's maximum, which is c at touching for a strong dashpot);
        energy_error (|v^2 + x^{5/2} + D - 1| at the end) [-].

    Raises
    ------
    ValueError
        For c negative or not finite.
    """
    c = float(c)
    if not (c >= 0 and math.isfinite(c)):
        raise ValueError(f"the dashpot coefficient c must be finite and >= 0, got {c}")
    # A fresh dict each call (the caller may change it), with the c asked for (0.0 and -0.0 share a key).
    return {**_solve_linear_damping(c), "c": c}


@functools.lru_cache(maxsize=4096)
def _solve_linear_damping(c: float) -> dict:
    """`solve_linear_damping` for a checked c, cached: the result is a pure function of c, and the
    inversions (`damping_for_restitution_linear`) start every root search at the same c (0, 1, 2,
    ...) and then ask for the root's restitution once more; each solve is three DOP853 runs at rtol
    1e-13 in Python (~0.05 s). Callers get a copy (`solve_linear_damping`)."""
    # Phase A, in u, from touching to v = V_HANDOVER (always before the maximum compression, x <= 1).
    hand = _event(lambda u, y, c: y[0] - V_HANDOVER, terminal=True, direction=-1)
    peak_a = _event(lambda u, y, c: -c * _force(u * u, y[0], c) + 1.875 * u * y[0], direction=-1)
    a = solve_ivp(_in_u, (0.0, 1.01), [1.0, 0.0, 0.0], "DOP853", args=(c,), rtol=RTOL, atol=ATOL,
                  events=[hand, peak_a], dense_output=True)
    u_a = float(a.t_events[0][0])
    v_a, tau_a, D_a = a.y_events[0][0]
    x_in = u_a * u_a
    # Phase B, in tau: the maximum, the force's zero and the force's peak, to x = x_in / 4 on the way out.
    top = _event(lambda t, y, c: y[1], direction=-1)
    zero = _event(lambda t, y, c: _force(y[0], y[1], c), direction=-1)
    peak = _event(lambda t, y, c: -c * _force(y[0], y[1], c) + 1.875 * math.sqrt(max(y[0], 0.0)) * y[1],
                  direction=-1)
    out = _event(lambda t, y, c: y[0] - 0.25 * x_in if y[1] < 0 else 1.0, terminal=True, direction=-1)
    stuck = _event(lambda t, y, c: y[1] if y[0] < 0.25 * x_in else -1.0, terminal=True, direction=1)
    b = solve_ivp(_in_tau, (tau_a, tau_a + RETURN_LIMIT), [x_in, v_a, D_a], "DOP853", args=(c,), rtol=RTOL,
                  atol=ATOL, events=[top, zero, peak, out, stuck], dense_output=True)
    x_max, tau_max = float(b.y_events[0][0][0]), float(b.t_events[0][0])
    peaks = [(ELASTIC * 0.0 + c, 0.0)]  # the force at touching: c
    for u, y in zip(a.t_events[1], a.y_events[1]):
        peaks.append((_force(u * u, y[0], c), float(y[1])))
    for t, y in zip(b.t_events[2], b.y_events[2]):
        peaks.append((_force(y[0], y[1], c), float(t)))
    force_max, tau_force_max = max(peaks)
    row = {"c": c, "x_max": x_max, "tau_max": tau_max, "force_max": float(force_max),
           "tau_force_max": float(tau_force_max)}
    if len(b.t_events[1]):
        row.update(tau_f=float(b.t_events[1][0]), eps_F0=float(-b.y_events[1][0][1]))
    if len(b.t_events[3]) == 0:  # the overlap did not return (stuck, or beyond RETURN_LIMIT)
        x_end, v_end, D_end = b.y[:, -1]
        row.update(eps_x0=0.0, tau_0=math.inf, energy_error=abs(v_end**2 + x_end**2.5 + D_end - 1.0))
        row.setdefault("eps_F0", 0.0)
        row.setdefault("tau_f", math.inf)
        return row
    x_c, v_c, D_c = b.y_events[3][0]
    tau_c = float(b.t_events[3][0])
    # Phase C, in u, from sqrt(x_c) down to 0 (v < 0 throughout: the overlap returns).
    zero_c = _event(lambda u, y, c: _force(u * u, y[0], c))  # F falls through 0 as u falls: the first crossing
    late = _event(lambda u, y, c: y[1] - RETURN_LIMIT, terminal=True)  # creeping: not back by RETURN_LIMIT
    cc = solve_ivp(_in_u, (math.sqrt(x_c), 0.0), [v_c, tau_c, D_c], "DOP853", args=(c,), rtol=RTOL, atol=ATOL,
                   events=[zero_c, late])
    if len(cc.t_events[1]):
        u_end = float(cc.t_events[1][0])
        v_end, _, D_end = cc.y_events[1][0]
        row.update(eps_x0=0.0, tau_0=math.inf, energy_error=abs(v_end**2 + u_end**5 + D_end - 1.0))
        if "eps_F0" not in row:
            hit = list(zip(cc.t_events[0], cc.y_events[0]))
            row.update(tau_f=float(hit[0][1][1]), eps_F0=float(-hit[0][1][0])) if hit else row.update(
                tau_f=math.inf, eps_F0=0.0)
        return row
    if "eps_F0" not in row:
        hit = [(u, y) for u, y in zip(cc.t_events[0], cc.y_events[0])]
        if hit:
            row.update(tau_f=float(hit[0][1][1]), eps_F0=float(-hit[0][1][0]))
    v_end, tau_end, D_end = cc.y[:, -1]
    row.update(eps_x0=float(-v_end), tau_0=float(tau_end), energy_error=abs(v_end**2 + D_end - 1.0))
    if "eps_F0" not in row:  # the force never turned negative before x = 0: F0 coincides with x0
        row.update(eps_F0=row["eps_x0"], tau_f=row["tau_0"])
    return row


def restitution_linear_damping(c: float, criterion: str = "x0") -> float:
    """eps of (1) under `criterion` ('x0' or 'F0').

    Parameters
    ----------
    c : float
        The dashpot coefficient of (1), finite and >= 0 [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    float
        The restitution coefficient (0 under x0 where the overlap does not return) [-].
    """
    return solve_linear_damping(c)[f"eps_{criterion}"]


def damping_for_restitution_linear(eps: float, criterion: str = "x0") -> float:
    """The c for which (1) restitutes `eps` under `criterion`, to ~1e-13.

    eps_x0 falls from 1 at c = 0 to 0 where the overlap stops returning, between c = 1.2 and 1.5.

    Parameters
    ----------
    eps : float
        The restitution coefficient to reach, 0 < eps < 1 [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    float
        The dashpot coefficient c of (1) [-].

    Raises
    ------
    ValueError
        For eps outside (0, 1), or when no c <= 1e3 restitutes eps.
    """
    if not 0.0 < eps < 1.0:
        raise ValueError(f"a restitution in (0, 1) is needed, got {eps}")
    high = 1.0
    while restitution_linear_damping(high, criterion) > eps:
        high *= 2.0
        if high > 1e3:
            raise ValueError(f"no dashpot restitutes {eps} under {criterion}")
    return brentq(lambda c: restitution_linear_damping(c, criterion) - eps, 0.0, high, xtol=1e-15, rtol=1e-15)


def phase_plane(c: float, points: int = 200) -> np.ndarray:
    """(tau, x, v) along the collision, for plots: `points` samples of phase B's dense output.

    Parameters
    ----------
    c : float
        The dashpot coefficient of (1), finite and >= 0 [-].
    points : int
        The number of samples [-].

    Returns
    -------
    numpy.ndarray
        Shape (points, 3): tau [delta_e/V], x [delta_e], v [V].
    """
    row = solve_linear_damping(c)
    end = row["tau_0"] if math.isfinite(row["tau_0"]) else row["tau_max"] * 4
    t = np.linspace(0.0, end, points)
    sol = solve_ivp(_in_tau, (0.0, end), [0.0, 1.0, 0.0], "DOP853", args=(c,), rtol=1e-10, atol=1e-14, t_eval=t)
    return np.vstack([sol.t, sol.y[0], sol.y[1]]).T
