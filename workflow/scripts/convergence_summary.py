"""Snakemake script: errors against the time step, fitted orders, and the convergence plot."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from common import start_rule  # noqa: E402
from postprocess.comparison import comparison_rows  # noqa: E402
from postprocess.convergence import convergence_table  # noqa: E402
from postprocess.run_manifest import manifest_dumps  # noqa: E402

log = start_rule(snakemake)
rows = []
for manifest in snakemake.input.manifests:
    for _, meta, _, m in manifest_dumps(manifest):
        for r in comparison_rows(meta, m):
            rows.append({k: r[k] for k in ("build", "engine", "geometry", "criterion", "K", "err_T", "err_A", "err_eps")}
                        | {"K": round(meta["K"], 12), "time_step_factor": meta["time_step_factor"]})
errors = pd.DataFrame(rows)
errors.to_csv(snakemake.output.errors, index=False, float_format="%.6g")
table = convergence_table(errors, snakemake.params.tolerance)
table.to_csv(snakemake.output.orders, index=False, float_format="%.4g")

Ks = sorted(errors.K.unique())
fig, axes = plt.subplots(len(Ks), 3, figsize=(15, 3.6 * len(Ks) + 0.8), squeeze=False)
# One colour per build, the line per geometry, the marker per criterion, and one legend of each
# for the whole figure: with a colour per curve, the 20 curves of six builds cycled through ten
# colours, and two builds' curves looked alike.
builds = sorted(errors.build.unique())
colours = {b: plt.get_cmap("tab10")(k % 10) for k, b in enumerate(builds)}
lines = {"sphere-sphere": "-", "sphere-plane": "--"}
markers = {"x0": "o", "F0": "s"}
# Builds that agree to the last digit draw one curve, the last build's: the markers are hollow,
# each build's larger than the next one's, so that coinciding builds show as concentric rings.
sizes = {b: 4.0 + 2.0 * (len(builds) - 1 - k) for k, b in enumerate(builds)}
for i, K in enumerate(Ks):
    for j, q in enumerate(("T", "A", "eps")):
        ax = axes[i, j]
        for (build, geometry, criterion), g in errors[errors.K == K].groupby(["build", "geometry", "criterion"]):
            g = g.sort_values("time_step_factor")
            ax.loglog(1.0 / g.time_step_factor, np.abs(g[f"err_{q}"]).clip(lower=1e-13),
                      lines[geometry], marker=markers[criterion], ms=sizes[build], mfc="none", mew=1.2, lw=1.0,
                      color=colours[build])
        ax.axhline(snakemake.params.tolerance[q], color="k", ls=":")
        ax.set_title(f"K = {K:g}: |{q} error|")
        ax.set_xlabel("dt / T_e")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(alpha=0.3, which="both")
handles = ([Line2D([], [], color=colours[b], lw=2, label=b) for b in builds]
           + [Line2D([], [], color="0.3", ls=ls, label=g) for g, ls in lines.items()]
           + [Line2D([], [], color="0.3", ls="", marker=m, mfc="none", label=f"criterion {c}") for c, m in markers.items()]
           + [Line2D([], [], color="k", ls=":", label="tolerance")])
fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=8, frameon=False)
# Margins in inches, not tight_layout: the grid is fixed (rows of three log-log panels whose tick
# labels are powers of ten), and tight_layout's measuring of every tick label took ~3 s, a third
# of the job.
height = fig.get_figheight()
fig.subplots_adjust(left=0.05, right=0.99, bottom=0.55 / height, top=1 - 0.75 / height, wspace=0.2, hspace=0.3)
fig.savefig(snakemake.output.plot, dpi=100)
log.info("%d error rows; orders:\n%s", len(errors), table.to_string())
