"""The critical dissipation K_c(beta): the K at which phi_1 or phi_2 first reaches beta.

phi_i = |Q_i - Q_ie| / Q_ie (the paper's relative deviations of Q1 = A^{1/2} T^2 and
Q2 = A / (sqrt(V V') T)). The paper reads K_c ~ 2.5 beta^{1/2} off its Fig. 1; here it is the
first root of max(phi_1, phi_2) = beta on the reference solution.
"""

from __future__ import annotations

import numpy as np

from .collision_ode import solve_collisions
from .series import hertz_ratios

#: The paper's rule K_c = 2.5 beta^{1/2} (text below eq. 7).
PAPER_RULE_PREFACTOR = 2.5


def largest_deviation(K, criterion: str = "x0") -> np.ndarray:
    """max(phi_1, phi_2) at each K, phi_i = |Q_i - Q_ie| / Q_ie.

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5}, in [0, 10] [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].

    Returns
    -------
    numpy.ndarray
        The larger of the relative deviations phi_1 and phi_2 at each K [-].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the relative deviations phi_i (text below eq. 7).
    """
    r = hertz_ratios(solve_collisions(K), criterion)
    return np.maximum(np.abs(r["Q1/Q1e"] - 1.0), np.abs(r["Q2/Q2e"] - 1.0))


def critical_dissipation(beta: float, criterion: str = "x0", K_max: float = 10.0) -> float:
    """Smallest K with max(phi_1, phi_2) = beta (relative accuracy ~1e-12).

    Parameters
    ----------
    beta : float
        The tolerated relative deviation of Q1 or Q2 from Hertz's, in (0, 1) [-].
    criterion : str
        The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
        force first returns to zero) [-].
    K_max : float
        The largest K searched [-].

    Returns
    -------
    float
        The critical dissipation parameter K_c(beta) [-].

    Raises
    ------
    ValueError
        For beta outside (0, 1), or when max(phi_1, phi_2) stays below beta for K <= K_max.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the rule K_c ~ 2.5 beta^{1/2}, read off its Fig. 1 (text below eq. 7).
    """
    if not 0 < beta < 1:
        raise ValueError(f"beta must lie in (0, 1), got {beta}")
    grid = np.linspace(0.0, K_max, 401)
    dev = largest_deviation(grid, criterion)
    above = np.nonzero(dev >= beta)[0]
    if len(above) == 0:
        raise ValueError(f"max(phi_1, phi_2) stays below {beta} for K <= {K_max}")
    i = above[0]
    from scipy.optimize import brentq  # here: scipy.optimize is a 0.6 s import, and the figures read only the prefactor

    return brentq(lambda k: largest_deviation([k], criterion)[0] - beta, grid[i - 1], grid[i],
                  xtol=1e-14, rtol=1e-13)
