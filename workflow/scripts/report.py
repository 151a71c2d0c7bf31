"""Snakemake script: the comparison report, its plots and the verdict the gate reads."""

import json
from pathlib import Path

import pandas as pd

from common import log_to
from postprocess.report import write_report, write_verdict

log = log_to(snakemake.log[0])
table = pd.read_csv(snakemake.input.summary)
series = pd.read_csv(snakemake.input.series)
manifests = [json.load(open(m)) for m in snakemake.input.manifests]
plans = [json.load(open(p)) for p in snakemake.input.plans]
timing = {"engine jobs": len(manifests),
          "engine process seconds (sum)": round(sum(m["engine_seconds"] for m in manifests), 2)}
not_run = [row for p in plans for row in p["not_run"]]
failed = [{"case": m["case"], "engine": m["engine"], **f} for m in manifests for f in m["failed"]]
optional = {key: pd.read_csv(snakemake.input[key])
            for key in ("convergence", "lammps_wall", "claims", "table1", "energy_check")
            if key in snakemake.input.keys()}
result = write_report(table, snakemake.params.tolerance, Path(snakemake.output.md).parent, series, timing,
                      not_run, failed, **optional)
write_verdict(result, snakemake.output.verdict)
log.info("verdict: %s (%d checks); failures: %s", "PASS" if result["pass"] else "FAIL",
         result["checked"], result["failures"] or "none")
