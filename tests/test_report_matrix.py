"""The report's matrix of the gated checks (report.report_matrix): one cell per build x law x
geometry x criterion, worst |error| over T, A, eps, pass only when all three pass, n/a cells with
their code's reason; Markdown and HTML renderings; distinct plot styles per build.

The checks are made by the gate itself (`gate_checks`) from hand-made summary rows and plans, so
the values asserted are the ones put in, passed through the real pipeline.
"""

import math
import re
from html.parser import HTMLParser

import pandas as pd
import pytest
from test_comparison import exact_metrics, meta_for

from analysis.comparison import comparison_rows
from verdict.gate import gate_checks, verdict_of
from report.report_matrix import (cell_text, error_matrix, matrix_cells, matrix_columns,
                                       matrix_html, matrix_markdown)

TOL = {"T": 5e-4, "A": 5e-4, "eps": 5e-4}
CRITERIA = {"viscoelastic": ["x0", "F0"], "viscoelastic_clipped": ["F0"], "elastic": ["x0"], "default": ["x0"]}
# Config order: deliberately not alphabetical, so that the rows must follow it.
BUILDS = ["yade-2023", "lammps-2021", "lammps-2025"]
CODE = {"yade-2023": "yade", "lammps-2021": "lammps", "lammps-2025": "lammps"}
NA_REASON = "YADE's law clips the force at zero: no tail to keep"


def summary_rows(run, build, law, geometry, K, T=1e-5, A=2e-5, eps=-3e-6):
    """summary.csv rows of one run (every column, from an exact run at K), its errors set to T, A, eps."""
    meta = {**meta_for(K=K, represents=CRITERIA[law]), "law": law, "geometry": geometry}
    rows = comparison_rows(meta, exact_metrics(meta))
    return [{**r, "case": "steel", "run": run, "build": build, "engine": CODE[build], "err_T": T, "err_A": A,
             "err_eps": eps, **({"matched_restitution": 0.8} if law == "default" else {})} for r in rows]


def planned(rows):
    runs = pd.DataFrame(rows).drop_duplicates("run")
    return pd.DataFrame({"case": runs.case, "name": runs.run, "build": runs.build, "engine": runs.engine,
                         "law": runs.law, "geometry": runs.geometry, "represents": [CRITERIA[law] for law in runs.law]})


@pytest.fixture
def study():
    """Three builds (two of one code); lammps-2025's T is 6e-4 off at K = 0.3 in the viscoelastic
    sphere-plane runs (fails); YADE cannot run the clipped law."""
    rows = []
    for build in reversed(BUILDS):  # the summary's order is not the config's
        for geometry in ("sphere-sphere", "sphere-plane"):
            rows += summary_rows(f"{build}-ve-{geometry}-1", build, "viscoelastic", geometry, 0.1, eps=-4e-5)
            bad = build == "lammps-2025" and geometry == "sphere-plane"
            rows += summary_rows(f"{build}-ve-{geometry}-2", build, "viscoelastic", geometry, 0.3,
                                 T=-6e-4 if bad else 2e-5)
            rows += summary_rows(f"{build}-el-{geometry}", build, "elastic", geometry, 0.0, T=1e-6, A=3e-7, eps=0.0)
            if build != "yade-2023":
                rows += summary_rows(f"{build}-cl-{geometry}", build, "viscoelastic_clipped", geometry, 0.1, A=7e-5)
    table = pd.DataFrame(rows)
    checks = gate_checks(table, planned(rows), pd.DataFrame(columns=["run", "problem", "log"]), TOL)
    not_available = [{"build": "yade-2023", "engine": "yade", "law": "viscoelastic_clipped", "geometry": g,
                      "reason": NA_REASON} for g in ("sphere-sphere", "sphere-plane")] * 2  # two cases' plans
    return table, checks, not_available


