"""Snakemake script: the study's report (report.md, report.html and plots/).

It shows the verdict the checks rule decided (checks.csv, verdict.json; verdict.gate), FAIL
at the top, and links every case's own report, every build comparison and the calibration.
"""

import json
from pathlib import Path

import pandas as pd

from common import log_to
from analysis.report_references import report_references
from engines.codes import CODES
from report.report import ReportInputs, write_report
from verdict.verdict_files import withdraw_gate
from records.run_manifest import read_manifest

log = log_to(snakemake.log[0])
out = Path(snakemake.output.md).parent
withdraw_gate(out)  # the study's PASS stamp goes while its report is remade (verdict.verdict_files)
table = pd.read_csv(snakemake.input.summary)
checks = pd.read_csv(snakemake.input.checks)
verdict = json.loads(Path(snakemake.input.verdict).read_text())
manifests = [read_manifest(m) for m in snakemake.input.manifests]
plans = [json.load(open(p)) for p in snakemake.input.plans]
failed_runs = [{"case": m["case"], "build": m.get("build", m["engine"]), "engine": m["engine"], **f}
               for m in manifests for f in m["failed"]]
timing = {"engine jobs": len(manifests),
          "engine process seconds (sum)": round(sum(m["engine_seconds"] for m in manifests), 2)}
not_run = [row for p in plans for row in p["not_run"]]
not_available = [row for p in plans for row in p.get("not_available", [])]  # plans from before codes had none
builds = list(snakemake.params.builds)  # config order: the rows of the report's matrix
code_notes = {code: CODES[code].notes for code in dict.fromkeys(b["code"] for b in snakemake.params.builds.values())}
# The other reports, linked with their verdicts: each case's, each build comparison's.
case_reports = []
for path, report in zip(snakemake.input.case_verdicts, snakemake.input.case_reports):
    v = json.loads(Path(path).read_text())
    case_reports.append({"case": Path(path).parent.name, "verdict": v["verdict"], "checked": v["checked"],
                         "failed": v["failed"], "report": Path(report).relative_to(out).as_posix()})
comparisons = []
for path in snakemake.input.comparisons:
    status = pd.read_csv(path).status.value_counts()
    folder = Path(path).parent
    comparisons.append({"pair": folder.name, "report": (folder / "compare.html").relative_to(out).as_posix(),
                        **{s: int(status.get(s, 0)) for s in ("regression", "fix", "unchanged", "new", "removed")}})
optional = {key: pd.read_csv(snakemake.input[key])
            for key in ("convergence", "convergence_orders", "convergence_spread", "largest_steps", "regressions",
                        "claims", "table1", "energy_check")
            if key in snakemake.input.keys()}
if "calibration" in snakemake.input.keys():
    optional["calibration"] = Path(snakemake.input.calibration).read_text()
if "oblique" in snakemake.input.keys():
    optional["oblique"] = Path(snakemake.input.oblique).read_text()
optional["reference"] = pd.read_csv(snakemake.input.reference)  # the curves of the plots, solved by its own rule
optional["references"] = report_references(table, optional["reference"])  # what the report shows of the solver
write_report(ReportInputs(table, checks, verdict, pd.read_csv(snakemake.input.series), timing, not_run, failed_runs,
                          builds=builds, not_available=not_available, code_notes=code_notes,
                          plan_notes=[note for p in plans for note in p.get("notes", [])],
                          ladder=snakemake.params.ladder, case_reports=case_reports, comparisons=comparisons,
                          **optional), out, workers=snakemake.threads)
log.info("report for verdict %s: %s", verdict["verdict"], snakemake.output.md)
