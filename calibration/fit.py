r"""Fitting the viscosity to measured restitution coefficients: the paper's section IV, exactly.

The model
---------
eps depends on the impact velocity only through K = alpha (V/V_D)^{1/5} (docs/physics.md), so
measured eps(V) fix V_D alone. The fit's parameter is

    k = K(V_ref),   V_ref = the highest measured velocity,   K_i = k (V_i / V_ref)^{1/5},

which is linear in eta at fixed bodies (K = 2 eta sqrt(R*) delta_e^{3/2} / (M* V)) and bounded
by the solver's range: every K_i lies in [0, k] subset of [0, K_MAX]. From it

    V_D = V_ref (alpha / k)^5,       eta = (M*^2 E*^3 / (R* V_D))^{1/5}  [Pa s].

The model eps(K) is the reference solver's (criterion x0 or F0), or any closed form
(`reference.restitution_closed_forms`), e.g. the paper's second-order series.

Least squares and the interval
------------------------------
Weighted least squares on eps (scipy.optimize.least_squares, trust-region reflective, k bounded
to [0, K_max]): residuals r_i = (eps_i - eps(K_i)) / sigma_i, S(k) = sum r_i^2.

- sigma_i given (the file's uncertainty column): chi^2 = S is absolute; the 95 % profile-likelihood
  interval is {k : S(k) - S_min <= chi2_1(0.95) = 3.841}; reduced chi^2 = S_min / (n - 1).
  When chi2_red > 1 the data scatter more than the stated sigma_i allow, and an interval from them
  would be too narrow: the interval is then the profile-t one on the scale the scatter estimates,
  {k : S(k) - S_min <= chi2_red t_{n-1}(0.975)^2} (the stated sigma_i widened by sqrt(chi2_red),
  with Student's quantile, since that scale is itself estimated from n - 1 degrees of freedom).
  It never narrows the stated interval. So the rule is conservative where the stated sigma_i are
  right (a set that scatters more than stated by chance is widened too): it covers 97.1 % in a
  linear model with 10 points, and 95.2 % and 95.0 % where they are 1.5 and 3 times too small
  (`calibration.synthetic.expected_coverage`). `Fit.widened` says which was used; above
  WARN_CHI2_RED the report warns that the stated uncertainties understate the scatter.
- sigma_i not given: all rows weigh the same and the scatter estimates the uncertainty,
  s^2 = S_min / (n - 1); the interval is the profile-t one,
  {k : S(k) - S_min <= s^2 t_{n-1}(0.975)^2}, exact for a model linear in k and the usual
  small-sample form of the profile likelihood otherwise.

With one parameter the profile is S itself, so the interval ends are the two roots of
S(k) - S_min - threshold (Brent's method), one on each side of the best k. An end that the data do
not reach inside [0, K_max] is reported as open (the interval is clipped there and flagged).

Data the model cannot fit - the best k at 0 (no dissipation, V_D infinite) or at K_max (more
dissipation than K = 10 gives) - raise `CalibrationError`; no number is returned.
"""

from __future__ import annotations

import math
from functools import lru_cache
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy import optimize, special
from scipy.interpolate import CubicSpline

from contact_model import CRITERIA
from contact_model.measurement_file import MeasurementError
from reference.closed_forms import K_PREFACTOR
from reference.collision_ode import K_RANGE, solve_collisions

#: Upper end of the fitted K: the reference solver's range.
K_MAX = K_RANGE[1]
LEVEL = 0.95


class CalibrationError(MeasurementError):
    """Measurements the model cannot fit; names the file (and the criterion)."""


def exact_restitution(criterion: str) -> Callable[[np.ndarray], np.ndarray]:
    """eps(K) of the reference solver under criterion 'x0' or 'F0'."""
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    attribute = "eps_x0" if criterion == "x0" else "eps_F0"
    return lambda K: getattr(solve_collisions(K), attribute)


@lru_cache(maxsize=2)
def tabulated_restitution(criterion: str, nodes: int = 4001) -> Callable[[np.ndarray], np.ndarray]:
    """eps(K) of the solver as a cubic spline on `nodes` even K in [0, K_MAX] (about 1e-11 from the
    solver, see the tests): the cheap model of the seeded coverage test, ~1000 times faster."""
    K = np.linspace(0.0, K_MAX, nodes)
    spline = CubicSpline(K, exact_restitution(criterion)(K))
    return lambda k: spline(np.asarray(k, dtype=float))


