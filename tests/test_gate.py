"""The gate decides every check from what was planned, what landed and what failed; the report
shows FAIL at the top with every failing check named; JUnit XML has one test case per check.

These drive the verdict's branches on small tables; tests/test_study_failures.py drives the same
paths end to end through the workflow with a real engine.
"""

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pandas as pd
import pytest

from verdict.gate import CHECK_COLUMNS, gate_checks, junit_xml, verdict_of, write_junit, write_verdict
from verdict.verdict_files import VERDICT_FILES, mark_stale
from report.report import ReportInputs, write_report

TOL = {"T": 1e-6, "A": 1e-6, "eps": 1e-6}
RUNGS = (250, 500, 1000, 2000)


def plan(*ladders):
    """Planned runs: every rung of the ladders (name, engine, law, geometry); the default law
    runs once (its name is its run's)."""
    represents = {"viscoelastic": ["x0", "F0"], "viscoelastic_clipped": ["F0"], "default": ["x0"]}
    return pd.DataFrame([{"case": "steel", "name": f"{n}-dt{f}" if law != "default" else n, "ladder": n, "engine": e,
                          "law": law, "geometry": g, "represents": represents[law]}
                         for n, e, law, g in ladders for f in (RUNGS if law != "default" else (1000,))])


def rows(name, engine="lammps", law="viscoelastic", geometry="sphere-sphere", K=0.1, res=1e-7, problem="", **err):
    """A ladder's limit rows (dt = 0, one per criterion), errors err_q and resolution `res`."""
    criteria = {"viscoelastic": ["x0", "F0"], "viscoelastic_clipped": ["F0"], "default": ["x0"]}[law]
    return [{"case": "steel", "run": name, "ladder": name, "engine": engine, "engine_version": "v", "law": law,
             "geometry": geometry, "criterion": c, "K": K, "dt": 0.0,
             "err_T": err.get("T", 1e-8), "err_A": err.get("A", 2e-8), "err_eps": err.get("eps", -3e-9),
             "resolution_T": res, "resolution_A": res, "resolution_eps": res, "problem": problem} for c in criteria]


def no_failures():
    return pd.DataFrame(columns=["run", "problem", "log"])


def test_an_engines_keyword_is_gated_against_its_own_equation_like_the_model():
    """The law 'default' (each code's restitution keyword) is gated: its errors are against its own
    equation, and one off by 0.5 in T fails its check as the model's laws do."""
    table = pd.DataFrame(rows("a") + rows("b", K=0.2) + rows("d", law="default", T=0.5))
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere"),
                                     ("b", "lammps", "viscoelastic", "sphere-sphere"),
                                     ("d", "lammps", "default", "sphere-sphere")), no_failures(), TOL)
    assert len(checks) == 3 * 3  # viscoelastic x0 and F0, the keyword's x0 (LAMMPS keeps the tail); x T, A, eps
    assert set(checks.law) == {"viscoelastic", "default"}
    failing = checks[~checks["pass"]]
    assert list(zip(failing.law, failing.quantity)) == [("default", "T")]
    v = verdict_of(checks, "sha", TOL)
    assert v["verdict"] == "FAIL" and v["checked"] == 9 and v["failed"] == 1


def test_worst_ladder_decides_and_the_boundary_counts_the_resolution():
    """|e| + resolution <= tolerance passes (inclusive); the check reports the largest |e| and the
    largest resolution of its ladders, and the failing ladder by name in its reason."""
    table = pd.DataFrame(rows("a", T=-4e-7) + rows("b", K=0.3, T=-6e-6) + rows("c", K=0.5, A=9e-7, res=1e-7))
    checks = gate_checks(table, plan(*[(n, "lammps", "viscoelastic", "sphere-sphere") for n in "abc"]),
                         no_failures(), TOL).set_index(["criterion", "quantity"])
    t = checks.loc[("x0", "T")]
    assert not t["pass"] and t.max_rel_error == pytest.approx(6e-6) and t.at_K == 0.3 and t.at_run == "b"
    assert t.resolution == pytest.approx(1e-7)
    assert t.reason.startswith("6.000e-06 > 1e-06 (resolution 1.0e-07; case steel, K = 0.3)")
    assert checks.loc[("x0", "A"), "pass"]  # 9e-7 + 1e-7 = the tolerance: passes
    v = verdict_of(checks.reset_index(), "sha", TOL)
    assert v["verdict"] == "FAIL" and v["failed"] == 2  # T under x0 and under F0
    assert all(f.startswith("lammps viscoelastic sphere-sphere") and " T: " in f for f in v["failures"])


