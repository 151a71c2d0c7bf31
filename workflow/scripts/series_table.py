"""Snakemake script: the computed Taylor coefficients beside the paper's (tidy CSV)."""

from common import start_rule
from reference import compare_with_paper

log = start_rule(snakemake)
table = compare_with_paper(snakemake.params.order)
table.to_csv(snakemake.output[0], index=False, float_format="%.12g")
log.info("wrote %d coefficients", len(table))
