"""Snakemake script: the time-step convergence runs of one engine (one engine process)."""

import json
from pathlib import Path

from common import log_to
from contact_model import load_case
from engines import run_sweep
from engines.plan import plan_at_velocity

log = log_to(snakemake.log[0])
c = snakemake.params.convergence
engine = snakemake.wildcards.engine
runs = plan_at_velocity(load_case(snakemake.input.case), engine, c["K"], c["time_step_factors"], c["velocity"],
                        "convergence")
out = Path(snakemake.output.manifest).parent
log.info("%d %s convergence runs into %s", len(runs), engine, out)
sweep = run_sweep(engine, runs, out).raise_first()
with open(snakemake.output.manifest, "w") as f:
    json.dump({"engine": engine, "engine_seconds": sweep.engine_seconds,
               "dumps": [str(sweep.dumps[r.name]) for r in runs]}, f, indent=1)
log.info("%d runs in an engine process of %.2f s", len(runs), sweep.engine_seconds)
