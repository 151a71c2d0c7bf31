"""Snakemake script: one release's checks of the history (analysis.history), in as few engine
processes as its code allows: the reduced cases' viscoelastic ladders and its restitution keywords'
promise in one sweep, its code's regression cases (LAMMPS) in theirs.

No verdict is withdrawn or marked stale: these runs are not the study's results (log_to)."""

import json
from pathlib import Path

import pandas as pd

from common import log_to
from contact_model.keywords import KEYWORDS
from engines import run_sweep
from engines.builds import Build
from engines.plan import history_plan
from analysis.history import (COLUMNS, REGRESSION_CHECKS, banner_date, history_row, limit_check, not_run_rows,
                                 promise_check, promise_check_row)
from analysis.keyword_promise import promise_rows, sweep_metrics
from analysis.regressions import ladder_limit, regression_table
from records.run_manifest import write_manifest

log = log_to(snakemake.log[0])
spec = snakemake.params.spec
h = snakemake.params.history
tolerance = {q: float(v) for q, v in snakemake.params.tolerance.items()}
install = json.loads(open(snakemake.input.install).read())
code = spec["code"]
base = {"code": code, "release": spec["release"], "build": (install["build"] or {}).get("id", ""),
        "banner": install["banner"], "date": banner_date(install["banner"])}
rows = [history_row(base, "version banner", "fail" if install["problem"] else "pass",
                    install["problem"] or f"{install['banner']} (release {spec['release']})")]

# The checks this release is asked for, each with its runs (engines.plan.history_plan: as the study's plan
# refuses and ladders them).
plan = history_plan(h, code, install["banner"], snakemake.params.ladder, base["build"])
ladders = plan.ladders  # check -> (criterion, [RunSpec])
keywords = {name: plan.promise.of(name) for name in plan.keywords}  # keyword -> {e: [RunSpec]}
unavailable = {promise_check(name): why for name, why in plan.missing.items()}  # check -> why not
checks = [*ladders, *(REGRESSION_CHECKS.values() if code == "lammps" else ()),
          *(promise_check(k) for k in keywords), *unavailable]

if install["build"] is None or install["problem"]:
    status = "not installed" if install["build"] is None else "run failed"
    rows += not_run_rows(base, [c for c in checks if c not in unavailable], status,
                         install["problem"] or "no build")
    dumps, failed, seconds = [], [], 0.0
    Path(snakemake.output.runs).mkdir(parents=True, exist_ok=True)  # no runs: an empty folder says so
else:
    build = Build(**install["build"])
    runs = plan.runs
    log.info("%s (%s): %d ladders, %d keywords, %d runs", build.id, install["banner"], len(ladders), len(keywords),
             len(runs))
    sweep = run_sweep(build, runs, f"{snakemake.output.runs}/cases", timeout_floor_s=snakemake.params.timeout_floor_s)
    seconds = sweep.engine_seconds
    for check, (criterion, rungs) in ladders.items():
        lost = [sweep.failures.get(r.name, "no dump") for r in rungs if r.name not in sweep.dumps]
        rows.append(limit_check(base, check, None if lost else ladder_limit(rungs, sweep, criterion), tolerance,
                                problem=str(lost[0]).splitlines()[0] if lost else ""))
    metrics, failures = sweep_metrics(sweep)
    for name, by_e in keywords.items():
        rows.append(promise_check_row(base, name, promise_rows(build.id, code, KEYWORDS[name], by_e, metrics,
                                                               failures), float(h["promise_tolerance"])))
    dumps = list(sweep.dumps.values())
    failed = sweep.failed_runs(runs)
    if code == "lammps":
        from engines.lammps import run_regression_cases

        cases, regressions = run_regression_cases(f"{snakemake.output.runs}/regressions",
                                                  executable=build.executable, build=build.id,
                                                  timeout_floor_s=snakemake.params.timeout_floor_s)
        seconds += regressions.engine_seconds
        dumps += list(regressions.dumps.values())
        table = regression_table(cases, regressions, build.id)
        for case in cases:
            user, control = (table[(table.case == case.name) & (table.role == role)].iloc[0].to_dict()
                             for role in ("user", "control"))
            problem, control_problem = (r["problem"] if isinstance(r["problem"], str) else "" for r in (user, control))
            row = limit_check(base, REGRESSION_CHECKS[case.name], None if problem else user, tolerance, problem)
            control_row = limit_check(base, "control", None if control_problem else control, tolerance,
                                      control_problem)
            if control_row["status"] != "pass":  # the case proves nothing if its control is off
                row.update(status="run failed", detail=f"its control run is off: {control_row['detail']}")
            elif problem:  # the contact as a user writes it breaks the run, as written as the study writes it not
                # How it breaks can change from run to run (the 2021 mixed pair reads uninitialised memory: lost
                # atoms, a missing fix, SIGSEGV): the row names where to read it, this job's log says it.
                log.info("%s %s: the run as a user writes it did not complete: %s", spec["release"], case.name,
                         problem)
                where = str(Path(snakemake.output.runs, "regressions", case.name, "lammps.log"))
                row.update(status="fail", detail=f"the run as a user writes it did not complete (engine log: {where}; "
                                                 f"{snakemake.log[0]}); its control did")
            rows.append(row)
    if snakemake.input.oblique_cases:
        # Each tangential model of the release on the oblique reduced set, gated as `snakemake oblique`
        # gates it, no defect declared: a defect of a release is the history's finding.
        from contact_model import load_case
        from engines.oblique_plan import oblique_plan
        from engines.oblique_sweep import run_oblique_sweep
        from analysis.history import oblique_history_rows
        from analysis.oblique import limit_rows, oblique_checks, rung_rows

        o = snakemake.params.oblique
        oblique = oblique_plan([load_case(p) for p in snakemake.input.oblique_cases], code, build.id,
                               install["banner"], o["ladder"])
        keep = set(o["reduced"]["angles"])
        oblique.runs = [r for r in oblique.runs if round(r.contact_angle, 6) in keep]
        swept = run_oblique_sweep(build, oblique.runs, f"{snakemake.output.runs}/oblique",
                                  timeout_floor_s=snakemake.params.timeout_floor_s)
        seconds += swept.engine_seconds
        dumps += list(swept.dumps.values())
        checked = oblique_checks(limit_rows(rung_rows(oblique.runs, swept)), float(o["tolerance"]), planned=oblique,
                                 failures=swept.failures)
        rows += oblique_history_rows(base, checked, oblique.refused, float(o["tolerance"]))
rows += [history_row(base, check, "not available", why) for check, why in unavailable.items()]
pd.DataFrame(rows, columns=COLUMNS).to_csv(snakemake.output.rows, index=False, float_format="%.12g")
write_manifest(snakemake.output.manifest, dumps, failed, case="history", build=base["build"], engine=code,
               engine_seconds=seconds)
for r in rows:
    log.info("%s %s: %s %s", spec["release"], r["check"], r["status"], r["detail"])
