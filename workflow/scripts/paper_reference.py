"""Snakemake script: the paper's results that need no engine (rule paper_reference): its claims
(results/paper/claims.csv), its Table 1 recomputed, Fig. 1 and Fig. 5."""

from pathlib import Path

from common import start_rule
from contact_model import load_case
from report.paper import figures
from report.paper.claims import claims
from report.paper.table1 import recompute_table_1

log = start_rule(snakemake)
out = snakemake.output
table = claims()
table.to_csv(out.claims, index=False, float_format="%.6g")
recompute_table_1(Path(snakemake.input.cases[0]).parent).to_csv(out.table1, index=False, float_format="%.4g")
log.info("%d claims: %s", len(table), table.verdict.value_counts().to_dict())

figures.figure_1(out.figure_1)

case = load_case(snakemake.input.fracture_case)
pair = case.pairs[0]
markers = {}
for p in case.pairs:  # R / L_d of the case's spheres, L_d = eta / (rho V_D)
    L_d = p.eta / (p.body_1.density * p.viscous_velocity)
    markers[f"{case.name} {p.geometry}"] = p.body_1.radius / L_d
curves = figures.figure_5(out.figure_5, snakemake.params.P0 / pair.E, markers)
curves.to_csv(out.figure_5_csv, index=False, float_format="%.6g")
log.info("Fig. 5: R/L_d of the case: %s", markers)
