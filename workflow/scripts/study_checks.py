"""Snakemake script: the study's checks and verdict (checks.csv, junit.xml, verdict.json).

The checks are decided in `verdict.gate` from the plans (what should exist), the summary
(what landed) and the manifests (what failed); the report rule shows them, FAIL at the top.
start_rule first marks the study's verdict stale (its gate.txt goes); the files are written by
`verdict.gate.write_verdict_files`, verdict.json last.
"""

import json

import pandas as pd

from common import start_rule
from verdict.gate import gate_checks, regression_checks, verdict_of, write_verdict_files
from records.files import file_sha256
from records.run_manifest import read_manifest

log = start_rule(snakemake)
tolerance = snakemake.params.tolerance
table = pd.read_csv(snakemake.input.summary)
manifests = [read_manifest(m) for m in snakemake.input.manifests]
plans = [json.load(open(p)) for p in snakemake.input.plans]
plan_runs = pd.DataFrame([{"case": p["case"], **r} for p in plans for r in p["runs"]])
failed_runs = [{"case": m["case"], "build": m.get("build", m["engine"]), "engine": m["engine"], **f}
               for m in manifests for f in m["failed"]]
checks = gate_checks(table, plan_runs, pd.DataFrame(failed_runs), tolerance)
if "regressions" in snakemake.input.keys():  # the engines' known defects: reported, not gating
    checks = pd.concat([checks, regression_checks(pd.read_csv(snakemake.input.regressions), tolerance)],
                       ignore_index=True)
verdict = verdict_of(checks, file_sha256(snakemake.input.summary), tolerance)
write_verdict_files(checks, verdict, snakemake.output)
log.info("verdict: %s (%d checks, %d failing; tolerance %s)", verdict["verdict"], verdict["checked"],
         verdict["failed"], verdict["tolerance"])
for warning in verdict["warnings"]:
    log.warning("%s", warning)
for failure in verdict["failures"]:
    log.warning("FAIL %s", failure)
