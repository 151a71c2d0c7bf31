"""One engine run beside the reference solver and the paper's series: the rows of summary.csv.

A run gives one row per criterion it represents (see `engines.run_spec.RunSpec.represents`).
For criterion c the engine's values are

    T = T_c,  A = pi R* delta_max,  eps = eps_c,  Q1 = A^{1/2} T^2,  Q2 = A / (sqrt(V V') T), V' = eps V,
    delta_max,  F_max   (records.quantities: every entry of its table),

the reference values are the same from the ODE solution at the run's K (times the Hertz scales
of the run), and the series values are the paper's truncated series (eqs. 4-7) times the same
scales. Relative errors: engine vs reference (err_*) and series vs reference (series_err_*).
"""

from __future__ import annotations

import math

from reference import paper_series_value, solve_collisions

from records.collision_metrics import CollisionMetrics, quantities_of
from records.quantities import QUANTITIES, reference_values

#: The quantities of a summary row, in order (records.quantities).
QUANTITY_NAMES = tuple(QUANTITIES)


def measured(T: float, A: float, eps: float, V: float) -> dict[str, float]:
    """T, A, eps plus Q1 = A^{1/2} T^2 and Q2 = A / (sqrt(V eps V) T) (SI).

    Parameters
    ----------
    T : float
        Contact time [s].
    A : float
        pi R* delta_max [m^2].
    eps : float
        Restitution [-].
    V : float
        Impact velocity [m/s].
    """
    return {"T": T, "A": A, "eps": eps, "Q1": math.sqrt(A) * T**2, "Q2": A / (math.sqrt(eps) * V * T)}


def hertz_Q(T_e: float, A_e: float, V: float) -> dict[str, float]:
    """Q1e = A_e^{1/2} T_e^2 and Q2e = A_e / (V T_e).

    Parameters
    ----------
    T_e : float
        Hertz's contact time [s].
    A_e : float
        pi R* delta_e [m^2].
    V : float
        Impact velocity [m/s].
    """
    return {"Q1": math.sqrt(A_e) * T_e**2, "Q2": A_e / (V * T_e)}


def comparison_rows(meta: dict, m: CollisionMetrics, reference_row: dict | None = None,
                    series=None) -> list[dict]:
    """The summary rows of one run. `meta` is its dump header; `reference_row` may be passed
    to reuse a solution of the ODE at the run's K; `series` is a table as
    `reference.series.load_paper_series` gives (default: the paper's, parsed once per process).

    Parameters
    ----------
    meta : dict
        The run's dump header (`records.dump_file.read_dump`): K, impact_velocity [m/s], T_e [s],
        A_e [m^2], effective_radius [m], time_step [s], represents (its criteria), case, engine, law,
        geometry, engine_version, and optionally build, delta_e [m], effective_mass [kg], ladder,
        time_step_factor, roundoff_floor, matched_restitution.
    m : records.collision_metrics.CollisionMetrics
        The run's collision, extracted from its dump.
    reference_row : dict or None
        A row of `reference.solve_collisions` at the run's K (solved here when None).
    series : DataFrame or None
        The paper's series coefficients, as `reference.series.load_paper_series` gives (None: the
        paper's).
    """
    K, V = meta["K"], meta["impact_velocity"]
    T_e, A_e, R = meta["T_e"], meta["A_e"], meta["effective_radius"]
    r = reference_row or solve_collisions([K]).row(0)
    Qe = hertz_Q(T_e, A_e, V)
    scale = {"T": T_e, "A": A_e, "eps": 1.0, **Qe}
    paper = {name: float(paper_series_value(q.series, K, series)) * scale[name] if q.series else math.nan
             for name, q in QUANTITIES.items()}
    delta_e = meta.get("delta_e", A_e / (math.pi * R))
    F_e = meta["effective_mass"] * V**2 / delta_e if "effective_mass" in meta else math.nan
    rows = []
    scales = {"T_e": T_e, "A_e": A_e, "delta_e": delta_e, "F_e": F_e}
    for criterion in meta["represents"]:
        engine = quantities_of(m, criterion, R, V)
        ref = reference_values(r, criterion, scales, R, V)
        row = {
            "case": meta["case"], "build": meta.get("build", meta["engine"]), "engine": meta["engine"],
            "engine_version": meta["engine_version"],
            "law": meta["law"], "geometry": meta["geometry"], "criterion": criterion,
            "V": V, "K": K, "dt": meta["time_step"], "T_e": T_e, "A_e": A_e, "Q1e": Qe["Q1"], "Q2e": Qe["Q2"],
            "samples_in_contact": m.samples_in_contact,
            # the ladder's columns (analysis.extrapolation): which ladder, its rung's step in
            # units of T_e, where contact started and ended on the step grid, the round-off floor
            "ladder": meta.get("ladder", ""), "time_step_factor": meta.get("time_step_factor", math.nan),
            "h": meta["time_step"] / T_e, "start_phase": m.start_phase, "end_phase": m.end_phase,
            "roundoff_floor": meta.get("roundoff_floor", math.nan),
        }
        for q in QUANTITIES:
            row[q] = engine[q]
            row[f"{q}_ref"] = ref[q]
            row[f"{q}_series"] = paper[q]
        for q in QUANTITIES:
            row[f"err_{q}"] = engine[q] / ref[q] - 1.0 if ref[q] else math.nan
        for q in QUANTITIES:
            row[f"series_err_{q}"] = paper[q] / ref[q] - 1.0 if ref[q] else math.nan
        if "matched_restitution" in meta:
            row["matched_restitution"] = meta["matched_restitution"]
        if "told_input" in meta:  # a keyword told its own input (yade:betan's beta), not a restitution
            row["told_input"] = meta["told_input"]
        rows.append(row)
    return rows
