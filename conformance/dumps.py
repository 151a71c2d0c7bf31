"""Reading a user's dumps: the study's dump format, or a plain CSV with a column map; every
refusal names the file, the row and the column.

Two formats (docs/conformance.md):

- the study's engine-independent dump (`records.dump_file`, ``# hertz-dem-dump: 1``): columns
  time, overlap, normal_velocity, normal_force in SI, with the header lines ``plan_id`` and
  ``run`` that tie it to its plan and run;
- a plain CSV (one header row of column names; lines starting with '#' are skipped) read through a
  column map (``columns.yaml``): which column is time, and either overlap, normal_velocity and
  normal_force, or the position and velocity of each body along the line of centres (x1, v1, and
  x2, v2 for two spheres; normal_force optional), each with its unit (pint). From positions the
  overlap is R1 + R2 - (x2 - x1) (two spheres) or R1 + x1 (the plane x = 0), its rate v1 - v2 (or
  v1), and without a force column the force is the plan's law evaluated on them.

A file is refused (`Refusal`) for a missing column, an unreadable unit, a value that is no finite
number (NaN), a time that does not increase, a time step or a number of samples other than the
plan's, another plan's id or run name, or too few samples in contact for the extraction.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from contact_model.quantities import units
from records.collision_metrics import PEAK_POINTS
from records.dump_file import COLUMNS, FORMAT_VERSION

MAGIC = "# hertz-dem-dump:"
#: The least samples in contact the extraction takes (records.collision_metrics).
MIN_CONTACT_SAMPLES = PEAK_POINTS + 1
#: How far a dump's time step may be from the plan's, relatively.
DT_TOLERANCE = 1e-6
#: The column map's entries: {name: the pint dimensionality of its unit, the SI unit}.
MAPPED = {"time": ("[time]", "s"), "overlap": ("[length]", "m"), "normal_velocity": ("[length] / [time]", "m/s"),
          "normal_force": ("[force]", "N"), "x1": ("[length]", "m"), "v1": ("[length] / [time]", "m/s"),
          "x2": ("[length]", "m"), "v2": ("[length] / [time]", "m/s")}


class Refusal(ValueError):
    """A file that cannot be gated; the message names the file (and the row and column where one is at fault)."""


@dataclass
class Series:
    """One run's samples in SI, and what its file says of the code that made it."""

    time: np.ndarray
    overlap: np.ndarray
    normal_velocity: np.ndarray
    normal_force: np.ndarray
    engine_version: str = "not given"


@dataclass
class ColumnMap:
    """A columns.yaml: {quantity: (column name, unit, factor to SI)}, and the file it came from."""

    path: Path
    entries: dict
    plan_id: str | None = None

    @property
    def by_position(self) -> bool:
        return "overlap" not in self.entries


