"""The reference values the reports show, computed here so that the report solves nothing: the
reference solution on the plots' K grid (`reference_curve`) and the viscoelastic model's
restitution beside each restitution keyword's run (`model_restitution`), both for a summary
table at once (`report_references`), and the rows of a summary table a report shows
(`report_rows`).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from contact_model import GATED_LAWS
from contact_model.laws import KEYWORD_LAWS
from reference import solve_collision, solve_collisions

from .checks import with_build


def report_rows(table: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """(full, shown, limits, ladder_runs) of a summary table: all its rows (with a build column,
    `with_build`); those the report shows against K (the ladders' limits, dt = 0, and the runs of
    laws without ladders; every row of a table from before ladders); the limits; the gated
    ladders' rungs.

    Parameters
    ----------
    table : DataFrame
        A summary table (results summary.csv rows), with columns law, K and, from ladder studies on,
        dt (0 for a ladder's limit).
    """
    table = with_build(table)
    full = table
    is_limit = (table.dt == 0) if "dt" in table.columns else pd.Series(False, index=table.index)
    ladder_runs = table[~is_limit & table.law.isin(GATED_LAWS)]
    limits = table[is_limit]
    table = table[is_limit | ~table.law.isin(GATED_LAWS)] if is_limit.any() else table
    return full, table, limits, ladder_runs


def reference_curve(K_max: float, reference: pd.DataFrame | None = None):
    """The reference solution on a K grid up to K_max: the study's reference table
    (results/reference/collisions.csv, solved once by its own rule) where it reaches K_max,
    solved here otherwise.

    Parameters
    ----------
    K_max : float
        The largest K of the curve [-].
    reference : DataFrame or None
        The study's reference table (results/reference/collisions.csv), with a K column; None or too
        short: solved here on 200 K from 0 to K_max.
    """
    if reference is not None and len(reference) and reference.K.max() >= K_max:
        return reference[reference.K <= K_max].reset_index(drop=True)
    return solve_collisions(np.linspace(0.0, K_max, 200))


def model_restitution(K: float, criterion: str) -> float:
    """The viscoelastic model's restitution at K by `criterion` (x0 or F0); NaN outside 0 < K <= 10.

    Parameters
    ----------
    K : float
        The dissipation parameter [-].
    criterion : str
        The end of contact, 'x0' or 'F0'.
    """
    return solve_collision(float(K))[f"eps_{criterion}"] if 0 < K <= 10 else math.nan


def report_references(table: pd.DataFrame, reference: pd.DataFrame | None = None) -> dict:
    """What a report of the summary table `table` shows of the reference solver: ``curve``, the
    reference solution up to the plots' K range (max(0.5, 1.05 max K) of the rows shown,
    `reference_curve`, from the study's table `reference` where it reaches that far; None without
    rows), and ``model_restitution``, {(K, criterion): eps} of the viscoelastic model at each
    restitution keyword's row (`model_restitution`).

    Parameters
    ----------
    table : DataFrame
        A summary table, as for `report_rows` (columns law, K, criterion, dt).
    reference : DataFrame or None
        The study's reference table, as for `reference_curve`.
    """
    _, shown, _, _ = report_rows(table)
    has_rows = len(shown) > 0
    K_max = max(0.5, float(shown.K.max()) * 1.05) if has_rows else 0.5
    curve = reference_curve(K_max, reference) if has_rows else None
    keyword_rows = shown[shown.law.isin(KEYWORD_LAWS)] if has_rows else shown.iloc[:0]
    model = {}
    for K, criterion in zip(keyword_rows.K, keyword_rows.criterion):
        if (float(K), criterion) not in model:
            model[(float(K), criterion)] = model_restitution(K, criterion)
    return {"curve": curve, "model_restitution": model}
