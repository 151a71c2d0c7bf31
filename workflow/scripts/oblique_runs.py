"""Snakemake script: one build's oblique ladders (analysis.oblique), in one engine process per
MPI rank count: rungs.csv, limits.csv, checks.csv and the manifest of the dumps."""

import pandas as pd

from common import start_oblique_rule
from analysis.oblique import limit_rows, oblique_checks, processor_boundary_checks, rung_rows
from contact_model import load_case
from engines.builds import Build, check_build
from engines.oblique_plan import oblique_plan
from engines.oblique_sweep import run_oblique_sweep
from records.run_manifest import write_manifest

log = start_oblique_rule(snakemake)
o = snakemake.params.oblique
build = Build(**snakemake.params.build)
banner = check_build(build)
reduced = snakemake.wildcards.set == "reduced"
factors = o["ladder"]
# The processor boundary (two MPI ranks) is checked in the full set; the reduced one keeps to `all`'s budget.
ranks = [1] if reduced else o.get("ranks", {}).get(build.code, [1])
cases = [load_case(path) for path in snakemake.input.cases]
plan = oblique_plan(cases, build.code, build.id, banner, factors, ranks, o.get("finer_ladders", []))
if reduced:  # `all`: the reduced set's impacts alone (config oblique.reduced.angles: of the contact point's slip)
    keep = set(o["reduced"]["angles"])
    plan.runs = [r for r in plan.runs if round(r.contact_angle, 6) in keep]
log.info("%s (%s): %d oblique runs (%d ladders) of %d cases; not run: %s", build.id, banner, len(plan.runs),
         len({r.ladder for r in plan.runs}), len(cases), "; ".join(f"{c} {m}: {why}" for (c, m), why in
                                                               plan.refused.items()) or "none")
sweep = run_oblique_sweep(build, plan.runs, snakemake.output.runs, timeout_floor_s=snakemake.params.timeout_floor_s)
rungs = rung_rows(plan.runs, sweep, known_defects=o.get("known_defects", []))
limits = limit_rows(rungs) if len(rungs) else pd.DataFrame()
checks = pd.concat([oblique_checks(limits, float(o["tolerance"]), planned=plan, failures=sweep.failures,
                                   known_defects=o.get("known_defects", [])),
                    processor_boundary_checks(rungs, plan, sweep.failures, o.get("known_defects", []))],
                   ignore_index=True)
rungs.to_csv(snakemake.output.rungs, index=False, float_format="%.17g")
limits.to_csv(snakemake.output.limits, index=False, float_format="%.17g")
checks.to_csv(snakemake.output.checks, index=False, float_format="%.6g")
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in plan.runs if r.name in sweep.dumps],
               sweep.failed_runs(plan.runs), case="oblique", build=build.id, engine=build.code,
               engine_seconds=sweep.engine_seconds)
log.info("%d runs landed, %d failed; engine %.2f s; checks: %s", len(sweep.dumps), len(sweep.failures),
         sweep.engine_seconds, checks.status.value_counts().to_dict() if len(checks) else {})