def cell(cells, build, law, geometry, criterion):
    sel = cells[(cells.build == build) & (cells.law == law) & (cells.geometry == geometry)
                & (cells.criterion == criterion)]
    assert len(sel) == 1
    return sel.iloc[0]


def test_cells_worst_error_pass_fail_and_not_available(study):
    table, checks, not_available = study
    cells = matrix_cells(checks, not_available, BUILDS)
    # Rows in config order, then law (gated laws' order), geometry, criterion.
    assert list(pd.unique(cells.build)) == BUILDS
    assert len(cells) == len(BUILDS) * 8  # viscoelastic 2 x 2, clipped 2 (F0), elastic 2 (x0)
    assert set(cells.law) == {"viscoelastic", "viscoelastic_clipped", "elastic"}

    bad = cell(cells, "lammps-2025", "viscoelastic", "sphere-plane", "x0")
    assert bad.status == "fail" and bad.failing == "T"
    assert bad.worst_error == pytest.approx(6e-4) and bad.worst_quantity == "T"
    assert bad.at_K == 0.3 and bad.at_run == "lammps-2025-ve-sphere-plane-2" and bad.case == "steel"
    assert bad.reason.startswith("T: 6.000e-04 > 0.0005")
    assert cell_text(bad) == "✘ 6.0e-04 (T)"
    # The same build's other geometry, and the other LAMMPS build in the same cell, pass: worst is
    # eps 4e-5 at K = 0.1, larger than T's 2e-5 and A's 2e-5.
    for good in (cell(cells, "lammps-2025", "viscoelastic", "sphere-sphere", "x0"),
                 cell(cells, "lammps-2021", "viscoelastic", "sphere-plane", "x0")):
        assert good.status == "pass" and good.failing == "" and good.reason == ""
        assert good.worst_quantity == "eps" and good.worst_error == pytest.approx(4e-5) and good.at_K == 0.1
        assert cell_text(good) == "✔ 4.0e-05"
    clipped = cell(cells, "lammps-2021", "viscoelastic_clipped", "sphere-sphere", "F0")
    assert clipped.status == "pass" and clipped.worst_quantity == "A" and clipped.worst_error == pytest.approx(7e-5)

    na = cells[cells.status == "n/a"]
    assert len(na) == 2 and set(na.build) == {"yade-2023"} and set(na.law) == {"viscoelastic_clipped"}
    assert set(na.criterion) == {"F0"} and (na.reason == NA_REASON).all() and na.worst_error.isna().all()
    assert cell_text(na.iloc[0]) == "n/a"
    # The matrix passes where the gate's verdict does: one failing cell, two failing checks (x0, F0).
    assert (cells.status == "fail").sum() == 2 and verdict_of(checks, "sha", TOL)["failed"] == 2


def test_text_matrix_groups_columns_law_geometry_criterion(study):
    _, checks, not_available = study
    matrix = error_matrix(matrix_cells(checks, not_available, BUILDS))
    assert list(matrix.index) == BUILDS
    assert list(matrix.columns) == [
        ("viscoelastic", "sphere-sphere", "x0"), ("viscoelastic", "sphere-sphere", "F0"),
        ("viscoelastic", "sphere-plane", "x0"), ("viscoelastic", "sphere-plane", "F0"),
        ("viscoelastic_clipped", "sphere-sphere", "F0"), ("viscoelastic_clipped", "sphere-plane", "F0"),
        ("elastic", "sphere-sphere", "x0"), ("elastic", "sphere-plane", "x0")]
    assert matrix.loc["yade-2023", ("viscoelastic_clipped", "sphere-plane", "F0")] == "n/a"
    assert matrix.loc["lammps-2025", ("viscoelastic", "sphere-plane", "F0")] == "✘ 6.0e-04 (T)"
    assert matrix.loc["yade-2023", ("elastic", "sphere-plane", "x0")] == "✔ 1.0e-06"


