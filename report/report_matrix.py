"""The gated checks as one compact matrix: engine builds x (law, geometry, criterion).

The gate (`verdict.gate`) makes one check per build x gated law x geometry x criterion x
quantity (T, A, eps). With several builds that long table is unreadable; a reader wants, per
build and per cell (law, geometry, criterion), one answer: does it pass, how far off is it at
worst, and, where a build's code cannot express the law, why not. This module computes that
matrix from the checks and the plans' ``not_available`` cells (pure functions, DataFrames in
and out) and renders it as Markdown and as an HTML table. The long table stays in checks.csv.

The engines' own restitution keywords (law ``default``) are gated against their own equation
and have their cells here like the model's laws.
"""

from __future__ import annotations

import math
from html import escape
from typing import Iterable, Mapping, Sequence

import numpy as np
import pandas as pd

from contact_model import CRITERIA, GATED_LAWS, GEOMETRIES, LAW_CRITERIA

from verdict.gate import GATED_QUANTITIES, with_build

#: The columns of a matrix cell (`matrix_cells`), in order.
CELL_COLUMNS = ["build", "engine", "law", "geometry", "criterion", "status", "worst_error", "worst_quantity",
                "tolerance", "failing", "case", "at_K", "at_run", "reason", "resolution"]
#: What the cell's status is shown as (the text carries it, not the colour alone).
SYMBOL = {"pass": "✔", "fail": "✘", "n/a": "n/a", "none": "–"}


def _records(rows) -> pd.DataFrame:
    """`rows` (a DataFrame, or an iterable of dicts) as a DataFrame."""
    return rows.copy() if isinstance(rows, pd.DataFrame) else pd.DataFrame(list(rows))


def build_order(builds: Sequence[str] | None, *tables: pd.DataFrame) -> list[str]:
    """The builds in the order of `builds` (config `builds:`), then any other build of `tables`
    (their `build` column) in the order it first appears."""
    order = list(builds or ())
    for t in tables:
        if len(t) and "build" in t.columns:
            order += [b for b in pd.unique(t["build"].astype(str)) if b not in order]
    return order


def _rank(values: Iterable, order: Sequence) -> list[int]:
    """Position of each value in `order` (unknown values last, in their own order)."""
    order = list(order)
    return [order.index(v) if v in order else len(order) for v in values]


def not_available_cells(not_available, law_criteria: Mapping[str, Sequence[str]] = LAW_CRITERIA) -> pd.DataFrame:
    """The plans' ``not_available`` entries of gated laws as matrix cells, one per criterion.

    Parameters
    ----------
    not_available : DataFrame or iterable of dict
        The ``not_available`` lists of any number of plan.json files: build, engine, law,
        geometry, reason (duplicates across cases are merged).
    law_criteria : mapping
        The criteria a law stands for (`contact_model.LAW_CRITERIA`); laws absent from it
        (``default``, whose criterion is each code's keyword's, not the law's) are left out.

    Returns
    -------
    DataFrame with the columns CELL_COLUMNS: status 'n/a', reason the code's reason, the
    error columns empty (NaN / '').
    """
    na = _records(not_available)
    if not len(na):
        return pd.DataFrame(columns=CELL_COLUMNS)
    na = with_build(na)
    na = na[na.law.isin(list(law_criteria))].drop_duplicates(["build", "law", "geometry"])
    rows = [{"build": r.build, "engine": r.engine, "law": r.law, "geometry": r.geometry, "criterion": c,
             "status": "n/a", "worst_error": math.nan, "worst_quantity": "", "tolerance": math.nan, "failing": "",
             "case": "", "at_K": math.nan, "at_run": "", "reason": str(r.reason), "resolution": math.nan}
            for r in na.itertuples() for c in law_criteria[r.law]]
    return pd.DataFrame(rows, columns=CELL_COLUMNS)


