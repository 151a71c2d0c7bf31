"""Snakemake script: the reference solution over the configured K grid, and the computed Taylor
coefficients beside the paper's (tidy CSVs)."""

import numpy as np
import pandas as pd

from common import start_rule
from reference import compare_with_paper, solve_collisions

log = start_rule(snakemake)
g = snakemake.params.grid
K = np.linspace(g["start"], g["stop"], g["num"])
table = pd.DataFrame(solve_collisions(K).rows())
table.to_csv(snakemake.output.collisions, index=False, float_format="%.15g")
log.info("solved %d K values in [%g, %g]; largest energy residual %.2e",
         len(K), K[0], K[-1], table.energy_residual.max())
series = compare_with_paper(snakemake.params.order)
series.to_csv(snakemake.output.series, index=False, float_format="%.12g")
log.info("wrote %d coefficients", len(series))
