"""Time-step convergence of the engines, from production steps (T_e/10) to the ladders' finest rung.

The user's question is which time step they may use in production: DEM codes run at dt = 10 %
to 40 % of the Rayleigh time, i.e. T_e/20 to T_e/50 for typical impacts. The convergence sweep
runs one material at one velocity with eta set for each K, in every build, geometry and
viscoelastic law the build's code can express, at dt = T_e/10 ... T_e/2000 (aligned like the
ladders' rungs: `engines.ladder`). From its errors (engine at dt vs reference solver):

- `convergence_table`: the observed order of each build x law x geometry x K x criterion x
  quantity (least-squares slope of log|error| against log dt over the steps of the ladders'
  range, dt <= T_e/250, where the leading power dominates: 1 with damping, 2 for Hertz alone);
- `largest_dt_table`: for each build x law x criterion x K and threshold, the largest dt that
  keeps T, A and eps within the threshold in both geometries, as T_e/N and as a fraction of
  the Rayleigh time (interpolated in log|error| against log dt between the two sweep steps that
  bracket it; the errors are power laws there);
- `build_spread`: how far the builds' errors differ at the same step, relative to their size
  (errors above round-off only).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from engines.ladder import observed_order

from records.quantities import GATED_QUANTITIES

from .checks import with_build

#: The steps over which the observed order is fitted: the ladders' range (dt <= T_e/250).
ORDER_RANGE = 1.0 / 250.0
KEYS = ["build", "law", "geometry", "K", "criterion"]


def convergence_table(errors: pd.DataFrame) -> pd.DataFrame:
    """Observed orders and the error at each production step, per build x law x geometry x K x
    criterion x quantity.

    Parameters
    ----------
    errors : DataFrame
        One row per run and criterion: build, law, geometry, K, criterion, h (dt / T_e), err_T,
        err_A, err_eps.

    Returns
    -------
    DataFrame with the KEYS, quantity, order (NaN with fewer than two steps in ORDER_RANGE
    above round-off) and one column 'error at T_e/N' per sweep step.
    """
    errors = with_build(errors)
    rows = []
    for keys, g in errors.groupby(KEYS, sort=True):
        g = g.sort_values("h", ascending=False)
        fine = g[g.h <= ORDER_RANGE * (1 + 1e-9)]
        for q in GATED_QUANTITIES:
            row = {**dict(zip(KEYS, keys)), "quantity": q,
                   "order": observed_order(fine.h, fine[f"err_{q}"], noise=1e-11)}
            row.update({f"error at T_e/{round(1 / h):d}": e for h, e in zip(g.h, g[f"err_{q}"])})
            rows.append(row)
    return pd.DataFrame(rows)


def largest_dt(h, error, threshold: float) -> tuple[float, str]:
    """The largest dt / T_e from which on every finer step keeps |error| <= threshold: between
    the finest failing step and the passing one below it, where log|error| (linear in log h)
    meets the threshold. Returns (value, how): how is 'interpolated', 'coarsest' (every step
    passes: at least the coarsest), 'beyond' (the finest step fails: the slope of its last two
    steps carried on below it, as the errors are power laws there) or 'none' (no slope to carry:
    NaN).

    Parameters
    ----------
    h : array_like
        The sweep's steps, dt / T_e [-], in any order.
    error : array_like
        The relative error at each step [-] (signed; its magnitude is compared).
    threshold : float
        The largest |error| allowed [-].
    """
    h, e = np.asarray(h, dtype=float), np.abs(np.asarray(error, dtype=float))
    order = np.argsort(h)  # finest first
    h, e = h[order], e[order]
    if not e[0] <= threshold:
        if len(h) < 2 or not (e[1] > e[0] > 0):
            return math.nan, "none"
        slope = math.log(e[1] / e[0]) / math.log(h[1] / h[0])
        return float(h[0] * (threshold / e[0]) ** (1.0 / slope)), "beyond"
    k = 0
    while k + 1 < len(h) and e[k + 1] <= threshold:
        k += 1
    if k + 1 == len(h):
        return float(h[-1]), "coarsest"
    lo, hi = max(e[k], 1e-300), e[k + 1]
    slope = math.log(hi / lo) / math.log(h[k + 1] / h[k])
    if not slope > 0:
        return float(h[k]), "interpolated"
    return float(h[k] * (threshold / lo) ** (1.0 / slope)), "interpolated"


def largest_dt_table(errors: pd.DataFrame, thresholds, rayleigh: dict) -> pd.DataFrame:
    """The largest time step per build x law x criterion x K and threshold (see `largest_dt`):
    the worst |error| over T, A and eps at each step, the smaller dt of the two geometries.

    Parameters
    ----------
    errors : DataFrame
        As for `convergence_table`.
    thresholds : sequence of float
        Relative errors, e.g. (1e-2, 1e-3, 1e-4).
    rayleigh : dict
        {geometry: T_R / T_e} of the sweep's contact pairs (`ContactPair.rayleigh_time` over the
        Hertz time at the sweep's velocity).

    Returns
    -------
    DataFrame with columns build, law, criterion, K, threshold, dt_over_T_e, T_e_over_dt,
    dt_over_T_R (each the smallest over the geometries), how ('interpolated', 'coarsest': every
    step of the sweep passes, 'beyond': finer than the sweep, extrapolated, 'none').
    """
    errors = with_build(errors)
    rows = []
    for (build, law, criterion, K), g in errors.groupby(["build", "law", "criterion", "K"], sort=False):
        for threshold in thresholds:
            in_Te, in_TR, hows = [], [], []
            for geometry, gg in g.groupby("geometry"):
                worst = gg.assign(worst=gg[[f"err_{q}" for q in GATED_QUANTITIES]].abs().max(axis=1)) \
                    .groupby("h").worst.max()
                value, how = largest_dt(worst.index.to_numpy(), worst.to_numpy(), threshold)
                in_Te.append(value)
                in_TR.append(value / rayleigh[geometry] if geometry in rayleigh else math.nan)
                hows.append(how)
            how = next(x for x in ("none", "beyond", "interpolated", "coarsest") if x in hows)
            dt_Te = math.nan if how == "none" else min(in_Te)
            rows.append({"build": build, "law": law, "criterion": criterion, "K": K, "threshold": threshold,
                         "dt_over_T_e": dt_Te, "T_e_over_dt": 1.0 / dt_Te if dt_Te > 0 else math.nan,
                         "dt_over_T_R": math.nan if how == "none" else min(in_TR), "how": how})
    return pd.DataFrame(rows)


#: Errors below this are round-off (the elastic eps is 1 to 1e-12): their spread says nothing.
SPREAD_FLOOR = 1e-9


SPREAD_COLUMNS = ["law", "geometry", "K", "criterion", "h", "quantity", "builds", "largest_error", "spread"]


def build_spread(errors: pd.DataFrame) -> pd.DataFrame:
    """How far the builds' errors differ at the same law, geometry, K, criterion and step:
    (max - min over the builds) / max |error|, per quantity, for the steps at which two or more
    builds ran and the largest |error| exceeds SPREAD_FLOOR. Returns columns law, geometry, K,
    criterion, h, quantity, builds, largest_error, spread: no rows (but these columns) for a
    study of one build.

    Parameters
    ----------
    errors : DataFrame
        As for `convergence_table`: one row per run and criterion with build (or engine), law,
        geometry, K, criterion, h (dt / T_e), err_T, err_A, err_eps.
    """
    errors = with_build(errors)
    rows = []
    for keys, g in errors.groupby(["law", "geometry", "K", "criterion", "h"], sort=False):
        if g.build.nunique() < 2:
            continue
        for q in GATED_QUANTITIES:
            e = g[f"err_{q}"].to_numpy(dtype=float)
            size = float(np.abs(e).max())
            if not size > SPREAD_FLOOR:
                continue
            rows.append({**dict(zip(["law", "geometry", "K", "criterion", "h"], keys)), "quantity": q,
                         "builds": g.build.nunique(), "largest_error": size,
                         "spread": float((e.max() - e.min()) / size)})
    return pd.DataFrame(rows, columns=SPREAD_COLUMNS)
