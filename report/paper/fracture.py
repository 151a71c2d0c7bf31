r"""The paper's size dependence of fracture (its Fig. 5): V_F / V_P against R / L_d.

Definitions (the paper's): V_P = (pi^5 R^3 P0^5 / (30 M E^4))^{1/2} is the impact velocity at
which an elastic (Hertz) collision reaches the maximum pressure P0; L_d = eta / (rho V_D) the
viscous length. V_F is the velocity at which the viscoelastic collision reaches P0.

The paper does not say at which instant, and by which pressure, fracture is judged. Three
readings, all with the Hertz relation p = 3F / (2 pi a^2), a^2 = R* delta, in Hertz units:

    'elastic at max compression'   p / P_e = x_max^{1/2}                 (the elastic stress when
                                   the contact is largest: what Hertz's P0 means; the default)
    'elastic at max force'         p / P_e = x(tau_F)^{1/2}              (the same stress at the
                                   instant of the largest total force)
    'total at max force'           p / P_e = (4/5) F_max / x(tau_F)      (the total force, viscous
                                   part included, spread over the contact at that instant)

with P_e = (2 E*/pi) (delta_e/R*)^{1/2} the Hertz maximum pressure, P_e / P0 = (V/V_P)^{2/5}.
V_F solves (V_F/V_P)^{2/5} p/P_e(K_F) = 1 with K_F = alpha (V_F/V_D)^{1/5}.

The curve is not universal: with M* = c_m rho R^3 (c_m = 2 pi/3 for two equal spheres, 4 pi/3
for a sphere on a plane),
    V_D = c_m^{1/3} (E/rho)^{1/2} (R/L_d)^{5/6},
    V_P = (pi^5 / (30 c_m))^{1/2} (P0/E)^{5/2} (E/rho)^{1/2},
so K_F = alpha (V_F/V_P)^{1/5} [(pi^5/(30 c_m))^{1/2} c_m^{-1/3}]^{1/5} (P0/E)^{1/2} (R/L_d)^{-1/6}:
it needs P0/E and c_m, besides R/L_d.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from reference import K_PREFACTOR, solve_collisions

DEFINITIONS = ("elastic at max compression", "elastic at max force", "total at max force")
MASS_FACTOR = {"sphere-sphere": 2 * math.pi / 3, "sphere-plane": 4 * math.pi / 3}


def pressure_ratio(K, definition: str) -> np.ndarray:
    """p / P_e (see module docstring) at dissipation K (array)."""
    t = solve_collisions(np.atleast_1d(K))
    if definition == "elastic at max compression":
        return np.sqrt(t.x_max)
    if definition == "elastic at max force":
        return np.sqrt(t.x_force_max)
    if definition == "total at max force":
        # p = 3F/(2 pi R x delta_e) and P_e = 3 F_e/(2 pi R delta_e), F_e = 5/4 in these units.
        return t.force_max / (1.25 * t.x_force_max)
    raise ValueError(f"unknown definition {definition!r}; known: {DEFINITIONS}")


def dissipation_prefactor(P0_over_E: float, geometry: str) -> float:
    """C in K_F = C (V_F/V_P)^{1/5} (R/L_d)^{-1/6}."""
    c = MASS_FACTOR[geometry]
    return K_PREFACTOR * (math.sqrt(math.pi**5 / (30 * c)) * c ** (-1 / 3)) ** 0.2 * math.sqrt(P0_over_E)


def fracture_velocity_ratios(R_over_Ld, P0_over_E: float, geometry: str = "sphere-sphere",
                             definition: str = DEFINITIONS[0]) -> np.ndarray:
    """V_F / V_P at each R/L_d: the smallest impact velocity whose pressure reaches P0.

    NaN where that needs K_F > 10, beyond the reference solver's range (small R/L_d).
    p/P_e(K) is solved once on a fine grid in log K and interpolated (cubic)."""
    K_grid = np.geomspace(1e-5, 10.0, 600)
    log_p = CubicSpline(np.log(K_grid), np.log(pressure_ratio(K_grid, definition)))
    out = []
    for lam in np.atleast_1d(R_over_Ld):
        C = dissipation_prefactor(P0_over_E, geometry) * lam ** (-1 / 6)
        log_y_max = 5 * math.log(10.0 / C)  # K_F = C y^{1/5} = 10
        log_y_min = 5 * math.log(1e-5 / C)

        def excess(log_y):  # log of p/P0 = (V/V_P)^{2/5} p/P_e, on a number or an array
            return 0.4 * log_y + log_p(math.log(C) + 0.2 * log_y)

        grid = np.linspace(log_y_min, log_y_max, 400)
        # excess() on the whole grid in one spline call: the same operations point by point, so
        # the same numbers, without 400 scalar spline calls per R/L_d (they were ~3 s of Fig. 5).
        values = excess(grid)
        crossing = np.nonzero((values[:-1] < 0) & (values[1:] >= 0))[0]
        out.append(math.exp(brentq(lambda g: float(excess(g)), grid[crossing[0]], grid[crossing[0] + 1],
                                   xtol=1e-12)) if len(crossing) else float("nan"))
    return np.array(out)
