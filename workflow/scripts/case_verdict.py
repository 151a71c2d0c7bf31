"""Snakemake script: one case's checks and verdict (what `snakemake <case>` gates on).

The same checks as the study's (postprocess.gate), over this case's plan, summary and manifests.
It withdraws nothing: it changes no result.
"""

import json

import pandas as pd

from common import log_to
from postprocess.gate import gate_checks, verdict_of, write_junit, write_verdict
from records.files import file_sha256
from records.run_manifest import read_manifest

log = log_to(snakemake.log[0])
tolerance = snakemake.params.tolerance
plan = json.load(open(snakemake.input.plan))
manifests = [read_manifest(m) for m in snakemake.input.manifests]
failed = pd.DataFrame([{"engine": m["engine"], **f} for m in manifests for f in m["failed"]])
checks = gate_checks(pd.read_csv(snakemake.input.summary), pd.DataFrame([{"case": plan["case"], **r}
                                                                          for r in plan["runs"]]), failed, tolerance)
verdict = verdict_of(checks, file_sha256(snakemake.input.summary), tolerance)
checks.to_csv(snakemake.output.checks, index=False, float_format="%.12g")
write_junit(checks, snakemake.output.junit)
write_verdict(verdict, snakemake.output.verdict)
log.info("%s: verdict %s (%d checks, %d failing)", plan["case"], verdict["verdict"], verdict["checked"],
         verdict["failed"])
