"""Snakemake script: errors against the time step from production steps on, observed orders, the
largest dt meeting each threshold (in T_e and in the Rayleigh time), the builds' spread, and the
convergence plot."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from common import start_rule  # noqa: E402
from contact_model import load_case  # noqa: E402
from analysis.comparison import comparison_rows  # noqa: E402
from analysis.convergence import build_spread, convergence_table, largest_dt_table  # noqa: E402
from records.files import save_figure  # noqa: E402
from records.quantities import gated_quantities  # noqa: E402
from records.run_manifest import manifest_dumps  # noqa: E402

log = start_rule(snakemake)
case = load_case(snakemake.params.case)
rows, T_e = [], {}
for manifest in snakemake.input.manifests:
    for _, meta, _, m in manifest_dumps(manifest):
        T_e[meta["geometry"]] = meta["T_e"]  # one velocity: one Hertz time per geometry
        for r in comparison_rows(meta, m):
            rows.append({k: r[k] for k in ("build", "engine", "law", "geometry", "criterion", "err_T", "err_A",
                                           "err_eps",
                                           "h", "time_step_factor")} | {"K": round(meta["K"], 12)})
errors = pd.DataFrame(rows)
rayleigh = {p.geometry: p.rayleigh_time() / T_e[p.geometry] for p in case.pairs if p.geometry in T_e}
errors["dt_over_T_R"] = errors.h / errors.geometry.map(rayleigh)
errors.to_csv(snakemake.output.errors, index=False, float_format="%.6g")
convergence_table(errors).to_csv(snakemake.output.orders, index=False, float_format="%.4g")
thresholds = snakemake.params.thresholds
largest = largest_dt_table(errors, thresholds, rayleigh)
largest.to_csv(snakemake.output.largest_dt, index=False, float_format="%.4g")
build_spread(errors).to_csv(snakemake.output.spread, index=False, float_format="%.4g")

# Rows of panels per K, a column per quantity; colour per build, line per geometry, marker per law
# and criterion; the thresholds dotted. Builds that agree draw one curve: hollow markers, each
# build's larger than the next one's, show them as concentric rings.
Ks = sorted(errors.K.unique())
GATED = gated_quantities()
fig, axes = plt.subplots(len(Ks), len(GATED), figsize=(5 * len(GATED), 3.6 * len(Ks) + 1.0), squeeze=False)
builds = list(dict.fromkeys(errors.build))
colours = {b: plt.get_cmap("tab10")(k % 10) for k, b in enumerate(builds)}
lines = {"sphere-sphere": "-", "sphere-plane": "--"}
markers = {("viscoelastic", "x0"): "o", ("viscoelastic", "F0"): "s", ("viscoelastic_clipped", "F0"): "^",
           ("elastic", "x0"): "D"}
sizes = {b: 4.0 + 2.0 * (len(builds) - 1 - k) for k, b in enumerate(builds)}
to_TR = rayleigh.get("sphere-plane", next(iter(rayleigh.values())))
for i, K in enumerate(Ks):
    for j, q in enumerate(GATED):
        ax = axes[i, j]
        for (build, law, geometry, criterion), g in errors[errors.K == K].groupby(["build", "law", "geometry",
                                                                                   "criterion"]):
            g = g.sort_values("h")
            ax.loglog(g.h, np.abs(g[f"err_{q}"]).clip(lower=1e-13), lines[geometry],
                      marker=markers.get((law, criterion), "x"), ms=sizes[build], mfc="none", mew=1.1, lw=0.9,
                      color=colours[build])
        for t in thresholds:
            ax.axhline(t, color="k", ls=":", lw=0.8)
        ax.set_title(f"K = {K:g}: |{q} error| against dt", fontsize=10)
        ax.set_xlabel("dt / T_e")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(alpha=0.3, which="both")
        top = ax.secondary_xaxis("top", functions=(lambda x: x / to_TR, lambda x: x * to_TR))
        top.set_xlabel("dt / T_R (sphere-plane)", fontsize=8)
        top.tick_params(labelsize=7)
handles = ([Line2D([], [], color=colours[b], lw=2, label=b) for b in builds]
           + [Line2D([], [], color="0.3", ls=ls, label=g) for g, ls in lines.items()]
           + [Line2D([], [], color="0.3", ls="", marker=m, mfc="none", label=f"{law} {c}")
              for (law, c), m in markers.items() if ((errors.law == law) & (errors.criterion == c)).any()]
           + [Line2D([], [], color="k", ls=":", label="thresholds " + ", ".join(f"{t:g}" for t in thresholds))])
fig.legend(handles=handles, loc="upper center", ncol=min(len(handles), 7), fontsize=8, frameon=False)
# Margins in inches, not tight_layout (it measured every tick label of the panels: seconds).
height = fig.get_figheight()
fig.subplots_adjust(left=0.05, right=0.99, bottom=0.55 / height, top=1 - 1.25 / height, wspace=0.2, hspace=0.55)
save_figure(fig, snakemake.output.plot, dpi=100)
log.info("%d error rows; largest dt:\n%s", len(errors), largest.to_string())
