"""Snakemake script: every run of one case in one engine, in one engine process.

A failed run of a gated (viscoelastic) law fails the rule, naming the run and the engine log.
A failed run of an out-of-the-box law is recorded in the manifest and reported as a finding:
that law is compared, not validated.
"""

import json
from pathlib import Path

from common import log_to
from contact_model import load_case
from engines import GATED_LAWS, run_sweep
from engines.plan import plan_runs

log = log_to(snakemake.log[0])
s = snakemake.params.settings
engine = snakemake.wildcards.engine
case = load_case(snakemake.input.case)
runs = plan_runs(case, [engine], s["laws"], s["K_grid"], s["time_step_factor"], s["default_law_match_K"],
                 s["max_overlap_ratio"]).runs
out = Path(snakemake.output.manifest).parent
log.info("%s: %d %s runs into %s", case.name, len(runs), engine, out)
sweep = run_sweep(engine, runs, out)
law = {r.name: r.law for r in runs}
for name, err in sweep.failures.items():
    log.warning("run failed: %s", err)
gated = [err for name, err in sweep.failures.items() if law[name] in GATED_LAWS]
if gated:
    raise gated[0]
with open(snakemake.output.manifest, "w") as f:
    json.dump({"case": case.name, "engine": engine, "engine_seconds": sweep.engine_seconds,
               "dumps": [str(sweep.dumps[r.name]) for r in runs if r.name in sweep.dumps],
               "failed": [{"run": n, "law": law[n], "problem": e.problem, "log": e.log_path}
                          for n, e in sweep.failures.items()]}, f, indent=1)
log.info("%d runs landed, %d out-of-the-box runs failed; engine process %.2f s",
         len(sweep.dumps), len(sweep.failures), sweep.engine_seconds)
