r"""The codes' tangential models against Mindlin–Deresiewicz partial slip (issue 38, "Against physics").

For one oblique case (a sphere on a plane: Chung & Ooi's test 4 by default) at a grid of incidences,
each registered model's own-equation reference (`reference.solve_oblique` with the registry's form,
the case's elastic normal law) is set beside the theory (`reference.solve_mindlin_deresiewicz`,
Thornton's incremental form of Mindlin–Deresiewicz), for the rebound spin omega', the tangential
restitution e_t and the rebound angle of the contact point. The departure of a model from the
theory at an angle is

    D_q(angle) = |q_model - q_MD| / max over the grid of |q_MD|    [-]

(the curve's own scale: e_t, omega' and the rebound angle all cross zero, where a pointwise
relative difference means nothing). The table gives, per model and quantity, the angles [deg] over
which D exceeds 1 % and 5 % (the first and the last such grid angle) and the largest D with its
angle. Models whose k_t0 is not 8 G* (a user's kt) or whose form the reference has not
(`contact_model.tangential_models.NoReference`) are left out, named.

    .venv/bin/python -m analysis.oblique_theory [cases/oblique/chung_ooi_test4.yaml] [--angles 1:85:1]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import pandas as pd

from contact_model.case_file import load_case
from contact_model.effective import effective_shear_modulus
from contact_model.tangential_models import TANGENTIAL_MODELS, NoReference, form_of
from reference import solve_oblique
from reference.mindlin_deresiewicz import solve_mindlin_deresiewicz, stiffness_ratio

DEFAULT_CASE = Path(__file__).resolve().parents[1] / "cases/oblique/chung_ooi_test4.yaml"
#: The quantities compared, as `reference.ObliqueResult` names them.
QUANTITIES = ("e_t", "omega_after", "rebound_angle")
#: The departures the table marks [-].
THRESHOLDS = (0.01, 0.05)
#: Models the comparison leaves out, and why (their k_t0 is the user's kt, not Mindlin's 8 G*).
USER_STIFFNESS = {"lammps:linear_history": "a constant k_t given by the user (not Mindlin's 8 G* a)",
                  "lammps:hertz/history": "k_t0 is the user's kt (NULL: 2 k_n/7), not Mindlin's 8 G*",
                  "esys:hertz_mindlin": "k_t0 is (16/3) G of E* (1.25 x 8 G* at nu = 0.23), not Mindlin's 8 G*, and "
                                        "it applies no torque (docs/tangential.md)"}


def plane_arguments(case, velocity: float, angle: float) -> dict:
    """`solve_oblique`'s contact arguments for the case's sphere on the plane at `angle` [deg] from the
    normal and impact speed `velocity` [m/s] (v_n = V cos angle, v_t = V sin angle, no spin).

    Parameters
    ----------
    case : contact_model.case_file.Case
        An oblique case with a sphere-plane pair.
    velocity : float
        |V| [m/s].
    angle : float
        Incidence [deg].

    Raises
    ------
    ValueError
        Naming the case file, where it has no sphere-plane pair or no friction.
    """
    pair = next((p for p in case.pairs if p.geometry == "sphere-plane"), None)
    if pair is None or case.friction is None:
        raise ValueError(f"{case.path}: the comparison needs a sphere-plane pair (`bodies:` with a plane) and "
                         f"`friction:`")
    th = math.radians(angle)
    b1 = pair.body_1
    return dict(geometry="sphere-plane", R1=b1.radius, m1=b1.mass, R2=math.inf, m2=math.inf, E_star=pair.E,
                G_star=effective_shear_modulus(b1, pair.body_2), R_star=pair.R, M_star=pair.M, mu=case.friction,
                v_n=velocity * math.cos(th), v_t=velocity * math.sin(th))


def comparable_models(geometry: str = "sphere-plane") -> tuple[list[str], dict[str, str]]:
    """The registry's models the theory is compared with, and {name: why not} for the others.

    Parameters
    ----------
    geometry : str
        The contact's geometry.
    """
    have, left_out = [], {}
    for name, model in TANGENTIAL_MODELS.items():
        if model.out_of_scope:
            left_out[name] = model.out_of_scope
            continue
        if name in USER_STIFFNESS:
            left_out[name] = USER_STIFFNESS[name]
            continue
        try:
            form_of(name, geometry)
        except (KeyError, NoReference) as err:
            left_out[name] = str(err)
            continue
        have.append(name)
    return have, left_out


def theory_curve(case, velocity: float, angles) -> pd.DataFrame:
    """The theory (`solve_mindlin_deresiewicz`) at every angle: columns angle [deg], e_t [-],
    omega_after [rad/s], rebound_angle [deg], vt_after [m/s], psi1, psi2 [-], slides_throughout.

    Parameters
    ----------
    case : contact_model.case_file.Case
        The oblique case (its sphere on the plane).
    velocity : float
        |V| [m/s].
    angles : iterable of float
        Incidences [deg].
    """
    rows = []
    for angle in angles:
        r = solve_mindlin_deresiewicz(**plane_arguments(case, velocity, angle))
        rows.append(dict(angle=float(angle), e_t=r.e_t, omega_after=r.omega_after, rebound_angle=r.rebound_angle,
                         vt_after=r.vt_after, psi1=r.psi1, psi2=r.psi2,
                         slides_throughout=[p[0] for p in r.phases] == ["slide"]))
    return pd.DataFrame(rows)


def model_curve(case, model: str, velocity: float, angles) -> pd.DataFrame:
    """A model's own-equation reference (`solve_oblique`, elastic normal law) at every angle, the
    columns of `theory_curve` (without psi).

    Parameters
    ----------
    case : contact_model.case_file.Case
        The oblique case.
    model : str
        A registry name (``lammps:mindlin``).
    velocity : float
        |V| [m/s].
    angles : iterable of float
        Incidences [deg].
    """
    form = form_of(model, "sphere-plane")
    rows = []
    for angle in angles:
        r = solve_oblique(**plane_arguments(case, velocity, angle), eta=0.0, clipped=False, form=form)
        rows.append(dict(angle=float(angle), e_t=r.e_t, omega_after=r.omega_after, rebound_angle=r.rebound_angle,
                         vt_after=r.vt_after))
    return pd.DataFrame(rows)


def departures(theory: pd.DataFrame, model: pd.DataFrame, thresholds=THRESHOLDS) -> dict:
    """Where and by how much a model's curve departs from the theory's (module docstring).

    Parameters
    ----------
    theory, model : DataFrame
        `theory_curve` and `model_curve` on the same angles.
    thresholds : sequence of float
        The departures [-] whose angle ranges are reported.

    Returns
    -------
    dict
        For each quantity q: ``D_<q>`` (array), ``max_<q>`` [-] and ``at_<q>`` [deg], and for each
        threshold x ``over_<x>_<q>``: (first, last) angle [deg] where D > x, or None.
    """
    out = {}
    angles = theory.angle.to_numpy()
    for q in QUANTITIES:
        scale = float(np.max(np.abs(theory[q])))
        D = np.abs(model[q].to_numpy() - theory[q].to_numpy()) / scale
        k = int(np.argmax(D))
        out[f"D_{q}"], out[f"max_{q}"], out[f"at_{q}"] = D, float(D[k]), float(angles[k])
        for x in thresholds:
            over = angles[D > x]
            out[f"over_{x:g}_{q}"] = (float(over[0]), float(over[-1])) if len(over) else None
    return out


def comparison_table(case, velocity: float, angles, models=None, curves=None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The table of departures (one row per model and quantity) and the theory's curve.

    Parameters
    ----------
    case : contact_model.case_file.Case
        The oblique case.
    velocity : float
        |V| [m/s].
    angles : sequence of float
        Incidences [deg].
    models : sequence of str, optional
        Registry names; default `comparable_models`.
    curves : dict, optional
        Filled with {model: its `model_curve`} (for a figure).
    """
    angles = list(angles)
    theory = theory_curve(case, velocity, angles)
    rows = []
    for name in models or comparable_models()[0]:
        curve = model_curve(case, name, velocity, angles)
        if curves is not None:
            curves[name] = curve
        d = departures(theory, curve)
        for q in QUANTITIES:
            def span(x, q=q):
                r = d[f"over_{x:g}_{q}"]
                return "never" if r is None else f"{r[0]:g}-{r[1]:g}"
            rows.append({"model": name, "quantity": q, "D > 1 % [deg]": span(0.01), "D > 5 % [deg]": span(0.05),
                         "largest D": f"{d[f'max_{q}']:.3g}", "at [deg]": f"{d[f'at_{q}']:g}"})
    return pd.DataFrame(rows), theory


