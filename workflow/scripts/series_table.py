"""Snakemake script: the computed Taylor coefficients beside the paper's (tidy CSV)."""

import logging

from reference import compare_with_paper

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO, format="%(asctime)s %(message)s")
table = compare_with_paper(snakemake.params.order)
table.to_csv(snakemake.output[0], index=False, float_format="%.12g")
logging.info("wrote %d coefficients", len(table))
