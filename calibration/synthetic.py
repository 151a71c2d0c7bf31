"""Synthetic measurements from a known viscosity: is the interval honest, and what does a closed
form do to the fitted eta?

A synthetic set is what an experiment like Gugan's would give if the viscoelastic model were
true: `points` impact velocities spaced evenly in log V over `decades` decades (Gugan: 0.5-6 m/s,
about one decade), eps from the reference solver at K_i = k_true (V_i / V_max)^{1/5}, plus normal
noise of standard deviation `noise` (Gugan's residual scatter is ~0.005). Since eta is linear in k
at fixed bodies, eta_fit / eta_true = k_fit / k_true: the bodies need not be chosen.

Coverage: the fraction of sets whose interval contains k_true. Its binomial standard error at
95 % over N sets is sqrt(0.95 * 0.05 / N) (1.5 % at N = 200, 0.69 % at N = 1000).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import integrate, stats

from reference.restitution_closed_forms import CLOSED_FORMS

from .fit import CalibrationError, exact_restitution, falling_range, fit_restitution, tabulated_restitution

#: The coverage study's default set: Gugan-like.
K_TRUE = 0.3
POINTS = 10
DECADES = 1.0
NOISE = 0.005


def synthetic_velocities(points: int = POINTS, decades: float = DECADES, V_max: float = 1.0) -> np.ndarray:
    """`points` velocities evenly spaced in log V over `decades` decades, the highest V_max."""
    return V_max * np.logspace(-decades, 0.0, points)


def synthetic_sets(n_sets: int, seed: int, k_true: float = K_TRUE, points: int = POINTS,
                   decades: float = DECADES, noise: float = NOISE, criterion: str = "x0"):
    """(V, eps_true, eps_observed[n_sets, points]) from the reference solver plus seeded noise."""
    V = synthetic_velocities(points, decades)
    eps_true = exact_restitution(criterion)(k_true * (V / V.max()) ** 0.2)
    rng = np.random.default_rng(seed)
    return V, eps_true, eps_true + noise * rng.standard_normal((n_sets, points))


@dataclass(frozen=True)
class Coverage:
    sets: int
    covered: int
    refused: int
    level: float
    k_true: float
    sigma_given: bool
    median_k: float

    @property
    def fraction(self) -> float:
        """Covered / fitted sets."""
        return self.covered / max(self.sets - self.refused, 1)

    @property
    def standard_error(self) -> float:
        """Binomial standard error of `fraction` if the true coverage is `level`."""
        return self.standard_error_at(self.level)

    def standard_error_at(self, coverage: float) -> float:
        """Binomial standard error of `fraction` if the true coverage is `coverage`."""
        return float(np.sqrt(coverage * (1 - coverage) / max(self.sets - self.refused, 1)))


def expected_coverage(understatement: float = 1.0, level: float = 0.95, dof: int = POINTS - 1) -> float:
    """The coverage the fit's interval rule gives with stated uncertainties, in a model linear in k.

    The stated sigma_i are the true ones divided by `understatement` (u >= 1: understated; 1: right).
    In stated units the estimate's error is u Z (Z standard normal) and, independently,
    chi2_red = u^2 X / dof with X ~ chi2(dof). The interval (`calibration.fit`) is the stated one,
    |error| <= z with z = Phi^-1((1 + level)/2), widened to t sqrt(chi2_red) with
    t = t_dof((1 + level)/2) where that is wider. So

        coverage(u) = E_X[ 2 Phi(max(z, t u sqrt(X / dof)) / u) - 1 ].

    The rule is conservative by design: coverage(1) = 0.971 for level 0.95 and 9 degrees of
    freedom (a set that scatters more than stated by chance is widened too), while coverage(u)
    tends to `level` as u grows (0.952 at u = 1.5, 0.950 at u = 3), where the stated interval
    alone would cover 2 Phi(z / u) - 1 (0.809 and 0.486).
    """
    z = stats.norm.ppf(0.5 + level / 2)
    t = stats.t.ppf(0.5 + level / 2, dof)

    def covered_given(x: float) -> float:
        half_width = max(z, t * understatement * np.sqrt(x / dof))
        return (2 * stats.norm.cdf(half_width / understatement) - 1) * stats.chi2.pdf(x, dof)

    return float(integrate.quad(covered_given, 0, stats.chi2.ppf(1 - 1e-12, dof), limit=200)[0])


def coverage(n_sets: int = 200, seed: int = 12, *, sigma_given: bool = False, level: float = 0.95,
             k_true: float = K_TRUE, points: int = POINTS, decades: float = DECADES, noise: float = NOISE,
             criterion: str = "x0", tabulated: bool = False, stated_noise: float | None = None) -> Coverage:
    """Fit `n_sets` seeded synthetic sets (exact model) and count the intervals that hold k_true.

    sigma_given: fit with each row's uncertainty stated as `stated_noise` (default: the true
    `noise`; smaller: uncertainties that understate the scatter, which the fit widens); otherwise
    estimate it from the scatter (profile-t interval). A set the fit refuses (a noisy eps above 1
    or a best K at 0) counts as refused, not as covered. tabulated: fit with the spline of the
    solver (`tabulated_restitution`) instead of the solver itself (the fast, seeded test)."""
    V, _, observed = synthetic_sets(n_sets, seed, k_true, points, decades, noise, criterion)
    sigma = np.full(points, noise if stated_noise is None else stated_noise) if sigma_given else None
    model = tabulated_restitution(criterion) if tabulated else None
    covered = refused = 0
    ks = []
    for eps in observed:
        if np.any(eps > 1) or np.any(eps <= 0):
            refused += 1  # the measurement reader would refuse such a set
            continue
        try:
            fit = fit_restitution(V, eps, sigma, criterion=criterion, level=level, model=model)
        except CalibrationError:
            refused += 1
            continue
        ks.append(fit.k)
        covered += fit.k_low <= k_true <= fit.k_high
    return Coverage(n_sets, covered, refused, level, k_true, sigma_given, float(np.median(ks)))


def closed_form_bias(k_values=(0.1, 0.3, 0.5, 1.0), n_sets: int = 50, seed: int = 12,
                     points: int = POINTS, decades: float = DECADES, noise: float = NOISE) -> pd.DataFrame:
    """The bias in a fitted eta (= k) from fitting each closed form instead of the exact model.

    For each form and k_true: the noise-free set (the systematic bias, eta_fit / eta_true - 1)
    and the median over `n_sets` noisy sets; data from the solver under the form's own
    criterion. A form fitted beyond its falling range, or whose best k hits it, is 'cannot fit'."""
    rows = []
    for form in CLOSED_FORMS.values():
        K_max = falling_range(form.eps)
        for k_true in k_values:
            V, eps_true, observed = synthetic_sets(n_sets, seed, k_true, points, decades, noise, form.criterion)
            row = {"form": form.name, "criterion": form.criterion, "k_true": k_true, "K_max_form": K_max}
            try:
                fit = fit_restitution(V, eps_true, criterion=form.criterion, model=form.eps,
                                      model_name=form.name, K_max=K_max)
                row["bias_noise_free"] = fit.k / k_true - 1
            except CalibrationError as err:
                row["bias_noise_free"], row["problem"] = np.nan, err.problem
            biases = []
            for eps in observed:
                try:
                    fit = fit_restitution(V, eps, criterion=form.criterion, model=form.eps,
                                          model_name=form.name, K_max=K_max)
                    biases.append(fit.k / k_true - 1)
                except CalibrationError:
                    pass
            row["bias_median_noisy"] = float(np.median(biases)) if biases else np.nan
            row["noisy_sets_fitted"] = len(biases)
            rows.append(row)
    return pd.DataFrame(rows)
