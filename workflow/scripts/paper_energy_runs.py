"""Snakemake script: the DEM runs overlaid on the paper's Fig. 4 (one engine process)."""

import json
from pathlib import Path

from common import log_to
from contact_model import load_case
from engines import run_sweep
from engines.plan import plan_at_velocity

log = log_to(snakemake.log[0])
e = snakemake.params.energy
engine = snakemake.params.engine
runs = plan_at_velocity(load_case(snakemake.input.case), engine, e["K"], [snakemake.params.time_step_factor],
                        e["velocity"], "energy")
sweep = run_sweep(engine, runs, Path(snakemake.output.manifest).parent).raise_first()
with open(snakemake.output.manifest, "w") as f:
    json.dump({"engine": engine, "engine_seconds": sweep.engine_seconds,
               "dumps": [str(sweep.dumps[r.name]) for r in runs]}, f, indent=1)
log.info("%d runs", len(runs))