def test_an_error_within_the_tolerance_but_not_its_resolution_is_not_a_pass():
    """|e| <= tol < |e| + r: the study cannot tell, so the check fails as not resolved; with a
    smaller resolution the same error passes, and |e| - r > tol fails as resolved."""
    from verdict.gate import judge

    assert judge(8e-7, 5e-7, 1e-6) == "unresolved" and judge(1.2e-6, 5e-7, 1e-6) == "unresolved"
    assert judge(8e-7, 1e-7, 1e-6) == "pass" and judge(1.2e-6, 1e-7, 1e-6) == "fail"
    assert judge(math.nan, 1e-7, 1e-6) == "nan" and judge(5e-7, math.nan, 1e-6) == "pass"
    table = pd.DataFrame(rows("a", eps=8e-7, res=5e-7))
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere")), no_failures(), TOL)
    eps = checks[checks.quantity == "eps"]
    assert not eps["pass"].any()
    # The wording says what is compared, and each comparison it states is true.
    assert eps.reason.str.startswith("not resolved at this tolerance: |error| + resolution = 8.000e-07 + 5.0e-07 = "
                                     "1.300e-06 > 1e-06 >= |error| - resolution = 3.0e-07 (case ").all()


def test_the_verdict_line_of_a_regression_check_says_what_it_compares():
    """5.229e-07 with resolution 5.1e-07 against 1e-06 is not resolved: its line must not read
    '5.229e-07 > 1e-06' (false), but '|error| + resolution = 1.033e-06 > 1e-06'."""
    from verdict.gate import regression_checks

    reported = regression_checks(pd.DataFrame(regression_rows("lammps-z", 5.229e-7, res=5.1e-7)), TOL)
    t = reported[reported.quantity == "T"].iloc[0]
    assert not t["pass"]
    assert t.reason == ("not resolved at this tolerance: |error| + resolution = 5.229e-07 + 5.1e-07 = 1.033e-06 > "
                        "1e-06 >= |error| - resolution = 1.3e-08 (written as the user would: "
                        f"{t.at_run})")
    assert "5.229e-07 > 1e-06" not in t.reason


def test_a_misaligned_ladder_fails_its_checks_with_the_reason_and_is_not_judged_by_its_number():
    """A misaligned ladder's limit means nothing: its checks fail by the problem alone, its number
    is neither quoted as a failure nor reported as the check's worst error; a sound ladder of the
    same check is still judged."""
    problem = "misaligned ladder: contact starts +0.25 steps from the planned phase 0.5 at dt = T_e/500"
    table = pd.DataFrame(rows("a", problem=problem, T=5e-6))
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere")), no_failures(), TOL)
    assert not checks["pass"].any() and checks.reason.str.startswith("misaligned ladder").all()
    assert not checks.reason.str.contains("5.000e-06", regex=False).any()
    both = gate_checks(pd.DataFrame(rows("a", problem=problem, T=5e-6) + rows("b", K=0.3, T=3e-6)),
                       plan(("a", "lammps", "viscoelastic", "sphere-sphere"), ("b", "lammps", "viscoelastic",
                                                                            "sphere-sphere")), no_failures(), TOL)
    t = both[(both.criterion == "x0") & (both.quantity == "T")].iloc[0]
    assert t.reason.startswith("misaligned ladder") and "3.000e-06 > 1e-06" in t.reason
    assert t.max_rel_error == pytest.approx(3e-6) and t.at_run == "b"


def test_a_failed_rung_fails_its_ladders_checks_naming_run_and_log():
    """One rung of ladder b crashed: b's limit cannot be made, its checks fail naming the rung and
    the engine log, even where the summary still held a limit row for b (an earlier study)."""
    table = pd.DataFrame(rows("a") + rows("b"))
    failed = pd.DataFrame([{"run": "b-dt1000", "problem": "lammps exited with status 139", "log": "runs/lammps.log"}])
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere"),
                                     ("b", "lammps", "viscoelastic", "sphere-sphere")), failed, TOL)
    assert not checks["pass"].any()
    assert (checks.failed == 1).all() and (checks.landed == 1).all() and (checks.planned == 2).all()
    assert all("1 of 2 ladders have a failed run; first: b-dt1000: lammps exited with status 139 (engine log: "
               "runs/lammps.log)" in r for r in checks.reason)


