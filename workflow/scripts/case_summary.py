"""Snakemake script: one case's dumps beside the reference and the paper's series (tidy CSV).

One row per run and criterion, then one row per ladder and criterion with dt = 0: the rungs'
errors extrapolated to dt -> 0, with their resolution (analysis.extrapolation), which the
gate judges. Every dump is verified against the sha256 its engine job recorded; a changed,
truncated or unreadable dump stops the rule naming the file. The `dump` column is relative to
the results folder, so that summaries do not depend on where the project lives.
"""

import json
import os
from pathlib import Path

import pandas as pd

from common import start_rule
from analysis.comparison import comparison_rows
from analysis.extrapolation import extrapolated_rows
from analysis.map_reference import map_errors
from records.run_manifest import manifest_dumps

log = start_rule(snakemake)
results = Path(snakemake.output[0]).parent.parent
loaded = [d for m in snakemake.input.manifests for d in manifest_dumps(m)]
# The reference solution of every run was solved once, by the plan: no ODE is solved here.
reference = {r["name"]: r["reference"] for r in json.load(open(snakemake.input.plan))["runs"]}
rows = []
for path, meta, columns, m in loaded:
    # beside the ODE reference, the discrete one: the engines' map replayed at this run's dt
    on_map = map_errors(meta, m, len(columns["time"]))
    for row in comparison_rows(meta, m, reference[Path(path).stem]):  # the paper's series: parsed once
        rows.append({**row, "run": Path(path).stem, "dump": os.path.relpath(path, results),
                     **{f"map_err_{q}": e for q, e in on_map.get(row["criterion"], {}).items()}})
# With no dump at all (every run failed) the table still has its columns: the gate then fails
# every planned check by name instead of the summary rule failing on an empty file.
table = pd.DataFrame(rows) if rows else pd.DataFrame(columns=["case", "build", "engine", "engine_version", "law",
                                                               "geometry",
                                                               "criterion", "V", "K", "dt", "err_T", "err_A", "err_eps",
                                                               "run", "dump", "ladder"])
table = pd.concat([table, extrapolated_rows(table)], ignore_index=True)
table.to_csv(snakemake.output[0], index=False, float_format="%.12g")
log.info("%d rows from %d dumps (%d of them ladder limits, dt = 0)", len(table), len(loaded),
         int((table.dt == 0).sum()))
