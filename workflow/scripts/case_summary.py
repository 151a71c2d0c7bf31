"""Snakemake script: one case's dumps beside the reference and the paper's series (tidy CSV)."""

import json

import numpy as np
import pandas as pd

from common import log_to
from postprocess.collision_metrics import collision_metrics
from postprocess.comparison import comparison_rows
from postprocess.dump_file import read_dump
from reference import solve_collisions
from reference.series import load_paper_series

log = log_to(snakemake.log[0])
dumps = [d for m in snakemake.input.manifests for d in json.load(open(m))["dumps"]]
loaded = [read_dump(d) for d in dumps]
Ks = np.unique([meta["K"] for meta, _ in loaded])
reference = dict(zip(Ks, solve_collisions(Ks).rows()))
series = load_paper_series()
rows = []
for path, (meta, c) in zip(dumps, loaded):
    m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                          impact_velocity=meta["impact_velocity"])
    for row in comparison_rows(meta, m, reference[meta["K"]], series):
        rows.append({**row, "dump": path})
table = pd.DataFrame(rows)
table.to_csv(snakemake.output[0], index=False, float_format="%.12g")
log.info("%d rows from %d dumps", len(table), len(dumps))
