"""Snakemake script: the DEM runs overlaid on the paper's Fig. 4 (one engine process)."""

from common import start_rule
from contact_model import load_case
from engines import run_sweep
from engines.builds import Build
from engines.plan import plan_at_velocity
from records.run_manifest import write_manifest

log = start_rule(snakemake)
e = snakemake.params.energy
build = Build(**snakemake.params.build)
runs = plan_at_velocity(load_case(snakemake.input.case), build.code, e["K"], [snakemake.params.time_step_factor],
                        e["velocity"], "energy", build=build.id, solved=snakemake.params.reference)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s).raise_first()
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs], build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs", len(runs))
