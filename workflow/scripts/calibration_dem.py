"""Snakemake script: the calibrated contact in one engine at every measured velocity."""

import json

from common import start_rule
from calibration.loop import loop_runs
from contact_model import load_case
from engines import run_sweep
from engines.builds import Build
from records.run_manifest import write_manifest

log = start_rule(snakemake, "results/calibration")
case = load_case(snakemake.input.case)
with open(snakemake.input.fit) as fh:
    summary = json.load(fh)
build = Build(**snakemake.params.build)
runs = loop_runs(case, summary, build.code, snakemake.params.time_step_factor, build=build.id)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s).raise_first()
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs], case=case.name, build=build.id,
               engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d %s runs, engine process %.2f s", len(runs), build.id, sweep.engine_seconds)
