"""Snakemake script: the runs of one case (results/<case>/plan.json), validated before any engine,
with the reference solution of every run solved once, in one batch, and handed on."""

import json

from common import start_rule
from contact_model import load_case
from engines.plan import plan_listing, plan_runs

log = start_rule(snakemake)
s = snakemake.params.settings
case = load_case(snakemake.input.case)
plan = plan_runs(case, s["builds"], s["laws"], s["K_grid"], s["time_step_factor"], s["default_law_match_K"],
                 s["max_overlap_ratio"])
with open(snakemake.output[0], "w") as f:
    json.dump(plan_listing(case, plan), f, indent=1)
log.info("%s: %d runs planned, %d velocities not run", case.path, len(plan.runs), len(plan.skipped))
for skipped in plan.skipped:
    log.warning("not run: %s %s K = %.3g: %s", case.name, skipped["geometry"], skipped["K"], skipped["reason"])
