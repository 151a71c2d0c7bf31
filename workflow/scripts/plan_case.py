"""Snakemake script: the runs of one case (results/<case>/plan.json), validated before any engine."""

import json

from common import start_rule
from contact_model import load_case
from engines.plan import plan_runs

log = start_rule(snakemake)
s = snakemake.params.settings
case = load_case(snakemake.input.case)
plan = plan_runs(case, s["engines"], s["laws"], s["K_grid"], s["time_step_factor"], s["default_law_match_K"],
                 s["max_overlap_ratio"])
runs = plan.runs
listed = [{"name": r.name, "engine": r.engine, "law": r.law, "geometry": r.pair.geometry,
           "represents": list(r.represents), "velocity": r.velocity, "K": r.K, "time_step": r.time_step,
           "steps": r.steps(), "matched_restitution": r.matched_restitution} for r in runs]
with open(snakemake.output[0], "w") as f:
    json.dump({"case": case.name, "file": case.path, "runs": listed, "not_run": plan.skipped}, f, indent=1)
log.info("%s: %d runs planned, %d velocities not run", case.path, len(listed), len(plan.skipped))
for skipped in plan.skipped:
    log.warning("not run: %s %s K = %.3g: %s", case.name, skipped["geometry"], skipped["K"], skipped["reason"])
