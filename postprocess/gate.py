"""The study's gate: one check per engine build x gated law x geometry x criterion x quantity.

A check is made for every combination the plans asked for, whether or not its runs landed:

    pass  <=>  every planned run of the group landed, none failed, and
               max over its runs of |q_engine / q_reference - 1| <= tolerance[q]    (q = T, A, eps)

So a run that crashed, hung or left no result fails its checks (it can never hide as a missing
row), a NaN error fails, and a study with no check at all is not a PASS. The verdict goes to
`verdict.json` (read by the `gate` rule) and to JUnit XML (one test case per check, read by CI).

Files are written atomically (a temporary file, then `os.replace`), so a reader sees the old
file or the new one, never half of one.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd

from engines.run_spec import GATED_LAWS

from .verdict_files import write_atomically

GATED_QUANTITIES = ("T", "A", "eps")
GROUP = ["build", "law", "geometry", "criterion"]
#: The columns of checks.csv. `gates`: whether the check decides the verdict (the model's laws)
#: or is reported only (an engine's regression cases, `regression_checks`).
CHECK_COLUMNS = ["build", "engine", "law", "geometry", "criterion", "quantity", "planned", "landed", "failed",
                 "max_abs_error", "at_K", "case", "at_run", "tolerance", "pass", "reason", "gates"]


def with_build(df: pd.DataFrame) -> pd.DataFrame:
    """`df` with a build column: tables from before engine builds were configurable have none,
    and their build is the engine's code (the only build of each code then)."""
    if "build" in df.columns or "engine" not in df.columns:
        return df
    return df.assign(build=df["engine"])


def planned_groups(plan_runs: pd.DataFrame) -> pd.DataFrame:
    """The gated runs of the plans, one row per run and criterion it represents.

    Parameters
    ----------
    plan_runs : DataFrame
        One row per planned run: case, name, engine, law, geometry, represents (list of criteria).

    Returns
    -------
    DataFrame with columns case, run, engine, law, geometry, criterion.
    """
    if plan_runs.empty:
        return pd.DataFrame(columns=["case", "run", "engine", *GROUP])
    gated = with_build(plan_runs)[plan_runs.law.isin(GATED_LAWS)].explode("represents")
    return gated.rename(columns={"name": "run", "represents": "criterion"})[["case", "run", "engine", *GROUP]]


