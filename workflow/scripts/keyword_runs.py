"""Snakemake script: one build's restitution keywords told every e of config `keywords:`, a ladder
each, in one engine process; their rows of the promise table (analysis.keyword_promise).

No verdict is withdrawn or marked stale: these runs are not the study's results (log_to, not
start_rule)."""

import pandas as pd

from common import log_to
from contact_model.keywords import KEYWORDS
from engines import run_sweep
from engines.builds import Build, check_build
from engines.plan import keyword_table_plan
from analysis.keyword_promise import COLUMNS, promise_rows, sweep_metrics
from records.run_manifest import write_manifest

log = log_to(snakemake.log[0])
k = snakemake.params.keywords
build = Build(**snakemake.params.build)
banner = check_build(build)
# Every restitution keyword of the build's code that its release has, told every e, a ladder each, as the
# study's plan refuses and ladders them (engines.plan.keyword_table_plan).
keywords, plan = keyword_table_plan(k, build.code, banner, snakemake.params.ladder, build.id)
V = float(k["velocity"])
runs = plan.runs
log.info("%s (%s): %s told %d restitutions, %d runs into %s", build.id, banner, ", ".join(keywords),
         len(k["restitution"]), len(runs), snakemake.output.runs)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s)
metrics, failures = sweep_metrics(sweep)
rows = []
for name in keywords:
    keyword = KEYWORDS[name]
    rows += promise_rows(build.id, build.code, keyword, plan.of(name), metrics, failures)
    rows += [{"code": build.code, "build": build.id, "keyword": name, "e_requested": e, "V": V,
              "criterion": keyword.criterion, "problem": f"not run: {why}"}
             for (kw, e), why in plan.refused.items() if kw == name]
pd.DataFrame(rows, columns=COLUMNS).to_csv(snakemake.output.rows, index=False, float_format="%.12g")
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs if r.name in sweep.dumps],
               sweep.failed_runs(runs), case="keywords", build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs landed, %d failed; engine process %.2f s", len(sweep.dumps), len(failures), sweep.engine_seconds)
