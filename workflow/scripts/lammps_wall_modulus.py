"""Snakemake script: the LAMMPS wall hertz/material regression case (a finding of the report)."""

import pandas as pd

from common import start_rule
from engines.lammps import wall_modulus_regression
from postprocess.collision_metrics import collision_metrics
from postprocess.comparison import comparison_rows
from postprocess.dump_file import read_dump

log = start_rule(snakemake)
(explicit, material), sweep = wall_modulus_regression(snakemake.output.runs, poisson=snakemake.params.poisson)
sweep.raise_first()
rows = []
for spec, words in ((explicit, "hertz kn = 4/3 E*"), (material, "hertz/material E eta nu")):
    meta, c = read_dump(sweep.dumps[spec.name])
    m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"], meta["impact_velocity"])
    (row,) = [r for r in comparison_rows(meta, m) if r["criterion"] == "x0"]
    rows.append({"wall model": words, "poisson": snakemake.params.poisson, "delta_max": m.delta_max, "T": m.T_x0,
                 "err_A": row["err_A"], "err_T": row["err_T"], "expected_err": (1 + snakemake.params.poisson) ** -0.4 - 1
                 if spec is material else 0.0})
pd.DataFrame(rows).to_csv(snakemake.output.csv, index=False, float_format="%.6g")
log.info("%s", rows)
