"""Snakemake script: one case's checks, verdict and report (what `snakemake <case>` gates on).

The same checks as the study's (verdict.gate), over this case's plan, summary and manifests,
and the study's report (report.report) of this case alone: results/<case>/report.md, .html
and plots/. It changes no result of the study's.

Its first act is to withdraw the case's PASS stamp (results/<case>/gate.txt): Snakemake removed
this rule's own outputs before it started, and the stamp, the case gate's output, must not stand
beside no verdict, nor survive this rule's failure (a full disk, a read-only plots folder). The
files are written by `verdict.gate.write_verdict_files`, verdict.json last.
"""

import json
from pathlib import Path

import pandas as pd

from common import log_to
from contact_model import Body, ContactPair
from engines.codes import CODES
from verdict.gate import gate_checks, verdict_of, write_verdict_files
from report.report import ReportInputs, stale_build_folders, write_report
from analysis.report_references import report_references
from analysis.timestep_maps import case_error_bands
from report.report_timestep import case_error_maps
from verdict.verdict_files import withdraw_gate
from records.files import file_sha256
from records.run_manifest import read_manifest

log = log_to(snakemake.log[0])
folder = Path(snakemake.output.md).parent
if withdraw_gate(folder):
    log.info("withdrew %s: the case's verdict is being made anew", folder / "gate.txt")
tolerance = snakemake.params.tolerance
plan = json.load(open(snakemake.input.plan))
manifests = [read_manifest(m) for m in snakemake.input.manifests]
failed = [{"case": plan["case"], "build": m.get("build", m["engine"]), "engine": m["engine"], **f}
          for m in manifests for f in m["failed"]]
table = pd.read_csv(snakemake.input.summary)
checks = gate_checks(table, pd.DataFrame([{"case": plan["case"], **r} for r in plan["runs"]]), pd.DataFrame(failed),
                     tolerance)
verdict = verdict_of(checks, file_sha256(snakemake.input.summary), tolerance)
for warning in verdict["warnings"]:
    log.warning("%s", warning)
builds = list(snakemake.params.builds)
code_notes = {code: CODES[code].notes for code in dict.fromkeys(b["code"] for b in snakemake.params.builds.values())}


def report():
    """The case's report, its time-step section (its laws' errors against dt / T_R,
    report.report_timestep) first."""
    pairs = {g: ContactPair(g, Body(**p["body_1"]), Body(**p["body_2"]), p["E"], p["eta"])
             for g, p in plan["pairs"].items()}
    (folder / "plots").mkdir(parents=True, exist_ok=True)
    reference = pd.read_csv(snakemake.input.reference)
    _, timestep = case_error_maps(plan, case_error_bands(plan, pairs), folder / "plots" / "timestep.png")
    write_report(ReportInputs(table, checks, verdict, pd.read_csv(snakemake.input.series), failed_runs=failed,
                              not_run=plan["not_run"], not_available=plan.get("not_available", []), builds=builds,
                              plan_notes=plan.get("notes", []), timestep=timestep,
                              stale_folders=stale_build_folders(Path(snakemake.output.md).parent, builds),
                              code_notes=code_notes, ladder=snakemake.params.ladder,
                              reference=reference, references=report_references(table, reference),
                              title=f"Viscoelastic Hertz contact in DEM engines: case {plan['case']}",
                              folder=folder.as_posix()), folder)


write_verdict_files(checks, verdict, snakemake.output, report=report)
log.info("%s: verdict %s (%d checks, %d failing; tolerance %s)", plan["case"], verdict["verdict"], verdict["checked"],
         verdict["failed"], verdict["tolerance"])
