"""The study's engine-independent dump: one CSV per engine run, with a commented header.

Format (version 1)::

    # hertz-dem-dump: 1
    # engine: "liggghts"
    # engine_version: "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, ...)"
    # case: "steel"
    # ... one line per metadata key, the value JSON-encoded ...
    time,overlap,normal_velocity,normal_force
    0,-1.2e-07,1,0
    ...

Columns (SI): time [s]; overlap delta [m] (negative before contact, where the engine reports
the gap); normal_velocity d(delta)/dt [m/s] (positive while approaching); normal_force [N]
(positive when repulsive). Every engine's driver writes this format; nothing downstream knows
which engine made a dump.

An oblique run (`engines.oblique_run`) adds four columns after these (OBLIQUE_COLUMNS), in the
conventions of docs/physics.md ("Oblique impacts": normal +x from body 1 to body 2, tangential
+y, spins about +z): tangential_velocity v_y1 - v_y2 [m/s] (the centres' relative tangential
velocity), omega_1 and omega_2 [rad/s] (0 for a plane), tangential_force [N] (the y component
of the contact force on body 1). A head-on dump has the four columns alone; a reader that
needs the tangential ones asks for them (`read_dump(..., oblique=True)`).
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import numpy as np

from .files import write_atomically
from .text_rows import read_rows

FORMAT_VERSION = 1
COLUMNS = ("time", "overlap", "normal_velocity", "normal_force")
OBLIQUE_COLUMNS = COLUMNS + ("tangential_velocity", "omega_1", "omega_2", "tangential_force")


class DumpError(ValueError):
    """A dump that cannot be used; the message names the file."""


def write_dump(path, meta: dict, data: np.ndarray) -> None:
    """Write `data` (N x 4, COLUMNS, or N x 8, OBLIQUE_COLUMNS) under a header made from `meta`,
    atomically.

    The file appears under its name only once it is complete, so an interrupted run never
    leaves a dump that looks valid.

    Parameters
    ----------
    path : str or os.PathLike
        Where to write it.
    meta : dict
        The header's metadata (build, engine version, case parameters, time step [s], ...).
    data : numpy.ndarray
        N x 4 samples: time [s], overlap [m], normal velocity [m/s], normal force [N]; or N x 8,
        those and the oblique run's tangential velocity [m/s], spins [rad/s] and tangential
        force [N] (OBLIQUE_COLUMNS).
    """
    path = Path(path)
    data = np.asarray(data, dtype=float)
    if data.ndim != 2 or data.shape[1] not in (len(COLUMNS), len(OBLIQUE_COLUMNS)):
        raise ValueError(f"dump data must have the {len(COLUMNS)} columns {COLUMNS} or the {len(OBLIQUE_COLUMNS)} "
                         f"columns {OBLIQUE_COLUMNS}, got shape {data.shape}")
    columns = COLUMNS if data.shape[1] == len(COLUMNS) else OBLIQUE_COLUMNS
    buf = io.StringIO()
    buf.write(f"# hertz-dem-dump: {FORMAT_VERSION}\n")
    for key, value in meta.items():
        buf.write(f"# {key}: {json.dumps(value)}\n")
    buf.write(",".join(columns) + "\n")
    # The rows as np.savetxt(fmt="%.17g", delimiter=",") writes them, character for character,
    # in one formatting call instead of one per row (it was most of an engine job's own time).
    row = ",".join(["%.17g"] * len(columns)) + "\n"
    buf.write((row * len(data)) % tuple(data.ravel().tolist()))
    write_atomically(path, buf.getvalue())


def read_dump(path, oblique: bool = False) -> tuple[dict, dict[str, np.ndarray]]:
    """Read a dump: (metadata dict, {column: array}).

    Parameters
    ----------
    path : str or os.PathLike
        The dump file (hertz-dem-dump: 1).
    oblique : bool
        Require the oblique run's columns too (OBLIQUE_COLUMNS); False: the four head-on ones,
        which an oblique dump also has (its other columns are then returned as well).
    """
    path = Path(path)
    try:
        content = path.read_bytes()
    except OSError as err:
        raise DumpError(f"{path}: cannot read dump: {err.strerror}")
    return parse_dump(content, path, oblique)


def parse_dump(content: bytes, path, oblique: bool = False) -> tuple[dict, dict[str, np.ndarray]]:
    """A dump's bytes as `read_dump` reads them: (metadata dict, {column: array}). For a caller that
    holds the bytes already (`records.run_manifest.verified_dump` hashes the very bytes it parses, so
    that the file cannot change between the check and the read).

    Parameters
    ----------
    content : bytes
        The dump file's bytes (hertz-dem-dump: 1, UTF-8).
    path : str or os.PathLike
        Where they were read from: for the error messages only.
    oblique : bool
        Require the oblique run's columns too (as `read_dump`).
    """
    path = Path(path)
    meta: dict = {}
    try:
        lines = content.decode("utf-8").splitlines()
    except UnicodeDecodeError as err:
        raise DumpError(f"{path}: not a text file (byte {err.start} is not UTF-8)")
    body_start = 0
    for body_start, line in enumerate(lines):
        if not line.startswith("#"):
            break
        key, _, value = line[1:].partition(":")
        try:
            meta[key.strip()] = json.loads(value)
        except json.JSONDecodeError:
            raise DumpError(f"{path}: header line {body_start + 1} is not 'key: <json>': {line!r}")
    if meta.get("hertz-dem-dump") != FORMAT_VERSION:
        raise DumpError(f"{path}: not a hertz-dem-dump version {FORMAT_VERSION} file")
    header = tuple(lines[body_start].split(",")) if body_start < len(lines) else ()
    allowed = (OBLIQUE_COLUMNS,) if oblique else (COLUMNS, OBLIQUE_COLUMNS)
    if header not in allowed:
        raise DumpError(f"{path}: expected the column line {' or '.join(','.join(c) for c in allowed)}")
    columns = header
    if not any(line.strip() for line in lines[body_start + 1:]):
        raise DumpError(f"{path}: no data rows")  # before numpy, which would warn about it too
    try:
        data = read_rows(lines[body_start + 1:])
    except ValueError as err:
        raise DumpError(f"{path}: unreadable data: {err}")
    if data.shape[0] == 0 or data.shape[1] != len(columns):
        raise DumpError(f"{path}: no data rows")
    if not np.all(np.isfinite(data)):
        row = int(np.nonzero(~np.all(np.isfinite(data), axis=1))[0][0])
        raise DumpError(f"{path}: non-finite value (NaN or inf) in data row {row + 1}")
    return meta, {c: data[:, i] for i, c in enumerate(columns)}


def finite_or_none(x: float):
    """JSON has no NaN: metadata numbers that may be NaN go through this.

    Parameters
    ----------
    x : float
        A metadata number, possibly NaN or infinite.
    """
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else x