def test_a_planned_run_with_no_result_fails_and_a_group_with_none_fails():
    checks = gate_checks(pd.DataFrame(rows("a")), plan(("a", "lammps", "viscoelastic", "sphere-sphere"),
                                                       ("b", "lammps", "viscoelastic", "sphere-sphere"),
                                                       ("c", "yade", "viscoelastic_clipped", "sphere-plane")),
                         no_failures(), TOL)
    lammps = checks[checks.engine == "lammps"]
    assert (not lammps["pass"].any()
            and lammps.reason.str.contains(r"1 of 2 planned ladders have no result \(first: b\)").all())
    yade = checks[checks.engine == "yade"]
    assert len(yade) == 3 and not yade["pass"].any() and yade.max_rel_error.isna().all()


def test_nan_error_fails_and_empty_study_is_not_a_pass():
    table = pd.DataFrame(rows("a", eps=math.nan))
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere")), no_failures(), TOL)
    eps = checks[checks.quantity == "eps"]
    assert not eps["pass"].any() and eps.reason.str.contains("NaN").all()
    empty = gate_checks(pd.DataFrame(), plan(), no_failures(), TOL)
    v = verdict_of(empty, "sha", TOL)
    assert len(empty) == 0 and v["verdict"] == "FAIL" and "no gated check" in v["failures"][0]
    root = junit_xml(empty).getroot()
    assert root.get("tests") == "1" and root.get("failures") == "1"


def test_junit_has_one_testcase_per_check_and_a_failure_for_each_failing_one(tmp_path):
    table = pd.DataFrame(rows("a", T=1e-2) + rows("b", engine="yade", geometry="sphere-plane"))
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere"),
                                     ("b", "yade", "viscoelastic", "sphere-plane")), no_failures(), TOL)
    write_junit(checks, tmp_path / "junit.xml")
    root = ET.parse(tmp_path / "junit.xml").getroot()
    cases = root.findall(".//testcase")
    assert len(cases) == len(checks) == 12
    failing = [c for c in cases if c.find("failure") is not None]
    assert {(c.get("classname"), c.get("name")) for c in failing} == {
        ("lammps.viscoelastic.sphere-sphere.x0", "T"), ("lammps.viscoelastic.sphere-sphere.F0", "T")}
    assert root.get("failures") == "2" and root.find("testsuite").get("tests") == "12"
    assert "1.000e-02 > 1e-06" in failing[0].find("failure").get("message")


def test_report_says_fail_first_and_names_every_failing_check(tmp_path):
    from test_comparison import exact_metrics, meta_for
    from analysis.comparison import comparison_rows

    meta = meta_for(K=0.1)
    table = pd.DataFrame([{**r, "run": "a", "build": "lammps", "engine": "lammps", "err_T": 1e-2}
                          for r in comparison_rows(meta, exact_metrics(meta))])
    table["geometry"] = "sphere-sphere"
    failed_runs = [{"case": "steel", "engine": "lammps", "law": "default", "run": "d",
                    "problem": "unreadable engine record | x", "log": "runs/lammps.log"}]
    checks = gate_checks(table, plan(("a", "lammps", "viscoelastic", "sphere-sphere"),
                                     ("d", "lammps", "default", "sphere-sphere")),
                         pd.DataFrame(failed_runs), TOL)
    verdict = verdict_of(checks, "0" * 64, TOL)
    write_report(ReportInputs(table, checks, verdict, failed_runs=failed_runs), tmp_path)
    text = (tmp_path / "report.md").read_text()
    first = [line for line in text.splitlines() if line.strip()][1]
    assert first.startswith("**Verdict: FAIL** — 4 of 9 gated checks")  # the keyword's 3 fail: its run failed
    for f in verdict["failures"]:
        assert f"- {f}" in text
    assert "| lammps | default | d | unreadable engine record \\| x | runs/lammps.log |" in text
    assert "FAIL" in (tmp_path / "report.html").read_text()