# The two quantiles of the interval, and the constant-loss test's p value, from scipy.special:
# what scipy.stats' t.ppf, chi2.ppf and f.sf compute, number for number (tests), without
# importing scipy.stats (~1 s, more than a fit).
def student_t_quantile(p: float, dof: int) -> float:
    """t_dof(p), the p-quantile of Student's t with `dof` degrees of freedom (scipy.stats.t.ppf)."""
    return special.stdtrit(dof, p)


def student_t_survival(t: float, dof: int) -> float:
    """P(X > t) for X ~ Student's t with `dof` degrees of freedom (scipy.stats.t.sf)."""
    return special.stdtr(dof, -t)


def chi2_quantile(p: float, dof: int) -> float:
    """chi2_dof(p) = 2 P^{-1}(dof/2, p), P the regularised lower incomplete gamma function
    (scipy.stats.chi2.ppf)."""
    return 2 * special.gammaincinv(dof / 2, p)


def f_survival(F: float, dfn: int, dfd: int) -> float:
    """P(X > F) for X ~ F(dfn, dfd), the complemented F distribution function (scipy.stats.f.sf)."""
    return special.fdtrc(dfn, dfd, F)


def dissipation_parameters(velocity, k: float, V_ref: float) -> np.ndarray:
    """K_i = k (V_i / V_ref)^{1/5}: the K of each impact when K(V_ref) = k."""
    return k * (np.asarray(velocity, dtype=float) / V_ref) ** 0.2


def viscous_velocity(k: float, V_ref: float) -> float:
    """V_D = V_ref (alpha / k)^5 [m/s] (K = alpha (V/V_D)^{1/5} at V = V_ref)."""
    return V_ref * (K_PREFACTOR / k) ** 5 if k > 0 else math.inf


@dataclass(frozen=True)
class Fit:
    """The result of one fit. K values are dimensionless, velocities in m/s.

    Attributes
    ----------
    model : 'exact' or the closed form's name.
    criterion : 'x0' or 'F0' (of the model).
    V_ref : the highest measured velocity; k = K(V_ref).
    k, k_low, k_high : best k and its profile interval at `level`.
    low_open, high_open : the interval reached 0 or K_max without the data closing it.
    K : K of each row at the best k.
    eps_fit : the model at those K.
    residuals : eps - eps_fit.
    sigma : the uncertainty of each row used in the fit (given, or the estimated common one).
    sigma_given : whether the rows carried uncertainties.
    chi2 : S_min (with sigma = 1 when none given); chi2_red = S_min / (n - 1).
    evaluations : model evaluations (least squares and interval), for the benchmark.
    widened : the stated sigma understate the scatter (chi2_red > 1): the interval is the
        profile-t one on the estimated scale (see the module's docstring).
    """

    model: str
    criterion: str
    V_ref: float
    k: float
    k_low: float
    k_high: float
    low_open: bool
    high_open: bool
    K: np.ndarray
    eps_fit: np.ndarray
    residuals: np.ndarray
    sigma: np.ndarray
    sigma_given: bool
    chi2: float
    chi2_red: float
    level: float = LEVEL
    evaluations: int = 0
    K_max: float = K_MAX
    extra: dict = field(default_factory=dict)
    widened: bool = False

    @property
    def n(self) -> int:
        return len(self.K)

    @property
    def V_D(self) -> float:
        """Viscous velocity V_D [m/s] at the best k."""
        return viscous_velocity(self.k, self.V_ref)

    @property
    def V_D_interval(self) -> tuple[float, float]:
        """(low, high) V_D [m/s]: V_D falls as k rises, so the ends swap."""
        return viscous_velocity(self.k_high, self.V_ref), viscous_velocity(self.k_low, self.V_ref)

    def viscosity(self, E: float, R: float, M: float) -> tuple[float, float, float]:
        """(eta, eta_low, eta_high) [Pa s] for bodies E* [Pa], R* [m], M* [kg]:
        eta = (M*^2 E*^3 / (R* V_D))^{1/5}, linear in k."""
        def eta(k):
            return (M**2 * E**3 / (R * viscous_velocity(k, self.V_ref))) ** 0.2 if k > 0 else 0.0

        return eta(self.k), eta(self.k_low), eta(self.k_high)


#: Above this reduced chi^2 the report warns that the stated uncertainties understate the scatter.
WARN_CHI2_RED = 2.0


def _initial_k(V, eps, V_ref, K_max) -> float:
    """A start from the first-order law eps = 1 - 2 I_1 K (median over the rows)."""
    guess = np.median((1.0 - eps) / 1.0089 / (V / V_ref) ** 0.2)
    return float(np.clip(guess, 1e-3 * K_max, 0.9 * K_max))