def matrix_cells(checks: pd.DataFrame, not_available=(), builds: Sequence[str] | None = None,
                 law_criteria: Mapping[str, Sequence[str]] = LAW_CRITERIA) -> pd.DataFrame:
    """One row per cell of the gated matrix: build x law x geometry x criterion.

    A cell holds the checks of its T, A and eps. It passes when every one of them passes; its
    error is the largest |relative error| among them.

    Parameters
    ----------
    checks : DataFrame
        `verdict.gate.gate_checks` (results/checks.csv): build, engine, law, geometry,
        criterion, quantity, max_rel_error, tolerance, pass, case, at_K, at_run (optional),
        reason.
    not_available : DataFrame or iterable of dict
        The plans' ``not_available`` cells (build, engine, law, geometry, reason): a law the
        build's code cannot express. A cell that has checks keeps them.
    builds : sequence of str, optional
        The build ids in config order: the order of the rows. Builds missing from it follow.
    law_criteria : mapping
        The criteria of each gated law (`contact_model.LAW_CRITERIA`).

    Returns
    -------
    DataFrame with the columns CELL_COLUMNS, sorted by build (config order), law (GATED_LAWS
    order), geometry, criterion (x0, F0):

    - status: 'pass' (every check of the cell passes), 'fail' or 'n/a';
    - worst_error: max over the cell's quantities of max_rel_error (NaN when no run of the
      cell gave a result, or n/a);
    - worst_quantity: the quantity of worst_error ('T', 'A' or 'eps'; '' when NaN);
    - tolerance: the tolerance of worst_quantity;
    - failing: the failing quantities, comma-separated in T, A, eps order ('' if none);
    - case, at_K, at_run: the case, K and run name where worst_error occurs;
    - reason: the reasons of the failing checks, each prefixed with its quantity
      ('T: 6.0e-04 > 0.0005 ...'), or the code's reason for an n/a cell; '' for a pass;
    - resolution: the largest resolution of the cell's checks (NaN without one: a checks table
      from before ladders).
    """
    checks = with_build(checks)
    cells = []
    if len(checks):
        for key, group in checks.groupby(["build", "law", "geometry", "criterion"], sort=False):
            group = group.iloc[np.argsort(_rank(group.quantity, GATED_QUANTITIES), kind="stable")]
            errors = group.max_rel_error.to_numpy(dtype=float)
            worst = group.iloc[int(np.nanargmax(errors))] if not np.isnan(errors).all() else None
            passed = group["pass"].astype(bool)
            failing = group[~passed.to_numpy()]
            reasons = [f"{r.quantity}: {r.reason}" for r in failing.itertuples()]
            cells.append({**dict(zip(["build", "law", "geometry", "criterion"], key)),
                          "engine": group.engine.iloc[0],
                          "status": "pass" if passed.all() else "fail",
                          "worst_error": math.nan if worst is None else float(worst.max_rel_error),
                          "worst_quantity": "" if worst is None else str(worst.quantity),
                          "tolerance": math.nan if worst is None else float(worst.tolerance),
                          "failing": ", ".join(failing.quantity.astype(str)),
                          "case": "" if worst is None else str(worst.case),
                          "at_K": math.nan if worst is None else float(worst.at_K),
                          "at_run": "" if worst is None or "at_run" not in group.columns
                          or pd.isna(worst.at_run) else str(worst.at_run),
                          "reason": "; ".join(reasons),
                          "resolution": (float(np.nanmax(group.resolution.to_numpy(dtype=float)))
                                         if "resolution" in group.columns
                                         and not group.resolution.isna().all() else math.nan)})
    gated = pd.DataFrame(cells, columns=CELL_COLUMNS)
    na = not_available_cells(not_available, law_criteria)
    if len(na) and len(gated):
        have = set(map(tuple, gated[["build", "law", "geometry", "criterion"]].to_numpy()))
        na = na[[k not in have for k in map(tuple, na[["build", "law", "geometry", "criterion"]].to_numpy())]]
    out = pd.concat([df for df in (gated, na) if len(df)], ignore_index=True) if len(gated) or len(na) \
        else pd.DataFrame(columns=CELL_COLUMNS)
    if not len(out):
        return out
    order = build_order(builds, out)
    keys = np.lexsort((_rank(out.criterion, CRITERIA), _rank(out.geometry, GEOMETRIES),
                       _rank(out.law, GATED_LAWS), _rank(out.build, order)))
    return out.iloc[keys].reset_index(drop=True)[CELL_COLUMNS]