def test_mark_stale_keeps_the_reports_readable_and_nothing_says_pass(tmp_path):
    """A rule about to change results marks the verdict stale: gate.txt and checks.csv (a pass per
    check) go, verdict.json says STALE (what it was, since when, by which job, how to get a
    verdict), junit.xml gains one failing case, both reports open with the banner; every file is
    dated 1970 so that Snakemake rewrites it."""
    write_verdict({"verdict": "PASS", "pass": True, "checked": 6, "failed": 0, "failures": []},
                  tmp_path / "verdict.json")
    assert not list(tmp_path.glob(".*.part"))  # written atomically: no temporary left behind
    (tmp_path / "gate.txt").write_text("PASS: 6 checks\n")
    (tmp_path / "checks.csv").write_text("build,pass\nlammps,True\n")
    (tmp_path / "report.md").write_text("# Report\n\n**Verdict: PASS**\n")
    (tmp_path / "report.html").write_text("<html><body><p>PASS</p></body></html>")
    junit_xml(pd.DataFrame(columns=CHECK_COLUMNS)).write(tmp_path / "junit.xml")
    (tmp_path / "summary.csv").write_text("kept")
    failures_before = int(ET.parse(tmp_path / "junit.xml").getroot().get("failures"))
    changed = mark_stale(tmp_path, "run_engine (case steel, build lammps)", "snakemake -j2 steel")
    assert sorted(Path(p).name for p in changed) == sorted(VERDICT_FILES)
    assert not (tmp_path / "gate.txt").exists() and not (tmp_path / "checks.csv").exists()
    assert (tmp_path / "summary.csv").read_text() == "kept"
    verdict = json.loads((tmp_path / "verdict.json").read_text())
    assert verdict["verdict"] == "STALE" and verdict["pass"] is False and verdict["checked"] == 6
    assert verdict["stale"]["was"] == "PASS" and verdict["stale"]["by"] == "run_engine (case steel, build lammps)"
    md = (tmp_path / "report.md").read_text()
    assert md.startswith("# Report\n\n<!-- stale -->\n> **STALE**: results changed since this verdict (PASS) was "
                         "written: run_engine (case steel, build lammps), since ")
    assert "For a verdict again: snakemake -j2 steel." in md and md.endswith("**Verdict: PASS**\n")
    assert "<strong>STALE</strong>" in (tmp_path / "report.html").read_text()
    root = ET.parse(tmp_path / "junit.xml").getroot()
    assert int(root.get("failures")) == failures_before + 1
    assert root.find(".//testcase[@name='stale']/failure") is not None
    assert all((tmp_path / n).stat().st_mtime == 0 for n in VERDICT_FILES if n not in ("gate.txt", "checks.csv"))
    # Marked again (another job): one banner, one stale case, and it still knows what it was and since when.
    since = verdict["stale"]["since"]
    mark_stale(tmp_path, "case_summary (case steel)")
    again = json.loads((tmp_path / "verdict.json").read_text())
    assert again["stale"]["was"] == "PASS" and again["stale"]["since"] == since
    assert again["stale"]["by"] == "case_summary (case steel)"
    assert (tmp_path / "report.md").read_text().count("<!-- stale -->") == 1
    assert len(ET.parse(tmp_path / "junit.xml").getroot().findall(".//testcase[@name='stale']")) == 1


def test_mark_stale_of_a_folder_with_no_verdict_writes_nothing(tmp_path):
    assert mark_stale(tmp_path, "plan_case (case steel)") == [] and list(tmp_path.iterdir()) == []


def regression_rows(build, user_err_T, control_err_T=2e-10, problem="", res=1e-8):
    """A regression case's table (analysis.regressions): the user's ladder and the control's,
    their limits with a resolution of `res`."""
    base = {"build": build, "case": "wall-modulus", "geometry": "sphere-plane", "K": 0.0,
            **{f"resolution_{q}": res for q in ("T", "A", "eps")}}
    return [{**base, "role": "user", "run": f"{build}-user", "problem": problem,
             "err_T": user_err_T, "err_A": user_err_T, "err_eps": 1e-9},
            {**base, "role": "control", "run": f"{build}-control", "problem": "",
             "err_T": control_err_T, "err_A": control_err_T, "err_eps": 1e-9}]