def test_a_failed_run_with_no_result_fails_its_cell_without_a_number():
    rows = summary_rows("a", "lammps-2021", "viscoelastic", "sphere-sphere", 0.1)
    plan = planned(rows + summary_rows("b", "lammps-2021", "viscoelastic_clipped", "sphere-sphere", 0.1))
    failed = pd.DataFrame([{"run": "b", "problem": "lammps exited with status 139", "log": "runs/x.log"}])
    cells = matrix_cells(gate_checks(pd.DataFrame(rows), plan, failed, TOL), (), ["lammps-2021"])
    c = cell(cells, "lammps-2021", "viscoelastic_clipped", "sphere-sphere", "F0")
    assert c.status == "fail" and math.isnan(c.worst_error) and c.failing == "T, A, eps"
    assert cell_text(c) == "✘ no result" and "1 of 1 ladders have a failed run; first: b: lammps exited" in c.reason


def test_a_law_no_build_can_run_still_gets_its_columns_of_na():
    rows = summary_rows("a", "lammps-2021", "elastic", "sphere-plane", 0.0)
    checks = gate_checks(pd.DataFrame(rows), planned(rows), pd.DataFrame(), TOL)
    na = [{"build": "lammps-2021", "engine": "lammps", "law": "viscoelastic", "geometry": "sphere-plane",
           "reason": "no viscous force"}]
    cells = matrix_cells(checks, na, ["lammps-2021"])
    assert matrix_columns(cells) == [("viscoelastic", "sphere-plane", "x0"), ("viscoelastic", "sphere-plane", "F0"),
                                     ("elastic", "sphere-plane", "x0")]


def test_markdown_has_legend_numbered_reasons_and_code_notes(study):
    _, checks, not_available = study
    cells = matrix_cells(checks, not_available, BUILDS)
    lines = matrix_markdown(cells, TOL, {"yade": ("a plane is a huge box",), "lammps": ()})
    table = [line for line in lines if line.startswith("|")]
    assert len(table) == 4 + len(BUILDS)  # law header, alignment, geometry and criterion rows, builds
    assert table[0].split("|")[2].strip() == "**viscoelastic**"
    yade = next(line for line in table if line.startswith("| **yade-2023**"))
    assert yade.count("n/a¹") == 2
    text = "\n".join(lines)
    assert f"1. yade: {NA_REASON}" in text and "- **yade**: a plane is a huge box" in text
    assert "✔" in text and "✘" in text and "[checks.csv](checks.csv)" in text and "T 0.0005" in text


class _Tables(HTMLParser):
    """Collects every <table>: its class and rows of (tag, attrs, text)."""

    def __init__(self):
        super().__init__()
        self.tables, self._cell = [], None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "table":
            self.tables.append({"class": attrs.get("class", ""), "rows": []})
        elif tag == "tr" and self.tables:
            self.tables[-1]["rows"].append([])
        elif tag in ("td", "th") and self.tables:
            self._cell = [tag, attrs, ""]
            self.tables[-1]["rows"][-1].append(self._cell)

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[2] += data


def parse_tables(html):
    parser = _Tables()
    parser.feed(html)
    return parser.tables


