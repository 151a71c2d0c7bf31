"""The paper's figures, recomputed: Fig. 1 (phi_1, phi_2 and xi against K), Fig. 3 (eps of every
DEM run collapsing on eps(K)), Fig. 4 (energy partition in time, reference and DEM) and Fig. 5
(fracture velocity against R/L_d). Fig. 2 needs the experimental data of the cited papers,
which the project does not have; it is not drawn.
"""

from __future__ import annotations

import itertools

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from reference import collision_trajectory, hertz_ratios, paper_series_value, solve_collisions  # noqa: E402
from reference.critical import PAPER_RULE_PREFACTOR  # noqa: E402
from records.files import save_figure  # noqa: E402

from analysis.energy import energy_partition  # noqa: E402


def figure_1(path, K_max: float = 1.0) -> None:
    """phi_1 and phi_2 against K: the paper's series (eq. 7, dashed) and the reference solver
    under both criteria; the paper's K = 2.5 beta^{1/2} bound; inset xi = 1 - eps^2."""
    K = np.linspace(0.0, K_max, 301)
    t = solve_collisions(K)
    fig, ax = plt.subplots(figsize=(7, 5))
    for q, color in (("Q1/Q1e", "k"), ("Q2/Q2e", "tab:blue")):
        name = "phi_1" if q == "Q1/Q1e" else "phi_2"
        ax.plot(K, np.abs(paper_series_value(q, K) - 1), "--", color=color, label=f"{name}, paper's series (eq. 7)")
        for criterion, ls in (("x0", "-"), ("F0", ":")):
            ax.plot(K, np.abs(hertz_ratios(t, criterion)[q] - 1), ls, color=color, lw=1.5,
                    label=f"{name}, reference solver, {criterion}")
    beta = np.linspace(0, 0.2, 200)
    ax.plot(PAPER_RULE_PREFACTOR * np.sqrt(beta), beta, color="tab:green", label="K = 2.5 beta^(1/2) (paper)")
    ax.axhline(0.01, color="grey", lw=0.5)
    ax.set_xlabel("K")
    ax.set_ylabel("phi_i = |Q_i - Q_ie| / Q_ie")
    ax.set_ylim(0, 0.1)
    ax.set_xlim(0, K_max)
    ax.legend(fontsize=7, loc="upper left")
    inset = fig.add_axes([0.62, 0.2, 0.25, 0.25])
    for criterion, ls in (("x0", "-"), ("F0", ":")):
        inset.plot(K, 1 - hertz_ratios(t, criterion)["eps"] ** 2, "k", ls=ls, lw=1)
    inset.plot(K, 1 - paper_series_value("eps", K) ** 2, "k--", lw=1)
    inset.set_title("xi = 1 - eps^2", fontsize=8)
    inset.tick_params(labelsize=7)
    save_figure(fig, path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def figure_3(summary: pd.DataFrame, path) -> None:
    """eps of every viscoelastic DEM run (all materials, engines, geometries) against K: the
    ladders' values extrapolated to dt -> 0 (summary rows with dt = 0; every run of a summary
    from before ladders)."""
    runs = summary[summary.law.isin(("viscoelastic", "viscoelastic_clipped"))]
    if "dt" in runs.columns and (runs.dt == 0).any():
        runs = runs[runs.dt == 0]
    K = np.linspace(0, max(0.55, runs.K.max() * 1.05), 200)
    t = solve_collisions(K)
    fig, ax = plt.subplots(figsize=(7, 5))
    for criterion, ls in (("x0", "-"), ("F0", "-.")):
        ax.plot(K, hertz_ratios(t, criterion)["eps"], "k", ls=ls, lw=1, label=f"reference solver, {criterion}")
    ax.plot(K, paper_series_value("eps", K), "k--", lw=1, label="paper's series (eq. 6)")
    # one marker per case, cycling: a study of more cases than markers (a user's own beside the
    # six shipped) failed here with a KeyError
    markers = dict(zip(sorted(runs.case.unique()), itertools.cycle("osD^vp*hX<>")))
    for (case, criterion), g in runs.groupby(["case", "criterion"]):
        ax.plot(g.K, g.eps, markers[case], mfc="none" if criterion == "x0" else None, ms=6, alpha=0.7,
                label=f"{case}, {criterion} ({len(g)} runs)")
    ax.set_xlabel("K = 1.924 (V/V_D)^(1/5)")
    ax.set_ylabel("restitution coefficient eps")
    ax.set_title(f"Every DEM ladder ({', '.join(pd.unique(runs.build)) if 'build' in runs else 'every engine'}; "
                 "both geometries), dt -> 0, on eps(K)", fontsize=9)
    ax.legend(fontsize=7)
    save_figure(fig, path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def figure_4(dumps: dict[float, tuple[dict, dict]], path) -> pd.DataFrame:
    """Kinetic, elastic and dissipated energy against time for each K of `dumps` (K -> (meta,
    columns) of one DEM run): the reference solver as lines, the DEM run as markers. Returns the
    largest deviation of the DEM partition from the reference per K."""
    fig, axes = plt.subplots(1, len(dumps), figsize=(6.5 * len(dumps), 4.5), squeeze=False)
    rows = []
    for ax, (K, (meta, cols)) in zip(axes[0], sorted(dumps.items())):
        ref = collision_trajectory(K, points_per_phase=300)
        dem = energy_partition(meta, cols)
        keep = (dem["tau"] >= -0.05) & (dem["tau"] <= ref["tau"][-1] + 0.05)
        every = max(1, keep.sum() // 60)
        for q, ls, color in (("kinetic", "-", "tab:blue"), ("elastic", "-.", "tab:orange"),
                             ("dissipated", "--", "tab:red")):
            ax.plot(ref["tau"], ref[q], ls, color=color, label=f"{q}, reference")
            ax.plot(dem["tau"][keep][::every], dem[q][keep][::every], "o", ms=3, color=color, mfc="none",
                    label=f"{q}, {meta['engine']}")
            in_contact = (dem["tau"] >= 0) & (dem["tau"] <= ref["tau"][-1])
            rows.append({"K": K, "energy": q, "engine": meta["engine"],
                         "max_abs_difference": float(np.max(np.abs(
                             dem[q][in_contact] - np.interp(dem["tau"][in_contact], ref["tau"], ref[q]))))})
        r = solve_collisions([K]).row(0)
        ax.axvline(r["tau_max"], color="grey", lw=0.5)
        ax.set_title(f"K = {K:g} ({meta['engine']}, {meta['geometry']}, dt = T_e/{meta['time_step_factor']:g}); "
                     f"lost before max. compression: {r['dissipated_at_max'] / r['dissipated_x0']:.0%}", fontsize=9)
        ax.set_xlabel("tau = t V / delta_e")
        ax.set_ylabel("fraction of (1/2) M* V^2")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    return pd.DataFrame(rows)


def figure_5(path, P0_over_E: float, markers: dict[str, float] | None = None) -> pd.DataFrame:
    """V_F / V_P against R / L_d for the three pressure definitions and both geometries."""
    # Imported here: scipy (its spline and root finder) is ~0.6 s that Figs. 1, 3 and 4 do not need.
    from .fracture import DEFINITIONS, MASS_FACTOR, fracture_velocity_ratios

    lam = np.geomspace(1e-3, 1e8, 120)
    fig, ax = plt.subplots(figsize=(7, 5))
    curves = []
    for definition, color in zip(DEFINITIONS, ("k", "tab:blue", "tab:red")):
        for geometry, ls in zip(MASS_FACTOR, ("-", "--")):
            y = fracture_velocity_ratios(lam, P0_over_E, geometry, definition)
            ax.semilogx(lam, y, ls, color=color, label=f"{definition}, {geometry}")
            curves.append(pd.DataFrame({"R/L_d": lam, "V_F/V_P": y, "definition": definition, "geometry": geometry}))
    for name, value in (markers or {}).items():
        ax.axvline(value, color="grey", lw=0.5)
        ax.text(value, ax.get_ylim()[1], f" {name}", fontsize=7, rotation=90, va="top")
    ax.axhline(1.0, color="grey", lw=0.5)
    ax.set_xlabel("R / L_d,   L_d = eta / (rho V_D)")
    ax.set_ylabel("V_F / V_P")
    ax.set_title(f"Fracture velocity, P0/E* = {P0_over_E:.4g} (ice, P0 = 130 MPa)", fontsize=9)
    ax.legend(fontsize=7)
    save_figure(fig, path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return pd.concat(curves, ignore_index=True)
