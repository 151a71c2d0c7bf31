"""The report's figures: the engines' ratios and errors against K, the out-of-the-box laws, each
build in a style of its own (`build_styles`), drawn in worker processes (`start_drawing`).

`report.report` decides which figures a report has and links them; the ladders' figure is
`report.report_resolution.plot_ladders`.
"""

from __future__ import annotations

import itertools
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cycler  # noqa: E402
from matplotlib.legend_handler import HandlerTuple  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from contact_model import CRITERIA, GATED_LAWS  # noqa: E402
from reference import hertz_ratios, paper_series_value  # noqa: E402
from records.files import save_figure, set_margins  # noqa: E402

from verdict.gate import GATED_QUANTITIES  # noqa: E402
from .panels import subplots  # noqa: E402
from .report_matrix import build_order  # noqa: E402

RATIO = {"eps": ("eps", 1.0), "T": ("T/T_e", "T_e"), "A": ("A/A_e", "A_e"),
         "Q1": ("Q1/Q1e", "Q1e"), "Q2": ("Q2/Q2e", "Q2e")}
#: The markers of the builds' cycle, paired with matplotlib's default colour cycle (tab10); a square
#: first, so that the smaller markers of the builds after it nest inside it.
MARKER_CYCLE = ("s", "o", "^", "D", "v", "P", "X", "<", "h", ">")
#: The geometries, in the order of the legend; sphere-plane markers carry a dot at their centre.
GEOMETRY_DOT = {"sphere-sphere": False, "sphere-plane": True}


def build_styles(builds) -> dict[str, dict]:
    """A distinct marker and colour per engine build, from the order of `builds` (config
    `builds:`): matplotlib's colour cycle zipped with MARKER_CYCLE. Markers are hollow and
    shrink along the list, so that builds that agree (the same point) show as nested markers,
    every one visible.

    Returns
    -------
    {build: {"color", "marker", "ms"}}, usable as keyword arguments of `Axes.plot`.
    """
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    cycle = cycler(color=(colors * len(MARKER_CYCLE))[:len(MARKER_CYCLE)]) + cycler(marker=MARKER_CYCLE)
    return {b: {**style, "ms": max(4.0, 14.0 - 2.0 * i)}
            for i, (b, style) in enumerate(zip(builds, itertools.cycle(cycle)))}


def _plot_points(ax, x, y, style: dict, geometry: str, semilogy: bool = False) -> None:
    """A build's points in one geometry: its hollow marker, with a dot at the centre on
    sphere-plane."""
    plot = ax.semilogy if semilogy else ax.plot
    plot(x, y, ls="none", mfc="none", mew=1.4, **style)
    if GEOMETRY_DOT.get(geometry):
        plot(x, y, ls="none", marker=".", ms=3.5, color=style["color"])


def _legend(ax, styles: dict, present, labels: dict | None = None, fontsize=7) -> None:
    """The axes' own entries, then one per build (its marker) and one per geometry."""
    grey = {"color": "0.3", "marker": "o", "ms": 8, "mfc": "none", "mew": 1.4, "ls": "none"}
    handles = [Line2D([], [], ls="none", mfc="none", mew=1.4, **styles[b]) for b in present]
    names = [(labels or {}).get(b, b) for b in present]
    handles += [Line2D([], [], **grey), (Line2D([], [], **grey), Line2D([], [], ls="none", marker=".", ms=3.5,
                                                                         color="0.3"))]
    names += list(GEOMETRY_DOT)
    own, own_names = ax.get_legend_handles_labels()
    ax.legend([*own, *handles], [*own_names, *names], fontsize=fontsize, handler_map={tuple: HandlerTuple(ndivide=1)})


def _builds(table: pd.DataFrame, builds=None) -> list[str]:
    """The builds of `table` in config order (`builds`), others after in order of appearance."""
    return [b for b in build_order(builds, table) if b in set(table.build)]


def _ratio(table, q):
    name, scale = RATIO[q]
    return table[q] / (table[scale] if isinstance(scale, str) else scale)


def _plot_build_ratios(ax, runs: pd.DataFrame, q: str, present, styles) -> None:
    """The ratio `q` (`_ratio`) of each present build's runs against K, one marker per geometry."""
    for build in present:
        for geometry in GEOMETRY_DOT:
            sel = runs[(runs.build == build) & (runs.geometry == geometry)]
            if len(sel):
                _plot_points(ax, sel.K, _ratio(sel, q), styles[build], geometry)


