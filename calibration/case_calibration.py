r"""Calibrating one case: its measurements and bodies in, everything a DEM user needs out.

For each criterion (x0, F0) the exact fit (`calibration.fit`) gives V_D and eta with their 95 %
interval; from the bodies of the case (E*, R*, M*) and the fitted eta follow

- the K range the data cover, K_i = alpha (V_i / V_D)^{1/5};
- xi = 1 - eps^2 at the highest speed (the model's, at the best fit);
- V_c(1 %) and V_c(5 %) (`ContactPair.critical_velocity`, the critical K of the solver);
- the parameters of every engine code that can run the viscoelastic law (`engines.codes.CODES`);
- eta when E* is scaled by the given factors: at fixed V_D, eta = eta_0 (E*/E*_0)^{3/5}.

Beside it, the paper's method: the same data fitted with the paper's second-order series
eps = 1 - 1.0089 K + 0.6107 K^2 (on its falling branch, K < 0.826), and the bias this causes in
eta against the exact x0 fit.

And checks of the model on the data:

- ``restitution_trend``: a straight line through the measured eps against ln V. The viscoelastic
  model's eps falls monotonically with V (K grows as V^{1/5}); where the data's slope is positive
  at one-sided p < RISING_P (Student's t, n - 2 degrees of freedom, the scale from the stated
  uncertainties widened by the scatter, or from the scatter alone), the data contradict the model:
  ``warnings`` says so, and the eta of the fit is flagged as not to be used.
- ``residual_trend``: a straight line through the x0 residuals against ln V; its slope is 0 (within
  its standard error) when the model's V-dependence is the data's.
- ``constant_loss``: the exact model with a velocity-independent loss added,
  eps^2 = (1 - xi_0) eps_x0(K)^2, fitted for (k, xi_0), and the F-test of xi_0 = 0 against it
  (the viscoelastic model has no loss at vanishing speed: eps -> 1 as V -> 0).
- ``gugan_form``: Gugan's own fit xi = 1 - eps^2 = K_0 + K_1 U^{0.4} (U in m/s), for comparison
  with his K_0 ~ 0.2.
- ``case_viscosity``: eps that the case file's viscosity (for the Jaques ball, the paper's
  Table 1 value) predicts at the measured velocities.

Everything here is pure: a `Case` in, a JSON-ready dict out.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from contact_model import ContactPair
from contact_model.case_file import Case
from contact_model.quantities import POISE, in_unit
from engines.codes import CODES
from reference.restitution_closed_forms import paper_series

from contact_model.measurement_file import MIN_ROWS, MIN_VELOCITIES, distinct_velocities

from .fit import (CRITERIA, K_MAX, CalibrationError, Fit, exact_restitution, f_survival, falling_range,
                  fit_restitution, student_t_survival)

#: The codes whose parameters of the calibrated contact are reported: those that run the
#: viscoelastic law (engines.codes; ESyS clips it, Kratos cannot express it).
ENGINES = tuple(name for name, c in CODES.items() if "viscoelastic" not in c.unavailable)
BETAS = (0.01, 0.05)
#: One-sided p value below which a rise of the measured eps with V counts as significant: the
#: viscoelastic model cannot produce it (its eps falls with V), and the calibration warns.
RISING_P = 0.01


def calibrated_pair(pair: ContactPair, eta: float) -> ContactPair:
    """The same bodies with viscosity eta [Pa s]."""
    return ContactPair(pair.geometry, pair.body_1, pair.body_2, pair.E, eta)


def linear_fit(x, y) -> dict:
    """y = a + b x by least squares: a, b, their standard errors and the rms residual."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    A = np.column_stack([np.ones_like(x), x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    dof = len(y) - 2
    s2 = float(resid @ resid) / dof if dof > 0 else math.nan
    cov = s2 * np.linalg.inv(A.T @ A)
    return {"a": float(coef[0]), "b": float(coef[1]), "a_se": float(math.sqrt(cov[0, 0])),
            "b_se": float(math.sqrt(cov[1, 1])), "rms": float(math.sqrt(np.mean(resid**2))), "dof": dof}


