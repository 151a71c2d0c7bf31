"""Snakemake script: fit eta to one case's measurements (results/calibration/<case>/)."""

from common import start_rule
from calibration.case_calibration import calibrate
from calibration.outputs import write_fit
from contact_model import load_case
from pathlib import Path

# The calibration does not change the study's results: only its own folder's verdict files (none)
# are withdrawn, not the study's gate.
log = start_rule(snakemake, "results/calibration")
case = load_case(snakemake.input.case)
summary, fits = calibrate(case, snakemake.params.modulus_factors)
write_fit(case, summary, fits, Path(snakemake.output.fit).parent)
for name in ("x0", "F0", "series"):
    f = summary["fits"][name]
    log.info("%s %s: eta = %.5g P [%.5g, %.5g], K(V_max) = %.5f, rms residual %.3g", case.name, name, f["eta_P"],
             *f["eta_interval_P"], f["K_at_V_ref"], f["rms_residual"])
# What makes the eta above unfit to use (the data contradict the model): in the log as in the report.
for warning in summary["warnings"]:
    log.warning("%s (%s): do not use the eta above: %s", case.name, case.measurements.path, warning)
