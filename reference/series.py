"""Series in K: the paper's published coefficients (as data) and the project's own, from the solver.

The five ratios a collision experiment measures, as functions of K (criterion x0 or F0)::

    T/T_e   = tau_end / tau_e
    A/A_e   = x_max
    eps     = -x'(tau_end)
    Q1/Q1e  = (A/A_e)^{1/2} (T/T_e)^2                 (Q1 = A^{1/2} T^2)
    Q2/Q2e  = (A/A_e) / (eps^{1/2} T/T_e)             (Q2 = A / (sqrt(V V') T), V' = eps V)

The project's Taylor coefficients come from Chebyshev interpolation of these ratios on a
symmetric interval [-r, r] around K = 0 (the ODE is regular for small negative K, where the
contact gains energy), converted to powers of K. A symmetric interval keeps the conversion
well conditioned: the n-th coefficient inherits the solver's error (~1e-12) times about
(degree^n / n!) / r^n. The spread between two radii is reported as the uncertainty.

Only the x0 criterion has a Taylor series: under F0 the end point tau_f = tau_0 - (4/5) K + ...
is analytic but eps_F0 - eps_x0 grows like K^{5/2} (the force vanishes at x ~ (4/5) K eps, in
the x^{1/2}-singular tail), so F0 quantities have half-integer powers from order 5/2 on.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping

import numpy as np
from numpy.polynomial import chebyshev

if TYPE_CHECKING:  # pandas is imported where a table is made: `import reference` stays light
    import pandas as pd

from .closed_forms import HERTZ_TAU
from .collision_ode import CollisionTable, solve_collisions

QUANTITIES = ("T/T_e", "A/A_e", "eps", "Q1/Q1e", "Q2/Q2e")
CRITERIA = ("x0", "F0")
PAPER_SERIES_FILE = Path(__file__).with_name("paper_series.csv")


def hertz_ratios(table: CollisionTable, criterion: str) -> dict[str, np.ndarray]:
    """The five measured ratios (see module docstring) under criterion 'x0' or 'F0'.

    Parameters
    ----------
    table : CollisionTable
        The solved collisions (`solve_collisions`), dimensionless [-].
    criterion : str
        The end-of-collision criterion, 'x0' or 'F0' [-].

    Returns
    -------
    dict of str to numpy.ndarray
        'T/T_e', 'A/A_e', 'eps', 'Q1/Q1e' and 'Q2/Q2e', one value per K of `table` [-].

    Raises
    ------
    ValueError
        For an unknown criterion.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    Q1 = A^{1/2} T^2 and Q2 = A / (sqrt(V V') T), eqs. 7a and 7b.
    """
    if criterion == "x0":
        tau, eps = table.tau_0, table.eps_x0
    elif criterion == "F0":
        tau, eps = table.tau_f, table.eps_F0
    else:
        raise ValueError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    t = tau / HERTZ_TAU
    a = table.x_max
    return {
        "T/T_e": t,
        "A/A_e": a,
        "eps": eps,
        "Q1/Q1e": np.sqrt(a) * t**2,
        "Q2/Q2e": a / (np.sqrt(eps) * t),
    }


def load_paper_series(path: Path = PAPER_SERIES_FILE) -> pd.DataFrame:
    """The paper's series coefficients: columns quantity, order, coefficient, equation, note.

    Parameters
    ----------
    path : pathlib.Path
        The series file (default: reference/paper_series.csv) [-].

    Returns
    -------
    pandas.DataFrame
        One row per published coefficient; the coefficients are dimensionless [-].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the series of eqs. 4-6, 7a and 7b.
    """
    import pandas as pd  # here, not at import: most users of `reference` never read the table

    return pd.read_csv(path, comment="#", dtype={"equation": str}).fillna({"note": ""})


@lru_cache(maxsize=None)
def paper_series_terms(path: Path = PAPER_SERIES_FILE) -> Mapping[str, tuple[tuple[int, float], ...]]:
    """{quantity: ((order, coefficient), ...)} of a series file, in the file's row order.

    Read once per process: the summaries and the closed-form fits evaluate the series thousands of
    times, and parsing the CSV each time was most of their run time (closed_forms: 3 500 reads,
    ~8 s). Read-only (a mapping proxy of tuples): no caller can change what the next one gets.

    Parameters
    ----------
    path : pathlib.Path
        The series file (default: reference/paper_series.csv) [-].

    Returns
    -------
    Mapping of str to tuple of (int, float)
        Per quantity, its (order, coefficient) pairs; the coefficients are dimensionless [-].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the series of eqs. 4-6, 7a and 7b.
    """
    series = load_paper_series(path)
    return MappingProxyType({q: tuple(zip(rows.order, rows.coefficient))
                             for q, rows in series.groupby("quantity", sort=False)})


def paper_series_value(quantity: str, K, series: pd.DataFrame | None = None) -> np.ndarray:
    """The paper's truncated series for `quantity` evaluated at K (the O(K^3) rest dropped).

        sum_n c_n K^n,   (n, c_n) the rows of `quantity` in `series` (default: the paper's file,
                         parsed once, `paper_series_terms`).

    Parameters
    ----------
    quantity : str
        One of 'T/T_e', 'A/A_e', 'eps', 'Q1/Q1e', 'Q2/Q2e' [-].
    K : float or array_like
        The dissipation parameter(s) [-].
    series : pandas.DataFrame or None
        A table as `load_paper_series` returns (None: the paper's file) [-].

    Returns
    -------
    numpy.ndarray
        The truncated series at each K [-].

    Raises
    ------
    KeyError
        When the series gives no coefficient for `quantity`.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the series of eqs. 4-6, 7a and 7b.
    """
    if series is None:
        terms = paper_series_terms().get(quantity, ())
    else:
        rows = series[series.quantity == quantity]
        terms = tuple(zip(rows.order, rows.coefficient))
    if not terms:
        raise KeyError(f"the paper gives no series for {quantity!r}")
    K = np.asarray(K, dtype=float)
    return sum(c * K**o for o, c in terms)


def _chebyshev_taylor(radius: float, degree: int, order: int) -> dict[str, np.ndarray]:
    """Taylor coefficients 0..order of every x0 ratio from Chebyshev interpolation on [-r, r]."""
    nodes = chebyshev.chebpts1(degree + 1)  # in [-1, 1]
    table = solve_collisions(radius * nodes, allow_negative=True)
    out = {}
    for name, values in hertz_ratios(table, "x0").items():
        cheb = chebyshev.chebfit(nodes, values, degree)
        power = chebyshev.cheb2poly(cheb)[: order + 1]  # coefficients in t = K / r
        out[name] = power / radius ** np.arange(order + 1)
    return out


def taylor_coefficients(order: int = 6, radius: float = 0.3, degree: int = 22) -> pd.DataFrame:
    """The project's Taylor coefficients in K of the five ratios, criterion x0.

    Parameters
    ----------
    order : int
        The highest order returned [-].
    radius : float
        The half-width r of the interval [-r, r] of K the Chebyshev interpolation is taken on [-].
    degree : int
        The degree of the Chebyshev interpolant [-].

    Returns
    -------
    pandas.DataFrame
        A tidy table: quantity, order, coefficient, uncertainty; the uncertainty is the difference
        to a second fit on [-0.8 r, 0.8 r] (it grows with the order). All dimensionless [-].
    """
    first = _chebyshev_taylor(radius, degree, order)
    second = _chebyshev_taylor(0.8 * radius, degree, order)
    rows = [
        {"quantity": q, "order": n, "coefficient": first[q][n],
         "uncertainty": abs(first[q][n] - second[q][n])}
        for q in QUANTITIES for n in range(order + 1)
    ]
    import pandas as pd

    return pd.DataFrame(rows)


def compare_with_paper(order: int = 6) -> pd.DataFrame:
    """Every published coefficient beside the project's.

    Parameters
    ----------
    order : int
        The highest order of the project's coefficients [-].

    Returns
    -------
    pandas.DataFrame
        quantity, order, paper, equation, computed, uncertainty, difference (paper - computed) and
        rounding (half a unit in the last printed digit of the paper's coefficient), note. The
        coefficients are dimensionless [-].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the series of eqs. 4-6, 7a and 7b.
    """
    own = taylor_coefficients(order)
    paper = load_paper_series()
    merged = own.merge(paper, on=["quantity", "order"], how="left")
    merged = merged.rename(columns={"coefficient_x": "computed", "coefficient_y": "paper"})
    merged["difference"] = merged.paper - merged.computed
    merged["rounding"] = 0.5e-4  # the paper prints 4 decimals
    return merged[["quantity", "order", "paper", "equation", "computed", "uncertainty",
                   "difference", "rounding", "note"]]
