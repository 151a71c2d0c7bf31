"""Snakemake script: the LAMMPS regression cases of every LAMMPS build in one table."""

import pandas as pd

from common import start_rule

log = start_rule(snakemake)
table = pd.concat([pd.read_csv(f) for f in snakemake.input], ignore_index=True)
table.to_csv(snakemake.output[0], index=False, float_format="%.6g")
log.info("%d rows from %d builds", len(table), len(snakemake.input))
