"""What the report says of the study's resolution: the sentence beside the verdict, the ladder
settings, and the figure of every gated ladder.

Every number comes from checks.csv (the checks' resolutions) and summary.csv (the rungs and the
ladders' limits), so that a reader can redo it from those two tables.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from records.files import save_figure, set_margins  # noqa: E402

from verdict.gate import GATED_QUANTITIES  # noqa: E402
from .panels import subplots  # noqa: E402


def resolution_sentence(checks: pd.DataFrame, tolerance: dict) -> str:
    """One sentence: the tolerance the gate resolves, the range of the checks' resolutions, and
    the smallest engine error the study can see (the largest resolution of any check) and the
    error that fails for certain (tolerance + that resolution). Checks whose ladders could not
    be judged (a failed run, a misaligned ladder: their own estimate means nothing) are left out
    and counted. '' without resolutions."""
    if not len(checks) or "resolution" not in checks.columns:
        return ""
    judged = (checks.failed == 0) & ~checks.reason.fillna("").str.contains("misaligned ladder", regex=False)
    unjudged = int((~judged).sum())
    checks = checks[judged]
    res = checks.resolution.to_numpy(dtype=float)
    res = res[np.isfinite(res)]
    if not len(res):
        return ""
    per_q = checks.groupby("quantity").resolution.max()
    tolerances = sorted({float(tolerance[q]) for q in GATED_QUANTITIES})
    tol_text = " / ".join(f"{t:g}" for t in tolerances)
    certain = ", ".join(f"{q} {tolerance[q] + per_q[q]:.2g}" for q in GATED_QUANTITIES if q in per_q)
    left_out = (f" ({unjudged} more could not be judged: a run failed or a ladder was misaligned)"
                if unjudged else "")
    return (f"**Resolution:** this study resolves relative errors of {tol_text} in T, A and eps: every gated run "
            "is a ladder of time steps extrapolated to dt -> 0, and a check passes only when its error plus its "
            f"resolution stays within the tolerance. Its {len(res)} gated checks{left_out} were judged at "
            f"resolutions of {res.min():.1e} to {res.max():.1e} (median {np.median(res):.1e}): the smallest "
            f"engine error it can see is {res.max():.1e}, and an engine error above {certain} fails for certain.")


def ladder_settings(ladder: dict | None) -> str:
    """The ladders in words, from config `ladder`."""
    if not ladder:
        return ""
    diss = ", ".join(f"T_e/{f:g}" for f in ladder["dissipative"])
    elastic = ", ".join(f"T_e/{f:g}" for f in ladder["elastic"])
    return (f"Ladders: the viscoelastic laws at dt = {diss} (each refined by sqrt(K) above K = 1), powers 1, 3/2, "
            f"2 eliminated; the engines' keywords (`default` and the keyword laws) at dt = {diss}, powers 1, 5/4, 2; "
            f"the elastic law at "
            f"dt = {elastic}, powers 2, 5/2 (`engines/ladder.py`). Every rung "
            "starts contact half a step after a sample and puts its singular end (x0 with the tail, F0 when "
            "clipped) a whole number of steps later.")


def plot_ladders(runs: pd.DataFrame, limits: pd.DataFrame, tolerance: dict, path, builds=None) -> None:
    """Every gated ladder: |rung error - its limit| against dt / T_e, one line per ladder and
    criterion, coloured by build, a panel per quantity, with the slopes 1 and 2 the expansion
    starts with; where the lines stop, the limit's resolution takes over (the tolerance dotted)."""
    builds = [b for b in (builds or []) if b in set(runs.build)] + [b for b in pd.unique(runs.build)
                                                                     if b not in set(builds or [])]
    colours = {b: plt.get_cmap("tab10")(k % 10) for k, b in enumerate(builds)}
    fig, axes = subplots(1, 3, figsize=(16, 4.8))
    limit_of = {(r.ladder, r.criterion): r for r in limits.itertuples()}
    # Each ladder's rungs, sorted by h once for the three panels, from the few columns drawn: sorting
    # every group of the whole summary, once per panel, was half of a case report's seconds.
    errors = [f"err_{q}" for q in GATED_QUANTITIES]
    ladders = []
    for (ladder, criterion), g in runs[["ladder", "criterion", "build", "h", *errors]].groupby(["ladder", "criterion"],
                                                                                          sort=False):
        limit = limit_of.get((ladder, criterion))
        if limit is not None:
            g = g.sort_values("h")
            ladders.append((limit, g.h.to_numpy(dtype=float), {c: g[c].to_numpy(dtype=float) for c in errors},
                            colours[g.build.iloc[0]]))
    for ax, q in zip(axes, GATED_QUANTITIES):
        segments = [np.column_stack([h, np.abs(err[f"err_{q}"] - getattr(limit, f"err_{q}")).clip(1e-14)])
                    for limit, h, err, _ in ladders]
        colors = [colour for *_, colour in ladders]
        ax.add_collection(LineCollection(segments, colors=colors, linewidths=0.6, alpha=0.5))
        h = np.array([1 / 8000, 1 / 100])
        for p, ls in ((1, "--"), (2, "-.")):
            ax.plot(h, 1e-2 * (h / h[-1]) ** p, "k", ls=ls, lw=1, label=f"slope {p}")
        res = limits[f"resolution_{q}"].to_numpy(dtype=float)
        if np.isfinite(res).any():
            ax.axhline(float(np.nanmax(res)), color="0.4", lw=1, label="largest resolution")
        ax.axhline(tolerance[q], color="k", ls=":", label="tolerance")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1 / 12000, 1 / 80)
        ax.set_ylim(1e-12, 1e-1)
        ax.set_xlabel("dt / T_e")
        ax.set_title(f"|{q} error at a rung - its limit dt -> 0|", fontsize=10)
        ax.grid(alpha=0.3, which="both")
    handles = [Line2D([], [], color=colours[b], lw=2, label=b) for b in builds]
    own, names = axes[0].get_legend_handles_labels()
    axes[0].legend(handles + own, builds + names, fontsize=7, loc="lower right")
    fig.suptitle("Every gated ladder: what the extrapolation removes from each rung (dissipative laws: slope 1; "
                 "elastic: slope 2)", fontsize=11)
    # Margins in inches, not tight_layout (records.files.set_margins): its log panels' tick labels
    # were measured one by one; room for the suptitle and titles above, dt / T_e below.
    set_margins(fig, left=0.6, right=0.15, top=0.7, bottom=0.55, wspace=0.16)
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def map_section(runs: pd.DataFrame, builds=None) -> list[str]:
    """The engines against their own map (`analysis.map_reference`): per build and law, the
    largest |engine - map| over every rung of every case, for T, A and eps, beside the largest
    round-off floor of those runs. [] when the summary has no map columns."""
    if not len(runs) or "map_err_T" not in runs.columns or runs.map_err_T.isna().all():
        return []
    runs = runs.dropna(subset=["map_err_T"])
    order = [b for b in (builds or []) if b in set(runs.build)] + [b for b in pd.unique(runs.build)
                                                                   if b not in set(builds or [])]
    rows = []
    for build in order:
        for law, g in runs[runs.build == build].groupby("law", sort=False):
            worst = {q: g[f"map_err_{q}"].abs().max() for q in GATED_QUANTITIES}
            rows.append(f"| {build} | {law} | {len(g)} | " + " | ".join(f"{worst[q]:.1e}" for q in GATED_QUANTITIES)
                        + f" | {g.roundoff_floor.max():.1e} |")
    largest = runs[[f"map_err_{q}" for q in GATED_QUANTITIES]].abs().max().max()
    return ["## The engines against their own map", "",
            "Beside the gate, which judges each ladder's limit against the ODE: every gated run against the map "
            "the engines share (`reference/engine_map.py`), replayed at the run's own time step. A build that "
            "implements the law exactly reproduces it to its own rounding at any dt, without extrapolation. "
            "Largest |engine / map - 1| over every rung of every case and criterion (`map_err_*` in summary.csv), "
            "and the largest round-off floor sqrt(N) u X / delta_max of those runs:", "",
            "| build | law | rows | T | A | eps | round-off floor |", "|---|---|---|---|---|---|---|", *rows, "",
            f"Every run is within {largest:.1e} of the map.", ""]