def test_regression_checks_are_reported_in_junit_as_skipped_and_never_decide_the_verdict():
    from verdict.gate import regression_checks

    model = gate_checks(pd.DataFrame(rows("a")), plan(("a", "lammps", "viscoelastic", "sphere-sphere")),
                        no_failures(), TOL)
    reported = regression_checks(pd.DataFrame(regression_rows("lammps-2021", -0.0996) +
                                              regression_rows("lammps-2025", 5e-8) +
                                              regression_rows("lammps-x", math.nan, problem="SIGSEGV") +
                                              regression_rows("lammps-y", 1e-7, control_err_T=0.2)), TOL)
    status = reported.set_index(["build", "quantity"])["pass"]
    assert not status[("lammps-2021", "T")] and status[("lammps-2025", "T")] and status[("lammps-2021", "eps")]
    assert not status[("lammps-x", "eps")]  # a crashed run fails every quantity, naming why
    assert "the run failed: SIGSEGV" in reported[reported.build == "lammps-x"].reason.iloc[0]
    y = reported[(reported.build == "lammps-y") & (reported.quantity == "T")].iloc[0]
    assert not y["pass"] and "the control run" in y.reason  # a wrong control proves nothing: it fails
    checks = pd.concat([model, reported], ignore_index=True)
    v = verdict_of(checks, "sha", TOL)
    assert v["verdict"] == "PASS" and v["checked"] == 6  # only the model's checks gate
    assert any(r.startswith("lammps-2021 regression:wall-modulus sphere-plane x0 T: 9.960e-02 > 1e-06 (resolution "
                            "1.0e-08; written as the user would: ") for r in v["reported"])
    root = junit_xml(checks).getroot()
    assert root.get("failures") == "0" and int(root.get("skipped")) == int((~reported["pass"]).sum())
    skipped = [c for c in root.iter("testcase") if c.find("skipped") is not None]
    assert all(c.get("classname").split(".")[1].startswith("regression:") for c in skipped)
    assert all(c.find("failure") is None for c in root.iter("testcase"))



def test_the_line_that_ends_the_study_log_gives_the_verdict_and_the_report(tmp_path):
    from verdict.verdict_files import verdict_line

    assert verdict_line(tmp_path).startswith(f"no verdict: {tmp_path / 'verdict.json'} was not written")
    (tmp_path / "report.html").write_text("<html></html>")
    write_verdict({"verdict": "FAIL", "pass": False, "checked": 114, "failed": 2, "failures": []},
                  tmp_path / "verdict.json")
    assert verdict_line(tmp_path) == f"FAIL: 112 of 114 gated checks pass; report: {tmp_path / 'report.html'}"
    mark_stale(tmp_path, "run_engine (case steel, build lammps)")
    assert verdict_line(tmp_path).startswith("STALE: results changed since this verdict (FAIL) was written")


def _mark_many(folder, n):
    for i in range(n):
        mark_stale(folder, f"job {i}")


def test_jobs_that_start_together_mark_the_verdict_stale_at_once_without_a_collision(tmp_path):
    """Every case's plan job starts at once and each marks the study's verdict stale: two
    processes marking one folder 200 times each raise nothing (each writes through a temporary of
    its own; one shared name made the second writer's rename fail), and the files stay whole."""
    import multiprocessing

    write_verdict({"verdict": "PASS", "pass": True, "checked": 1, "failed": 0, "failures": []},
                  tmp_path / "verdict.json")
    (tmp_path / "report.md").write_text("# Report\n\nPASS\n")
    junit_xml(pd.DataFrame(columns=CHECK_COLUMNS)).write(tmp_path / "junit.xml")
    ctx = multiprocessing.get_context("fork")
    workers = [ctx.Process(target=_mark_many, args=(tmp_path, 200)) for _ in range(2)]
    for w in workers:
        w.start()
    for w in workers:
        w.join(60)
    assert [w.exitcode for w in workers] == [0, 0]
    assert json.loads((tmp_path / "verdict.json").read_text())["verdict"] == "STALE"
    assert (tmp_path / "report.md").read_text().count("<!-- stale -->") == 1
    assert len(ET.parse(tmp_path / "junit.xml").getroot().findall(".//testcase[@name='stale']")) == 1
    assert not list(tmp_path.glob(".*.part"))


