"""`python -m conformance gate DIR`: a user's dumps gated exactly as the study gates its builds.

For every run of DIR/plan.json its dump (DIR/dumps/<run>.csv, `conformance.dumps`) is read, the
collision extracted (`records.collision_metrics`), and the summary rows made as
workflow/scripts/case_summary.py makes them (`comparison_rows` against the run's reference row of
the plan, the engines' map beside it); every ladder is extrapolated to dt -> 0 with its resolution
(`extrapolated_rows`), and judged by the study's gate (`gate_checks`, `verdict_of`) at the plan's
tolerances (config/config.yaml `tolerance:` when it was exported). Written into DIR: summary.csv,
checks.csv, junit.xml, report.md, report.html (and plots/), verdict.json last.

A keyword's promise (what its equation restitutes against the e it was told, beside what the
dumps restitute) is reported in verdict.json and the report, not gated, as in the study.

Exit status: 0 PASS, 1 FAIL, 2 unusable input (a plan that is not one, a dump missing, of another
plan, or unreadable: every refusal listed, nothing gated, no verdict left in DIR).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from contact_model import Body, ContactPair
from contact_model.keywords import promised_restitution
from engines.run_spec import RunSpec
from records.collision_metrics import ExtractionError, collision_metrics
from records.files import file_sha256, write_atomically

from .dumps import MAGIC, Refusal, load_column_map, read_mapped_csv, read_study_dump
from .export import PLAN_FORMAT, plan_id
from .study import (ReportInputs, comparison_rows, extrapolated_rows, gate_checks, map_errors, tolerance_problems,
                    verdict_of, write_report, write_verdict_files)

#: What a refused gate removes from DIR: a verdict of earlier dumps must not stand beside these.
VERDICT_FILES = ("verdict.json", "junit.xml", "checks.csv", "report.md", "report.html", "summary.csv")
PASS, FAIL, UNUSABLE = 0, 1, 2


@dataclass
class Outcome:
    """What the gate decided: its exit status, the verdict (None when refused) and the refusals."""

    status: int
    verdict: dict | None = None
    refusals: list[str] = field(default_factory=list)


def load_plan(folder: Path) -> dict:
    """DIR/plan.json, refused when missing, unreadable, not a plan, or edited since it was exported."""
    path = folder / "plan.json"
    try:
        plan = json.loads(path.read_text())
    except OSError as err:
        raise Refusal(f"{path}: cannot read the plan: {err.strerror} (export one with python -m conformance export)")
    except json.JSONDecodeError as err:
        raise Refusal(f"{path}: line {err.lineno}: not JSON: {err.msg}")
    if not isinstance(plan, dict) or plan.get("format") != PLAN_FORMAT:
        raise Refusal(f"{path}: not a {PLAN_FORMAT} file")
    if plan_id(plan) != plan.get("plan_id"):
        raise Refusal(f"{path}: its content does not match its plan_id: the plan was edited after it was exported")
    problems = tolerance_problems(plan["tolerance"])
    if problems:
        raise Refusal(f"{path}: " + "; ".join(problems))
    return plan


def spec_of(run: dict) -> RunSpec:
    """The study's RunSpec of a plan's run (its reference row from the plan: no ODE solved)."""
    def body(b):
        if b["plane"]:
            return Body(math.inf, math.inf, b["young_Pa"], b["poisson"])
        return Body(b["radius_m"], b["density_kg_m3"], b["young_Pa"], b["poisson"])

    pair = ContactPair(run["geometry"], body(run["body_1"]), body(run["body_2"]), run["effective"]["E_star_Pa"],
                       run["eta_Pa_s"])
    spec = RunSpec(run["case"], run["carrier_code"], run["law"], pair, run["impact_velocity_m_s"],
                   run["time_step_factor"], matched_restitution=run["told_e"], told_input=run.get("told_beta"),
                   reference=run["reference"],
                   build=run["build"])
    if spec.name != run["name"] or not math.isclose(spec.time_step, run["dt_s"], rel_tol=1e-12):
        raise Refusal(f"plan.json: run {run['name']!r} is not what this study's planner makes of it "
                      f"({spec.name}, dt {spec.time_step:.9g} s): export the plan again")
    return spec


def _read(folder: Path, run: dict, plan: dict, columns) -> object:
    path = folder / run["dump"]
    if not path.is_file():
        raise Refusal(f"{path}: missing: run {run['name']} has no dump (every run of the plan needs one)")
    with open(path, errors="replace") as f:
        first = f.readline()
    if first.startswith(MAGIC):
        return read_study_dump(path, run, plan["plan_id"])
    if columns is None:
        raise Refusal(f"{path}: line 1: neither a hertz-dem-dump (its first line '{MAGIC} 1') nor a CSV with a "
                      f"column map ({folder / 'columns.yaml'} or --columns)")
    return read_mapped_csv(path, run, columns)


def promise_rows(table: pd.DataFrame) -> list[dict]:
    """A keyword's promise, per ladder limit: told e, what its equation restitutes, what the dumps do (dt -> 0)."""
    rows = []
    if "matched_restitution" not in table.columns:
        return rows
    for r in table[(table.dt == 0) & table.matched_restitution.notna()].itertuples():
        from engines.codes import keyword_of

        keyword = keyword_of(r.law, r.engine)
        own = promised_restitution(keyword, float(r.matched_restitution))
        rows.append({"ladder": r.ladder, "keyword": keyword, "criterion": r.criterion,
                     "told_e": float(r.matched_restitution), "eps_its_equation": own,
                     "promise_error": own - float(r.matched_restitution), "eps_dumps_dt0": float(r.eps)})
    return rows


