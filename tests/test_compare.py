"""Comparing two studies check by check: regressions, fixes, the noise floor, JUnit, the exit
status; unit tests on small tables (the real-engine pair is in tests/test_study_failures.py)."""

import xml.etree.ElementTree as ET

import pandas as pd
import pytest

from verdict.compare import CompareError, compare_checks, load_checks, main

GROUP = {"engine": "lammps", "law": "viscoelastic", "geometry": "sphere-sphere", "criterion": "x0"}


def checks(**errors):
    """A checks table: quantity -> (max_rel_error, pass)."""
    return pd.DataFrame([{**GROUP, "quantity": q, "max_rel_error": e, "pass": ok, "reason": "" if ok else "x"}
                         for q, (e, ok) in errors.items()])


def status(base, cand, **kw):
    return dict(zip(compare_checks(base, cand, **kw).quantity, compare_checks(base, cand, **kw).status))


def test_failing_now_or_grown_past_the_factor_is_a_regression_and_the_reverse_a_fix():
    base = checks(T=(1e-4, True), A=(1e-4, True), eps=(8e-4, False))
    cand = checks(T=(6e-4, False), A=(2.5e-4, True), eps=(1e-6, True))
    assert status(base, cand) == {"T": "regression", "A": "regression", "eps": "fix"}
    assert status(base, cand, factor=3.0) == {"T": "regression", "A": "unchanged", "eps": "fix"}
    assert status(cand, base) == {"T": "fix", "A": "fix", "eps": "regression"}


def test_round_off_level_changes_are_not_regressions():
    base, cand = checks(T=(1e-12, True)), checks(T=(5e-11, True))
    assert status(base, cand) == {"T": "unchanged"}  # both below the 1e-9 noise floor
    assert status(base, cand, noise_floor=0.0) == {"T": "regression"}


def test_checks_in_one_study_only_are_new_or_removed():
    base, cand = checks(T=(1e-4, True)), checks(A=(1e-4, True))
    assert status(base, cand) == {"T": "removed", "A": "new"}


def test_summary_and_checks_give_the_same_checks(tmp_path):
    from test_gate import rows

    table = pd.DataFrame(rows("a", T=3e-4) + rows("b", K=0.2, T=-7e-4))
    table.to_csv(tmp_path / "summary.csv", index=False)
    from_summary = load_checks(tmp_path / "summary.csv")
    t = from_summary.set_index(["criterion", "quantity"]).loc[("x0", "T")]
    assert t.max_rel_error == pytest.approx(7e-4) and not t["pass"] and t.at_K == 0.2
    (tmp_path / "results").mkdir()
    from_summary.to_csv(tmp_path / "results" / "checks.csv", index=False, float_format="%.12g")
    again = load_checks(tmp_path / "results")
    assert (compare_checks(from_summary, again).status == "unchanged").all()


def test_command_writes_reports_and_exits_1_on_a_regression_2_on_bad_input(tmp_path, capsys):
    base, cand = tmp_path / "base.csv", tmp_path / "cand.csv"
    checks(T=(1e-4, True), A=(1e-4, True)).to_csv(base, index=False)
    checks(T=(9e-4, False), A=(1e-4, True)).to_csv(cand, index=False)
    out = tmp_path / "out"
    assert main([str(base), str(cand), "--out", str(out)]) == 1
    said = capsys.readouterr().out
    assert "1 regressions, 0 fixes" in said and "REGRESSION lammps viscoelastic sphere-sphere x0 T" in said
    assert (out / "compare.md").read_text().splitlines()[2].startswith("**REGRESSION**")
    root = ET.parse(out / "compare-junit.xml").getroot()
    failing = [c for c in root.iter("testcase") if c.find("failure") is not None]
    assert root.get("tests") == "2" and [(c.get("classname"), c.get("name")) for c in failing] == [
        ("lammps.viscoelastic.sphere-sphere.x0", "T")]
    assert main([str(cand), str(base), "--out", str(out)]) == 0  # the reverse: a fix
    assert "0 regressions, 1 fixes" in capsys.readouterr().out
    assert main([str(tmp_path / "missing"), str(cand), "--out", str(out)]) == 2
    assert "missing: cannot read it as CSV" in capsys.readouterr().err
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    with pytest.raises(CompareError, match=r"other\.csv: neither a checks\.csv nor a summary\.csv"):
        load_checks(tmp_path / "other.csv")


def test_two_builds_of_one_study_are_compared_with_builds(tmp_path, capsys):
    study = pd.concat([checks(T=(0.0996, False), A=(1e-6, True)).assign(build="lammps-2021"),
                       checks(T=(5e-7, True), A=(1e-6, True)).assign(build="lammps-2025"),
                       checks(T=(1e-6, True)).assign(build="yade-2023")], ignore_index=True)
    path, out = tmp_path / "checks.csv", tmp_path / "out"
    study.to_csv(path, index=False)
    assert main([str(path), str(path), "--out", str(out), "--builds", "lammps-2021=lammps-2025"]) == 0
    assert "0 regressions, 1 fixes" in capsys.readouterr().out
    comparison = pd.read_csv(out / "compare.csv")
    assert set(comparison.build) == {"lammps-2021 -> lammps-2025"}  # yade left out
    assert dict(zip(comparison.quantity, comparison.status)) == {"T": "fix", "A": "unchanged"}
    assert main([str(path), str(path), "--out", str(out), "--builds", "lammps-2025=lammps-2021"]) == 1
    capsys.readouterr()
    assert main([str(path), str(path), "--out", str(out), "--builds", "lammps-2021"]) == 2
    assert "--builds 'lammps-2021': write it as BASELINE_BUILD=CANDIDATE_BUILD" in capsys.readouterr().err
    assert main([str(path), str(path), "--out", str(out), "--builds", "lammps-2021=lammps-1999"]) == 2
    assert ("the candidate study has no check of build 'lammps-1999'; its builds: lammps-2021, lammps-2025, "
            "yade-2023") in capsys.readouterr().err
