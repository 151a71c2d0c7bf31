"""Snakemake script: one of the paper's figures (rule paper_figure_1, _3, _4 or _5)."""

import pandas as pd

from common import start_rule
from contact_model import load_case
from postprocess.run_manifest import manifest_dumps
from postprocess.paper import figures

log = start_rule(snakemake)
which = snakemake.params.figure
if which == 1:
    figures.figure_1(snakemake.output.png)
elif which == 3:
    figures.figure_3(pd.read_csv(snakemake.input.summary), snakemake.output.png)
elif which == 4:
    dumps = {}
    for _, meta, cols, _ in manifest_dumps(snakemake.input.manifest):
        if meta["geometry"] == "sphere-sphere":
            dumps[round(meta["K"], 9)] = (meta, cols)
    check = figures.figure_4(dumps, snakemake.output.png)
    check.to_csv(snakemake.output.csv, index=False, float_format="%.4g")
    log.info("DEM vs reference energy partition:\n%s", check.to_string())
elif which == 5:
    case = load_case(snakemake.input.case)
    P0 = snakemake.params.P0
    pair = case.pairs[0]
    markers = {}
    for p in case.pairs:  # R / L_d of the case's spheres, L_d = eta / (rho V_D)
        L_d = p.eta / (p.body_1.density * p.viscous_velocity)
        markers[f"{case.name} {p.geometry}"] = p.body_1.radius / L_d
    curves = figures.figure_5(snakemake.output.png, P0 / pair.E, markers)
    curves.to_csv(snakemake.output.csv, index=False, float_format="%.6g")
    log.info("R/L_d of the case: %s", markers)
