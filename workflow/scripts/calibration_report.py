"""Snakemake script: results/calibration/report.md."""

import json
from pathlib import Path

import pandas as pd

from common import start_rule
from calibration.outputs import answer_lines, case_section, closed_forms_section

log = start_rule(snakemake, "results/calibration")
out = Path(snakemake.output[0])
lines = ["# Calibrating eta from measured restitution", "",
         "Each measured case is fitted with the exact reference eps(K) under both criteria (95 % profile-likelihood "
         "intervals), beside the paper's second-order series; then run in a DEM engine at the measured velocities. "
         "Command: `snakemake -j2 calibration`. Method: `calibration/fit.py`; format of the measurement files: "
         "`contact_model/measurement_file.py` and docs/calibration.md.", ""]
summaries = [json.loads(Path(fit).read_text()) for fit in snakemake.input.fits]
lines += ["**The answers** (eta for the engines' viscoelastic contact; the sections below say how):", ""]
for summary in summaries:
    lines += answer_lines(summary)
    for warning in summary.get("warnings", []):  # the data contradict the model: said in the log too
        log.warning("%s: do not use its eta: %s", summary["case"], warning)
lines += [""]
for fit, summary, residuals, loop in zip(snakemake.input.fits, summaries, snakemake.input.residuals,
                                         snakemake.input.loops):
    folder = Path(fit).parent.relative_to(out.parent).as_posix()
    lines += case_section(summary, pd.read_csv(residuals), pd.read_csv(loop), folder)
lines += closed_forms_section(pd.read_csv(snakemake.input.errors), pd.read_csv(snakemake.input.bias))
out.write_text("\n".join(lines) + "\n")
log.info("wrote %s", out)
