"""The record an oblique deck writes (LAMMPS's and LIGGGHTS's `fix print`; YADE's and ESyS's
comma-separated rows, `deck_record`): read and checked before it becomes a dump, so that a run whose
record is unreadable, short, of another width, not finite or holding no collision fails, named,
instead of writing a dump that looks valid."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from records.collision_metrics import ExtractionError, collision_metrics
from records.dump_file import OBLIQUE_COLUMNS
from records.text_rows import read_rows

from .errors import EngineRunFailed
from .oblique_run import ObliqueRun


def deck_record(engine: str, run: ObliqueRun, status: dict, raw: Path, log: Path) -> np.ndarray:
    """The rows of the comma-separated record a Python-driven deck (YADE's, ESyS's) wrote of `run`,
    once its status says the run landed: the per-run failure bookkeeping of those drivers.

    Parameters
    ----------
    engine : str
        The engine's name, leading the message of a run the deck reports failed.
    run : ObliqueRun
        The run (its name is the failure's).
    status : dict
        The deck's status of the run: ``{"ok": True, ...}`` or ``{"ok": False, "error": str}``.
    raw : Path
        The record: a header line, then one comma-separated row per step (SI).
    log : Path
        The engine's log, named in a failure.

    Returns
    -------
    numpy.ndarray
        One row per line of the record (2-D even for one row); its width is the caller's to check.

    Raises
    ------
    EngineRunFailed
        ``"<engine>: <error>"`` where the deck reports the run failed; the record cannot be read.
    """
    if not status["ok"]:
        raise EngineRunFailed(run.name, f"{engine}: {status['error']}", log)
    try:
        return read_rows(raw, delimiter=",", skiprows=1)
    except (OSError, ValueError) as err:
        raise EngineRunFailed(run.name, f"unreadable engine record {raw}: {err}", log)


def read_oblique_record(raw: Path, run: ObliqueRun, log: Path, first_row=None) -> np.ndarray:
    """The engine's record of `run` as an array of the 8 columns of `records.dump_file.OBLIQUE_COLUMNS`.

    Parameters
    ----------
    raw : Path
        The record: a header line, then one row per step (SI).
    run : ObliqueRun
        The run it records (its name, and its normal velocity for the collision's extraction) [m/s].
    log : Path
        The engine's log, named in a failure.
    first_row : sequence of float, optional
        A row put before the record's first (a code whose record starts at step 1: the state at t = 0).

    Returns
    -------
    numpy.ndarray
        One row per sample, 8 columns (SI).

    Raises
    ------
    EngineRunFailed
        The record cannot be read, has fewer than 3 rows or another width, holds NaN or inf, or no
        collision can be extracted from its normal columns.
    """
    try:
        data = read_rows(raw, delimiter=None, skiprows=1)
    except (OSError, ValueError) as err:
        raise EngineRunFailed(run.name, f"unreadable engine record {raw}: {err}", log)
    if data.shape[0] < 3 or data.shape[1] != len(OBLIQUE_COLUMNS):
        raise EngineRunFailed(run.name, f"engine record {raw} has {data.shape[0]} rows of {data.shape[1]} "
                              f"columns, not {len(OBLIQUE_COLUMNS)}", log)
    if not np.all(np.isfinite(data)):
        row = int(np.nonzero(~np.all(np.isfinite(data), axis=1))[0][0])
        raise EngineRunFailed(run.name, f"the engine produced NaN or inf (record row {row + 1})", log)
    if first_row is not None:
        data = np.vstack([first_row, data])
    try:
        collision_metrics(*data[:, :4].T, impact_velocity=run.normal.velocity)
    except ExtractionError as err:
        raise EngineRunFailed(run.name, str(err), log)
    return data
