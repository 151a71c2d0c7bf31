"""Snakemake script: the LAMMPS wall hertz/material regression case in one LAMMPS build."""

import pandas as pd

from common import start_rule
from engines.builds import Build
from engines.lammps import wall_modulus_regression
from engines.script_engine import first_line_with
from postprocess.collision_metrics import collision_metrics
from postprocess.comparison import comparison_rows
from postprocess.dump_file import read_dump

log = start_rule(snakemake)
build = Build(**snakemake.params.build)
poisson = snakemake.params.poisson
(explicit, material), sweep = wall_modulus_regression(snakemake.output.runs, poisson=poisson,
                                                      executable=build.executable, build=build.id)
sweep.raise_first()
rows = []
for spec, words in ((explicit, "hertz kn = 4/3 E*"), (material, "hertz/material E eta nu")):
    meta, c = read_dump(sweep.dumps[spec.name])
    m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"], meta["impact_velocity"])
    (row,) = [r for r in comparison_rows(meta, m) if r["criterion"] == "x0"]
    # The 2021 defect's signature: a wall E* (1 + nu) times too large gives T off by (1 + nu)^(-2/5) - 1.
    rows.append({"build": build.id, "engine_version": meta["engine_version"], "case": "wall modulus",
                 "wall model": words, "poisson": poisson, "delta_max": m.delta_max, "T": m.T_x0,
                 "err_A": row["err_A"], "err_T": row["err_T"],
                 "err_T_if_1-nu_defect": (1 + poisson) ** -0.4 - 1 if spec is material else 0.0})
pd.DataFrame(rows).to_csv(snakemake.output.csv, index=False, float_format="%.6g")
log.info("%s", rows)
