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

The file must be a regular file of at most MAX_BYTES (1 MB; its kind and size checked before it is
read: a device such as /dev/zero is refused unread) with at most MAX_ROWS data rows (counted before
they are parsed), and hold at least
MIN_ROWS (3) rows at MIN_VELOCITIES (2) or more distinct velocities: the fit of eta has one
parameter and the calibration's model checks (a residual trend in V, a constant loss) two, and
each needs a degree of freedom left to estimate the scatter.

Every refusal is a `MeasurementError` (a `contact_model.CaseError`) naming the file, the row
(data row and line number) and the column: too few rows or velocities, eps <= 0 or eps > 1, a
non-positive velocity, a missing unit, a malformed number. A message repeats a cell only escaped
and cut short, and a header cell only when it looks like a column name: the text of a file that
is no measurement file (a stray /etc/passwd) is never repeated.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .quantities import NUMBER, CaseError, quantity, shown
from .strict_yaml import read_utf8

COLUMNS = ("velocity", "restitution", "rebound_velocity", "restitution_uncertainty",
           "rebound_velocity_uncertainty")
#: Columns that hold a velocity (a unit in the header or in every cell).
VELOCITY_COLUMNS = ("velocity", "rebound_velocity", "rebound_velocity_uncertainty")
_HEADER = re.compile(r"\s*([A-Za-z_]+)\s*(?:\[([^\]]*)\])?\s*")
_PLAIN = re.compile(NUMBER)
#: A header cell that a message may repeat: a short name, with a short unit in brackets.
_NAME_LIKE = re.compile(r"[A-Za-z_]{1,40}(?:\s*\[[^\]]{0,20}\])?")
#: The largest measurement file read [bytes]: a few thousand rows of a few numbers; checked before reading.
MAX_BYTES = 1_000_000
#: The most data rows read (each is a solve of the collision in every step of the fit).
MAX_ROWS = 10_000
#: The fewest data rows the calibration fits: 1 parameter (K at V_max) for eta, 2 for its model
#: checks (a line through the residuals against ln V; the constant loss xi_0 beside K), each with
#: a degree of freedom left for the scatter.
MIN_ROWS = 3
#: The fewest distinct impact velocities: a trend in V needs two.
MIN_VELOCITIES = 2


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
        """'row i+1 (line n)' of the i-th data row (0-based), for messages.

        Parameters
        ----------
        i : int
            The index of the data row, 0-based [-].

        Returns
        -------
        str
        """
        return f"row {i + 1} (line {self.lines[i]})"


def _plain_number(text: str, path, where: str) -> float:
    if not _PLAIN.fullmatch(text):
        raise MeasurementError(path, where, f"cannot read {shown(text)} as a plain number (write e.g. 0.857; "
                                            "no comma decimals, digit groups, units or text here)")
    x = float(text)
    if not math.isfinite(x):
        raise MeasurementError(path, where, f"{shown(text)} is beyond double precision")
    return x


