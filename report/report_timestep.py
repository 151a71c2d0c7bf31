"""The reports' time-step figures, from the advisor's maps (`analysis.timestep_maps`, computed by
the workflow's scripts and handed in):

- each case report: its laws' errors against dt / T_R (0.02-0.5), the band over the contact's start
  phases shaded, with the lines of 1e-2, 1e-3 and 1e-4 (`case_error_maps`);
- the study's report: the largest dt / T_R that holds 1e-2, 1e-3 and 1e-4 at every phase, for the
  viscoelastic law over K and for each code's restitution keyword over e (`plot_largest_steps`, of
  `analysis.timestep_maps.largest_steps`).
"""

from __future__ import annotations

import pandas as pd

from records.files import save_figure

from analysis.timestep_maps import FRACTIONS, SHOWN, TOLERANCES  # noqa: F401  (the figures' steps and lines)


def plot_error_maps(bands: pd.DataFrame, path) -> None:
    """|error| against dt / T_R, one panel per geometry and quantity, one band per law."""
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .panels import subplots

    geometries = list(dict.fromkeys(bands.geometry))
    fig, axes = subplots(len(geometries), len(SHOWN), figsize=(4.2 * len(SHOWN), 3.4 * len(geometries)),
                         squeeze=False, sharex=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    laws = list(dict.fromkeys(bands.law))
    for i, g in enumerate(geometries):
        for j, q in enumerate(SHOWN):
            ax = axes[i][j]
            for k, law in enumerate(laws):
                s = bands[(bands.geometry == g) & (bands.quantity == q) & (bands.law == law)]
                if not len(s):
                    continue
                colour = colours[k % len(colours)]
                ax.fill_between(s.dt_over_T_R, s.abs_err_min.clip(lower=1e-9), s.abs_err_max.clip(lower=1e-9),
                                color=colour, alpha=0.25, lw=0)
                ax.plot(s.dt_over_T_R, s.abs_err_max.clip(lower=1e-9), color=colour, lw=1,
                        label=law if (i, j) == (0, 0) else None)
            for tol in TOLERANCES:
                ax.axhline(tol, color="k", lw=0.6, ls=":")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xticks([0.02, 0.05, 0.1, 0.2, 0.5], ["0.02", "0.05", "0.1", "0.2", "0.5"])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_title(f"{g}: {q}", fontsize=9)
            ax.grid(alpha=0.3, which="both")
            if i == len(geometries) - 1:
                ax.set_xlabel("dt / T_R")
            if j == 0:
                ax.set_ylabel("|relative error|")
    fig.legend(loc="lower center", ncol=min(len(laws), 5), fontsize=8)
    # Margins in inches, not tight_layout: it measures every tick label of the log axes, about a
    # quarter of a case report's seconds. Room below for the legend's rows of five laws.
    width, height = fig.get_size_inches()
    legend = 0.3 + 0.22 * (1 + (len(laws) - 1) // 5)
    fig.subplots_adjust(left=0.75 / width, right=1 - 0.15 / width, top=1 - 0.3 / height,
                        bottom=(legend + 0.45) / height, wspace=0.28, hspace=0.3)
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def plot_largest_steps(table: pd.DataFrame, path) -> None:
    """The largest dt / T_R for each tolerance: over K (viscoelastic) and over e (the keywords)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .panels import subplots

    fig, (left, right) = subplots(1, 2, figsize=(11, 4.2), sharey=True)
    styles = {1e-2: "-", 1e-3: "--", 1e-4: ":"}
    v = table[table.law == "viscoelastic"]
    for tol, s in v.groupby("tolerance"):
        left.plot(s.K, s.dt_max_over_T_R, "ko" + styles.get(tol, "-"), mfc="none", label=f"{tol:g}")
    left.set_xlabel("K (the viscoelastic law)")
    left.set_ylabel("largest dt / T_R (T, A, eps at every phase)")
    left.legend(title="tolerance", fontsize=8)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (law, g) in enumerate(table[table.law != "viscoelastic"].groupby("law", sort=False)):
        for tol, s in g.groupby("tolerance"):
            right.plot(s.e, s.dt_max_over_T_R, marker="o", mfc="none", ls=styles.get(tol, "-"),
                       color=colours[k % len(colours)], label=law if tol == TOLERANCES[0] else None)
    right.set_xlabel("e told (each code's restitution keyword)")
    right.legend(fontsize=7)
    for ax in (left, right):
        ax.set_yscale("log")
        ax.grid(alpha=0.3, which="both")
    fig.suptitle("The largest time step that holds each tolerance (solid 1e-2, dashed 1e-3, dotted 1e-4)",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def case_error_maps(plan: dict, bands: pd.DataFrame, path) -> tuple[pd.DataFrame, list[str]]:
    """The case report's time-step section: the errors of the plan's laws mapped over dt / T_R
    (`bands`, from `analysis.timestep_maps.case_error_bands`) drawn into `path`; (the bands, the
    section's Markdown lines)."""
    if bands.empty:
        return pd.DataFrame(), []
    plot_error_maps(bands, path)
    lines = ["## How wrong at the step you run?", "",
             "Each law's relative error against the time step in units of the Rayleigh time T_R, on the engines' "
             "discrete map (every build follows it to 1e-12 at these steps: docs/timestep.md), at the velocity of "
             "K nearest 0.1; the band spans 12 phases of the contact's start within a step, the line is its worst "
             "(laws that run one equation share a band); "
             "dotted: 1e-2, 1e-3, 1e-4. For your own step and tolerance: `python -m postprocess.timestep "
             f"{plan['file']} --law <law> --dt 0.2T_R`.", "", "![time steps](plots/timestep.png)", ""]
    return bands, lines
