"""From the rungs of each ladder to its limit dt -> 0: the rows the gate judges.

A gated run is a ladder of runs that differ in their time step alone (`engines.ladder`, the
summary's ``ladder`` column). For every ladder and criterion, `extrapolated_rows` makes one row
of the same columns as a run's, with ``dt`` = 0 (the limit), and

    err_q         the relative error engine vs reference extrapolated to dt -> 0 (q: the gated
                  quantities of `records.quantities`, T, A, eps; the derived ones, Q1 and Q2,
                  follow from them), and T, A, eps the engine's values in that limit;
    estimate_q    the ladder's own bound of what the extrapolation leaves (`engines.ladder`);
    roundoff      what the round-off of positions can leave: sqrt(sum_k (w_k floor_k)^2), w the
                  Richardson weights and floor_k each rung's `RunSpec.roundoff_floor`;
    resolution_q  max(estimate_q, roundoff, RESOLUTION_FLOOR): the smallest error of q this ladder
                  can tell from 0 (`engines.ladder.RESOLUTION_FLOOR`: 1e-8, where the estimate
                  stops being a series' and becomes rounding);
    order_q       the observed order of the rungs' errors about the limit (1 for the
                  dissipative laws, 2 for the elastic one: the engines' map);
    rungs_q       the rungs' raw errors, coarsest first, ';'-separated, and rung_factors the
                  rungs' T_e / dt;
    map_err_q     of the rungs' differences from the engines' map replayed at their own dt
                  (`analysis.map_reference`), the largest in magnitude (signed);
    phase_offset  the largest distance (in steps) of a rung's contact start from the planned
                  phase; a ladder beyond `engines.ladder.PHASE_TOLERANCE` is misaligned, and
                  ``problem`` says so (the gate fails its checks: its limit is not trustworthy).

Every number here follows from the rung rows of summary.csv by the functions of
`engines.ladder`, so a reader can redo it from that table alone.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from engines.ladder import (PHASE_TOLERANCE, RESOLUTION_FLOOR, START_PHASE, extrapolate, ladder_roundoff,
                            phase_offset, powers_of)

from records.quantities import QUANTITIES, gated_quantities


def reported_limits() -> tuple[str, ...]:
    """The quantities reported beside the gated ones, extrapolated the same way (no resolution,
    no gate): those read off the collision that the gate does not judge (the maximum overlap and
    force of the physical-results table), from the table at the call."""
    return tuple(name for name, q in QUANTITIES.items() if not q.gated and q.derive is None)


def limit_derived() -> tuple[str, ...]:
    """The quantities whose limit follows from the gated ones' (Q1, Q2): derived and not gated."""
    return tuple(name for name, q in QUANTITIES.items() if not q.gated and q.derive is not None)

#: Columns a limit row takes from its finest rung unchanged (the run's description).
_DESCRIPTION = ["case", "build", "engine", "engine_version", "law", "geometry", "criterion", "V", "K", "T_e", "A_e",
                "Q1e", "Q2e", "ladder", "eps_ref", "matched_restitution", "told_input"]


def extrapolated_rows(rows: pd.DataFrame) -> pd.DataFrame:
    """One limit row (dt = 0) per ladder and criterion of `rows` (summary rows of runs, with the
    columns of `analysis.comparison.comparison_rows`); ladders of fewer than three rungs
    (a rung that did not land) and runs outside any ladder are left out.

    Parameters
    ----------
    rows : DataFrame
        Summary rows of runs (`analysis.comparison.comparison_rows`), with the columns ladder,
        criterion, h (dt / T_e), law, K, engine, roundoff_floor, start_phase, end_phase,
        time_step_factor, samples_in_contact, err_<q>, <q>_ref, <q>_series and series_err_<q>.

    Returns
    -------
    DataFrame with the columns of `rows` (dt 0, run the ladder's name, dump empty) and those of
    the module's docstring.
    """
    if not len(rows) or "ladder" not in rows.columns:
        return pd.DataFrame()
    out = []
    laddered = rows[rows.ladder.fillna("").astype(str) != ""]
    for (_, criterion), g in laddered.groupby(["ladder", "criterion"], sort=False):
        if len(g) < 3:
            continue
        g = g.sort_values("h", ascending=False)  # coarsest first
        out.append(_limit_row(g))
    return pd.DataFrame(out)


