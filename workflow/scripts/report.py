"""Snakemake script: the verdict (verdict.json, junit.xml) and the comparison report with its plots.

The checks are decided in `postprocess.gate` from the plans (what should exist), the summary
(what landed) and the manifests (what failed); the report shows them, FAIL at the top.
"""

import json
from pathlib import Path

import pandas as pd

from common import start_rule
from engines.codes import CODES
from postprocess.gate import gate_checks, regression_checks, verdict_of, write_junit, write_verdict
from postprocess.report import ReportInputs, write_report
from records.files import file_sha256
from records.run_manifest import read_manifest

log = start_rule(snakemake)
tolerance = snakemake.params.tolerance
table = pd.read_csv(snakemake.input.summary)
series = pd.read_csv(snakemake.input.series)
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
timing = {"engine jobs": len(manifests),
          "engine process seconds (sum)": round(sum(m["engine_seconds"] for m in manifests), 2)}
not_run = [row for p in plans for row in p["not_run"]]
not_available = [row for p in plans for row in p.get("not_available", [])]  # plans from before codes had none
builds = list(snakemake.params.builds)  # config order: the rows of the report's matrix
code_notes = {code: CODES[code].notes for code in dict.fromkeys(b["code"] for b in snakemake.params.builds.values())}
optional = {key: pd.read_csv(snakemake.input[key])
            for key in ("convergence", "convergence_orders", "convergence_spread", "regressions", "claims", "table1",
                        "energy_check")
            if key in snakemake.input.keys()}
if "calibration" in snakemake.input.keys():
    optional["calibration"] = Path(snakemake.input.calibration).read_text()
optional["reference"] = pd.read_csv(snakemake.input.reference)  # the curves of the plots, solved by its own rule
out = Path(snakemake.output.md).parent
checks.to_csv(snakemake.output.checks, index=False, float_format="%.12g")
write_report(ReportInputs(table, checks, verdict, series, timing, not_run, failed_runs, builds=builds,
                          not_available=not_available, code_notes=code_notes, ladder=snakemake.params.ladder,
                          **optional), out, workers=snakemake.threads)
write_junit(checks, snakemake.output.junit)
write_verdict(verdict, snakemake.output.verdict)  # last: its presence means the rest is written
log.info("verdict: %s (%d checks, %d failing)", verdict["verdict"], verdict["checked"], verdict["failed"])
for failure in verdict["failures"]:
    log.warning("FAIL %s", failure)