def cell_text(cell) -> str:
    """What a cell shows: '✔ 4.1e-09 (res 1.6e-07)' (the worst extrapolated error and the
    resolution it was judged at), '✘ 4.0e-06 (res 1.6e-07; T, A)' (with the failing quantities),
    '✘ no result', 'n/a', or '–' for a cell of a build that has none (neither planned nor
    unavailable)."""
    status = cell["status"]
    if status in ("n/a", "none"):
        return SYMBOL[status]
    error = cell["worst_error"]
    if error is None or (isinstance(error, float) and math.isnan(error)):
        return f"{SYMBOL[status]} no result"
    resolution = cell.get("resolution", math.nan)
    notes = [] if resolution is None or math.isnan(resolution) else [f"res {resolution:.1e}"]
    if status == "fail" and cell["failing"]:
        notes.append(cell["failing"])
    return f"{SYMBOL[status]} {error:.1e}" + (f" ({'; '.join(notes)})" if notes else "")


def matrix_columns(cells: pd.DataFrame) -> list[tuple[str, str, str]]:
    """The (law, geometry, criterion) columns of the matrix, grouped law -> geometry ->
    criterion: those with a cell (planned or n/a), in GATED_LAWS, GEOMETRIES, CRITERIA order."""
    if not len(cells):
        return []
    cols = cells[["law", "geometry", "criterion"]].drop_duplicates()
    keys = np.lexsort((_rank(cols.criterion, CRITERIA), _rank(cols.geometry, GEOMETRIES), _rank(cols.law, GATED_LAWS)))
    return [tuple(c) for c in cols.iloc[keys].to_numpy()]


def error_matrix(cells: pd.DataFrame) -> pd.DataFrame:
    """The matrix as text: one row per build (the order of `cells`), one column per
    (law, geometry, criterion) (a three-level column index), each value `cell_text` ('–' where
    the build has no such cell)."""
    columns = matrix_columns(cells)
    builds = list(pd.unique(cells.build)) if len(cells) else []
    text = {(r.build, (r.law, r.geometry, r.criterion)): cell_text(r._asdict()) for r in cells.itertuples()}
    data = [[text.get((b, c), SYMBOL["none"]) for c in columns] for b in builds]
    index = pd.MultiIndex.from_tuples(columns, names=["law", "geometry", "criterion"]) if columns else None
    return pd.DataFrame(data, index=pd.Index(builds, name="build"), columns=index)


def supplied_footnotes(cells: pd.DataFrame, supplied: Mapping[str, Mapping[str, str]] | None) -> dict:
    """{(build, law): footnote mark '†1', ...} of the cells whose law the study itself supplies in
    that build (`supplied`: {build: {law: what}}, `engines.codes.EngineCode.supplied_in` of the
    build's release), one per build and law, in the order of the matrix."""
    notes: dict[tuple[str, str], str] = {}
    for r in cells[cells.status != "n/a"].itertuples() if len(cells) and supplied else ():
        if r.law in (supplied.get(r.build) or {}):
            notes.setdefault((r.build, r.law), f"†{len(notes) + 1}")
    return notes


def na_footnotes(cells: pd.DataFrame) -> dict[tuple[str, str], int]:
    """{(engine code, reason): footnote number} of the n/a cells, numbered from 1 in the order
    of the matrix (one note per reason, however many cells and codes share it)."""
    notes: dict[tuple[str, str], int] = {}
    numbers: dict[str, int] = {}
    for r in cells[cells.status == "n/a"].itertuples() if len(cells) else ():
        notes.setdefault((r.engine, r.reason), numbers.setdefault(r.reason, len(numbers) + 1))
    return notes


def na_note_lines(notes: dict[tuple[str, str], int]) -> list[tuple[int, str, str]]:
    """(number, 'code, code', reason) of each footnote of `na_footnotes`, in order."""
    by_number: dict[int, tuple[list[str], str]] = {}
    for (code, reason), n in notes.items():
        by_number.setdefault(n, ([], reason))[0].append(code)
    return [(n, ", ".join(codes), reason) for n, (codes, reason) in sorted(by_number.items())]