def gate(folder, columns_file=None, log=print, plots: bool = True) -> Outcome:
    """Gate the dumps of `folder` against its plan (see the module's docstring); `plots` False leaves the
    report's figures undrawn."""
    folder = Path(folder)
    refusals = []
    try:
        plan = load_plan(folder)
        column_path = Path(columns_file) if columns_file else folder / "columns.yaml"
        columns = load_column_map(column_path) if (columns_file or column_path.is_file()) else None
        if columns is not None and columns.plan_id not in (None, plan["plan_id"]):
            raise Refusal(f"{column_path}: plan_id {str(columns.plan_id)[:16]}... is another plan's")
    except Refusal as err:
        return _refused(folder, [str(err)], log)
    named = {(folder / r["dump"]).resolve() for r in plan["runs"]}
    dumps = folder / "dumps"
    if dumps.is_dir():
        refusals += [f"{p}: not a dump of this plan (no run of plan {plan['plan_id'][:12]} writes it): another "
                     "plan's, or a run renamed" for p in sorted(dumps.iterdir())
                     if p.is_file() and not p.name.startswith(".") and p.resolve() not in named]
    read = []
    for run in plan["runs"]:  # every dump read and checked first: one refused, nothing is gated
        try:
            read.append((run, spec_of(run), _read(folder, run, plan, columns)))
        except Refusal as err:
            refusals.append(str(err))
    if refusals:
        return _refused(folder, refusals, log)
    rows = []
    for run, spec, series in read:
        meta = {**spec.metadata(), "engine_version": series.engine_version}
        try:
            m = collision_metrics(series.time, series.overlap, series.normal_velocity, series.normal_force,
                                  spec.velocity)
        except ExtractionError as err:
            refusals.append(f"{folder / run['dump']}: the collision cannot be read: {err}")
            continue
        on_map = map_errors(meta, m, len(series.time))
        for row in comparison_rows(meta, m, run["reference"]):
            rows.append({**row, "run": run["name"], "dump": run["dump"],
                         **{f"map_err_{q}": e for q, e in on_map.get(row["criterion"], {}).items()}})
    if refusals:
        return _refused(folder, refusals, log)
    table = pd.DataFrame(rows)
    table = pd.concat([table, extrapolated_rows(table)], ignore_index=True)
    write_atomically(folder / "summary.csv", table.to_csv(index=False, float_format="%.12g"))
    tolerance = plan["tolerance"]
    planned = pd.DataFrame([{"case": r["case"], "name": r["name"], "engine": r["carrier_code"], "build": r["build"],
                             "law": r["law"], "geometry": r["geometry"], "represents": r["represents"],
                             "ladder": r["ladder"]} for r in plan["runs"]])
    checks = gate_checks(table, planned, pd.DataFrame(), tolerance)
    verdict = verdict_of(checks, file_sha256(folder / "summary.csv"), tolerance)
    verdict.update(plan_id=plan["plan_id"], runs=len(plan["runs"]), promise=promise_rows(table))

    def report():
        notes = list(plan["notes"]) + [
            f"Gated by the conformance kit (python -m conformance gate) against plan {plan['plan_id'][:12]}: "
            f"{len(plan['runs'])} runs of the build `{plan['build']}` (its laws' equations are those of "
            f"`{plan['carrier_code']}` in the study's tables; no engine of the study ran)."]
        notes += [f"Promise of `{p['keyword']}` ({p['criterion']}): told e = {p['told_e']:.6g}, its equation "
                  f"restitutes {p['eps_its_equation']:.6f} ({p['promise_error']:+.2e}), the dumps at dt -> 0 "
                  f"{p['eps_dumps_dt0']:.6f}: reported, not gated" for p in verdict["promise"]]
        inputs = ReportInputs(table, checks, verdict, builds=[plan["build"]], not_run=plan["not_run"],
                              not_available=plan["not_available"], plan_notes=notes,
                              ladder=plan["settings"]["ladder"],
                              title=f"Conformance of {plan['build']}: {', '.join(plan['laws'])}, "
                                    f"cases {', '.join(c['case'] for c in plan['cases'])}",
                              folder=folder.as_posix())
        write_report(inputs, folder, plots=plots)  # plots False (gate --no-plots): the figures left undrawn

    write_verdict_files(checks, verdict, {"checks": folder / "checks.csv", "junit": folder / "junit.xml",
                                          "verdict": folder / "verdict.json"}, report=report)
    log(f"{verdict['verdict']}: {verdict['checked'] - verdict['failed']} of {verdict['checked']} checks pass "
        f"({len(plan['runs'])} runs); {folder / 'report.md'}")
    for failure in verdict["failures"]:
        log(f"  {failure}")
    return Outcome(PASS if verdict["pass"] else FAIL, verdict)


def _refused(folder: Path, refusals: list[str], log) -> Outcome:
    """Nothing gated: every refusal said, and no verdict of earlier dumps left standing in `folder`."""
    for name in VERDICT_FILES:
        try:
            os.unlink(folder / name)
        except FileNotFoundError:
            pass
    log(f"UNUSABLE: {len(refusals)} problem(s); nothing was gated:")
    for r in refusals:
        log(f"  {r}")
    return Outcome(UNUSABLE, None, refusals)
