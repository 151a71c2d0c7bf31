"""Snakemake script: DEM eps at the measured velocities against the fit and the data."""

import json

import pandas as pd

from common import start_rule
from calibration.case_calibration import case_fits
from calibration.outputs import loop_table, plot_fit
from contact_model import load_case
from records.run_manifest import manifest_dumps

log = start_rule(snakemake, "results/calibration")
case = load_case(snakemake.input.case)
with open(snakemake.input.fit) as fh:
    summary = json.load(fh)
loop = loop_table(manifest_dumps(snakemake.input.manifest), summary, pd.read_csv(snakemake.input.residuals))
loop.to_csv(snakemake.output.csv, index=False, float_format="%.10g")
fits = case_fits(case)  # the Fit objects for the plot: the fits alone, not calibrate's whole summary
plot_fit(case, fits, snakemake.output.png, loop)
log.info("DEM - fit: largest |difference| %.3g\n%s", loop.dem_minus_fit.abs().max(), loop.to_string())
