"""Observed order of convergence of the engines' errors in the time step.

For a quantity whose error behaves like C dt^p, p is the slope of log|error| against log dt.
It is fitted by least squares over the step sizes whose error stands clear of round-off
(|error| > 1e-11, above the round-off floor of ~1e-12); fewer than three such points give no order (NaN).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

NOISE = 1e-11


def observed_order(dt, error) -> float:
    """Least-squares slope of log|error| against log dt (NaN if < 3 points above NOISE)."""
    dt, error = np.asarray(dt, float), np.abs(np.asarray(error, float))
    keep = error > NOISE
    if keep.sum() < 3:
        return float("nan")
    return float(np.polyfit(np.log(dt[keep]), np.log(error[keep]), 1)[0])


def largest_passing_factor(factors, error, tolerance: float):
    """The smallest time-step factor (largest dt = T_e/factor) from which on every finer step
    meets the tolerance; None if even the finest fails."""
    order = np.argsort(factors)[::-1]  # finest first
    passing = None
    for i in order:
        if abs(error[i]) > tolerance:
            break
        passing = factors[i]
    return passing


def convergence_table(errors: pd.DataFrame, tolerance: dict) -> pd.DataFrame:
    """Orders and largest passing dt per engine build x geometry x K x criterion x quantity."""
    from .gate import with_build

    errors = with_build(errors)
    rows = []
    for keys, g in errors.groupby(["build", "geometry", "K", "criterion"]):
        g = g.sort_values("time_step_factor")
        for q in ("T", "A", "eps"):
            f = g.time_step_factor.to_numpy()
            e = g[f"err_{q}"].to_numpy()
            rows.append({**dict(zip(["build", "geometry", "K", "criterion"], keys)), "quantity": q,
                         "order": observed_order(1.0 / f, e),
                         "error_at_T_e/1000": float(e[f == 1000][0]) if (f == 1000).any() else float("nan"),
                         "largest_passing_dt": (f"T_e/{int(p)}" if (p := largest_passing_factor(f, e, tolerance[q]))
                                                else "none")})
    return pd.DataFrame(rows)