def gate_checks(table: pd.DataFrame, plan_runs: pd.DataFrame, failed_runs: pd.DataFrame,
                tolerance: dict) -> pd.DataFrame:
    """Every gated check with its outcome.

    Parameters
    ----------
    table : DataFrame
        summary.csv: one row per landed run and criterion, with columns run, case, K, the GROUP
        columns and err_T, err_A, err_eps (relative errors, engine vs reference).
    plan_runs : DataFrame
        The planned runs (see `planned_groups`).
    failed_runs : DataFrame
        Runs the engine did not complete: columns run, problem, log.
    tolerance : dict
        Relative tolerance per quantity, e.g. ``{"T": 5e-4, "A": 5e-4, "eps": 5e-4}``.

    Returns
    -------
    DataFrame, one row per check, sorted by GROUP and quantity: the GROUP columns, quantity,
    planned, landed, failed (run counts), max_abs_error (NaN without a result), at_K, case and
    at_run (the K, case and run name of that largest error; NaN/empty without a result),
    tolerance, pass (bool) and reason (why it failed; empty when it passed).
    """
    planned = planned_groups(plan_runs)
    table = with_build(table)
    landed = table[table.law.isin(GATED_LAWS)] if len(table) else table
    code_of_build = {**dict(zip(landed.build, landed.engine)), **dict(zip(planned.build, planned.engine))} \
        if len(landed) else dict(zip(planned.build, planned.engine))
    failed_runs = failed_runs if len(failed_runs) else pd.DataFrame(columns=["run", "problem", "log"])
    failed = planned.merge(failed_runs[["run", "problem", "log"]], on="run", how="inner")
    keys = sorted(set(map(tuple, planned[GROUP].to_numpy())) |
                  (set(map(tuple, landed[GROUP].to_numpy())) if len(landed) else set()))
    rows = []
    for key in keys:
        sel_plan, sel, sel_failed = (_of_group(df, key) for df in (planned, landed, failed))
        n_planned, n_landed, n_failed = len(sel_plan), len(sel), len(sel_failed)
        missing = sorted(set(sel_plan.run) - set(sel.run if len(sel) else ()) - set(sel_failed.run))
        for q in GATED_QUANTITIES:
            row = {**dict(zip(GROUP, key)), "engine": code_of_build.get(key[0], ""), "quantity": q, "planned": n_planned, "landed": n_landed,
                   "failed": n_failed, "max_abs_error": math.nan, "at_K": math.nan, "case": "", "at_run": "",
                   "tolerance": float(tolerance[q]), "pass": False, "reason": ""}
            if n_landed:
                errors = np.abs(sel[f"err_{q}"].to_numpy(dtype=float))
                bad = np.isnan(errors)
                i = int(np.nanargmax(errors)) if not bad.all() else 0
                row.update(max_abs_error=float(errors[i]), at_K=float(sel.K.iloc[i]), case=str(sel.case.iloc[i]),
                           at_run=str(sel.run.iloc[i]) if "run" in sel.columns else "")
            reasons = []
            if n_failed:
                first = sel_failed.iloc[0]
                reasons.append(f"{n_failed} of {n_planned} runs failed; first: {first.run}: {first.problem} "
                               f"(engine log: {first.log})")
            if missing:
                reasons.append(f"{len(missing)} of {n_planned} planned runs have no result (first: {missing[0]})")
            if n_landed and np.isnan(np.abs(sel[f"err_{q}"].to_numpy(dtype=float))).any():
                reasons.append("a run's error is NaN (the engine gave no value for this criterion)")
            if n_landed == 0 and not reasons:
                reasons.append("no run landed")
            if n_landed and not math.isnan(row["max_abs_error"]) and row["max_abs_error"] > row["tolerance"]:
                reasons.insert(0, f"{row['max_abs_error']:.3e} > {row['tolerance']:g} "
                                  f"(case {row['case']}, K = {row['at_K']:.4g})")
            row["pass"] = not reasons
            row["reason"] = "; ".join(reasons)
            rows.append(row)
    return pd.DataFrame([{**r, "gates": True} for r in rows], columns=CHECK_COLUMNS)


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
        for q in GATED_QUANTITIES:
            error = abs(float(user[f"err_{q}"]))
            reasons = []
            if failed:
                reasons.append(f"the run failed: {user.problem}")
            elif not error <= tolerance[q]:
                reasons.append(f"{error:.3e} > {tolerance[q]:g} (written as the user would: {user.run})")
            control_error = abs(float(control[f"err_{q}"]))
            if not control_error <= tolerance[q]:
                why = control.problem if isinstance(control.problem, str) and control.problem else control.run
                reasons.append(f"the control run (written as the study writes it) is off too: {control_error:.3e}; {why}")
            rows.append({"build": build, "engine": "", "law": f"regression:{case}", "geometry": user.geometry,
                         "criterion": "x0", "quantity": q, "planned": 1, "landed": 0 if failed else 1,
                         "failed": 1 if failed else 0, "max_abs_error": error, "at_K": float(user.K),
                         "case": f"regression:{case}", "at_run": user.run, "tolerance": float(tolerance[q]), "pass": not reasons,
                         "reason": "; ".join(reasons), "gates": False})
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
    checks, `regression_checks`, are listed under `reported`)."""
    reported = checks[~checks["gates"].astype(bool)] if "gates" in checks.columns else checks.iloc[:0]
    checks = gating(checks)
    failing = checks[~checks["pass"]]
    ok = len(checks) > 0 and failing.empty
    failures = [f"{check_name(r)}: {r['reason']}" for _, r in failing.iterrows()]
    if not len(checks):
        failures = ["no gated check was made: the plans hold no run of a gated law"]
    return {"verdict": "PASS" if ok else "FAIL", "pass": ok, "checked": int(len(checks)),
            "failed": int(len(failing)) if len(checks) else 0, "failures": failures,
            "tolerance": {q: float(tolerance[q]) for q in GATED_QUANTITIES}, "summary_sha256": summary_sha256,
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
        measured = ("no result" if math.isnan(r["max_abs_error"]) else
                    f"max |relative error| {r['max_abs_error']:.3e} (tolerance {r['tolerance']:g}) at K = "
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
    tree = junit_xml(checks)
    import io

    buf = io.BytesIO()
    tree.write(buf, encoding="utf-8", xml_declaration=True)
    write_atomically(path, buf.getvalue())


def write_verdict(verdict: dict, path) -> None:
    write_atomically(path, json.dumps(verdict, indent=1) + "\n")