def _velocity_cell(text: str, unit_factor: float | None, path, where: str) -> float:
    """A velocity cell [m/s]: a plain number times the header's unit, or a quantity."""
    if unit_factor is not None:
        return _plain_number(text, path, where) * unit_factor
    if _PLAIN.fullmatch(text):
        raise MeasurementError(path, where, f"{shown(text)} has no unit: give the unit in the header "
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
            named = (f"unknown column {cell!r}" if _NAME_LIKE.fullmatch(cell) else
                     f"not a column name ({len(cell)} characters of other text, not shown: is this a measurement "
                     "file?)")
            raise MeasurementError(path, where, f"{named}; known: {', '.join(COLUMNS)} "
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
                raise MeasurementError(path, where, f"the unit {shown(unit)} of {name!r}: {err.problem}") from None
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
    """Validate the text of measurement file `path`; see the module docstring.

    Parameters
    ----------
    text : str
        The file's text.
    path : str or pathlib.Path
        The file, named in every message.

    Returns
    -------
    Measurements
        The impact velocities [m/s] and restitution coefficients [-] in SI, in file order.

    Raises
    ------
    MeasurementError
        Naming the file, the row and the problem.
    """
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
    if len(rows) - 1 > MAX_ROWS:
        raise MeasurementError(path, "(file)", f"has {len(rows) - 1} data rows; at most {MAX_ROWS} are read")
    header_line, header_text = rows[0]
    parsed = []
    for n, t in rows:
        try:
            parsed.append((n, next(csv.reader([t], strict=True))))
        except csv.Error as err:
            raise MeasurementError(path, f"line {n}", f"not valid CSV: {shown(str(err), 120)}") from None
    columns = _header([c.strip() for c in parsed[0][1]], path, header_line)
    data = parsed[1:]
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
            raise MeasurementError(path, where, f"the impact velocity must be positive, got {shown(text)}")
        if "restitution" in columns:
            text, _, where = cell("restitution")
            e = _plain_number(text, path, where)
        else:
            text, factor, where = cell("rebound_velocity")
            e = _velocity_cell(text, factor, path, where) / v
        if not 0 < e <= 1:
            raise MeasurementError(path, where, f"the restitution coefficient must lie in (0, 1], got {e:g}"
                                   + ("" if "restitution" in columns else f" (rebound {shown(text)} / impact)"))
        s = None
        if "restitution_uncertainty" in columns:
            text, _, where = cell("restitution_uncertainty")
            s = _plain_number(text, path, where)
        elif "rebound_velocity_uncertainty" in columns:
            text, factor, where = cell("rebound_velocity_uncertainty")
            s = _velocity_cell(text, factor, path, where) / v
        if s is not None and not s > 0:
            raise MeasurementError(path, where, f"an uncertainty must be positive, got {shown(text)}")
        V.append(v), eps.append(e), sigma.append(s), lines.append(line)
    if len(data) < MIN_ROWS:  # after the rows: a wrong cell is named first
        raise MeasurementError(path, "(file)", _too_few(f"{len(data)} data row(s)"))
    if distinct_velocities(V) < MIN_VELOCITIES:
        raise MeasurementError(path, "(file)", _too_few(f"{len(V)} rows, all at one impact velocity ({V[0]:g} m/s)"))
    return Measurements(str(path), np.array(V), np.array(eps),
                        None if sigma[0] is None else np.array(sigma), tuple(lines), "\n".join(comments))


def distinct_velocities(velocity) -> int:
    """How many distinct impact velocities there are.

    Equal to 12 significant digits counting as one (200 cm/s and 2 m/s are one velocity, whatever
    the conversion's last bit).

    Parameters
    ----------
    velocity : sequence of float
        The impact velocities [m/s].

    Returns
    -------
    int
        The number of distinct velocities.
    """
    return len({float(f"{v:.12g}") for v in velocity})


def _too_few(what: str) -> str:
    """Why the calibration cannot use `what` (too few rows or velocities), and what it needs."""
    return (f"has {what}; the calibration needs at least {MIN_ROWS} rows at {MIN_VELOCITIES} or more distinct "
            "velocities: its fit of eta has 1 parameter (K at the highest velocity) and its model checks 2 (a line "
            "through the residuals against ln V; a constant loss beside K), each with a degree of freedom left to "
            "estimate the scatter. For eta from one restitution at one velocity: python -m "
            "contact_model.viscosity_for_restitution")


def load_measurements(path) -> Measurements:
    """Read and validate a measurement file (UTF-8 CSV; see the module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The measurement file.

    Returns
    -------
    Measurements
        The impact velocities [m/s] and restitution coefficients [-] in SI, in file order.

    Raises
    ------
    MeasurementError
        Naming the file, the row and the problem.
    """
    path = Path(path)
    return parse_measurements(read_utf8(path, MeasurementError, MAX_BYTES, "a measurement file is a few thousand"),
                              path)
