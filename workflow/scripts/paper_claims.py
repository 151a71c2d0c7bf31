"""Snakemake script: the paper's claims (results/paper/claims.csv) and its Table 1 recomputed."""

from pathlib import Path

from common import start_rule
from postprocess.paper.claims import claims
from postprocess.paper.table1 import recompute_table_1

log = start_rule(snakemake)
table = claims()
table.to_csv(snakemake.output.claims, index=False, float_format="%.6g")
recompute_table_1(Path(snakemake.input.cases[0]).parent).to_csv(snakemake.output.table1, index=False,
                                                                float_format="%.4g")
log.info("%d claims: %s", len(table), table.verdict.value_counts().to_dict())