def plot_ratios(table: pd.DataFrame, criterion: str, path: Path, curve, builds=None) -> None:
    """eps, T/T_e, A/A_e, Q1/Q1e, Q2/Q2e against K: every build a marker of its own
    (`build_styles`, in the order of `builds`), hollow, with a dot at the centre on sphere-plane;
    the reference solver as a line (`curve`, `analysis.report_references.reference_curve`), the paper's
    series dashed."""
    K = np.asarray(curve.K)
    ref = hertz_ratios(curve, criterion)
    runs = table[(table.criterion == criterion) & table.law.isin(GATED_LAWS)]
    # The columns drawn alone: every selection below copies its rows, of every column it keeps.
    drawn = ["build", "geometry", "K", *RATIO, *(scale for _, scale in RATIO.values() if isinstance(scale, str))]
    runs = runs[[c for c in dict.fromkeys(drawn) if c in runs.columns]]
    present = _builds(runs, builds)
    styles = build_styles(build_order(builds, table))
    fig, axes = subplots(1, 5, figsize=(20, 4.2))
    for ax, q in zip(axes, RATIO):
        name = RATIO[q][0]
        ax.plot(K, ref[name], "k-", lw=1.5, label="reference ODE")
        ax.plot(K, paper_series_value(name, K), "k--", lw=1, label="paper's series")
        _plot_build_ratios(ax, runs, q, present, styles)
        ax.set_xlabel("K")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    _legend(axes[0], styles, present)
    fig.suptitle(f"Criterion {criterion}: every engine run of every case (viscoelastic laws)")
    # Margins in inches, not tight_layout (records.files.set_margins): room for the suptitle and
    # the titles above, the tick labels and K below, the ratios' tick labels left of each panel.
    set_margins(fig, left=0.55, right=0.15, top=0.75, bottom=0.5, wspace=0.2)
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def plot_errors(table: pd.DataFrame, tolerance: dict, path: Path, builds=None) -> None:
    """|relative error| (extrapolated to dt -> 0) against K, one row of panels per criterion
    (x0, F0) and one column per quantity; builds as in `plot_ratios`; each point's resolution as
    a grey bar from the point up to |error| + resolution; the tolerance as a line."""
    runs = table[table.law.isin(GATED_LAWS)]
    # The columns drawn alone: every selection below copies its rows, of every column it keeps.
    drawn = ["build", "geometry", "criterion", "K",
             *(f"{kind}_{q}" for q in GATED_QUANTITIES for kind in ("err", "resolution"))]
    runs = runs[[c for c in drawn if c in runs.columns]]
    present = _builds(runs, builds)
    styles = build_styles(build_order(builds, table))
    fig, axes = subplots(2, 3, figsize=(15, 7.5), sharex=True, squeeze=False)
    for row, criterion in zip(axes, CRITERIA):
        for ax, q in zip(row, GATED_QUANTITIES):
            for build in present:
                for geometry in GEOMETRY_DOT:
                    sel = runs[(runs.build == build) & (runs.geometry == geometry) & (runs.criterion == criterion)]
                    if len(sel):
                        e = np.abs(sel[f"err_{q}"]).clip(lower=1e-12)
                        if f"resolution_{q}" in sel.columns:
                            ax.vlines(sel.K, e, e + sel[f"resolution_{q}"].fillna(0.0), color="0.75", lw=3, zorder=0)
                        _plot_points(ax, sel.K, e, styles[build], geometry, semilogy=True)
            ax.axhline(tolerance[q], color="k", ls=":", label="tolerance")
            ax.set_title(f"criterion {criterion}: |{q}_engine / {q}_reference - 1| at dt -> 0", fontsize=10)
            ax.grid(alpha=0.3, which="both")
    for ax in axes[-1]:
        ax.set_xlabel("K")
    _legend(axes[0][0], styles, present)
    # Margins in inches, not tight_layout (records.files.set_margins), which measured every tick
    # label of the six log panels: room for the titles above each row and the decades left of it.
    set_margins(fig, left=0.6, right=0.15, top=0.35, bottom=0.5, wspace=0.18, hspace=0.14)
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def start_drawing(plots, workers: int = 1):
    """Draw `plots` ((function, args), ...) in up to `workers` forked processes, or in turn, here,
    when workers is 1; returns the function that waits for them (raising a plot's failure). The
    figures are independent and are most of the report's time (~4 of ~5.5 s), at the end of the
    study, where the other core has nothing left to do: the report's text is written meanwhile."""
    if workers <= 1 or len(plots) <= 1:
        for function, args in plots:
            function(*args)
        return lambda: None
    # fork: the children have matplotlib imported already (spawn would import it again, ~1 s each)
    pool = ProcessPoolExecutor(min(workers, len(plots)), mp_context=multiprocessing.get_context("fork"))
    futures = [pool.submit(function, *args) for function, args in plots]
    pool.shutdown(wait=False)  # no more plots: the workers end with the last one

    def wait():
        for future in futures:
            future.result()

    return wait
