r"""The engines' out-of-the-box damping (Tsuji type) and how to tune it to a restitution coefficient.

The default laws damp with a coefficient proportional to delta^{1/4}:

    LIGGGHTS ``model hertz``:  gamma = 2 sqrt(5/6) beta sqrt(S_n M*),   S_n = 2 E* sqrt(R* delta)
    YADE Hertz-Mindlin:        c_n   = 2 beta sqrt(M* k_n),              k_n = (3/2) k_no sqrt(delta)
    LAMMPS ``damping tsuji``:  eta_n = alpha(e) sqrt(M* k_n),            k_n = (4/3) E* sqrt(R* delta)

with k_no = (4/3) E* sqrt(R*). In the Hertz units of `reference` (x = delta/delta_e,
tau = t V/delta_e) all give

    x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0,
    b = 2.5 beta (LIGGGHTS),  b = 2 sqrt(15/8) beta (YADE),  b = sqrt(5/4) alpha(e) (LAMMPS),

whose restitution coefficient depends on b only, not on the impact velocity: that is why these
laws give a constant restitution, and why they drift from the viscoelastic law, whose K grows
as V^{1/5}. LIGGGHTS maps its input e to |beta| = -ln e / sqrt(ln^2 e + pi^2), which with
b = 2.5 beta restitutes exactly e under criterion x0 (tests/test_constant_restitution.py). YADE
maps its en to beta with the polynomial fit of Thornton et al. (2013) (pkg/dem/HertzMindlin.cpp),
meant for the clipped force (criterion F0); the study measures how close that fit comes.

LAMMPS (src/GRANULAR: pair_granular.cpp in 29 Sep 2021, gran_sub_mod_damping.cpp,
GranSubModDampingTsuji, in 22 Jul 2025) maps its e with `lammps_tsuji_alpha`, Marshall's (2009)
polynomial fit of Tsuji et al.'s (1992) alpha-e curve. That curve was drawn with the particle's
mass, which for two equal spheres is twice M*; LAMMPS applies alpha to M* and so damps
sqrt(2) too little: told e = 0.9049 it restitutes 0.9320 under x0 (measured in both builds to
3e-7: tests/test_engine_lammps.py). With the sqrt(2) (LAMMPS's development branch, PR #5113 of
2026, `damp *= MY_SQRT2`) the fit restitutes e to within its own error, 3e-4 at e = 0.905.

x^{1/4} is singular at x = 0; as in `reference.collision_ode`, the ends are integrated with
w = x^{1/4} as independent variable (dv/dw = -4 b w^4 - 5 w^9 / v, dtau/dw = 4 w^3 / v).
"""

from __future__ import annotations

import math

from scipy.integrate import solve_ivp
from scipy.optimize import brentq

LIGGGHTS_B_PER_BETA = 2.5                  # 2 sqrt(5/6) sqrt(15/8)
LAMMPS_B_PER_ALPHA = math.sqrt(5 / 4)      # sqrt(M* k_n) in Hertz units
YADE_B_PER_BETA = 2.0 * math.sqrt(15 / 8)  # 2 sqrt(15/8)
_TOL = dict(rtol=1e-12, atol=1e-14)


def lammps_tsuji_alpha(e: float) -> float:
    """LAMMPS's `damping tsuji` coefficient alpha(e) for a restitution e (its documentation and
    source: Marshall 2009's fit of Tsuji et al. 1992):

        alpha = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5 + 4.8218 e^6

    so that b = LAMMPS_B_PER_ALPHA * alpha(e) in `restitution_of_damping`."""
    return (1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4
            - 18.022 * e**5 + 4.8218 * e**6)


def restitution_of_damping(b: float, criterion: str = "x0") -> float:
    """Restitution coefficient of x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 (b >= 0).

    criterion 'x0': velocity when the overlap returns to zero (attractive tail kept);
    'F0': velocity when the force 5/4 x^{3/2} + b x^{1/4} x' first vanishes (clipped force).
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
    """The b that gives restitution `eps` (0.3 < eps <= 1)."""
    if not 0.3 < eps <= 1.0:
        raise ValueError(f"restitution must lie in (0.3, 1], got {eps}")
    if eps == 1.0:
        return 0.0
    return brentq(lambda b: restitution_of_damping(b, criterion) - eps, 0.0, 5.0, xtol=1e-13)


__all__ = ["restitution_of_damping", "damping_for_restitution", "lammps_tsuji_alpha", "LAMMPS_B_PER_ALPHA",
           "LIGGGHTS_B_PER_BETA", "YADE_B_PER_BETA"]
