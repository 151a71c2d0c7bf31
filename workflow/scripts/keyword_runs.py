"""Snakemake script: one build's restitution keywords told every e of config `keywords:`, a ladder
each, in one engine process; their rows of the promise table (postprocess.keyword_promise).

No verdict is withdrawn or marked stale: these runs are not the study's results (log_to, not
start_rule)."""

import pandas as pd

from common import log_to
from contact_model import load_case
from contact_model.keywords import KEYWORDS, keyword_reference, missing_in
from contact_model.laws import KEYWORD_LAWS
from engines import RunSpec, run_sweep
from engines.builds import Build, check_build
from engines.codes import keyword_of, law_unavailable
from engines.plan import keyword_own_K, ladder_factors
from postprocess.keyword_promise import COLUMNS, promise_rows, sweep_metrics
from records.run_manifest import write_manifest

log = log_to(snakemake.log[0])
k = snakemake.params.keywords
build = Build(**snakemake.params.build)
banner = check_build(build)
# Every restitution keyword of the build's code that its release has: the code's own (law
# `default`) and the others that are laws of their own (LAMMPS 2025: tsuji and coeff_restitution).
keywords = {}
for law_name in KEYWORD_LAWS:
    name = keyword_of(law_name, build.code)
    if (law_unavailable(build.code, law_name) is None and name is not None and KEYWORDS[name].told == "e"
            and not missing_in(name, banner)):
        keywords.setdefault(name, law_name)
pair = load_case(snakemake.input.case).pair(k["geometry"])
V = float(k["velocity"])
K = pair.dissipation_parameter(V)
rungs, refused = {}, {}  # {(keyword, e): ladder}, {(keyword, e): why not run}
for name, law_name in keywords.items():
    keyword = KEYWORDS[name]
    for e in k["restitution"]:
        if keyword.refuses(float(e)):  # not run: the engine would stop the whole sweep there
            refused[(name, float(e))] = keyword.refuses(float(e))
            continue
        row = keyword_reference(name, float(e), K)
        rungs[(name, float(e))] = [RunSpec("keywords", build.code, law_name, pair, V, f, matched_restitution=float(e),
                                           build=build.id, reference=row)
                                   for f in ladder_factors(snakemake.params.ladder, law_name, K,
                                                           keyword_own_K(name, row))]
runs = [r for ladder in rungs.values() for r in ladder]
log.info("%s (%s): %s told %d restitutions, %d runs into %s", build.id, banner, ", ".join(keywords),
         len(k["restitution"]), len(runs), snakemake.output.runs)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s)
metrics, failures = sweep_metrics(sweep)
rows = []
for name in keywords:
    keyword = KEYWORDS[name]
    rows += promise_rows(build.id, build.code, keyword, {e: ladder for (kw, e), ladder in rungs.items() if kw == name},
                         metrics, failures)
    rows += [{"code": build.code, "build": build.id, "keyword": name, "e_requested": e, "V": V,
              "criterion": keyword.criterion, "problem": f"not run: {why}"}
             for (kw, e), why in refused.items() if kw == name]
pd.DataFrame(rows, columns=COLUMNS).to_csv(snakemake.output.rows, index=False, float_format="%.12g")
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs if r.name in sweep.dumps],
               sweep.failed_runs(runs), case="keywords", build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs landed, %d failed; engine process %.2f s", len(sweep.dumps), len(failures), sweep.engine_seconds)