def cell_title(cell) -> str:
    """The hover text of a cell: pass/FAIL, the failing quantities with their reasons, and the
    largest error with its quantity, run, case and K; an n/a cell's reason."""
    status = cell["status"]
    if status == "n/a":
        return f"not available in {cell['engine']}: {cell['reason']}"
    if status == "none":
        return "no run of this build in this cell"
    largest = ""
    if cell["worst_quantity"]:
        run = f"in run {cell['at_run']} " if cell["at_run"] else ""
        resolution = cell.get("resolution", math.nan)
        judged = "" if resolution is None or math.isnan(resolution) else f", judged at a resolution of {resolution:.1e}"
        largest = (f"largest extrapolated error: {cell['worst_quantity']} {cell['worst_error']:.3e} (tolerance "
                   f"{cell['tolerance']:g}{judged}) {run}(case {cell['case']}, K = {cell['at_K']:.4g})")
    if status == "pass":
        return "pass — " + (largest or "T, A and eps within tolerance")
    return "FAIL — " + "; ".join(filter(None, [cell["reason"], largest]))


def _superscript(n: int) -> str:
    return str(n).translate(str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹"))


def matrix_markdown(cells: pd.DataFrame, tolerance: Mapping[str, float],
                    code_notes: Mapping[str, Sequence[str]] | None = None,
                    supplied: Mapping[str, Mapping[str, str]] | None = None) -> list[str]:
    """The matrix as Markdown lines: the table (the law, geometry and criterion header rows,
    one row per build), its legend, the n/a reasons as numbered notes, what the study supplies of
    a law in a code (`supplied`, marked † at the cell) and each code's notes."""
    columns = matrix_columns(cells)
    if not columns:
        return ["No gated check was made.", ""]
    notes = na_footnotes(cells)
    marks = supplied_footnotes(cells, supplied)
    by_key = {(r.build, (r.law, r.geometry, r.criterion)): r._asdict() for r in cells.itertuples()}

    def group_row(level):
        out, previous = [], None
        for c in columns:
            label = c[: level + 1]
            out.append(f"**{c[level]}**" if label != previous else "")
            previous = label
        return out

    def text(build, column):
        cell = by_key.get((build, column))
        if cell is None:
            return SYMBOL["none"]
        t = cell_text(cell)
        if (cell["build"], cell["law"]) in marks:
            t += " " + marks[(cell["build"], cell["law"])]
        return t + _superscript(notes[(cell["engine"], cell["reason"])]) if cell["status"] == "n/a" else t

    builds = list(pd.unique(cells.build))
    lines = ["| build | " + " | ".join(group_row(0)) + " |", "|---|" + ":---:|" * len(columns),
             "| | " + " | ".join(group_row(1)) + " |", "| | " + " | ".join(group_row(2)) + " |"]
    lines += [f"| **{b}** | " + " | ".join(text(b, c) for c in columns) + " |" for b in builds]
    has_none = any((b, c) not in by_key for b in builds for c in columns)
    lines += ["", legend(tolerance, na=bool(notes), none=has_none), ""]
    if notes:
        lines += ["Not available (the build's code cannot express the law; nothing is run, nothing is gated):", ""]
        lines += [f"{n}. {codes}: {md_text(reason)}" for n, codes, reason in na_note_lines(notes)] + [""]
    if marks:
        lines += ["Supplied by the study, not the engine (the cells marked †):", ""]
        lines += [f"- {mark} {build}, {law}: {md_text(supplied[build][law])}" for (build, law), mark in marks.items()]
        lines += [""]
    lines += code_notes_markdown(code_notes, list(pd.unique(cells.engine)))
    return lines


def legend(tolerance: Mapping[str, float], na: bool = True, none: bool = True) -> str:
    """The matrix's legend (Markdown); the n/a and '–' entries only where the matrix has such
    cells (`na`, `none`)."""
    tolerances = ", ".join(f"{q} {tolerance[q]:g}" for q in GATED_QUANTITIES)
    return (f"✔ pass: T, A and eps all within tolerance ({tolerances}) with their resolution added; ✘ fail, with "
            "the failing quantities in brackets. The number is the cell's worst |relative error| over T, A and eps, "
            "every case and every K, engine extrapolated to dt -> 0 vs reference solver; res: the largest "
            "resolution of its checks (the smallest error the cell's ladders can tell from zero: the larger of "
            "the extrapolation's own error bound and the round-off of positions)."
            + (" n/a: the build's code cannot express the law (the reasons below)." if na else "")
            + (" – : the build has no run in that cell." if none else "")
            + " Every check, with the K, case and run of its worst error: [checks.csv](checks.csv).")


def md_text(text: str) -> str:
    """Plain text for Markdown: the physics' asterisks (R*, E*, M*) and underscores (DEM_D_...)
    escaped, so that they print instead of turning text italic."""
    return text.replace("\\", "\\\\").replace("*", "\\*").replace("_", "\\_")


def code_notes_markdown(code_notes: Mapping[str, Sequence[str]] | None, codes: Sequence[str]) -> list[str]:
    """Each code's notes (`engines.codes.EngineCode.notes`) as a Markdown list, codes in order."""
    items = [(c, n) for c in codes for n in (code_notes or {}).get(c, ())]
    if not items:
        return []
    return ["How the codes run the study:", ""] + [f"- **{c}**: {md_text(n)}" for c, n in items] + [""]


def matrix_html(cells: pd.DataFrame, supplied: Mapping[str, Mapping[str, str]] | None = None) -> str:
    """The matrix as an HTML table (class 'matrix'): three header rows (law, geometry,
    criterion; the build column spans them), one row per build; each cell a <td> of class
    'pass', 'fail', 'na' or 'none' whose text is `cell_text` and whose title is `cell_title`,
    n/a cells with the number of their note (`na_footnotes`) in a <sup>."""
    columns = matrix_columns(cells)
    if not columns:
        return "<p>No gated check was made.</p>"
    notes = na_footnotes(cells)
    marks = supplied_footnotes(cells, supplied)
    by_key = {(r.build, (r.law, r.geometry, r.criterion)): r._asdict() for r in cells.itertuples()}

    def spans(level):
        out = []
        for c in columns:
            if out and out[-1][0] == c[: level + 1]:
                out[-1][1] += 1
            else:
                out.append([c[: level + 1], 1])
        return out

    # A thicker line where a law starts, so that the groups read as groups.
    law_starts = {i for i, c in enumerate(columns) if i == 0 or columns[i - 1][0] != c[0]}
    geometry_starts = {i for i, c in enumerate(columns) if i == 0 or columns[i - 1][:2] != c[:2]}

    def edge(i):
        return " law-start" if i in law_starts else " geometry-start" if i in geometry_starts else ""

    head = ['<tr><th rowspan="3" class="build">build</th>']  # every group of the law row starts a law
    head += [f'<th colspan="{n}" class="law law-start">{escape(key[0])}</th>' for key, n in spans(0)]
    head += ["</tr>\n<tr>"]
    first = 0
    for key, n in spans(1):
        head.append(f'<th colspan="{n}" class="geometry{edge(first)}">{escape(key[1])}</th>')
        first += n
    head += ["</tr>\n<tr>"]
    head += [f'<th class="criterion{edge(i)}">{escape(c[2])}</th>' for i, c in enumerate(columns)] + ["</tr>"]
    body = []
    for b in pd.unique(cells.build):
        tds = []
        for i, c in enumerate(columns):
            cell = by_key.get((b, c), {"status": "none"})
            status = cell["status"]
            # the resolution on a line of its own: eight cells of "✔ 3.2e-08 (res 1.8e-07)" overflow a page
            text = escape(cell_text(cell)).replace(" (res ", '<br><span class="res">(res ', 1)
            text += "</span>" if '<span class="res">' in text else ""
            if status == "n/a":
                text += f"<sup>{notes[(cell['engine'], cell['reason'])]}</sup>"
            elif (cell.get("build"), cell.get("law")) in marks:
                text += f"<sup>{marks[(cell['build'], cell['law'])]}</sup>"
            css = {"n/a": "na"}.get(status, status)
            tds.append(f'<td class="{css}{edge(i)}" title="{escape(cell_title(cell), quote=True)}">{text}</td>')
        body.append(f'<tr><th scope="row" class="build">{escape(str(b))}</th>{"".join(tds)}</tr>')
    return ('<table class="matrix">\n<thead>\n' + "".join(head) + "\n</thead>\n<tbody>\n" + "\n".join(body)
            + "\n</tbody>\n</table>")