def test_html_table_rows_columns_classes_and_titles(study):
    _, checks, not_available = study
    cells = matrix_cells(checks, not_available, BUILDS)
    [table] = parse_tables(matrix_html(cells))
    assert table["class"] == "matrix"
    head, body = table["rows"][:3], table["rows"][3:]
    laws = [(c[2], int(c[1].get("colspan", 1))) for c in head[0][1:]]
    assert laws == [("viscoelastic", 4), ("viscoelastic_clipped", 2), ("elastic", 2)]
    assert [c[2] for c in head[1]] == ["sphere-sphere", "sphere-plane"] * 3
    assert [int(c[1].get("colspan", 1)) for c in head[1]] == [2, 2, 1, 1, 1, 1]
    assert [c[2] for c in head[2]] == ["x0", "F0", "x0", "F0", "F0", "F0", "x0", "x0"]
    assert [row[0][2] for row in body] == BUILDS and all(row[0][0] == "th" for row in body)
    assert all(len(row) == 1 + 8 for row in body)
    by_build = {row[0][2]: row[1:] for row in body}
    classes = {b: [c[1]["class"].split()[0] for c in row] for b, row in by_build.items()}
    assert classes["lammps-2025"] == ["pass", "pass", "fail", "fail", "pass", "pass", "pass", "pass"]
    assert classes["yade-2023"] == ["pass"] * 4 + ["na", "na"] + ["pass"] * 2
    fail = by_build["lammps-2025"][2]
    assert fail[2] == "✘ 6.0e-04 (T)"  # the text says it, not the colour alone
    assert fail[1]["title"].startswith("FAIL — T: 6.000e-04 > 0.0005 (case steel, K = 0.3)")
    assert ("largest extrapolated error: T 6.000e-04 (tolerance 0.0005) in run lammps-2025-ve-sphere-plane-2"
            in fail[1]["title"])
    na = by_build["yade-2023"][4]
    assert na[2] == "n/a1" and NA_REASON in na[1]["title"]  # "n/a" and its note's number (<sup>)
    ok = by_build["lammps-2021"][0]
    assert ok[2] == "✔ 4.0e-05"
    assert ok[1]["title"].startswith("pass — largest extrapolated error: eps 4.000e-05 (tolerance 0.0005) "
                                     "in run lammps-2021-ve-")