def restitution_trend(velocity, restitution, sigma=None) -> dict:
    """A straight line eps = a + b ln V through the measured restitution, and whether it rises.

    Parameters
    ----------
    velocity : impact velocities V [m/s], at least 2 distinct and 3 in all.
    restitution : measured eps [-].
    sigma : standard uncertainty of each eps [-], or None (the scatter gives the scale).

    Returns
    -------
    dict
        b (the slope d eps / d ln V [-]) and its standard error b_se, t = b / b_se, dof = n - 2,
        p_rising (one-sided p value of b > 0, Student's t with dof), rising (p_rising < RISING_P).
        The standard error comes from the stated sigma widened by the line's scatter where it is
        larger (chi2_red > 1), or from the scatter alone without sigma: a rise is claimed only
        where the data carry it.
    """
    x = np.log(np.asarray(velocity, dtype=float))
    y = np.asarray(restitution, dtype=float)
    w = np.ones(len(x)) if sigma is None else 1.0 / np.asarray(sigma, dtype=float)
    A = np.column_stack([np.ones_like(x), x]) * w[:, None]
    dof = len(y) - 2
    if dof < 1 or np.ptp(x) == 0:
        raise ValueError(f"a trend needs {MIN_ROWS} rows at {MIN_VELOCITIES} distinct velocities, got {len(y)} rows "
                         f"at {len(set(x.tolist()))}")
    coef, *_ = np.linalg.lstsq(A, y * w, rcond=None)
    resid = y * w - A @ coef
    chi2_red = float(resid @ resid) / dof
    scale = chi2_red if sigma is None else max(1.0, chi2_red)
    b_se = float(math.sqrt(scale * np.linalg.inv(A.T @ A)[1, 1]))
    b = float(coef[1])
    t = b / b_se if b_se > 0 else (math.inf if b > 0 else -math.inf if b < 0 else 0.0)
    p = float(student_t_survival(t, dof))
    return {"b": b, "b_se": b_se, "t_statistic": t, "dof": dof, "p_rising": p, "rising": bool(p < RISING_P),
            "p_limit": RISING_P}


def constant_loss_test(velocity, restitution, sigma, fit: Fit) -> dict:
    """Fit eps = (1 - xi_0)^{1/2} eps_x0(k (V/V_max)^{1/5}) for (k, xi_0) and F-test xi_0 = 0.

    F = (S_1 - S_2) / (S_2 / (n - 2)), S_1 the one-parameter fit's sum of squares, S_2 this one's;
    p from F(1, n - 2). Returns xi_0 (with its standard error from the Jacobian), k, F, p."""
    V = np.asarray(velocity, dtype=float)
    eps = np.asarray(restitution, dtype=float)
    if len(V) < MIN_ROWS:
        raise ValueError(f"the constant-loss test fits 2 parameters: it needs {MIN_ROWS} rows, got {len(V)}")
    w = np.ones(len(V)) if sigma is None else 1.0 / np.asarray(sigma, dtype=float)
    x = (V / V.max()) ** 0.2
    model = exact_restitution("x0")

    def residuals(p):
        return (eps - np.sqrt(1.0 - p[1]) * model(p[0] * x)) * w

    res = optimize.least_squares(residuals, [fit.k, 0.0], bounds=([0.0, -1.0], [K_MAX, 0.999]), method="trf",
                                 xtol=1e-12)
    S2 = float(res.fun @ res.fun)
    dof = len(V) - 2
    F = (fit.chi2 - S2) / (S2 / dof) if S2 > 0 else math.inf
    J = res.jac
    s2 = S2 / dof if sigma is None else 1.0
    cov = s2 * np.linalg.pinv(J.T @ J)
    return {"xi_0": float(res.x[1]), "xi_0_se": float(math.sqrt(cov[1, 1])), "k": float(res.x[0]),
            "rms_residual": float(np.sqrt(np.mean((res.fun / w) ** 2))), "F": float(F),
            "p_value": float(f_survival(F, 1, dof))}


def _fit_summary(fit: Fit, pair: ContactPair, modulus_factors) -> dict:
    eta, eta_low, eta_high = fit.viscosity(pair.E, pair.R, pair.M)
    tuned = calibrated_pair(pair, eta)
    V_D_low, V_D_high = fit.V_D_interval
    out = {
        "model": fit.model, "criterion": fit.criterion, "n": fit.n, "level": fit.level,
        "V_ref": fit.V_ref, "K_at_V_ref": fit.k, "K_at_V_ref_interval": [fit.k_low, fit.k_high],
        "interval_open": {"low": bool(fit.low_open), "high": bool(fit.high_open)},
        "V_D": fit.V_D, "V_D_interval": [V_D_low, V_D_high],
        "eta_Pa_s": eta, "eta_interval_Pa_s": [eta_low, eta_high],
        "eta_P": eta / POISE, "eta_interval_P": [eta_low / POISE, eta_high / POISE],
        "K_range": [float(fit.K.min()), float(fit.K.max())],
        "chi2": fit.chi2, "chi2_red": fit.chi2_red, "sigma_given": fit.sigma_given, "widened": bool(fit.widened),
        "sigma": float(fit.sigma[0]) if not fit.sigma_given else None,
        "rms_residual": float(np.sqrt(np.mean(fit.residuals**2))),
        "xi_at_V_max": float(1.0 - fit.eps_fit[np.argmax(fit.K)] ** 2),
    }
    if fit.model == "exact":
        out["V_c"] = {f"{b:g}": tuned.critical_velocity(b, fit.criterion) for b in BETAS}
        out["engine_parameters"] = {e: CODES[e].contact_parameters(tuned) for e in ENGINES}
        out["modulus_sensitivity"] = [
            {"factor": f, "E_Pa": f * pair.E, "eta_Pa_s": fit.viscosity(f * pair.E, pair.R, pair.M)[0],
             "eta_ratio": f**0.6} for f in modulus_factors]
    return out


