"""Snakemake script: all cases' summaries in one tidy table (results/summary.csv)."""

import pandas as pd

from common import start_rule

log = start_rule(snakemake)
table = pd.concat([pd.read_csv(p) for p in snakemake.input], ignore_index=True)
table.to_csv(snakemake.output[0], index=False, float_format="%.12g")
log.info("%d rows from %d cases", len(table), len(snakemake.input))