def test_the_keywords_section_gives_each_keywords_own_equation_its_promise_and_the_model(tmp_path):
    """A build's restitution keyword (law 'default'), told e = 0.904886 at K = 0.1: the report's
    keyword table gives what its equation restitutes (LAMMPS tsuji: 0.931997, by the closed form),
    the promise error, the engine's eps from its own-equation error, the viscoelastic model's eps,
    and the keyword's known defect."""
    from contact_model.keywords import promised_restitution
    from report.report import ReportInputs, write_report
    from reference import solve_collision

    rows = summary_rows("lammps-2021-def", "lammps-2021", "default", "sphere-sphere", 0.1, eps=2e-9)
    for r in rows:
        r["matched_restitution"] = 0.904886
    table = pd.DataFrame(rows)
    checks = gate_checks(table, planned(rows), pd.DataFrame(columns=["run", "problem", "log"]), TOL)
    write_report(ReportInputs(table, checks, verdict_of(checks, "0" * 64, TOL), builds=["lammps-2021"]), tmp_path)
    md = (tmp_path / "report.md").read_text()
    section = md.split("## The engines' restitution keywords")[1].split("\n## ")[0]
    own = promised_restitution("lammps:tsuji", 0.904886)
    row = next(line for line in section.splitlines() if line.startswith("| steel | lammps-2021 |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[3] == "`lammps:tsuji`" and cells[4] == "x0" and float(cells[6]) == 0.904886
    assert float(cells[7]) == pytest.approx(own, rel=1e-6) and float(cells[8]) == pytest.approx(own - 0.904886,
                                                                                                rel=1e-5)
    assert float(cells[10]) == pytest.approx(2e-9)
    assert float(cells[11]) == pytest.approx(solve_collision(0.1)["eps_x0"], rel=1e-6)
    assert "Known defect of `lammps:tsuji`" in section and "PR #5113" in section


def test_report_shows_the_matrix_and_links_the_checks(study, tmp_path):
    from report.report import ReportInputs, write_report

    table, checks, not_available = study
    verdict = verdict_of(checks, "0" * 64, TOL)
    write_report(ReportInputs(table, checks, verdict, builds=BUILDS, not_available=not_available,
                              code_notes={"yade": ("a plane is a huge box",)}), tmp_path)
    md = (tmp_path / "report.md").read_text()
    assert "@@" not in md and "| **lammps-2025** |" in md and "[checks.csv](checks.csv)" in md
    assert f"1. yade: {NA_REASON}" in md and "a plane is a huge box" in md
    html = (tmp_path / "report.html").read_text()
    tables = parse_tables(html)
    matrices = [t for t in tables if t["class"] == "matrix"]
    assert len(matrices) == 1 and [r[0][2] for r in matrices[0]["rows"][3:]] == BUILDS
    assert 'href="checks.csv"' in html and NA_REASON in html
    assert (tmp_path / "plots" / "errors.png").stat().st_size > 0
    # What the study does not validate, under the verdict, before anything else
    head = md.split("\n## ")[0]
    assert ("**The tangential half** (tangential force, friction, rotation, oblique impacts) is not "
            "part of this matrix") in head
    assert "ESyS and Kratos are not run oblique yet" in head and "The tangential half</strong>" in html


@pytest.mark.workflow  # a pool of drawing processes, the report twice: end to end
def test_report_drawn_in_two_processes_is_the_same_report(study, tmp_path):
    """workers=2 (the report rule's two threads) draws the plots in forked processes while the
    text is written: the same report.md and report.html (but the minute it was generated), every
    plot; a plot that fails still fails the report."""
    from report import report

    table, checks, not_available = study
    verdict = verdict_of(checks, "0" * 64, TOL)
    texts = {}
    for workers in (1, 2):
        out = tmp_path / str(workers)
        report.write_report(report.ReportInputs(table, checks, verdict, builds=BUILDS, not_available=not_available),
                            out, workers=workers)
        texts[workers] = [re.sub(r"Generated [^`]*UTC", "", (out / name).read_text())
                          for name in ("report.md", "report.html")]
        assert sorted(p.name for p in (out / "plots").iterdir()) == ["errors.png", "ratios_F0.png", "ratios_x0.png"]
    assert texts[1] == texts[2]
    from report.report_plots import plot_errors, start_drawing

    wait = start_drawing([(plot_errors, (table, TOL, tmp_path / "e.png", BUILDS)),
                          (plot_errors, (table, {}, tmp_path / "f.png", BUILDS))], workers=2)
    with pytest.raises(KeyError):  # no tolerance for T: the second plot fails in its process
        wait()


def test_every_build_gets_its_own_marker_and_colour_in_config_order():
    from report.report_plots import build_styles

    builds = ["liggghts-3.8", "yade-2023", "lammps-2021", "lammps-2025", "esys-2.3.5", "kratos-10.4"]
    styles = build_styles(builds)
    assert list(styles) == builds
    assert len({(s["marker"], s["color"]) for s in styles.values()}) == len(builds)
    assert len({s["marker"] for s in styles.values()}) == len(builds)  # not colour alone
    assert styles["lammps-2021"]["marker"] != styles["lammps-2025"]["marker"]
    sizes = [s["ms"] for s in styles.values()]
    assert sizes == sorted(sizes, reverse=True) and sizes[-1] >= 4  # later builds nest inside earlier ones
    # From the order, not from the code: swapping two builds swaps their styles.
    assert build_styles(["lammps-2025", "lammps-2021"])["lammps-2025"]["marker"] == styles["liggghts-3.8"]["marker"]


@pytest.mark.workflow  # a real browser reads the report: end to end, not a unit (conftest.tier_of)
def test_report_in_a_browser(study, tmp_path):
    """The report renders in a headless browser (Debian's chromium; CI installs it) and the
    browser's DOM holds the matrix with one row per build."""
    import shutil

    from report.report import ReportInputs, write_report

    import processes
    from engine_cases import missing

    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        missing("chromium is not installed; install it with: sudo apt-get install chromium")
    table, checks, not_available = study
    write_report(ReportInputs(table, checks, verdict_of(checks, "0" * 64, TOL), builds=BUILDS,
                              not_available=not_available), tmp_path)
    out = processes.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                         "--dump-dom", (tmp_path / "report.html").as_uri()], capture_output=True, text=True,
                        timeout=120)
    matrices = [t for t in parse_tables(out.stdout) if t["class"] == "matrix"]
    assert len(matrices) == 1 and [r[0][2] for r in matrices[0]["rows"][3:]] == BUILDS


