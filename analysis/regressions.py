"""The table of an engine's regression cases (e.g. `engines.lammps.regression_cases`), per build.

One row per case and role: the contact written the way a user would write it ('user') and the
same contact written the way the study writes it ('control'), each run as a ladder of time steps
and extrapolated to dt -> 0 like the gated runs (`analysis.extrapolation`): the relative
errors in T, A and eps against the reference solver (criterion x0) with their resolution or,
for a ladder with a run that did not complete, the problem. `verdict.gate.regression_checks`
turns it into (non-gating) checks.
"""

from __future__ import annotations

import math

import pandas as pd

from engines.plan import rungs_of

from records.collision_metrics import collision_metrics
from .comparison import comparison_rows
from records.dump_file import read_dump
from records.quantities import gated_quantities
from .extrapolation import extrapolated_rows


def regression_table(cases, sweep, build: str) -> pd.DataFrame:
    """The rows of `cases` (each with name, description, user_writes, run, control, defect_err_T)
    as run in `sweep` (an `engines.Sweep`) by build id `build`.

    Parameters
    ----------
    cases : iterable
        Regression cases (`engines.lammps.regression_cases`), each with name, description,
        user_writes, run and control (`engines.run_spec.RunSpec`s, each run as the ladder
        `engines.plan.rungs_of` makes of it) and defect_err_T [-].
    sweep : engines.Sweep
        The runs done: ``dumps`` ({run name: dump path}) and ``failures`` ({run name: why}).
    build : str
        The build id the cases ran as.

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
                   "geometry": spec.pair.geometry, "K": spec.K, "run": spec.ladder,
                   "defect_err_T": case.defect_err_T if role == "user" else None}
            rungs = rungs_of(spec)
            failed = [r.name for r in rungs if r.name in sweep.failures or r.name not in sweep.dumps]
            if failed:  # a ladder that did not complete: its checks fail, naming why
                problem = sweep.failures.get(failed[0], f"{failed[0]}: no dump")
                row.update(engine_version="", problem=str(problem), err_T=math.nan, err_A=math.nan, err_eps=math.nan)
                rows.append(row)
                continue
            limit = ladder_limit(rungs, sweep, "x0")
            row.update(engine_version=limit["engine_version"], problem="",
                       **{f"{k}_{q}": limit[f"{k}_{q}"] for q in gated_quantities()
                          for k in ("err", "resolution", "rungs")})
            rows.append(row)
    return pd.DataFrame(rows)


def ladder_limit(rungs, sweep, criterion: str) -> dict:
    """The limit row dt -> 0 (`analysis.extrapolation`: err_<q>, resolution_<q>, rungs_<q> for
    T, A and eps) of one ladder's dumps in `sweep` (an `engines.Sweep`), under `criterion` ('x0'
    or 'F0').

    Parameters
    ----------
    rungs : sequence of engines.run_spec.RunSpec
        The ladder's rungs (`engines.plan.rungs_of`).
    sweep : engines.Sweep
        The runs done; ``dumps`` must hold each rung's dump.
    criterion : str
        The end of contact, 'x0' or 'F0'.
    """
    runs = []
    for spec in rungs:
        meta, c = read_dump(sweep.dumps[spec.name])
        m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                              meta["impact_velocity"])
        runs += [{**r, "run": spec.name} for r in comparison_rows(meta, m) if r["criterion"] == criterion]
    (limit,) = extrapolated_rows(pd.DataFrame(runs)).to_dict("records")
    return limit
