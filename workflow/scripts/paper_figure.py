"""Snakemake script: one of the paper's figures made from engine runs (rule paper_figure_3 or _4;
Figs. 1 and 5 need no engine: rule paper_reference)."""

import pandas as pd

from common import start_rule
from records.run_manifest import manifest_dumps
from report.paper import figures

log = start_rule(snakemake)
which = snakemake.params.figure
if which == 3:
    figures.figure_3(pd.read_csv(snakemake.input.summary), snakemake.output.png)
elif which == 4:
    dumps = {}
    for _, meta, cols, _ in manifest_dumps(snakemake.input.manifest):
        if meta["geometry"] == "sphere-sphere":
            dumps[round(meta["K"], 9)] = (meta, cols)
    check = figures.figure_4(dumps, snakemake.output.png)
    check.to_csv(snakemake.output.csv, index=False, float_format="%.4g")
    log.info("DEM vs reference energy partition:\n%s", check.to_string())
else:
    raise ValueError(f"paper_figure.py makes Figs. 3 and 4, not {which}")