def test_legend_names_only_the_kinds_of_cell_the_matrix_has(study):
    _, checks, not_available = study
    with_na = "\n".join(matrix_markdown(matrix_cells(checks, not_available, BUILDS), TOL))
    without = "\n".join(matrix_markdown(matrix_cells(checks, (), BUILDS), TOL))
    assert "n/a: the build's code" in with_na and "n/a" not in without
    assert "– : the build has no run" in without  # YADE has no clipped cell, and none is n/a


def test_a_cell_shows_its_extrapolated_error_and_the_resolution_it_was_judged_at():
    """Ladder limits (dt = 0) with their resolutions: '✔ 4.1e-09 (res 1.6e-07)' where the check
    passes with its resolution added, '✘ 8.0e-07 (res 5.0e-07; eps)' where the error is within
    the tolerance but not resolved at it; the hover text says the resolution too."""
    from report.report_matrix import cell_title

    tol = {"T": 1e-6, "A": 1e-6, "eps": 1e-6}
    rows = []
    for build, eps, res in (("lammps-2021", 4.1e-9, 1.6e-7), ("lammps-2025", 8e-7, 5e-7)):
        for r in summary_rows(f"{build}-ve", build, "viscoelastic", "sphere-plane", 0.1, T=1e-9, A=2e-9, eps=eps):
            rows.append({**r, "dt": 0.0, "ladder": r["run"], **{f"resolution_{q}": res for q in ("T", "A", "eps")}})
    checks = gate_checks(pd.DataFrame(rows), planned(rows), pd.DataFrame(columns=["run", "problem", "log"]), tol)
    cells = matrix_cells(checks, (), ["lammps-2021", "lammps-2025"])
    good = cell(cells, "lammps-2021", "viscoelastic", "sphere-plane", "x0")
    bad = cell(cells, "lammps-2025", "viscoelastic", "sphere-plane", "x0")
    assert cell_text(good) == "✔ 4.1e-09 (res 1.6e-07)" and good.resolution == pytest.approx(1.6e-7)
    assert cell_text(bad) == "✘ 8.0e-07 (res 5.0e-07; eps)"
    assert "judged at a resolution of 1.6e-07" in cell_title(good)
    assert "not resolved at this tolerance" in cell_title(bad)


def test_a_law_the_study_supplies_in_a_code_is_said_at_its_cells(study):
    """YADE 2023's viscoelastic damping is the driver's own Python (engines.codes ``supplied``): its
    four viscoelastic cells carry † and a note says what the study supplies; no other cell does."""
    from engines.codes import CODES

    _, checks, not_available = study
    cells = matrix_cells(checks, not_available, BUILDS)
    supplied = {"yade-2023": CODES["yade"].supplied_in("YADE 2023.02a (PrecisionDouble)")}
    assert supplied["yade-2023"] == CODES["yade"].supplied
    # From 2024.02a YADE damps the clipped law itself (MindlinPhys.beta): only the tail is the study's.
    assert set(CODES["yade"].supplied_in("YADE 2025.2.0 (PrecisionDouble)")) == {"viscoelastic"}
    md = "\n".join(matrix_markdown(cells, TOL, supplied=supplied))
    yade_row = next(line for line in md.splitlines() if line.startswith("| **yade-2023** |"))
    assert yade_row.count("†1") == 4 and "†" not in "".join(line for line in md.splitlines()
                                                             if line.startswith("| **lammps"))
    assert "- †1 yade-2023, viscoelastic: YADE 2023.02a has no viscoelastic Hertz law, and from 2024.02a" in md
    html = matrix_html(cells, supplied)
    assert html.count("<sup>†1</sup>") == 4
    assert "†" not in "\n".join(matrix_markdown(cells, TOL))  # nothing supplied, nothing marked