def load_column_map(path) -> ColumnMap:
    """Read and check a columns.yaml: every entry {column: name, unit: pint unit} of the right dimension."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as err:
        raise Refusal(f"{path}: cannot read the column map: {err}")
    if not isinstance(data, dict):
        raise Refusal(f"{path}: a column map is a mapping of quantity: {{column: name, unit: unit}}")
    plan_id = data.pop("plan_id", None)
    unknown = set(data) - set(MAPPED)
    if unknown:
        raise Refusal(f"{path}: unknown entr{'y' if len(unknown) == 1 else 'ies'} {', '.join(sorted(unknown))}; "
                      f"known: {', '.join(MAPPED)}")
    need = ["time"] + (["overlap", "normal_velocity", "normal_force"] if "overlap" in data else ["x1", "v1"])
    for name in need:
        if name not in data:
            raise Refusal(f"{path}: no entry {name!r}: the map needs time and either overlap, normal_velocity and "
                          "normal_force, or x1, v1 (and x2, v2 for two spheres)")
    entries = {}
    for name, entry in data.items():
        if not isinstance(entry, dict) or not isinstance(entry.get("column"), str) or "unit" not in entry:
            raise Refusal(f"{path}: entry {name!r}: give {{column: <name in the CSV>, unit: <unit>}}")
        entries[name] = (entry["column"], str(entry["unit"]), _factor(path, name, str(entry["unit"])))
    return ColumnMap(path, entries, plan_id)


def _factor(path, name: str, unit: str) -> float:
    """The factor that takes `unit` to the SI unit of quantity `name`, refusing an unreadable unit or one
    of another dimension."""
    dimension, si = MAPPED[name]
    try:
        q = units().Quantity(1.0, unit)
    except Exception as err:  # pint raises several kinds (UndefinedUnitError, DefinitionSyntaxError, ...)
        raise Refusal(f"{path}: entry {name!r}: unit {unit!r} is not a unit pint reads ({type(err).__name__})")
    if q.dimensionality != units().Quantity(1.0, si).dimensionality:
        raise Refusal(f"{path}: entry {name!r}: unit {unit!r} is {q.dimensionality}, not {dimension}")
    return float(q.to(si).magnitude)


def _numbers(path, names, rows, first_line) -> dict[str, np.ndarray]:
    """{column: floats} of `rows` (lists of cells), refusing a cell that is no finite number, naming it."""
    out = {n: np.empty(len(rows)) for n in names}
    width = len(names)
    for i, cells in enumerate(rows):
        where = f"row {i + 1} (line {first_line + i})"
        if len(cells) != width:
            raise Refusal(f"{path}: {where}: {len(cells)} cells where the header has {width}")
        for name, cell in zip(names, cells):
            try:
                x = float(cell)
            except ValueError:
                raise Refusal(f"{path}: {where}, column {name!r}: {cell[:40]!r} is not a number")
            if not math.isfinite(x):
                raise Refusal(f"{path}: {where}, column {name!r}: {cell.strip()!r} is not a finite number")
            out[name][i] = x
    return out


def read_study_dump(path, run: dict, plan_id: str) -> Series:
    """A dump in the study's format, checked against its run of the plan (`check_series`)."""
    path = Path(path)
    lines = _lines(path)
    meta, n = {}, 0
    while n < len(lines) and lines[n].startswith("#"):
        key, _, value = lines[n][1:].partition(":")
        try:
            meta[key.strip()] = json.loads(value)
        except json.JSONDecodeError:
            raise Refusal(f"{path}: header line {n + 1} is not 'key: <json>': {lines[n][:60]!r}")
        n += 1
    if meta.get("hertz-dem-dump") != FORMAT_VERSION:
        raise Refusal(f"{path}: line 1: not a hertz-dem-dump version {FORMAT_VERSION} file")
    if "plan_id" not in meta:
        raise Refusal(f"{path}: header: no plan_id line (# plan_id: \"{plan_id}\"): the dump cannot be tied to "
                      "this plan")
    if meta["plan_id"] != plan_id:
        raise Refusal(f"{path}: header: plan_id {str(meta['plan_id'])[:16]}... is another plan's (this plan is "
                      f"{plan_id[:16]}...)")
    if meta.get("run") != run["name"]:
        raise Refusal(f"{path}: header: run {str(meta.get('run'))[:80]!r} is not this file's run {run['name']!r}")
    if n >= len(lines):
        raise Refusal(f"{path}: no column line ({','.join(COLUMNS)}) after the header")
    header = [c.strip() for c in lines[n].split(",")]
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise Refusal(f"{path}: line {n + 1}: no column {missing[0]!r} (the columns are {','.join(COLUMNS)})")
    rows = [line.split(",") for line in lines[n + 1:] if line.strip()]
    data = _numbers(path, header, rows, n + 2)
    series = Series(*(data[c] for c in COLUMNS), engine_version=str(meta.get("engine_version", "not given")))
    check_series(path, series, run, {c: c for c in COLUMNS}, n + 2)
    return series


def read_mapped_csv(path, run: dict, columns: ColumnMap) -> Series:
    """A plain CSV read through the column map, in SI, checked against its run (`check_series`)."""
    path = Path(path)
    lines = _lines(path)
    n = 0
    while n < len(lines) and (lines[n].startswith("#") or not lines[n].strip()):
        n += 1
    if n >= len(lines):
        raise Refusal(f"{path}: no header row of column names")
    parsed = list(csv.reader(lines[n:]))
    header = [c.strip() for c in parsed[0]]
    wanted = dict(columns.entries)
    if columns.by_position and run["geometry"] == "sphere-sphere":
        for name in ("x2", "v2"):
            if name not in wanted:
                raise Refusal(f"{columns.path}: no entry {name!r}: run {run['name']} is of two spheres")
    for name, (column, _, _) in wanted.items():
        if column not in header:
            raise Refusal(f"{path}: line {n + 1}: no column {column!r} ({name} in {columns.path.name}); the "
                          f"columns are {', '.join(header)[:200]}")
    rows = [r for r in parsed[1:] if any(c.strip() for c in r)]
    data = _numbers(path, header, rows, n + 2)
    si = {name: data[column] * factor for name, (column, _, factor) in wanted.items()}
    shown = {name: column for name, (column, _, _) in wanted.items()}
    if columns.by_position:
        R1 = run["body_1"]["radius_m"]
        if run["geometry"] == "sphere-sphere":
            overlap = R1 + run["body_2"]["radius_m"] - (si["x2"] - si["x1"])
            rate = si["v1"] - si["v2"]
        else:
            overlap, rate = R1 + si["x1"], si["v1"].copy()
        force = si["normal_force"] if "normal_force" in si else law_force(run, overlap, rate)
        shown.update(overlap=f"{shown['x1']} (as the overlap)", normal_velocity=f"{shown['v1']} (as d(delta)/dt)")
        series = Series(si["time"], overlap, rate, force)
    else:
        series = Series(si["time"], si["overlap"], si["normal_velocity"], si["normal_force"])
    check_series(path, series, run, shown, n + 2)
    return series


