"""Snakemake script: the literature's closed forms for eps(K) against the reference solver."""

from common import start_rule
from calibration.synthetic import closed_form_bias
from reference.restitution_closed_forms import closed_form_errors

log = start_rule(snakemake, "results/calibration")
s = snakemake.params.settings
errors = closed_form_errors(s["K_intervals"])
errors.to_csv(snakemake.output.errors, index=False, float_format="%.6g")
bias = closed_form_bias(s["bias_K"], n_sets=s["bias_sets"])
bias.to_csv(snakemake.output.bias, index=False, float_format="%.6g")
log.info("closed forms:\n%s\nbias:\n%s", errors.to_string(), bias.to_string())
