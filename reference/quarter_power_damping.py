r"""The Hertz collision with Tsuji-type damping, solved in closed form up to one quadrature.

The engines' restitution keywords (LIGGGHTS ``model hertz`` with ``coefficientRestitution``,
LAMMPS ``damping tsuji`` and ``coeff_restitution``, YADE's ``en``/``betan``, Kratos's Hertz law,
ESyS's ``HertzMindlinVisco``) all damp with a coefficient proportional to delta^{1/4}. In the
Hertz units of `reference` (x = delta/delta_e, tau = t V/delta_e) each is::

    x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,                 (1)

with b >= 0 set by the keyword (`contact_model.keywords`), optionally with the force
F = (5/4) x^{3/2} + b x^{1/4} x' clipped at zero.

Why it has a closed form
------------------------
With u = x^{5/4} and v = x' the phase-plane equation of (1) is::

    dv/du = -(4 b / 5) - u / v,

the phase-plane equation of the linear oscillator u_ss + 2 zeta u_s + u = 0 with zeta = 2b/5 in a
time s of its own (u_s = v). Both start at (u, v) = (0, 1), so they trace the same curve: the
restitution, the maximum compression and the zero of the force are the linear oscillator's, and
only the time differs. Since dx = (4/5) u^{-1/5} du = (4/5) u^{-1/5} v ds and dtau = dx / v::

    tau(s) = (4/5) int_0^s u(s')^{-1/5} ds'.                                            (2)

For zeta < 1, with w = sqrt(1 - zeta^2)::

    u(s) = e^{-zeta s} sin(w s) / w,    v(s) = e^{-zeta s} (cos(w s) - (zeta / w) sin(w s)),

and for zeta > 1 the same with sinh, cosh and W = sqrt(zeta^2 - 1) (zeta = 1: the limit). The
force is F = (5/4) x^{1/4} (u + 2 zeta v): it vanishes where the linear spring-dashpot force
does. Hence

- x0 (the tail kept: contact ends at x = 0, s = pi / w): eps_x0 = exp(-zeta pi / w) for
  zeta < 1; for zeta >= 1 the bodies never separate (eps_x0 = 0, T infinite);
- F0 (the force clipped: contact ends at F = 0, at the first s > 0 with u + 2 zeta v = 0, before
  the maximum rebound speed): eps_F0 = -v(s_F), for every zeta;
- x_max = u_max^{4/5}, at tan(w s) = w / zeta;

and tau at each of them is the quadrature (2), whose integrand has the integrable singularity
s^{-1/5} at s = 0 (and (s_0 - s)^{-1/5} at the x0 end), taken by `scipy.integrate.quad` with the
matching algebraic weight. Everything is to ~1e-14, a reference an ODE solver of (1) is checked
against (tests/test_quarter_power_damping.py), not the other way round.

All in the units of `reference.collision_ode`: lengths of delta_e, times of delta_e / V, velocities
of V, forces of M* V^2 / delta_e.
"""

from __future__ import annotations

import math

from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

#: The 5/4 of (5/4) x^{3/2}: the elastic coefficient in Hertz units.
ELASTIC = 1.25
_QUAD = dict(epsabs=0.0, epsrel=2e-14, limit=200)


def damping_ratio(b: float) -> float:
    """zeta = 2 b / 5: the damping ratio of the linear oscillator that (1) maps onto.

    Parameters
    ----------
    b : float
        The damping coefficient of b x^{1/4} x' in (1), finite and >= 0 [-].

    Returns
    -------
    float
        The damping ratio zeta [-].

    Raises
    ------
    ValueError
        For b negative or not finite.

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    if not (b >= 0 and math.isfinite(b)):
        raise ValueError(f"the damping coefficient b must be a finite number >= 0, got {b!r}")
    return 0.4 * b


def _uv(s: float, zeta: float) -> tuple[float, float]:
    """(u, v) of the linear oscillator at its time s, from (0, 1)."""
    if zeta < 1.0:
        w = math.sqrt(1.0 - zeta * zeta)
        e = math.exp(-zeta * s)
        return e * math.sin(w * s) / w, e * (math.cos(w * s) - zeta / w * math.sin(w * s))
    if zeta == 1.0:
        e = math.exp(-s)
        return s * e, e * (1.0 - s)
    W = math.sqrt(zeta * zeta - 1.0)
    e = math.exp(-zeta * s)
    return e * math.sinh(W * s) / W, e * (math.cosh(W * s) - zeta / W * math.sinh(W * s))


def _s_max(zeta: float) -> float:
    """The oscillator's time of the maximum compression (v = 0)."""
    if zeta < 1.0:
        w = math.sqrt(1.0 - zeta * zeta)
        return math.atan2(w, zeta) / w
    if zeta == 1.0:
        return 1.0
    W = math.sqrt(zeta * zeta - 1.0)
    return math.atanh(W / zeta) / W


def _s_force_zero(zeta: float) -> float:
    """The oscillator's time where u + 2 zeta v first vanishes after the start (the F0 end)."""
    if zeta == 0.0:
        return math.pi
    g = lambda s: sum((a * c for a, c in zip(_uv(s, zeta), (1.0, 2.0 * zeta))))  # noqa: E731
    lo = _s_max(zeta)  # F > 0 up to the maximum compression
    hi = lo
    while g(hi) > 0:
        hi = hi + max(lo, 1.0)
        if hi > 1e3:
            raise ValueError(f"zeta = {zeta}: the force does not vanish")
    return brentq(g, lo, hi, xtol=1e-15, rtol=8.9e-16)