def case_fits(case: Case) -> dict[str, Fit]:
    """The fits of `case`'s measurements by name: the exact model under 'x0' and 'F0', and the
    paper's series ('series', on its falling branch). What `calibrate` summarises; alone, for
    the plot of the DEM loop, which needs no summary."""
    m = case.measurements
    if m is None:
        raise ValueError(f"{case.path}: the case has no measurements")
    fits = {c: fit_restitution(m.velocity, m.restitution, m.uncertainty, criterion=c, source=m.path)
            for c in CRITERIA}
    fits["series"] = fit_restitution(m.velocity, m.restitution, m.uncertainty, criterion="x0", model=paper_series,
                                     model_name="paper_series", K_max=falling_range(paper_series), source=m.path)
    return fits


def calibrate(case: Case, modulus_factors=(0.8, 1.25)) -> tuple[dict, dict[str, Fit]]:
    """Calibrate the viscosity of `case` on its measurements (see the module docstring).

    Returns (summary, fits): a JSON-ready summary and the `Fit`s by name ('x0', 'F0', 'series').
    ``summary["warnings"]`` lists what makes its eta unfit to use (the data contradict the model).
    Raises `CalibrationError` (a `CaseError`) when the data cannot be fitted: fewer than MIN_ROWS
    rows or MIN_VELOCITIES distinct velocities (the loader refuses them first), or a best fit at
    K = 0 or K_max."""
    m = case.measurements
    if m is None:
        raise ValueError(f"{case.path}: the case has no measurements")
    if len(m) < MIN_ROWS or distinct_velocities(m.velocity) < MIN_VELOCITIES:
        raise CalibrationError(m.path, "(file)", f"has {len(m)} rows at {distinct_velocities(m.velocity)} distinct "
                                                 f"velocities; the calibration needs at least {MIN_ROWS} rows at "
                                                 f"{MIN_VELOCITIES} or more velocities (1 parameter for eta, 2 for "
                                                 "its model checks, each with a degree of freedom for the scatter)")
    pair = case.pairs[0]
    fits = case_fits(case)
    summary = {
        "case": case.name, "case_file": case.path, "measurements": m.path, "provenance": m.provenance,
        "geometry": pair.geometry, "E_Pa": pair.E, "R_m": pair.R, "M_kg": pair.M,
        "eta_case_Pa_s": pair.eta, "velocity_range": [float(m.velocity.min()), float(m.velocity.max())],
        "fits": {name: _fit_summary(f, pair, modulus_factors) for name, f in fits.items()},
    }
    # eta also in the unit the case file writes its viscosity in (what the user reads and edits).
    summary["viscosity_unit"] = case.viscosity_unit
    per_Pa_s = in_unit(1.0, "Pa*s", case.viscosity_unit)  # viscosity units are linear: one factor
    for f in summary["fits"].values():
        f["eta_case_unit"] = f["eta_Pa_s"] * per_Pa_s
        f["eta_interval_case_unit"] = [e * per_Pa_s for e in f["eta_interval_Pa_s"]]
    exact = summary["fits"]["x0"]["eta_Pa_s"]
    summary["series_bias"] = summary["fits"]["series"]["eta_Pa_s"] / exact - 1.0
    summary["constant_loss"] = constant_loss_test(m.velocity, m.restitution, m.uncertainty, fits["x0"])
    summary["gugan_form"] = linear_fit(m.velocity**0.4, 1.0 - m.restitution**2)
    K_case = np.array([pair.dissipation_parameter(v) for v in m.velocity])
    summary["case_viscosity"] = {"eta_P": pair.eta / POISE, "eta_ratio_fit_to_case": summary["fits"]["x0"]["eta_Pa_s"]
                                 / pair.eta if pair.eta > 0 else math.nan,
                                 "K": K_case.tolist(), "eps_x0": exact_restitution("x0")(K_case).tolist()}
    # Residual trend: a straight line in ln V through the x0 residuals (0 slope if the model fits).
    r = fits["x0"].residuals
    trend = linear_fit(np.log(m.velocity), r)
    summary["residual_trend"] = {**trend, "t_statistic": trend["b"] / trend["b_se"] if trend["b_se"] > 0 else math.nan}
    rise = summary["restitution_trend"] = restitution_trend(m.velocity, m.restitution, m.uncertainty)
    summary["warnings"] = []
    if rise["rising"]:
        summary["warnings"].append(
            f"the measured eps rises with the impact velocity (slope {rise['b']:+.3g} ± {rise['b_se']:.2g} per unit "
            f"of ln V, t = {rise['t_statistic']:.1f}, one-sided p = {rise['p_rising']:.2g} < {RISING_P:g}), which the "
            "viscoelastic model cannot produce: its eps falls monotonically with V. The fitted eta is the "
            "least-squares compromise of a model that does not describe these data, not a property of the contact: "
            "do not use it. Check the data (velocity and rebound swapped? another loss at low speed, adhesion or "
            "plasticity?)")
    return summary, fits