def draw_psi(theory: pd.DataFrame, curves: dict, case, velocity: float, path) -> None:
    """Maw, Barber & Fawcett's plane, as Chung & Ooi plot it: Psi_2 against Psi_1 for the theory and
    every model, with the rigid-body line Psi_2 = (Psi_1 - kappa (1 + eps) M*/m_t)/eps (eps = 1,
    M*/m_t = 7/2 for a solid sphere on a plane). Written to `path` (PNG).

    Parameters
    ----------
    theory : DataFrame
        `theory_curve`.
    curves : dict
        {model: `model_curve`} on the same angles.
    case : contact_model.case_file.Case
        The case (its moduli and friction give kappa and mu).
    velocity : float
        |V| [m/s].
    path : str or os.PathLike
        The PNG file.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from records.files import save_figure

    a = plane_arguments(case, velocity, 0.0)
    kappa, mu = stiffness_ratio(a["E_star"], a["G_star"]), case.friction
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for k, (name, curve) in enumerate(curves.items()):
        th = np.radians(curve.angle)
        psi1 = kappa * np.tan(th) / mu
        v_n = velocity * np.cos(th)
        psi2 = kappa * curve.e_t * velocity * np.sin(th) / (mu * v_n)  # eps = 1: v_n' = v_n
        ax.plot(psi1, psi2, "-", lw=0.9, color=f"C{k}", label=name)
    ax.plot(theory.psi1, theory.psi2, "k:", lw=1.8, label="Mindlin-Deresiewicz partial slip")
    x = np.linspace(0.0, float(theory.psi1.max()), 50)
    ax.plot(x, x - kappa * 2.0 * 3.5, "k--", lw=1.0, label="rigid body, gross sliding")
    ax.set_xlim(0.0, min(12.0, float(theory.psi1.max())))
    ax.set_ylim(-4.0, 6.0)
    ax.set_xlabel("Psi_1 = kappa v_s / (mu v_n)")
    ax.set_ylabel("Psi_2 = kappa v_s' / (mu v_n')")
    ax.set_title(f"{case.name}: kappa = 4G*/E* = {kappa:.4f}, mu = {mu:g}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, Path(path), dpi=110)
    plt.close(fig)


def _angles(text: str) -> list[float]:
    """'1:85:1' -> [1, 2, ..., 85] (start:stop:step, stop included), or a comma list."""
    if ":" in text:
        start, stop, step = (float(x) for x in text.split(":"))
        return [float(x) for x in np.arange(start, stop + step / 2, step)]
    return [float(x) for x in text.split(",")]


def main(argv=None) -> int:
    """Print the table of departures (markdown) for a case; module docstring.

    Parameters
    ----------
    argv : list of str, optional
        The command line after the program name (None: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0.
    """
    parser = argparse.ArgumentParser(prog="python -m analysis.oblique_theory", description=__doc__.split("\n\n")[0])
    parser.add_argument("case", nargs="?", default=str(DEFAULT_CASE), help="an oblique case file with a plane")
    parser.add_argument("--angles", default="1:85:1", help="start:stop:step or a comma list [deg] (default 1:85:1)")
    parser.add_argument("--velocity", type=float, default=None, help="|V| [m/s] (default: the case's first)")
    parser.add_argument("--psi-figure", default=None, help="also draw Psi_2 against Psi_1 into this PNG file")
    args = parser.parse_args(argv)
    case = load_case(args.case)
    velocity = args.velocity if args.velocity is not None else case.velocities[0]
    curves = {}
    table, theory = comparison_table(case, velocity, _angles(args.angles), curves=curves)
    if args.psi_figure:
        draw_psi(theory, curves, case, velocity, args.psi_figure)
    _, left_out = comparable_models()
    print(f"{case.name}: |V| = {velocity:g} m/s, mu = {case.friction:g}; D = |q_model - q_MD| / max|q_MD| over "
          f"{len(theory)} angles {theory.angle.min():g}-{theory.angle.max():g} deg\n")
    print("| " + " | ".join(table.columns) + " |")
    print("|" + "---|" * len(table.columns))
    for row in table.itertuples(index=False):
        print("| " + " | ".join(str(v) for v in row) + " |")
    args_ = plane_arguments(case, velocity, 0.0)
    onset = math.degrees(math.atan(case.friction / stiffness_ratio(args_["E_star"], args_["G_star"])))
    gross = theory[theory.slides_throughout]
    print(f"\nThe theory slides from touching (Psi_1 >= 1) above {onset:.3f} deg, throughout from "
          f"{gross.angle.min():g} deg on this grid" if len(gross) else f"\nPsi_1 = 1 at {onset:.3f} deg")
    print("\nleft out: " + "; ".join(f"{k} ({v})" for k, v in left_out.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())


def case_file_of(name: str, folder=None) -> Path | None:
    """The case file ``<name>.yaml`` under cases/ (searched below it), or None.

    Parameters
    ----------
    name : str
        The case's name (a summary row's ``case``).
    folder : str or os.PathLike, optional
        Where to look; default the project's cases/.
    """
    folder = Path(folder) if folder is not None else DEFAULT_CASE.parents[1]
    return next(iter(sorted(folder.rglob(f"{name}.yaml"))), None)


def theory_for_rows(rows: pd.DataFrame, step: float = 1.0) -> pd.DataFrame | None:
    """The theory's curve for the limit rows of one case on the plane (report figures): the case file
    found by name, the impact speed of the rows, angles from their smallest to their largest in
    `step` degrees. None where it does not apply: not a plane, a law other than the elastic one (the
    theory is elastic), a spin, or no case file of that name.

    Parameters
    ----------
    rows : DataFrame
        Limit rows of one case (columns case, geometry, law, spin, angle, normal_velocity,
        tangential_velocity).
    step : float
        The grid's step [deg].
    """
    if not len(rows) or set(rows.geometry) != {"sphere-plane"} or set(rows.get("law", ["elastic"])) != {"elastic"}:
        return None
    if (rows.spin != 0).any():
        return None
    path = case_file_of(str(rows.case.iloc[0]))
    if path is None:
        return None
    case = load_case(path)
    velocity = float(np.hypot(rows.normal_velocity.iloc[0], rows.tangential_velocity.iloc[0]))
    lo, hi = float(rows.angle.min()), float(rows.angle.max())
    lo = min(lo, 1.0)  # from near normal incidence, where the theory and the codes part
    return theory_curve(case, velocity, np.arange(lo, hi + step / 2, step))