def law_force(run: dict, overlap, rate) -> np.ndarray:
    """The plan's law's normal force [N] at each sample (0 out of contact; clipped at 0 where the law clips)."""
    eq = run["law_equation"]
    d = np.where(overlap > 0, overlap, 0.0)
    force = eq["k_n_N_per_m1.5"] * d**1.5
    if eq["damping_power"] is not None:
        force = force + eq["damping_coefficient_SI"] * d ** eq["damping_power"] * rate
    force = np.where(overlap > 0, force, 0.0)
    return np.maximum(force, 0.0) if eq["clipped"] else force


def _lines(path: Path) -> list[str]:
    try:
        return path.read_text().splitlines()
    except OSError as err:
        raise Refusal(f"{path}: cannot read: {err.strerror}")
    except UnicodeDecodeError as err:
        raise Refusal(f"{path}: not a text file (byte {err.start} is not UTF-8)")


def check_series(path, s: Series, run: dict, shown: dict, first_line: int) -> None:
    """Refuse a series whose time does not increase, whose step or length is not the run's, or with too few
    samples in contact; `shown` names each quantity's column in the file, `first_line` the file's line of row 1."""
    def where(i):
        return f"row {i + 1} (line {first_line + i})"

    t = s.time
    if len(t) < 2:
        raise Refusal(f"{path}: {len(t)} data rows; the plan records {run['samples']}")
    steps = np.diff(t)
    bad = np.nonzero(steps <= 0)[0]
    if len(bad):
        i = int(bad[0]) + 1
        raise Refusal(f"{path}: {where(i)}, column {shown['time']!r}: time {t[i]:.17g} s does not increase "
                      f"(row before: {t[i - 1]:.17g} s)")
    dt = run["dt_s"]
    off = np.nonzero(np.abs(steps - dt) > DT_TOLERANCE * dt)[0]
    if len(off):
        i = int(off[0]) + 1
        raise Refusal(f"{path}: {where(i)}, column {shown['time']!r}: the step {steps[i - 1]:.9g} s is not the "
                      f"plan's dt = {dt:.9g} s of run {run['name']} (a dump of another plan, or not every step "
                      "recorded)")
    if abs(t[0]) > DT_TOLERANCE * dt:
        raise Refusal(f"{path}: {where(0)}, column {shown['time']!r}: the first sample is at {t[0]:.9g} s, not 0")
    if len(t) != run["samples"]:
        raise Refusal(f"{path}: {len(t)} data rows, the plan records {run['samples']} (steps 0 to {run['steps']}) "
                      f"of run {run['name']}: a dump of another plan, or of a run cut short")
    d = s.overlap
    touching = np.nonzero(d > 0)[0]
    if d[0] > 0:
        raise Refusal(f"{path}: {where(0)}, column {shown['overlap']!r}: the bodies overlap at the first sample "
                      f"({d[0]:.3g} m); the plan starts them {run['contact_starts_s']:.3g} s before contact")
    if len(touching) == 0:
        raise Refusal(f"{path}: column {shown['overlap']!r}: the overlap never becomes positive: no contact")
    i_s = int(touching[0])
    after = np.nonzero(d[i_s:] <= 0)[0]
    if len(after) == 0:
        raise Refusal(f"{path}: {where(len(d) - 1)}, column {shown['overlap']!r}: still in contact at the last "
                      "sample")
    n = int(after[0])
    if n < MIN_CONTACT_SAMPLES:
        raise Refusal(f"{path}: {where(i_s)} to {where(i_s + n - 1)}, column {shown['overlap']!r}: {n} samples in "
                      f"contact, fewer than {MIN_CONTACT_SAMPLES}: the extraction cannot read the collision")
