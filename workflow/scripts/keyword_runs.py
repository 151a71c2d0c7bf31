"""Snakemake script: one build's restitution keyword told every e of config `keywords:`, a ladder
each, in one engine process; its rows of the promise table (postprocess.keyword_promise).

No verdict is withdrawn or marked stale: these runs are not the study's results (log_to, not
start_rule)."""

import pandas as pd

from common import log_to
from contact_model import load_case
from contact_model.keywords import KEYWORDS, keyword_reference
from engines import RunSpec, run_sweep
from engines.builds import Build
from engines.codes import CODES
from engines.plan import ladder_factors
from postprocess.keyword_promise import COLUMNS, promise_rows
from records.collision_metrics import collision_metrics
from records.dump_file import read_dump
from records.run_manifest import write_manifest

log = log_to(snakemake.log[0])
k = snakemake.params.keywords
build = Build(**snakemake.params.build)
keyword = KEYWORDS[CODES[build.code].keyword]
pair = load_case(snakemake.input.case).pair(k["geometry"])
V = float(k["velocity"])
K = pair.dissipation_parameter(V)
rungs_by_e, refused = {}, {}
for e in k["restitution"]:
    if keyword.refuses(float(e)):  # not run: the engine would stop the whole sweep there
        refused[float(e)] = keyword.refuses(float(e))
        continue
    row = keyword_reference(keyword.name, float(e), K)
    rungs_by_e[float(e)] = [RunSpec("keywords", build.code, "default", pair, V, f, matched_restitution=float(e),
                                    build=build.id, reference=row)
                            for f in ladder_factors(snakemake.params.ladder, "default", K)]
runs = [r for rungs in rungs_by_e.values() for r in rungs]
log.info("%s: %s told %d restitutions, %d runs into %s", build.id, keyword.name, len(rungs_by_e), len(runs),
         snakemake.output.runs)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s)
metrics = {}
for name, path in sweep.dumps.items():
    meta, c = read_dump(path)
    metrics[name] = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                                      impact_velocity=meta["impact_velocity"])
failures = {name: str(err) for name, err in sweep.failures.items()}
rows = promise_rows(build.id, build.code, keyword, rungs_by_e, metrics, failures)
rows += [{"code": build.code, "build": build.id, "keyword": keyword.name, "e_requested": e, "V": V,
          "criterion": keyword.criterion, "problem": f"not run: {why}"} for e, why in refused.items()]
pd.DataFrame(rows, columns=COLUMNS).to_csv(snakemake.output.rows, index=False, float_format="%.12g")
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs if r.name in sweep.dumps],
               sweep.failed_runs(runs), case="keywords", build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs landed, %d failed; engine process %.2f s", len(sweep.dumps), len(failures), sweep.engine_seconds)
