"""Measured restitution coefficients (a CSV file that a case refers to) -> SI arrays.

The format is a tidy CSV, one impact per row, units explicit::

    # Provenance: who measured what, where it was published (lines starting with '#').
    velocity [m/s],restitution,restitution_uncertainty
    0.50,0.857,0.005
    1.00,0.842,0.005

Columns (any order, each at most once; any other column is an error):

``velocity``
    The impact velocity V (relative normal velocity before contact), positive. Either the header
    carries the unit in brackets (``velocity [m/s]``, ``velocity [cm/s]``) and the cells are plain
    numbers, or the header is bare and every cell is a quantity read strictly like a case file's
    (``50 cm/s``). A bare header with a plain number in a cell is a missing unit, refused.
``restitution``
    The restitution coefficient eps = V'/V, dimensionless, in (0, 1]; plain numbers, no unit.
``rebound_velocity``
    Instead of ``restitution``: the rebound velocity V' (same unit rules as ``velocity``);
    eps = V'/V. Exactly one of ``restitution`` and ``rebound_velocity`` is given.
``restitution_uncertainty`` (optional)
    The standard uncertainty of eps in that row, positive, dimensionless. With it the fit is
    weighted and chi^2 is absolute; without it all rows weigh the same and the scatter of the
    residuals estimates the uncertainty.
``rebound_velocity_uncertainty`` (optional, only with ``rebound_velocity``)
    The standard uncertainty of V'; it gives that of eps as sigma_V' / V.

Numbers are plain decimals (``0.857``, ``5e-1``): no comma decimals, digit groups or text. Lines
starting with '#' are comments (the provenance); blank lines are skipped.

Every refusal is a `MeasurementError` (a `contact_model.CaseError`) naming the file, the row
(data row and line number) and the column: fewer than 2 rows, eps <= 0 or eps > 1, a
non-positive velocity, a missing unit, a malformed number.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .quantities import NUMBER, CaseError, quantity
from .strict_yaml import read_utf8

COLUMNS = ("velocity", "restitution", "rebound_velocity", "restitution_uncertainty",
           "rebound_velocity_uncertainty")
#: Columns that hold a velocity (a unit in the header or in every cell).
VELOCITY_COLUMNS = ("velocity", "rebound_velocity", "rebound_velocity_uncertainty")
_HEADER = re.compile(r"\s*([A-Za-z_]+)\s*(?:\[([^\]]*)\])?\s*")
_PLAIN = re.compile(NUMBER)
MAX_BYTES = 10_000_000


class MeasurementError(CaseError):
    """A measurement file that cannot be used; names the file, the row and the column."""

    def __init__(self, path, where: str, problem: str):
        super().__init__(path, where, problem)
        self.args = (f"{path}: {where}: {problem}",)

    def __str__(self):
        return self.args[0]


@dataclass(frozen=True)
class Measurements:
    """Measured eps(V) of one contact (SI).

    Attributes
    ----------
    path : the file read.
    velocity : impact velocities V [m/s], in file order.
    restitution : eps = V'/V [-].
    uncertainty : standard uncertainty of eps per row [-], or None (unweighted fit).
    lines : the file line of each row (1-based), for messages.
    provenance : the comment lines, '#' removed, joined by newlines.
    """

    path: str
    velocity: np.ndarray
    restitution: np.ndarray
    uncertainty: np.ndarray | None
    lines: tuple[int, ...]
    provenance: str

    def __len__(self) -> int:
        return len(self.velocity)

    def where(self, i: int) -> str:
        """'row i+1 (line n)' of the i-th data row (0-based)."""
        return f"row {i + 1} (line {self.lines[i]})"


def _plain_number(text: str, path, where: str) -> float:
    if not _PLAIN.fullmatch(text):
        raise MeasurementError(path, where, f"cannot read {text!r} as a plain number (write e.g. 0.857; "
                                            "no comma decimals, digit groups, units or text here)")
    x = float(text)
    if not math.isfinite(x):
        raise MeasurementError(path, where, f"{text!r} is beyond double precision")
    return x


def _velocity_cell(text: str, unit_factor: float | None, path, where: str) -> float:
    """A velocity cell [m/s]: a plain number times the header's unit, or a quantity."""
    if unit_factor is not None:
        return _plain_number(text, path, where) * unit_factor
    if _PLAIN.fullmatch(text):
        raise MeasurementError(path, where, f"{text!r} has no unit: give the unit in the header "
                                            "(e.g. 'velocity [m/s]') or in the cell (e.g. '0.5 m/s')")
    try:
        return quantity(text, "velocity", path)
    except CaseError as err:
        raise MeasurementError(path, where, err.problem) from None


