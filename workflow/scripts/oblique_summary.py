"""Snakemake script: the oblique impacts' summary.csv, checks.csv, report.md with its figures, and
verdict.json (report.oblique_report)."""

import pandas as pd

from common import start_oblique_rule
from report.oblique_report import write_oblique_report

log = start_oblique_rule(snakemake)


def read_all(paths):
    frames = [pd.read_csv(p) for p in paths if open(p).read().strip()]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()


rungs, limits, checks = (read_all(snakemake.input[k]) for k in ("rungs", "limits", "checks"))
summary = pd.concat([rungs, limits], ignore_index=True)
summary.to_csv(snakemake.output.summary, index=False, float_format="%.17g")
checks.to_csv(snakemake.output.checks, index=False, float_format="%.6g")
verdict = write_oblique_report(summary, limits, checks, snakemake.output.report, snakemake.output.verdict,
                               snakemake.output.figures, float(snakemake.params.tolerance),
                               junit_path=snakemake.output.junit)
log.info("oblique impacts: %s (%d checks)", verdict["verdict"], len(checks))
