"""Snakemake script: errors against the time step, fitted orders, and the convergence plot."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
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
fig, axes = plt.subplots(len(Ks), 3, figsize=(15, 3.6 * len(Ks)), squeeze=False)
styles = {"sphere-sphere": "-", "sphere-plane": "--"}
for i, K in enumerate(Ks):
    for j, q in enumerate(("T", "A", "eps")):
        ax = axes[i, j]
        for (build, geometry, criterion), g in errors[errors.K == K].groupby(["build", "geometry", "criterion"]):
            g = g.sort_values("time_step_factor")
            ax.loglog(1.0 / g.time_step_factor, np.abs(g[f"err_{q}"]).clip(lower=1e-13),
                      styles[geometry], marker="o" if criterion == "x0" else "s", ms=4,
                      label=f"{build}, {geometry}, {criterion}")
        ax.axhline(snakemake.params.tolerance[q], color="k", ls=":")
        ax.set_title(f"K = {K:g}: |{q} error|")
        ax.set_xlabel("dt / T_e")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(alpha=0.3, which="both")
axes[0, 0].legend(fontsize=6)
fig.tight_layout()
fig.savefig(snakemake.output.plot, dpi=100)
log.info("%d error rows; orders:\n%s", len(errors), table.to_string())
