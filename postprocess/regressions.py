"""The table of an engine's regression cases (e.g. `engines.lammps.regression_cases`), per build.

One row per case and role: the run written the way a user would write the contact ('user') and
the same contact written the way the study writes it ('control'), with the relative errors in T,
A and eps against the reference solver (criterion x0) or, for a run that did not complete, the
problem. `postprocess.gate.regression_checks` turns it into (non-gating) checks.
"""

from __future__ import annotations

import math

import pandas as pd

from .collision_metrics import collision_metrics
from .comparison import comparison_rows
from .dump_file import read_dump


def regression_table(cases, sweep, build: str) -> pd.DataFrame:
    """The rows of `cases` (each with name, description, user_writes, run, control, defect_err_T)
    as run in `sweep` (an `engines.Sweep`) by build id `build`.

    Returns
    -------
    DataFrame with columns build, case, what, role, written as, geometry, K, run, defect_err_T
    (the error in T the known defect predicts, user rows only), engine_version, problem (empty
    when the run landed), err_T, err_A, err_eps (NaN when it did not).
    """
    rows = []
    for case in cases:
        for role, spec in (("control", case.control), ("user", case.run)):
            row = {"build": build, "case": case.name, "what": case.description, "role": role,
                   "written as": case.user_writes if role == "user" else "as the study writes it",
                   "geometry": spec.pair.geometry, "K": spec.K, "run": spec.name,
                   "defect_err_T": case.defect_err_T if role == "user" else None}
            if spec.name in sweep.failures:  # a run that did not complete: its checks fail, naming why
                row.update(engine_version="", problem=str(sweep.failures[spec.name]),
                           err_T=math.nan, err_A=math.nan, err_eps=math.nan)
            else:
                meta, c = read_dump(sweep.dumps[spec.name])
                m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                                      meta["impact_velocity"])
                (x0,) = [r for r in comparison_rows(meta, m) if r["criterion"] == "x0"]
                row.update(engine_version=meta["engine_version"], problem="",
                           err_T=x0["err_T"], err_A=x0["err_A"], err_eps=x0["err_eps"])
            rows.append(row)
    return pd.DataFrame(rows)
