"""Helpers the gate judges with, below it so that analysis (the release history, the convergence
tables) judges and reads tables as the gate does without importing it: `with_build` (a table's
build column) and `judge` / `judgement` (a check's outcome from its error, resolution and
tolerance). The gate (`verdict.gate`) imports them from here.
"""

from __future__ import annotations

import math

import pandas as pd


def with_build(df: pd.DataFrame) -> pd.DataFrame:
    """`df` with a build column: tables from before engine builds were configurable have none,
    and their build is the engine's code (the only build of each code then).

    Parameters
    ----------
    df : DataFrame
        A results table (summary rows, convergence errors, ...); its ``engine`` column gives the
        build where it has no ``build`` column.
    """
    if "build" in df.columns or "engine" not in df.columns:
        return df
    return df.assign(build=df["engine"])


def judgement(error: float, resolution: float, tolerance: float) -> str:
    """Why a check that is not 'pass' (`judge`) fails, saying what is compared.

    A resolved failure: '4.000e-06 > 1e-06 (resolution 1.6e-07; ' (the caller adds where and the
    closing parenthesis): |error| exceeds the tolerance by more than its resolution. Unresolved:
    'not resolved at this tolerance: |error| + resolution = 5.229e-07 + 5.1e-07 = 1.033e-06 > 1e-06
    >= |error| - resolution = 1.3e-08 (' -- the error alone is within the tolerance, but not with
    its resolution added, so the ladders cannot tell.

    Parameters
    ----------
    error : float
        The check's error (signed) [-].
    resolution : float
        The smallest error the ladder can tell from 0 [-] (NaN counts as 0).
    tolerance : float
        What |error| is judged against [-].
    """
    e, r = abs(error), (0.0 if math.isnan(resolution) else resolution)
    if e - r > tolerance:
        return f"{e:.3e} > {tolerance:g} (resolution {r:.1e}; "
    return (f"not resolved at this tolerance: |error| + resolution = {e:.3e} + {r:.1e} = {e + r:.3e} > {tolerance:g}"
            f" >= |error| - resolution = {e - r:.1e} (")


def judge(error: float, resolution: float, tolerance: float) -> str:
    """'pass' when |error| + resolution <= tolerance, 'fail' when |error| - resolution >
    tolerance (resolved), 'unresolved' between, 'nan' when the error is NaN.

    Parameters
    ----------
    error : float
        The check's error (signed) [-]; NaN gives 'nan'.
    resolution : float
        The smallest error the ladder can tell from 0 [-] (NaN counts as 0).
    tolerance : float
        What |error| is judged against [-].
    """
    if math.isnan(error):
        return "nan"
    r = 0.0 if math.isnan(resolution) else resolution
    if abs(error) + r <= tolerance:
        return "pass"
    return "fail" if abs(error) - r > tolerance else "unresolved"
