"""The study's gate: one check per engine build x gated law x geometry x criterion x quantity.

A gated run is a ladder of runs at several time steps (`engines.ladder`), judged by its limit
dt -> 0 (`analysis.extrapolation`: the extrapolated error e and its resolution r, the
smallest error the ladder can tell from zero). A check is made for every combination the plans
asked for, whether or not its runs landed:

    pass  <=>  every planned ladder of the group landed (all its rungs), none failed or is
               misaligned, and for every ladder  |e_q| + r_q <= tolerance[q]   (q = T, A, eps)

so a PASS is a claim the study can back: the engine's error is within the tolerance even at the
far end of what the ladder leaves open. A ladder with |e_q| - r_q > tolerance fails: the error is
resolved, and too large. One in between fails as unresolved: the study cannot tell at this
tolerance (its reason says so). A run that crashed, hung or left no result fails its ladder's
checks (it can never hide as a missing row), a NaN error fails, and a study with no check at
all is not a PASS. The tolerance is relative and lies in (0, 1) (`tolerance_problems`: config
`tolerance.T` of 1 or more is refused); above 1e-2 the verdict carries a warning saying so. The
verdict goes to `verdict.json` (read by the `gate` rule, with the tolerances it was judged
against), to JUnit XML (one test case per check, read by CI) and to checks.csv, all through
`write_verdict_files`.

Files are written atomically (a temporary file, then `os.replace`), so a reader sees the old
file or the new one, never half of one.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd

from contact_model import GATED_LAWS

from records.files import write_atomically
from records.quantities import GATED_QUANTITIES  # noqa: F401  (T, A, eps; the reports import it from here)
from records.quantities import gated_quantities  # read at each call: the table's gated quantities

from analysis.checks import judge, judgement, with_build  # noqa: F401  (the reports import with_build from here)

from .verdict_files import tolerance_problems, tolerance_warnings, write_junit_xml
from .verdict_files import write_verdict  # noqa: F401  (the one writer of verdict.json; its callers import it from here too)

GROUP = ["build", "law", "geometry", "criterion"]
#: The columns of checks.csv. `gates`: whether the check decides the verdict (the model's laws)
#: or is reported only (an engine's regression cases, `regression_checks`). For the ladder with
#: the largest |extrapolated error| (max_rel_error, at_K, case, at_run): its observed order, its
#: rungs' T_e / dt and raw errors (coarsest first); resolution is the largest of the group's.
CHECK_COLUMNS = ["build", "engine", "law", "geometry", "criterion", "quantity", "planned", "landed", "failed",
                 "max_rel_error", "resolution", "at_K", "case", "at_run", "tolerance", "pass", "reason", "gates",
                 "observed_order", "rung_factors", "rung_errors"]


def limit_rows(table: pd.DataFrame) -> pd.DataFrame:
    """The rows of summary.csv the gate judges: the ladders' limits (dt = 0) of the gated laws.
    A table from before ladders (no dt = 0 row) is judged run by run, each run its own ladder
    with resolution 0."""
    table = with_build(table)
    if not len(table):
        return table
    gated = table[table.law.isin(GATED_LAWS)]
    if "dt" in gated.columns and (gated.dt == 0).any():
        return gated[gated.dt == 0]
    return gated.assign(ladder=gated["run"] if "run" in gated.columns else [f"row-{i}" for i in range(len(gated))])


def planned_groups(plan_runs: pd.DataFrame) -> pd.DataFrame:
    """The gated runs of the plans, one row per run and criterion it represents.

    Parameters
    ----------
    plan_runs : DataFrame
        One row per planned run: case, name, engine, law, geometry, represents (list of criteria)
        and ladder (the ladder it is a rung of; a plan without it: each run its own).

    Returns
    -------
    DataFrame with columns case, run, ladder, engine, build, law, geometry, criterion.
    """
    columns = ["case", "run", "ladder", "engine", *GROUP]
    if plan_runs.empty:
        return pd.DataFrame(columns=columns)
    gated = with_build(plan_runs)[plan_runs.law.isin(GATED_LAWS)].explode("represents")
    if "ladder" not in gated.columns:
        gated = gated.assign(ladder=gated["name"])
    return gated.rename(columns={"name": "run", "represents": "criterion"})[columns]


def gate_checks(table: pd.DataFrame, plan_runs: pd.DataFrame, failed_runs: pd.DataFrame,
                tolerance: dict) -> pd.DataFrame:
    """Every gated check with its outcome.

    Parameters
    ----------
    table : DataFrame
        summary.csv: one row per landed run and criterion, and one per ladder and criterion with
        dt = 0 (`analysis.extrapolation`): columns run, case, K, the GROUP columns, err_T,
        err_A, err_eps (relative errors, engine vs reference), resolution_T, ... and problem.
    plan_runs : DataFrame
        The planned runs (see `planned_groups`).
    failed_runs : DataFrame
        Runs the engine did not complete: columns run, problem, log.
    tolerance : dict
        Relative tolerance per quantity, e.g. ``{"T": 1e-6, "A": 1e-6, "eps": 1e-6}``.

    Returns
    -------
    DataFrame, one row per check, sorted by GROUP and quantity, with the columns CHECK_COLUMNS:
    planned, landed, failed count ladders; max_rel_error is the largest |extrapolated error|
    (NaN without a result), at_K, case and at_run (the ladder's name) say where; resolution is
    the largest resolution of the group's ladders; pass (bool) and reason (why it failed; empty
    when it passed).
    """
    planned = planned_groups(plan_runs)
    limits = limit_rows(table)
    code_of_build = {**(dict(zip(limits.build, limits.engine)) if len(limits) else {}),
                     **dict(zip(planned.build, planned.engine))}
    failed_runs = failed_runs if len(failed_runs) else pd.DataFrame(columns=["run", "problem", "log"])
    failed = planned.merge(failed_runs[["run", "problem", "log"]], on="run", how="inner")
    keys = sorted(set(map(tuple, planned[GROUP].to_numpy())) |
                  (set(map(tuple, limits[GROUP].to_numpy())) if len(limits) else set()))
    rows = []
    for key in keys:
        sel_plan, sel, sel_failed = (_of_group(df, key) for df in (planned, limits, failed))
        ladders = list(dict.fromkeys(sel_plan.ladder if len(sel_plan) else sel.ladder if len(sel) else ()))
        failed_ladders = list(dict.fromkeys(sel_failed.ladder))
        sel = sel[~sel.ladder.isin(failed_ladders)] if len(sel) else sel
        n_planned, n_landed, n_failed = len(ladders), len(sel), len(failed_ladders)
        missing = [x for x in ladders if x not in set(sel.ladder if len(sel) else ()) and x not in failed_ladders]
        # A ladder with a problem (misaligned) is reported by it: its limit means nothing, so it is
        # not judged by its number.
        flawed = (sel["problem"].astype(object).fillna("").astype(str) if len(sel) and "problem" in sel.columns
                  else pd.Series("", index=sel.index, dtype=object))
        problems = [p for p in flawed if p]
        for q in gated_quantities():
            row = {**dict(zip(GROUP, key)), "engine": code_of_build.get(key[0], ""), "quantity": q,
                   "planned": n_planned, "landed": n_landed, "failed": n_failed, "max_rel_error": math.nan,
                   "resolution": math.nan, "at_K": math.nan, "case": "", "at_run": "",
                   "tolerance": float(tolerance[q]), "pass": False, "reason": "", "gates": True,
                   "observed_order": math.nan, "rung_factors": "", "rung_errors": ""}
            reasons = [problems[0] + (f" ({len(problems)} ladders)" if len(problems) > 1 else "")] if problems else []
            if n_landed:
                errors = sel[f"err_{q}"].to_numpy(dtype=float)
                known = f"resolution_{q}" in sel.columns  # a summary from before ladders has none
                res = sel[f"resolution_{q}"].to_numpy(dtype=float) if known else np.zeros(len(sel))
                res = np.where(np.isnan(res), 0.0, res)
                sound = (flawed == "").to_numpy()
                shown = np.where(sound, errors, np.nan) if sound.any() else errors  # a flawed limit is no error
                i = int(np.nanargmax(np.abs(shown))) if not np.isnan(shown).all() else 0
                worst = sel.iloc[i]
                row.update(max_rel_error=float(abs(errors[i])), resolution=float(res.max()) if known else math.nan,
                           at_K=float(worst.K),
                           case=str(worst.case), at_run=str(worst.ladder),
                           observed_order=float(worst.get(f"order_{q}", math.nan)),
                           rung_factors=(str(worst.get("rung_factors", ""))
                                         if pd.notna(worst.get("rung_factors", "")) else ""),
                           rung_errors=(str(worst.get(f"rungs_{q}", ""))
                                        if pd.notna(worst.get(f"rungs_{q}", "")) else ""))
                outcomes = [judge(e, r, tolerance[q]) if ok else "flawed" for e, r, ok in zip(errors, res, sound)]
                # the sound ladder that fails by most, first
                for j in np.argsort(-(np.abs(np.nan_to_num(errors, nan=np.inf)) + res)):
                    if outcomes[j] == "fail" and not known:  # a summary from before ladders
                        reasons.append(f"{abs(errors[j]):.3e} > {tolerance[q]:g} (case {sel.case.iloc[j]}, "
                                       f"K = {sel.K.iloc[j]:.4g})")
                        break
                    if outcomes[j] in ("fail", "unresolved"):
                        reasons.append(f"{judgement(errors[j], res[j], tolerance[q])}case {sel.case.iloc[j]}, "
                                       f"K = {sel.K.iloc[j]:.4g})")
                        break
                if "nan" in outcomes:
                    reasons.append("a run's error is NaN (the engine gave no value for this criterion)")
            if n_failed:
                first = sel_failed.iloc[0]
                reasons.append(f"{n_failed} of {n_planned} ladders have a failed run; first: {first.run}: "
                               f"{first.problem} (engine log: {first.log})")
            if missing:
                reasons.append(f"{len(missing)} of {n_planned} planned ladders have no result (first: {missing[0]})")
            if n_landed == 0 and not reasons:
                reasons.append("no run landed")
            row["pass"] = not reasons
            row["reason"] = "; ".join(reasons)
            rows.append(row)
    return pd.DataFrame(rows, columns=CHECK_COLUMNS)


def regression_checks(regressions: pd.DataFrame, tolerance: dict) -> pd.DataFrame:
    """The checks of an engine code's regression cases (e.g. `engines.lammps.regression_cases`):
    one per build x case x quantity, on the run written the way a user would write it.

    They do not gate (``gates`` False): a known defect of a build is a finding about that build,
    and it shows in the report and in `compare` (a fixed defect is a fix, a defect coming back a
    regression) without failing the study. Their control runs, written the way the study writes
    the contact, must pass, or the case proves nothing: a failing control fails its check.

    Parameters
    ----------
    regressions : DataFrame
        One row per build, case and role ('user', 'control'): build, case, geometry, K, run,
        problem (why the run failed; empty when it landed), err_T, err_A, err_eps.
    tolerance : dict
        Relative tolerance per quantity.

    Returns
    -------
    DataFrame with the columns of `gate_checks`: law is 'regression:<case>', criterion 'x0'.
    """
    rows = []
    for (build, case), sel in regressions.groupby(["build", "case"], sort=False):
        user = sel[sel.role == "user"].iloc[0]
        control = sel[sel.role == "control"].iloc[0]
        failed = isinstance(user.problem, str) and bool(user.problem)
        for q in gated_quantities():
            error = abs(float(user[f"err_{q}"]))
            resolution = float(user.get(f"resolution_{q}", 0.0)) if not failed else math.nan
            reasons = []
            if failed:
                reasons.append(f"the run failed: {user.problem}")
            elif judge(error, resolution, tolerance[q]) != "pass":
                reasons.append(f"{judgement(error, resolution, tolerance[q])}written as the user would: {user.run})")
            control_error = abs(float(control[f"err_{q}"]))
            control_resolution = float(control.get(f"resolution_{q}", 0.0))
            if judge(control_error, control_resolution, tolerance[q]) != "pass":
                why = control.problem if isinstance(control.problem, str) and control.problem else control.run
                reasons.append("the control run (written as the study writes it) is off too: "
                               f"{control_error:.3e}; {why}")
            rows.append({"build": build, "engine": "", "law": f"regression:{case}", "geometry": user.geometry,
                         "criterion": "x0", "quantity": q, "planned": 1, "landed": 0 if failed else 1,
                         "failed": 1 if failed else 0, "max_rel_error": error, "resolution": resolution,
                         "at_K": float(user.K), "case": f"regression:{case}", "at_run": user.run,
                         "tolerance": float(tolerance[q]), "pass": not reasons, "reason": "; ".join(reasons),
                         "gates": False, "rung_errors": str(user.get(f"rungs_{q}", "")) if not failed else ""})
    return pd.DataFrame(rows, columns=CHECK_COLUMNS)


def _of_group(df: pd.DataFrame, key: tuple) -> pd.DataFrame:
    """The rows of `df` whose GROUP columns equal `key`."""
    if not len(df):
        return df
    mask = np.ones(len(df), dtype=bool)
    for column, value in zip(GROUP, key):
        mask &= (df[column] == value).to_numpy()
    return df[mask]


def check_name(row) -> str:
    """'build law geometry criterion quantity', how a check is named everywhere."""
    return f"{row['build']} {row['law']} {row['geometry']} {row['criterion']} {row['quantity']}"


def gating(checks: pd.DataFrame) -> pd.DataFrame:
    """The checks that decide the verdict (all of a checks table from before `gates` existed)."""
    return checks[checks["gates"].astype(bool)] if "gates" in checks.columns else checks


def verdict_of(checks: pd.DataFrame, summary_sha256: str, tolerance: dict) -> dict:
    """The verdict: PASS only when there are gating checks and every one passes (the reported-only
    checks, `regression_checks`, are listed under `reported`). It states the tolerances it was
    judged against (`tolerance`) and, for one above 1e-2, a warning (`warnings`).

    Raises
    ------
    ValueError
        A tolerance that is no relative tolerance (not in (0, 1)), naming it: 'tolerance.T = 10 is
        not a relative tolerance: it must lie in (0, 1) ...'.
    """
    problems = tolerance_problems(tolerance)
    if problems:
        raise ValueError("; ".join(problems))
    reported = checks[~checks["gates"].astype(bool)] if "gates" in checks.columns else checks.iloc[:0]
    checks = gating(checks)
    failing = checks[~checks["pass"]]
    ok = len(checks) > 0 and failing.empty
    failures = [f"{check_name(r)}: {r['reason']}" for _, r in failing.iterrows()]
    if not len(checks):
        failures = ["no gated check was made: the plans hold no run of a gated law"]
    return {"verdict": "PASS" if ok else "FAIL", "pass": ok, "checked": int(len(checks)),
            "failed": int(len(failing)) if len(checks) else 0, "failures": failures,
            "tolerance": {q: float(tolerance[q]) for q in gated_quantities()},
            "warnings": tolerance_warnings(tolerance),
            "summary_sha256": summary_sha256,
            "reported": [f"{check_name(r)}: {'pass' if r['pass'] else r['reason']}" for _, r in reported.iterrows()]}


def junit_xml(checks: pd.DataFrame, suite: str = "hertz-dem-gate") -> ET.ElementTree:
    """JUnit XML: one <testcase> per check (classname 'build.law.geometry.criterion', name the
    quantity), a <failure> with the reason where a gating check failed, and <skipped> with the
    reason where a reported-only check (a build's known defect, `regression_checks`) failed."""
    gates = checks["gates"].astype(bool) if "gates" in checks.columns else pd.Series(True, index=checks.index)
    n_fail = int((~checks["pass"] & gates).sum()) if len(checks) else 0
    n_skip = int((~checks["pass"] & ~gates).sum()) if len(checks) else 0
    suites = ET.Element("testsuites", name=suite, tests=str(len(checks)), failures=str(n_fail), errors="0",
                        skipped=str(n_skip))
    ts = ET.SubElement(suites, "testsuite", name=suite, tests=str(len(checks)), failures=str(n_fail), errors="0",
                       skipped=str(n_skip))
    for i, r in checks.iterrows():
        case = ET.SubElement(ts, "testcase", classname=".".join(str(r[k]) for k in GROUP), name=str(r["quantity"]),
                             time="0")
        measured = ("no result" if math.isnan(r["max_rel_error"]) else
                    f"max |relative error| {r['max_rel_error']:.3e} (tolerance {r['tolerance']:g}) at K = "
                    f"{r['at_K']:.4g}, case {r['case']}; {r['landed']} of {r['planned']} runs landed")
        if not r["pass"] and not gates[i]:
            ET.SubElement(case, "skipped", message=f"reported, not gated (a known defect of this build): {r['reason']}")
        elif not r["pass"]:
            failure = ET.SubElement(case, "failure", message=r["reason"], type="tolerance" if r["failed"] == 0
                                    and r["landed"] == r["planned"] else "engine-run")
            failure.text = measured
        ET.SubElement(case, "system-out").text = measured
    if not gates.any():
        case = ET.SubElement(ts, "testcase", classname="gate", name="any gated check", time="0")
        ET.SubElement(case, "failure", message="no gated check was made", type="empty")
        for element in (suites, ts):
            element.set("tests", str(len(checks) + 1)), element.set("failures", "1")
    ET.indent(suites)
    return ET.ElementTree(suites)


def write_junit(checks: pd.DataFrame, path) -> None:
    """junit.xml of `checks` (`junit_xml`), through the one JUnit writer (`write_junit_xml`)."""
    write_junit_xml(junit_xml(checks).getroot(), path)


def write_checks(checks: pd.DataFrame, path) -> None:
    """checks.csv, atomically."""
    write_atomically(path, checks.to_csv(index=False, float_format="%.12g"))


def write_verdict_files(checks: pd.DataFrame, verdict: dict, paths, report=None) -> None:
    """The one place a verdict is written (the study's checks rule, a case's verdict rule): checks.csv,
    junit.xml, then the report (`report`, a callable that writes it, where the rule has one), then
    verdict.json, last, so that its presence means the rest is written. Each file is written
    atomically. gate.txt is not among them: the gate rules write it from verdict.json
    (`verdict.verdict_files.gate_text`), and these rules withdraw it before they start
    (`verdict.verdict_files.withdraw_gate`).

    Parameters
    ----------
    checks : DataFrame
        `gate_checks` (and `regression_checks`).
    verdict : dict
        `verdict_of(checks, ...)`.
    paths : mapping
        With keys checks, junit and verdict: where each goes (a rule's `snakemake.output`).
    report : callable, optional
        Writes the report (its markdown, HTML and plots); called after junit.xml, before verdict.json.
    """
    write_checks(checks, paths["checks"])
    write_junit(checks, paths["junit"])
    if report is not None:
        report()
    write_verdict(verdict, paths["verdict"])
