"""Snakemake script: the largest dt / T_R holding each tolerance at every start phase, over K and e
(analysis.timestep_maps.largest_steps, drawn by report.report_timestep), for the study's report."""

from common import start_rule
from contact_model import load_case
from analysis.timestep_maps import largest_steps
from report.report_timestep import plot_largest_steps
from records.files import write_atomically

log = start_rule(snakemake)
pair = load_case(snakemake.input.case).pair("sphere-sphere")
table = largest_steps(pair, [float(K) for K in snakemake.params.K], [float(e) for e in snakemake.params.restitution])
plot_largest_steps(table, snakemake.output.plot)
write_atomically(snakemake.output.csv, table.to_csv(index=False, float_format="%.6g"))
log.info("largest dt over T_R: %d rows", len(table))
