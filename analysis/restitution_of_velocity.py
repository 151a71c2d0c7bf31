r"""Which damping form can follow a measured restitution eps(V)? Each fitted to the measurements.

The engines' keywords come in three damping forms (`contact_model.laws`), and each ties the
restitution to the impact velocity V its own way, whatever its one coefficient:

- ``half`` (the viscoelastic law: LAMMPS ``damping viscoelastic``, LIGGGHTS ``hertz/stiffness``
  with ``gamman``, ESyS ``HertzianViscoElastic``; the study's law): K = K_1 (V / 1 m/s)^{1/5},
  eps = eps(K) of x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0 (`reference.solve_collisions`): eps falls
  with V;
- ``quarter`` (every restitution keyword: LIGGGHTS ``coefficientRestitution``, LAMMPS ``tsuji``
  and ``coeff_restitution``, YADE ``en``/``betan``, Kratos, ESyS ``HertzMindlinVisco``): eps is
  the same at every V;
- ``velocity`` (LAMMPS ``damping velocity`` and ``mass_velocity`` at a fixed eta_n):
  c = c_1 (V / 1 m/s)^{-1/5}, eps = eps(c) of x'' + c x' + (5/4) x^{3/2} = 0
  (`reference.linear_damping`): eps rises with V.

`fit_forms` fits each form's one coefficient to measured (V, eps) by least squares and says how
much of the measurements' variation about their mean it explains (R^2 = 1 - SS_res / SS_tot). A
form *follows* the measurements when R^2 >= FOLLOWS_R2 and its fitted eps changes between the
smallest and the largest V with the measured sign.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import minimize_scalar

from records.files import save_figure

#: The share of the measured variation a form must explain to be said to follow eps(V).
FOLLOWS_R2 = 0.9
#: The legend's name of each form.
FORM_LABEL = {"half": "δ^½ δ' (viscoelastic law)", "quarter": "δ^¼ δ' (restitution keywords)",
              "velocity": "δ' (LAMMPS velocity, mass_velocity)"}
#: (form, criterion, its coefficient's name, the keywords of that form) of each fitted curve.
FORMS = (
    ("half", "F0", "K at 1 m/s", "viscoelastic law (LAMMPS viscoelastic, LIGGGHTS hertz/stiffness, ESyS "
                                 "HertzianViscoElastic), clipped"),
    ("half", "x0", "K at 1 m/s", "viscoelastic law, the tail kept"),
    ("quarter", "any", "e", "every restitution keyword (LIGGGHTS, LAMMPS tsuji / coeff_restitution, YADE en / "
                            "betan, Kratos, ESyS HertzMindlinVisco)"),
    ("velocity", "x0", "c at 1 m/s", "LAMMPS damping velocity / mass_velocity (the tail kept)"),
)


def form_restitution(form: str, criterion: str, coefficient: float, V: np.ndarray) -> np.ndarray:
    """eps at impact velocities V [m/s] of damping `form` with its coefficient at 1 m/s.

    Parameters
    ----------
    form : str
        The damping form: 'half', 'quarter' or 'velocity'.
    criterion : str
        The end of contact, 'x0' or 'F0' (ignored for 'quarter').
    coefficient : float
        The form's coefficient at 1 m/s: K [-] ('half'), e [-] ('quarter'), c [-] ('velocity').
    V : array_like
        Impact velocities [m/s].
    """
    from contact_model.damping_forms import damping_form

    if form == "quarter":  # its eps is its one coefficient (e), at every velocity
        return np.full_like(np.asarray(V, dtype=float), coefficient)
    return damping_form(form).restitution_at(coefficient, criterion, V)


def fit_forms(V, eps) -> pd.DataFrame:
    """Each form of FORMS fitted to the measurements (V [m/s], eps): one row each with its
    coefficient, rms and largest residual, R^2, its eps at the smallest and largest V, and
    whether it follows the measurements (`FOLLOWS_R2`, the trend's sign).

    Parameters
    ----------
    V : array_like
        The measured impact velocities [m/s].
    eps : array_like
        The measured restitution at each V [-].
    """
    V, eps = np.asarray(V, dtype=float), np.asarray(eps, dtype=float)
    total = float(np.sum((eps - eps.mean()) ** 2))
    trend = np.sign(eps[np.argmax(V)] - eps[np.argmin(V)])
    rows = []
    for form, criterion, name, keywords in FORMS:
        if form == "quarter":
            best = float(eps.mean())
        else:
            cost = lambda lp: float(np.sum((form_restitution(form, criterion, np.exp(lp), V) - eps) ** 2))  # noqa: E731
            best = float(np.exp(minimize_scalar(cost, bounds=(np.log(1e-4), np.log(3.0)), method="bounded",
                                                options={"xatol": 1e-9}).x))
        fitted = form_restitution(form, criterion, best, V)
        residual = fitted - eps
        r2 = 1.0 - float(np.sum(residual**2)) / total if total > 0 else float("nan")
        ends = form_restitution(form, criterion, best, np.array([V.min(), V.max()]))
        follows = bool(r2 >= FOLLOWS_R2 and np.sign(ends[1] - ends[0]) == trend)
        rows.append({"form": form, "criterion": criterion, "keywords": keywords, "coefficient": name,
                     "value": best, "rms_residual": float(np.sqrt(np.mean(residual**2))),
                     "max_abs_residual": float(np.abs(residual).max()), "R2": r2,
                     "eps_at_V_min": float(ends[0]), "eps_at_V_max": float(ends[1]), "follows": follows})
    return pd.DataFrame(rows)


def plot_forms(V, eps, fits: pd.DataFrame, path, title: str) -> None:
    """The measurements and each fitted form's eps(V) on one figure.

    Parameters
    ----------
    V : array_like
        The measured impact velocities [m/s].
    eps : array_like
        The measured restitution at each V [-].
    fits : DataFrame
        `fit_forms`' table: columns form, criterion, value, R2.
    path : str or path-like
        Where the figure is saved (`records.files.save_figure`).
    title : str
        The figure's title.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    V = np.asarray(V, dtype=float)
    grid = np.geomspace(V.min() * 0.8, V.max() * 1.25, 60)
    fig, ax = plt.subplots(figsize=(9, 5))
    ax.plot(V, eps, "ko", label="measured")
    styles = ("-", "--", ":", "-.")
    for k, r in enumerate(fits.itertuples()):
        ax.plot(grid, form_restitution(r.form, r.criterion if r.form != "quarter" else "x0", r.value, grid),
                styles[k % len(styles)], label=f"{FORM_LABEL[r.form]}, {r.criterion}: R² = {r.R2:.2f}")
    ax.set_xscale("log")
    ax.set_xlabel("impact velocity V [m/s]")
    ax.set_ylabel("restitution eps")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