def _limit_row(g: pd.DataFrame) -> dict:
    finest = g.iloc[-1]
    h = g.h.to_numpy(dtype=float)
    # The expansion depends on whether the contact dissipates (K > 0), not on the law's name: an
    # elastic contact written as 'viscoelastic' with eta = 0 converges as dt^2 too.
    powers = powers_of(0.0 if finest.law == "elastic" or float(finest.K) == 0 else 1.0, str(finest.law),
                       str(finest.engine))
    floors = g.roundoff_floor.to_numpy(dtype=float)
    roundoff = ladder_roundoff(h, floors, powers) if np.isfinite(floors).all() else math.nan
    offsets = [phase_offset(p, START_PHASE) for p in g.start_phase.to_numpy(dtype=float)]
    worst_offset = max(offsets, key=abs)
    row = {c: finest[c] for c in _DESCRIPTION if c in g.columns}
    row.update(dt=0.0, h=0.0, time_step_factor=math.inf, run=finest.ladder, dump="",
               samples_in_contact=int(finest.samples_in_contact), rungs=len(g),
               rung_factors=";".join(f"{f:g}" for f in g.time_step_factor), roundoff=roundoff,
               phase_offset=worst_offset, start_phase=float(g.start_phase.iloc[-1]),
               end_phase=float(g.end_phase.iloc[-1]), roundoff_floor=float(floors.max()))
    problem = ""
    if not abs(worst_offset) <= PHASE_TOLERANCE:
        k = int(np.argmax(np.abs(offsets)))
        problem = (f"misaligned ladder: contact starts {offsets[k]:+.3g} steps from the planned phase "
                   f"{START_PHASE:g} at dt = T_e/{g.time_step_factor.iloc[k]:g} (tolerance {PHASE_TOLERANCE:g}): "
                   "its rungs' errors are not one series in dt, so their limit means nothing")
    row["problem"] = problem
    limits = {}
    gated = gated_quantities()
    for q in gated:
        e = extrapolate(h, g[f"err_{q}"].to_numpy(dtype=float), powers)
        limits[q] = e.value
        row.update({f"err_{q}": e.value, f"estimate_{q}": e.estimate, f"order_{q}": e.order,
                    f"resolution_{q}": max(e.estimate, roundoff if math.isfinite(roundoff) else 0.0, RESOLUTION_FLOOR),
                    f"rungs_{q}": ";".join(f"{x:.6e}" for x in g[f"err_{q}"])})
        if f"map_err_{q}" in g.columns and g[f"map_err_{q}"].notna().any():
            on_map = g[f"map_err_{q}"].to_numpy(dtype=float)
            row[f"map_err_{q}"] = float(on_map[np.nanargmax(np.abs(on_map))])
    for q in reported_limits():  # reported, not gated: the limit and the rungs alone
        if f"err_{q}" in g.columns and g[f"err_{q}"].notna().all():
            e = extrapolate(h, g[f"err_{q}"].to_numpy(dtype=float), powers)
            row.update({f"{q}_ref": float(finest[f"{q}_ref"]), f"err_{q}": e.value,
                        q: float(finest[f"{q}_ref"]) * (1.0 + e.value), f"estimate_{q}": e.estimate})
    # The engine's values in the limit, and Q1, Q2 (and their errors) from them.
    following = gated + limit_derived()  # T, A, eps, Q1, Q2
    ref = {q: float(finest[f"{q}_ref"]) for q in following}
    engine = {q: ref[q] * (1.0 + limits[q]) for q in gated}
    values = {**engine, "R": math.nan, "V": float(finest.V)}  # R: no derived one left needs it
    for q in limit_derived():
        engine[q] = values[q] = QUANTITIES[q].derive(values)
    for q in following:
        row[q] = engine[q]
        row[f"{q}_ref"] = ref[q]
        row[f"{q}_series"] = finest[f"{q}_series"]
        row[f"series_err_{q}"] = finest[f"series_err_{q}"]
    for q in limit_derived():
        row[f"err_{q}"] = engine[q] / ref[q] - 1.0
    return row
