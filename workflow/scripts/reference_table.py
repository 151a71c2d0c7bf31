"""Snakemake script: write the reference solution over the configured K grid as a tidy CSV."""

import numpy as np
import pandas as pd

from common import start_rule
from reference import solve_collisions

log = start_rule(snakemake)
g = snakemake.params.grid
K = np.linspace(g["start"], g["stop"], g["num"])
table = pd.DataFrame(solve_collisions(K).rows())
table.to_csv(snakemake.output[0], index=False, float_format="%.15g")
log.info("solved %d K values in [%g, %g]; largest energy residual %.2e",
             len(K), K[0], K[-1], table.energy_residual.max())
