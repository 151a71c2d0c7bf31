"""Snakemake script: the time-step convergence runs of one engine (one engine process)."""

from common import start_rule
from contact_model import load_case
from engines import run_sweep
from engines.builds import Build
from engines.plan import plan_at_velocity
from records.run_manifest import write_manifest

log = start_rule(snakemake)
c = snakemake.params.convergence
build = Build(**snakemake.params.build)
runs = plan_at_velocity(load_case(snakemake.input.case), build.code, c["K"], c["time_step_factors"], c["velocity"],
                        "convergence", build=build.id, solved=snakemake.params.reference, every_law=True)
log.info("%d %s convergence runs into %s", len(runs), build.id, snakemake.output.runs)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s).raise_first()
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs], build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs in an engine process of %.2f s", len(runs), sweep.engine_seconds)
