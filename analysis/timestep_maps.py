"""The time-step advisor's maps for the reports (`report.report_timestep` draws them):

- a case report's errors against dt / T_R (0.02-0.5) over the contact's start phases, for each of
  its laws (`case_error_bands`, `error_bands`);
- the study's report: the largest dt / T_R that holds 1e-2, 1e-3 and 1e-4 at every phase, for the
  viscoelastic law over K and for each code's restitution keyword over e (`largest_steps`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pandas as pd

from contact_model.keywords import KEYWORDS, keyword_reference
from contact_model.laws import DAMPING_POWER
from engines.codes import CODES, keyword_of
from reference import solve_collision

from .map_reference import map_law
from .timestep import Collision, errors_at, largest_step

#: The steps of the case reports' error maps [T_R] and the tolerances drawn and tabulated.
FRACTIONS = np.geomspace(0.02, 0.5, 10)
TOLERANCES = (1e-2, 1e-3, 1e-4)
#: Start phases per step in the figures (the advisor itself takes 24).
FIGURE_PHASES = (np.arange(12) + 0.5) / 12
#: What the study's figure shows: T, A and eps, the gated quantities, the worst of them.
SHOWN = ("T", "A", "eps")


def collision_of_run(run: dict, pair) -> Collision:
    """The advisor's collision of one run of a plan listing (engines.plan.plan_listing) in `pair`.

    Parameters
    ----------
    run : dict
        A run of the plan listing: law, engine, K [-], velocity [m/s], reference (the reference
        solver's row), matched_restitution (a keyword's told restitution [-], or absent).
    pair : contact_model.contact_pair.ContactPair
        The run's contact pair (its geometry, scales and Rayleigh time).
    """
    coefficient, power, clipped = map_law({"law": run["law"], "engine": run["engine"], "K": run["K"],
                                           "matched_restitution": run.get("matched_restitution")})
    keyword = keyword_of(run["law"], run["engine"])
    criterion = KEYWORDS[keyword].criterion if keyword else ("F0" if run["law"] == "viscoelastic_clipped" else "x0")
    s = pair.scales(run["velocity"])
    return Collision(law=run["law"] if not keyword or run["law"] != "default" else f"default ({run['engine']})",
                     geometry=pair.geometry, power=power, coefficient=coefficient, clipped=clipped,
                     criterion=criterion, reference=run["reference"], V=run["velocity"], T_e=s["T_e"],
                     T_R=pair.rayleigh_time(), delta_e=s["delta_e"], K=run["K"])


def error_bands(collisions: list[Collision]) -> pd.DataFrame:
    """Per collision, step (FRACTIONS of T_R) and quantity: the min, median and max relative error
    over FIGURE_PHASES (NaN where the step cannot be read).

    Parameters
    ----------
    collisions : list of Collision
        The collisions mapped.
    """
    rows = []
    for c in collisions:
        for x in FRACTIONS:
            e = errors_at(c, x * c.T_R * c.V / c.delta_e, FIGURE_PHASES)
            for q in SHOWN:
                v = np.abs(e[q])
                ok = np.isfinite(v).all()
                rows.append({"law": c.law, "geometry": c.geometry, "K": c.K, "V": c.V, "quantity": q,
                             "dt_over_T_R": x, "abs_err_min": float(v.min()) if ok else math.nan,
                             "abs_err_max": float(v.max()) if ok else math.nan})
    return pd.DataFrame(rows)


def case_error_bands(plan: dict, pairs: dict) -> pd.DataFrame:
    """A case report's time-step bands (`error_bands`): for each geometry and law of the plan, the
    run closest to K = 0.1 (a keyword's told restitution), its errors mapped over dt / T_R; laws
    that run one equation share a band. Empty when the plan has no run.

    Parameters
    ----------
    plan : dict
        The case's plan listing (`engines.plan.plan_listing`): ``runs``, each a dict with geometry,
        law, engine, K [-], velocity [m/s], reference.
    pairs : dict
        {geometry: contact_model.contact_pair.ContactPair} of the case.
    """
    chosen = {}
    for run in plan["runs"]:
        key = (run["geometry"], run["law"], run["engine"] if run["law"] == "default" else "")
        if key not in chosen or abs(run["K"] - 0.1) < abs(chosen[key]["K"] - 0.1):
            chosen[key] = run
    if not chosen:
        return pd.DataFrame()
    # One band per equation: laws that run the same one (LIGGGHTS's and ESyS's keywords and LAMMPS's
    # coeff_restitution; YADE's en and betan and Kratos; the two linear dashpots) share a label.
    same: dict[tuple, Collision] = {}
    for run in chosen.values():
        c = collision_of_run(run, pairs[run["geometry"]])
        key = (c.geometry, c.power, round(c.coefficient, 6), c.clipped, c.criterion)
        same[key] = replace(same[key], law=f"{same[key].law}, {c.law}") if key in same else c
    collisions = list(same.values())
    return error_bands(collisions)


def largest_steps(pair, K_values, restitutions, tolerances=TOLERANCES) -> pd.DataFrame:
    """The largest dt / T_R holding each tolerance at every phase for T, A and eps (the worst of
    them): the viscoelastic law at each K of `K_values`, each code's restitution keyword told each
    e of `restitutions` (`pair` at 1 m/s). Columns: law, K, e, tolerance, dt_max_over_T_R.

    Parameters
    ----------
    pair : contact_model.contact_pair.ContactPair
        The contact pair.
    K_values : iterable of float
        The viscoelastic law's dissipation parameters [-] (each at the velocity giving it).
    restitutions : iterable of float
        The restitutions each code's keyword is told [-].
    tolerances : iterable of float
        The relative errors to hold [-].
    """
    rows = []
    for K in K_values:
        V = pair.velocity_for_dissipation(K)
        s = pair.scales(V)
        c = Collision(law="viscoelastic", geometry=pair.geometry, power=0.5, coefficient=K, clipped=False,
                      criterion="x0", reference=solve_collision(K), V=V, T_e=s["T_e"], T_R=pair.rayleigh_time(),
                      delta_e=s["delta_e"], K=K)
        cache = {}
        for tol in tolerances:
            worst = min(largest_step(c, tol, FIGURE_PHASES, cache)[q] for q in SHOWN)
            rows.append({"law": "viscoelastic", "K": K, "e": math.nan, "tolerance": tol, "dt_max_over_T_R": worst})
    s = pair.scales(1.0)
    # One curve per equation: the codes whose keywords compute the same one share it.
    equations: dict[tuple, list[str]] = {}
    for code in CODES:
        k = KEYWORDS[CODES[code].keyword]
        key = (k.form, k.clipped, round(k.b(k.told_for(0.5)), 6))
        equations.setdefault(key, []).append(code)
    for codes in equations.values():
        k = KEYWORDS[CODES[codes[0]].keyword]
        for e in restitutions:
            if k.refuses(k.told_for(e)):
                continue
            row = keyword_reference(k.name, e)
            c = Collision(law=k.name, geometry=pair.geometry, power=DAMPING_POWER[k.form], coefficient=row["b"],
                          clipped=k.clipped, criterion=k.criterion, reference=row, V=1.0, T_e=s["T_e"],
                          T_R=pair.rayleigh_time(), delta_e=s["delta_e"], K=math.nan)
            cache = {}
            for tol in tolerances:
                worst = min(largest_step(c, tol, FIGURE_PHASES, cache)[q] for q in SHOWN)
                rows.append({"law": " = ".join(f"{code} default" for code in codes), "K": math.nan, "e": e,
                             "tolerance": tol, "dt_max_over_T_R": worst})
    return pd.DataFrame(rows)
