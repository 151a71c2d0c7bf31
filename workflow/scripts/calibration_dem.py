"""Snakemake script: the calibrated contact in one engine at every measured velocity."""

import json

from common import start_rule
from calibration.outputs import loop_runs
from contact_model import load_case
from engines import run_sweep
from postprocess.run_manifest import write_manifest

log = start_rule(snakemake, "results/calibration")
case = load_case(snakemake.input.case)
with open(snakemake.input.fit) as fh:
    summary = json.load(fh)
engine = snakemake.params.engine
runs = loop_runs(case, summary, engine, snakemake.params.time_step_factor)
sweep = run_sweep(engine, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s).raise_first()
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs], case=case.name, engine=engine,
               engine_seconds=sweep.engine_seconds)
log.info("%d %s runs, engine process %.2f s", len(runs), engine, sweep.engine_seconds)