def test_a_tolerance_of_1_or_more_is_no_relative_tolerance_and_one_above_1e_2_is_warned():
    """tolerance_problems names the key of every value outside (0, 1); verdict_of refuses them,
    and states what a verdict was judged against, with a warning above 1e-2."""
    from verdict.verdict_files import LOOSE_TOLERANCE, tolerance_problems, tolerance_warnings

    assert tolerance_problems(TOL) == [] and tolerance_warnings(TOL) == []
    assert tolerance_problems({"T": 10, "A": 1.0, "eps": 0}) == [
        f"tolerance.{q} = {v} is not a relative tolerance: it must lie in (0, 1) (1e-6 is one part in a million, "
        "the study's)" for q, v in (("T", 10), ("A", 1.0), ("eps", 0))]
    assert tolerance_problems({"T": 1e-6, "A": 1e-6}) == [
        "tolerance.eps is missing: give the relative tolerance of eps, e.g. 1e-6"]
    checks = gate_checks(pd.DataFrame(rows("a")), plan(("a", "lammps", "viscoelastic", "sphere-sphere")),
                         no_failures(), TOL)
    with pytest.raises(ValueError, match=r"^tolerance\.T = 10 is not a relative tolerance: it must lie in \(0, 1\)"):
        verdict_of(checks, "sha", {**TOL, "T": 10})
    assert LOOSE_TOLERANCE == 1e-2
    loose = {**TOL, "T": 0.05}
    assert tolerance_warnings({**TOL, "T": 1e-2}) == []  # at 1e-2: no warning
    v = verdict_of(checks, "sha", loose)
    assert v["verdict"] == "PASS" and v["tolerance"] == {"T": 0.05, "A": 1e-6, "eps": 1e-6}
    assert v["warnings"] == ["tolerance.T = 0.05 is above 1e-2: a PASS at it allows T to be off by 5 %"]
    assert verdict_of(checks, "sha", TOL)["warnings"] == []


def test_gate_txt_and_the_verdict_line_state_the_tolerances_and_the_warnings(tmp_path):
    from verdict.verdict_files import gate_text, verdict_line

    v = {"verdict": "PASS", "pass": True, "checked": 30, "failed": 0, "failures": [],
         "tolerance": {"T": 0.05, "A": 1e-6, "eps": 1e-6},
         "warnings": ["tolerance.T = 0.05 is above 1e-2: a PASS at it allows T to be off by 5 %"]}
    assert gate_text(v, "abc") == (
        "PASS: 30 engine build x law x geometry x criterion x quantity checks within tolerance (relative: T 0.05, "
        "A 1e-06, eps 1e-06; summary sha256 abc)\n"
        "Warning: tolerance.T = 0.05 is above 1e-2: a PASS at it allows T to be off by 5 %\n")
    write_verdict(v, tmp_path / "verdict.json")
    assert verdict_line(tmp_path) == ("PASS: 30 of 30 gated checks pass (tolerance, relative: T 0.05, A 1e-06, "
                                      "eps 1e-06)\nWarning: tolerance.T = 0.05 is above 1e-2: a PASS at it allows T "
                                      "to be off by 5 %")


def test_the_verdict_files_are_written_from_one_place_verdict_json_last(tmp_path):
    """write_verdict_files: checks.csv, junit.xml, the report, then verdict.json; a report that fails
    leaves no verdict.json (and no temporary file)."""
    from verdict.gate import write_verdict_files

    checks = gate_checks(pd.DataFrame(rows("a")), plan(("a", "lammps", "viscoelastic", "sphere-sphere")),
                         no_failures(), TOL)
    paths = {"checks": tmp_path / "checks.csv", "junit": tmp_path / "junit.xml", "verdict": tmp_path / "verdict.json"}
    seen = []

    def report():
        seen.append(sorted(p.name for p in tmp_path.iterdir()))
        raise OSError(30, "Read-only file system", str(tmp_path / "plots"))

    with pytest.raises(OSError, match="Read-only file system"):
        write_verdict_files(checks, verdict_of(checks, "sha", TOL), paths, report=report)
    assert seen == [["checks.csv", "junit.xml"]] and not paths["verdict"].exists()
    assert not list(tmp_path.glob(".*.part"))
    write_verdict_files(checks, verdict_of(checks, "sha", TOL), paths)
    assert pd.read_csv(paths["checks"])["pass"].all() and len(pd.read_csv(paths["checks"])) == 6
    assert json.loads(paths["verdict"].read_text())["tolerance"] == TOL
