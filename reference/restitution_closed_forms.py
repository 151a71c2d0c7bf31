r"""Closed forms of the literature for the restitution coefficient eps(K), to be checked against
the reference solver.

All are functions of the project's dissipation parameter K = alpha (V/V_D)^{1/5}
(docs/physics.md), each under the end-of-collision criterion it assumes.

The forms
---------
``paper_series`` (x0)
    He & Wettlaufer, "Hertz beyond expectations", eq. 6: eps = 1 - 1.0089 K + 0.6107 K^2
    (the coefficients as printed, from reference/paper_series.csv).
``taylor_6`` (x0)
    The project's own 6th-order Taylor series in K (`reference.series.taylor_coefficients`,
    Chebyshev interpolation of the solver around K = 0).
``ramirez_1999`` (x0)
    R. Ramirez, T. Poeschel, N. V. Brilliantov and T. Schwager, "Coefficient of restitution of
    colliding viscoelastic spheres", Phys. Rev. E 60, 4465 (1999), arXiv:cond-mat/9905382:
    eps = 1 - C_1 (K/k_0) + C_2 (K/k_0)^2 + ..., C_1 = 1.153449, C_2 = 0.79826; the terms beyond
    the second order are not used here.
``muller_poschel_2011`` (F0)
    P. Mueller and T. Poeschel, "Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution", Phys. Rev. E 84, 021302 (2011), arXiv:1102.5247, the
    [1/4] Pade approximant in v*::

        eps = (1 + 0.501086 v*) / (1 + 0.501086 v* + 1.15345 v*^2 + 0.577977 v*^3 + 0.532178 v*^4).

    It assumes that the bodies separate when the force vanishes (F0).

The numbers of Ramirez et al. and of Mueller & Poeschel are taken from the quotation of the two
papers in the project's issue 12: the project's search reached the papers' abstracts (titles,
journal references and arXiv numbers above), not their tables of coefficients;
the tests check them against the reference solver and against each other, which they pass to
the printed precision.

Conversion of their variables to K
----------------------------------
Both papers expand in a scaled impact velocity; in this project's variables it is

    K / k_0 = v*^2,    k_0 = (5/4)^{3/5} = 1.14326...,

so the first-order coefficient is C_1 = 2 I_1 k_0 = 1.1534489 (I_1 = (2/5) B(3/5, 3/2), the
project's `FIRST_ORDER_INTEGRAL`), i.e. eps = 1 - 2 I_1 K = 1 - 1.0089 K as in the paper, and
C_2 / k_0^2 = 0.61073 (the paper's 0.6107).

The F0 end of the collision
---------------------------
Near the end the overlap is small and x' ~ -eps_x0; the force x^{1/2}((5/4) x + K x') vanishes at
x = (4/5) K eps_x0, and over the remaining overlap the (attractive) force slows the bodies
further. The local analysis gives

    eps_F0 - eps_x0 = (4/15) (4/5)^{3/2} K^{5/2} eps_x0^{3/2} + ...       (`f0_correction`)

In v*, (4/15)(4/5)^{3/2} K^{5/2} = (4/15) v*^5 exactly, so the v*^5 coefficient of any F0
expansion must be 4/15 = 0.26667; the Pade approximant's is 0.266666 (tests).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:
    import pandas as pd

#: k_0 = (5/4)^{3/5}: K / k_0 = v*^2 (Ramirez et al. 1999; Mueller & Poeschel 2011).
K0 = 1.25**0.6
#: Ramirez et al. (1999), as quoted in issue 12.
RAMIREZ_C1 = 1.153449
RAMIREZ_C2 = 0.79826
#: Mueller & Poeschel (2011), [1/4] Pade approximant in v*, as quoted in issue 12.
PADE_NUMERATOR = (1.0, 0.501086)
PADE_DENOMINATOR = (1.0, 0.501086, 1.15345, 0.577977, 0.532178)


def paper_series(K) -> np.ndarray:
    """eps_x0 = 1 - 1.0089 K + 0.6107 K^2 (the paper's eq. 6, coefficients as printed).

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5} [-].

    Returns
    -------
    numpy.ndarray
        The restitution coefficient eps_x0 at each K [-].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations", eq. 6.
    """
    from .series import paper_series_value

    return paper_series_value("eps", K)


@lru_cache(maxsize=4)
def _taylor_eps(order: int) -> tuple[float, ...]:
    from .series import taylor_coefficients

    t = taylor_coefficients(order)
    return tuple(t[t.quantity == "eps"].sort_values("order").coefficient)


def taylor_6(K) -> np.ndarray:
    """eps_x0 as the project's 6th-order Taylor polynomial in K (computed from the solver).

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5} [-].

    Returns
    -------
    numpy.ndarray
        The restitution coefficient eps_x0 at each K [-].
    """
    return np.polynomial.polynomial.polyval(np.asarray(K, dtype=float), _taylor_eps(6))


def scaled_velocity(K) -> np.ndarray:
    """v* = (K / k_0)^{1/2}, the expansion variable of Ramirez et al. and Mueller & Poeschel.

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5} [-].

    Returns
    -------
    numpy.ndarray
        The scaled velocity v* at each K [-].

    References
    ----------
    Ramirez, R., Poeschel, T., Brilliantov, N. V. & Schwager, T. (1999). Coefficient of restitution of
    colliding viscoelastic spheres. Phys. Rev. E 60, 4465.
    Mueller, P. & Poeschel, T. (2011). Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution. Phys. Rev. E 84, 021302.
    """
    return np.sqrt(np.asarray(K, dtype=float) / K0)


def ramirez_1999(K) -> np.ndarray:
    """eps_x0 = 1 - C_1 (K/k_0) + C_2 (K/k_0)^2, C_1 = 1.153449, C_2 = 0.79826 (Ramirez et al. 1999).

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5} [-].

    Returns
    -------
    numpy.ndarray
        The restitution coefficient eps_x0 at each K [-].

    References
    ----------
    Ramirez, R., Poeschel, T., Brilliantov, N. V. & Schwager, T. (1999). Coefficient of restitution of
    colliding viscoelastic spheres. Phys. Rev. E 60, 4465.
    """
    q = np.asarray(K, dtype=float) / K0
    return 1.0 - RAMIREZ_C1 * q + RAMIREZ_C2 * q**2


def muller_poschel_2011(K) -> np.ndarray:
    """eps_F0, the [1/4] Pade approximant in v* = (K/k_0)^{1/2} (Mueller & Poeschel 2011).

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s), K = alpha (V/V_D)^{1/5} [-].

    Returns
    -------
    numpy.ndarray
        The restitution coefficient eps_F0 at each K [-].

    References
    ----------
    Mueller, P. & Poeschel, T. (2011). Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution. Phys. Rev. E 84, 021302.
    """
    v = scaled_velocity(K)
    return (np.polynomial.polynomial.polyval(v, PADE_NUMERATOR)
            / np.polynomial.polynomial.polyval(v, PADE_DENOMINATOR))


def f0_correction(K, eps_x0) -> np.ndarray:
    """Leading term of eps_F0 - eps_x0 = (4/15) (4/5)^{3/2} K^{5/2} eps_x0^{3/2}.

    Parameters
    ----------
    K : float or array_like
        The dissipation parameter(s) [-].
    eps_x0 : float or array_like
        The restitution coefficient(s) under the x0 criterion at the same K [-].

    Returns
    -------
    numpy.ndarray
        The leading term of eps_F0 - eps_x0 [-].
    """
    K = np.asarray(K, dtype=float)
    return 4.0 / 15.0 * 0.8**1.5 * K**2.5 * np.asarray(eps_x0, dtype=float) ** 1.5


@dataclass(frozen=True)
class ClosedForm:
    """A closed form eps(K) of the literature: its function, the criterion it assumes, where from."""

    name: str
    eps: Callable
    criterion: str
    source: str


CLOSED_FORMS = {
    f.name: f for f in (
        ClosedForm("paper_series", paper_series, "x0", "He & Wettlaufer, Hertz beyond expectations, eq. 6"),
        ClosedForm("taylor_6", taylor_6, "x0", "this project: 6th-order Taylor series from the solver"),
        ClosedForm("ramirez_1999", ramirez_1999, "x0",
                   "Ramirez, Poeschel, Brilliantov & Schwager, PRE 60, 4465 (1999)"),
        ClosedForm("muller_poschel_2011", muller_poschel_2011, "F0", "Mueller & Poeschel, PRE 84, 021302 (2011)"),
    )
}

#: The K intervals [0, K_max] of the closed-form table.
K_INTERVALS = (0.1, 0.5, 1.0, 5.0)


def closed_form_errors(K_intervals=K_INTERVALS, points: int = 501) -> pd.DataFrame:
    """Largest |eps_form - eps_ref| and the largest relative error of each closed form on each
    [0, K_max], under the criterion each form assumes; where on the interval.

    Parameters
    ----------
    K_intervals : sequence of float
        The upper ends K_max of the intervals [0, K_max] [-].
    points : int
        The K sampled on each interval, its ends included [-].

    Returns
    -------
    pandas.DataFrame
        A tidy table: form, criterion, K_max, max_abs_error, K_at_max, max_rel_error, source; all
        numbers dimensionless [-].
    """
    import pandas as pd

    from .collision_ode import solve_collisions

    # `points` K on each interval, its ends included
    grid = np.unique(np.concatenate([np.linspace(0.0, k, points) for k in K_intervals]))
    table = solve_collisions(grid)
    ref = {"x0": table.eps_x0, "F0": table.eps_F0}
    rows = []
    for form in CLOSED_FORMS.values():
        err = form.eps(grid) - ref[form.criterion]
        rel = np.abs(err) / ref[form.criterion]
        for K_max in K_intervals:
            inside = grid <= K_max
            i = int(np.argmax(np.abs(err[inside])))
            rows.append({"form": form.name, "criterion": form.criterion, "K_max": K_max,
                         "max_abs_error": float(abs(err[inside][i])), "K_at_max": float(grid[inside][i]),
                         "max_rel_error": float(rel[inside].max()), "source": form.source})
    return pd.DataFrame(rows)