def fit_restitution(velocity, restitution, sigma=None, *, criterion: str = "x0",
                    model: Callable | None = None, model_name: str = "exact", K_max: float = K_MAX,
                    level: float = LEVEL, source: str = "(data)") -> Fit:
    """Fit k = K(V_max) to measured eps(V) by (weighted) least squares; its profile interval.

    Parameters
    ----------
    velocity : impact velocities [m/s], positive.
    restitution : measured eps, in (0, 1].
    sigma : standard uncertainty of each eps, or None (common, estimated from the scatter).
    criterion : the criterion of the exact model ('x0' or 'F0'); the label of a given `model`.
    model : eps(K) as a vectorised function; default: the reference solver under `criterion`.
    K_max : the largest k the model is valid for (10 for the solver; a series' monotone range).
    level : confidence level of the interval.
    source : the data's file, for error messages.

    Returns
    -------
    Fit

    Raises
    ------
    CalibrationError if the best k lies at 0 or at K_max (the data cannot be fitted).
    """
    V = np.asarray(velocity, dtype=float)
    eps = np.asarray(restitution, dtype=float)
    n = len(V)
    if n < 2:
        raise CalibrationError(source, "(file)", f"has {n} data row(s); a fit needs at least 2")
    model = exact_restitution(criterion) if model is None else model
    weights = np.ones(n) if sigma is None else 1.0 / np.asarray(sigma, dtype=float)
    V_ref = float(V.max())
    x = (V / V_ref) ** 0.2
    calls = [0]

    def residuals(p):
        calls[0] += 1
        return (eps - model(p[0] * x)) * weights

    def S(k):
        r = residuals([k])
        return float(r @ r)

    where = f"all rows (model {model_name}, criterion {criterion})"
    result = optimize.least_squares(residuals, [_initial_k(V, eps, V_ref, K_max)], bounds=([0.0], [K_max]),
                                    method="trf", x_scale=[0.1], xtol=1e-10, ftol=1e-12, gtol=1e-12)
    k = float(result.x[0])
    S_min = S(k)
    # The solver stops near, not on, a bound: the best k lies outside (0, K_max) when a bound
    # fits as well as the point found.
    if result.active_mask[0] < 0 or S(0.0) <= S_min:
        raise CalibrationError(source, where, "the best fit has no dissipation (K = 0, V_D infinite): eps does not "
                                              "fall with the velocity the way the viscoelastic model needs; no "
                                              "viscosity can be given")
    if result.active_mask[0] > 0 or S(K_max) <= S_min:
        raise CalibrationError(source, where, f"the best fit needs K > {K_max:g} at {V_ref:g} m/s, beyond the range "
                                              "the model covers: the data cannot be fitted; no viscosity is given")
    dof = n - 1
    widened = False
    if sigma is None:
        s2 = S_min / dof
        threshold = s2 * student_t_quantile(0.5 + level / 2, dof) ** 2
        used_sigma, chi2_red = np.full(n, math.sqrt(s2)), 1.0
    else:
        used_sigma, chi2_red = np.asarray(sigma, dtype=float), S_min / dof
        stated = chi2_quantile(level, 1)
        scattered = chi2_red * student_t_quantile(0.5 + level / 2, dof) ** 2
        widened = chi2_red > 1 and scattered > stated
        threshold = scattered if widened else stated

    def excess(kk):
        return S(kk) - S_min - threshold

    if threshold <= 0:  # a perfect fit without given uncertainties: no scatter to estimate
        k_low = k_high = k
        low_open = high_open = False
    else:
        low_open = excess(0.0) < 0
        k_low = 0.0 if low_open else optimize.brentq(excess, 0.0, k, xtol=1e-8 * k, rtol=1e-8)
        high_open = excess(K_max) < 0
        k_high = K_max if high_open else optimize.brentq(excess, k, K_max, xtol=1e-8 * k, rtol=1e-8)
    eps_fit = model(k * x)
    return Fit(model_name, criterion, V_ref, k, k_low, k_high, low_open, high_open, k * x, eps_fit,
               eps - eps_fit, used_sigma, sigma is not None, S_min, chi2_red, level, calls[0], K_max,
               widened=widened)


def falling_range(model: Callable, K_max: float = K_MAX, points: int = 10001) -> float:
    """The K up to which eps(K) falls (a closed form may turn up, e.g. the paper's series beyond
    K = 1.0089 / (2 * 0.6107) = 0.826): a fit must stay on that branch, or it has two answers."""
    K = np.linspace(0.0, K_max, points)
    rising = np.nonzero(np.diff(model(K)) >= 0)[0]
    return float(K[rising[0]]) if len(rising) else K_max