def _header(cells: list[str], path, line: int) -> dict[str, tuple[int, float | None]]:
    """{column: (index, SI factor of the header's unit or None)}."""
    columns: dict[str, tuple[int, float | None]] = {}
    for index, cell in enumerate(cells):
        match = _HEADER.fullmatch(cell)
        where = f"header (line {line}), column {index + 1}"
        if not match or match.group(1) not in COLUMNS:
            raise MeasurementError(path, where, f"unknown column {cell!r}; known: {', '.join(COLUMNS)} "
                                                "(velocities with a unit: 'velocity [m/s]')")
        name, unit = match.group(1), match.group(2)
        if name in columns:
            raise MeasurementError(path, where, f"column {name!r} is given twice")
        factor = None
        if unit is not None:
            if name not in VELOCITY_COLUMNS:
                raise MeasurementError(path, where, f"{name!r} is dimensionless: write it without a unit")
            try:
                factor = quantity(f"1 {unit.strip()}", "velocity", path)
            except CaseError as err:
                raise MeasurementError(path, where, f"the unit [{unit}] of {name!r}: {err.problem}") from None
        columns[name] = (index, factor)
    if "velocity" not in columns:
        raise MeasurementError(path, f"header (line {line})", "no 'velocity' column (e.g. 'velocity [m/s]')")
    if ("restitution" in columns) == ("rebound_velocity" in columns):
        raise MeasurementError(path, f"header (line {line})",
                               "give exactly one of 'restitution' and 'rebound_velocity [unit]'")
    if "rebound_velocity_uncertainty" in columns and "rebound_velocity" not in columns:
        raise MeasurementError(path, f"header (line {line})",
                               "'rebound_velocity_uncertainty' needs a 'rebound_velocity' column")
    if "rebound_velocity_uncertainty" in columns and "restitution_uncertainty" in columns:
        raise MeasurementError(path, f"header (line {line})",
                               "give one of 'restitution_uncertainty' and 'rebound_velocity_uncertainty'")
    return columns


def parse_measurements(text: str, path) -> Measurements:
    """Validate the text of measurement file `path` (used in messages); see the module docstring."""
    comments, rows = [], []
    for number, raw in enumerate(io.StringIO(text), start=1):
        stripped = raw.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            comments.append(stripped[1:].strip())
            continue
        rows.append((number, raw))
    if not rows:
        raise MeasurementError(path, "(file)", "has no header and no data rows")
    header_line, header_text = rows[0]
    try:
        parsed = [(n, next(csv.reader([t], strict=True))) for n, t in rows]
    except csv.Error as err:
        raise MeasurementError(path, "(file)", f"not valid CSV: {err}")
    columns = _header([c.strip() for c in parsed[0][1]], path, header_line)
    data = parsed[1:]
    if len(data) < 2:
        raise MeasurementError(path, "(file)", f"has {len(data)} data row(s); a fit needs at least 2")
    V, eps, sigma, lines = [], [], [], []
    for i, (line, cells) in enumerate(data):
        row = f"row {i + 1} (line {line})"
        if len(cells) != len(parsed[0][1]):
            raise MeasurementError(path, row, f"has {len(cells)} cells, the header {len(parsed[0][1])}")

        def cell(name):
            index, factor = columns[name]
            return cells[index].strip(), factor, f"{row}, column '{name}'"

        text, factor, where = cell("velocity")
        v = _velocity_cell(text, factor, path, where)
        if not v > 0:
            raise MeasurementError(path, where, f"the impact velocity must be positive, got {text!r}")
        if "restitution" in columns:
            text, _, where = cell("restitution")
            e = _plain_number(text, path, where)
        else:
            text, factor, where = cell("rebound_velocity")
            e = _velocity_cell(text, factor, path, where) / v
        if not 0 < e <= 1:
            raise MeasurementError(path, where, f"the restitution coefficient must lie in (0, 1], got {e:g}"
                                   + ("" if "restitution" in columns else f" (rebound {text!r} / impact)"))
        s = None
        if "restitution_uncertainty" in columns:
            text, _, where = cell("restitution_uncertainty")
            s = _plain_number(text, path, where)
        elif "rebound_velocity_uncertainty" in columns:
            text, factor, where = cell("rebound_velocity_uncertainty")
            s = _velocity_cell(text, factor, path, where) / v
        if s is not None and not s > 0:
            raise MeasurementError(path, where, f"an uncertainty must be positive, got {text!r}")
        V.append(v), eps.append(e), sigma.append(s), lines.append(line)
    return Measurements(str(path), np.array(V), np.array(eps),
                        None if sigma[0] is None else np.array(sigma), tuple(lines), "\n".join(comments))


def load_measurements(path) -> Measurements:
    """Read and validate a measurement file (UTF-8 CSV; see the module docstring)."""
    path = Path(path)
    return parse_measurements(read_utf8(path, MeasurementError, MAX_BYTES, "a measurement file is a few kB"), path)