def _tau(s_end: float, zeta: float, ends_at_zero: bool) -> float:
    """(2): tau at the oscillator time s_end, split at the maximum compression; the integrand's
    s^{-1/5} singularity at 0 (and at s_end when u(s_end) = 0) is taken by quad's 'alg' weight."""
    s_mid = min(_s_max(zeta), s_end)

    def start(s):
        u = _uv(s, zeta)[0]
        return (u / s) ** -0.2 if s > 0 else 1.0  # u ~ s: the bounded factor of u^{-1/5} = s^{-1/5} (u/s)^{-1/5}

    first, _ = quad(start, 0.0, s_mid, weight="alg", wvar=(-0.2, 0.0), **_QUAD)
    if s_end <= s_mid:
        return 0.8 * first
    if ends_at_zero:
        def end(s):
            u = _uv(s, zeta)[0]
            return (u / (s_end - s)) ** -0.2 if s < s_end else abs(_uv(s_end, zeta)[1]) ** -0.2
        second, _ = quad(end, s_mid, s_end, weight="alg", wvar=(0.0, -0.2), **_QUAD)
    else:
        second, _ = quad(lambda s: _uv(s, zeta)[0] ** -0.2, s_mid, s_end, **_QUAD)
    return 0.8 * (first + second)


def solve_quarter_power(b: float) -> dict:
    """The characteristics of (1) for damping coefficient `b` (see the module's docstring).

    Parameters
    ----------
    b : float
        The damping coefficient of b x^{1/4} x' in (1), finite and >= 0 [-].

    Returns
    -------
    dict
        b and zeta [-]; x_max [delta_e], tau_max [delta_e/V]; eps_x0 [-] and tau_0 (x0 criterion:
        NaN and inf when the bodies never separate, zeta >= 1), eps_F0 [-] and tau_f (F0
        criterion); force_max [M* V^2/delta_e] and tau_force_max (the largest force,
        F = (5/4) x^{1/4} (u + 2 zeta v), and when).

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    zeta = damping_ratio(b)
    s_m = _s_max(zeta)
    u_max = _uv(s_m, zeta)[0]
    s_f = _s_force_zero(zeta)
    # Hertz alone (zeta = 0): the force vanishes at x = 0 itself, where u^{-1/5} is singular
    row = {"b": float(b), "zeta": zeta, "x_max": u_max ** 0.8, "tau_max": _tau(s_m, zeta, False),
           "eps_F0": -_uv(s_f, zeta)[1], "tau_f": _tau(s_f, zeta, zeta == 0.0)}
    if zeta < 1.0:
        w = math.sqrt(1.0 - zeta * zeta)
        s_0 = math.pi / w
        row.update(eps_x0=math.exp(-zeta * math.pi / w), tau_0=_tau(s_0, zeta, True))
    else:
        row.update(eps_x0=math.nan, tau_0=math.inf)

    def minus_force(s):
        u, v = _uv(s, zeta)
        return -ELASTIC * u ** 0.2 * (u + 2.0 * zeta * v)

    best = minimize_scalar(minus_force, bounds=(1e-9, s_m), method="bounded", options={"xatol": 1e-13})
    row.update(force_max=-float(best.fun), tau_force_max=_tau(float(best.x), zeta, False))
    return row


def restitution_quarter_power(b: float, criterion: str = "x0") -> float:
    """eps of (1) under `criterion` in closed form.

    exp(-zeta pi / w) (x0; 0 for zeta >= 1, the bodies never separate) or -v at the force zero (F0).

    Parameters
    ----------
    b : float
        The damping coefficient of b x^{1/4} x' in (1), finite and >= 0 [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    float
        The restitution coefficient [-].

    Raises
    ------
    ValueError
        For an unknown criterion or an invalid b.

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    zeta = damping_ratio(b)
    if criterion == "x0":
        return math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta)) if zeta < 1.0 else 0.0
    if criterion == "F0":
        return -_uv(_s_force_zero(zeta), zeta)[1]
    raise ValueError(f"unknown criterion {criterion!r}; known: x0, F0")


def damping_for_restitution_quarter_power(eps: float, criterion: str = "x0") -> float:
    """The b of (1) whose restitution under `criterion` is `eps`.

    Under x0 it is closed: zeta = -ln eps / sqrt(ln^2 eps + pi^2), b = 5 zeta / 2.

    Parameters
    ----------
    eps : float
        The restitution coefficient to reach, 0 < eps <= 1 [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    float
        The damping coefficient b of (1) [-].

    Raises
    ------
    ValueError
        For eps outside (0, 1], or an eps_F0 below what the clipped law reaches.

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    """
    if not 0.0 < eps <= 1.0:
        raise ValueError(f"a restitution coefficient must lie in (0, 1], got {eps!r}")
    if eps == 1.0:
        return 0.0
    if criterion == "x0":
        lg = math.log(eps)
        return 2.5 * -lg / math.sqrt(lg * lg + math.pi * math.pi)
    # eps_F0 falls monotonically from 1 (b = 0) towards its limit as b grows: bracket, then solve
    hi = 1.0
    while restitution_quarter_power(hi, "F0") > eps:
        hi *= 2.0
        if hi > 1e4:
            raise ValueError(f"no damping gives eps_F0 = {eps} (below what the clipped law reaches)")
    return brentq(lambda b: restitution_quarter_power(b, "F0") - eps, 0.0, hi, xtol=1e-15, rtol=1e-15)
