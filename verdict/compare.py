"""Compare two studies, check by check: what a CI shows when an engine build changes.

    python -m postprocess.compare BASELINE CANDIDATE [--out DIR] [--factor 2] [--noise-floor 1e-9]
                                  [--builds BASELINE_BUILD=CANDIDATE_BUILD]

BASELINE and CANDIDATE are each a results folder (its checks.csv, written by the study's report
rule, with the runs that failed) or a summary.csv (its checks are made here, from the runs it
holds, against --tolerance). For every engine build x law x geometry x criterion x quantity:

    regression  fails in the candidate and passed in the baseline, or
                e_c > factor * max(e_b, floor)
    fix         passes in the candidate and failed in the baseline, or
                e_b > factor * max(e_c, floor)
    unchanged   otherwise;  new / removed: a check in one study only

with e the largest |relative error| (engine vs reference, extrapolated to dt -> 0) and floor the
larger of the noise floor and the two checks' resolutions: a change the ladders cannot resolve is
no change. Checks are matched by build id; with
--builds, the baseline's build BASELINE_BUILD is matched with the candidate's CANDIDATE_BUILD
(two builds of one code, e.g. Debian's LAMMPS against today's, in one study or in two), and the
other builds are left out. The noise floor keeps round-off-level
errors (1e-12 against 1e-11) from counting as a change. Writes compare.md, compare.html,
compare.csv and compare-junit.xml (one test case per check, a <failure> for each regression) into
--out, and exits 1 when there is a regression, 0 otherwise, 2 on unusable input.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pandas as pd

from .gate import GATED_QUANTITIES, GROUP, gate_checks, limit_rows, with_build
from .verdict_files import html_page, junit_bytes, write_junit_xml
from records.files import write_atomically

KEY = [*GROUP, "quantity"]
DEFAULT_TOLERANCE = {"T": 1e-6, "A": 1e-6, "eps": 1e-6}


class CompareError(ValueError):
    """A study that cannot be compared; the message names the path."""


def load_checks(path, tolerance: dict = DEFAULT_TOLERANCE) -> pd.DataFrame:
    """The checks of a study: `path` is a results folder (its checks.csv) or a summary.csv."""
    path = Path(path)
    if path.is_dir():
        if (path / "checks.csv").exists():
            path = path / "checks.csv"
        elif (path / "summary.csv").exists():
            path = path / "summary.csv"
        else:
            raise CompareError(f"{path}: neither checks.csv nor summary.csv in this folder (run the study first)")
    try:
        table = pd.read_csv(path)
    except (OSError, ValueError) as err:
        raise CompareError(f"{path}: cannot read it as CSV ({err})")
    table = with_build(table)  # a study from before builds: each code was its own build
    # checks.csv of a study from before the column said what it holds (a relative error)
    table = table.rename(columns={"max_abs_error": "max_rel_error"})
    if set(KEY + ["max_rel_error", "pass"]) <= set(table.columns):
        return table  # a checks.csv
    needed = set(GROUP + ["K", "case"] + [f"err_{q}" for q in GATED_QUANTITIES])
    if not needed <= set(table.columns):
        raise CompareError(f"{path}: neither a checks.csv nor a summary.csv (missing columns "
                           f"{sorted(needed - set(table.columns))})")
    # A summary alone: every ladder it holds (its dt = 0 rows; in a summary from before ladders,
    # every run) was planned and landed (failed runs are not in it).
    runs = limit_rows(table if "run" in table else table.assign(run=[f"row-{i}" for i in range(len(table))]))
    planned = runs.groupby(["case", "ladder", "build", "engine", "law", "geometry"]).criterion.apply(list).reset_index()
    planned = planned.rename(columns={"criterion": "represents"}).assign(name=lambda d: d.ladder)
    return gate_checks(runs, planned, pd.DataFrame(), tolerance)


def pair_builds(baseline: pd.DataFrame, candidate: pd.DataFrame, baseline_build: str, candidate_build: str
                ) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The checks of `baseline_build` in `baseline` and of `candidate_build` in `candidate`, both
    under the build name 'BASELINE_BUILD -> CANDIDATE_BUILD', so that `compare_checks` matches
    them; CompareError when either study has no check of its build."""
    baseline, candidate = with_build(baseline), with_build(candidate)
    for study, build, what in ((baseline, baseline_build, "baseline"), (candidate, candidate_build, "candidate")):
        if not (study.build == build).any():
            raise CompareError(f"the {what} study has no check of build {build!r}; its builds: "
                               f"{', '.join(map(str, study.build.unique()))}")
    name = f"{baseline_build} -> {candidate_build}"
    return (baseline[baseline.build == baseline_build].assign(build=name),
            candidate[candidate.build == candidate_build].assign(build=name))


def compare_checks(baseline: pd.DataFrame, candidate: pd.DataFrame, factor: float = 2.0,
                   noise_floor: float = 1e-9) -> pd.DataFrame:
    """One row per check of either study: KEY, baseline/candidate error and pass, change
    (candidate / baseline error) and status (regression, fix, unchanged, new, removed)."""
    baseline, candidate = with_build(baseline), with_build(candidate)
    baseline, candidate = (t if "resolution" in t.columns else t.assign(resolution=0.0) for t in (baseline, candidate))
    b = baseline[KEY + ["max_rel_error", "pass", "resolution"]].rename(
        columns={"max_rel_error": "baseline_error", "pass": "baseline_pass", "resolution": "baseline_resolution"})
    c = candidate[KEY + ["max_rel_error", "pass", "reason", "resolution"]].rename(
        columns={"max_rel_error": "candidate_error", "pass": "candidate_pass", "reason": "candidate_reason",
                 "resolution": "candidate_resolution"})
    both = b.merge(c, on=KEY, how="outer", indicator=True)
    rows = []
    for r in both.to_dict("records"):
        eb, ec = r["baseline_error"], r["candidate_error"]
        floor = max([noise_floor] + [x for x in (r["baseline_resolution"], r["candidate_resolution"])
                                     if isinstance(x, float) and not math.isnan(x)])
        if r["_merge"] == "left_only":
            status = "removed"
        elif r["_merge"] == "right_only":
            status = "new"
        elif bool(r["baseline_pass"]) and not bool(r["candidate_pass"]):
            status = "regression"
        elif not bool(r["baseline_pass"]) and bool(r["candidate_pass"]):
            status = "fix"
        elif not math.isnan(ec) and not math.isnan(eb) and ec > factor * max(eb, floor):
            status = "regression"
        elif not math.isnan(ec) and not math.isnan(eb) and eb > factor * max(ec, floor):
            status = "fix"
        else:
            status = "unchanged"
        change = ec / eb if eb and not math.isnan(eb) and not math.isnan(ec) else math.nan
        rows.append({**{k: r[k] for k in KEY}, "baseline_error": eb, "candidate_error": ec, "change": change,
                     "resolution": floor,
                     "baseline_pass": r["baseline_pass"], "candidate_pass": r["candidate_pass"], "status": status,
                     "candidate_reason": r["candidate_reason"] if isinstance(r["candidate_reason"], str) else ""})
    order = {"regression": 0, "fix": 1, "new": 2, "removed": 3, "unchanged": 4}
    out = pd.DataFrame(rows, columns=[*KEY, "baseline_error", "candidate_error", "change", "resolution",
                                      "baseline_pass",
                                      "candidate_pass", "status", "candidate_reason"])
    return out.sort_values(by=KEY, key=None).sort_values(by="status", key=lambda s: s.map(order),
                                                          kind="stable").reset_index(drop=True)


def _name(r) -> str:
    return " ".join(str(r[k]) for k in KEY)


def _error(e) -> str:
    """An error as printed: 'no result' where the run left none (it failed or crashed)."""
    return "no result" if isinstance(e, float) and math.isnan(e) else f"{e:.3e}"


def _verdict_line(r) -> str:
    what = {True: "pass", False: "FAIL"}
    return (f"{_name(r)}: {_error(r['baseline_error'])} ({what.get(r['baseline_pass'], '-')}) -> "
            f"{_error(r['candidate_error'])} ({what.get(r['candidate_pass'], '-')})")


def markdown(comparison: pd.DataFrame, baseline: str, candidate: str, factor: float, noise_floor: float,
             title: str = "Comparison of two studies") -> str:
    counts = comparison.status.value_counts()
    regressions = comparison[comparison.status == "regression"]
    fixes = comparison[comparison.status == "fix"]
    lines = [f"# {title}", "",
             f"**{'REGRESSION' if len(regressions) else 'NO REGRESSION'}** — baseline `{baseline}`, candidate "
             f"`{candidate}`: " + ", ".join(f"{counts.get(s, 0)} {s}" for s in
                                            ("regression", "fix", "unchanged", "new", "removed")) + ".", "",
             f"A regression is a check that fails in the candidate and passed in the baseline, or whose largest "
             f"relative error (extrapolated to dt -> 0) grew more than {factor:g}x (errors below the larger of "
             f"{noise_floor:g} and the two checks' resolutions count as that); a fix is the reverse.", ""]
    for title, sel in (("Regressions", regressions), ("Fixes", fixes)):
        if len(sel):
            lines += [f"## {title}", ""] + [f"- {_verdict_line(r)}" for r in sel.to_dict("records")] + [""]
    lines += ["## Every check", "", "| " + " | ".join(KEY + ["baseline", "candidate", "change", "resolution",
                                                              "status"]) + " |",
              "|" + "---|" * (len(KEY) + 5)]
    for r in comparison.to_dict("records"):
        lines.append("| " + " | ".join([str(r[k]) for k in KEY] + [f"{r['baseline_error']:.3g}",
                                                                    f"{r['candidate_error']:.3g}",
                                                                    f"{r['change']:.3g}", f"{r['resolution']:.2g}",
                                                                    r["status"]]) + " |")
    return "\n".join(lines) + "\n"


def junit(comparison: pd.DataFrame) -> bytes:
    """JUnit XML (`junit_element`) as written (`verdict.verdict_files.junit_bytes`)."""
    return junit_bytes(junit_element(comparison))


def junit_element(comparison: pd.DataFrame) -> ET.Element:
    """JUnit XML: one test case per check, a <failure> for each regression."""
    n = int((comparison.status == "regression").sum())
    suites = ET.Element("testsuites", name="hertz-dem-compare", tests=str(len(comparison)), failures=str(n))
    suite = ET.SubElement(suites, "testsuite", name="hertz-dem-compare", tests=str(len(comparison)),
                          failures=str(n), errors="0", skipped="0")
    for r in comparison.to_dict("records"):
        case = ET.SubElement(suite, "testcase", classname=".".join(str(r[k]) for k in GROUP),
                             name=str(r["quantity"]), time="0")
        text = f"{r['status']}: {_verdict_line(r)}"
        if r["status"] == "regression":
            ET.SubElement(case, "failure", message=text, type="regression").text = r["candidate_reason"] or text
        ET.SubElement(case, "system-out").text = text
    ET.indent(suites)
    return suites


def describe_build(folder, build: str) -> str:
    """'lammps-2025 (LAMMPS (22 Jul 2025 - Update 4), /work/.venv-lammps/bin/lmp)': a build of the
    results `folder` by the version its runs recorded (summary.csv) and the executable its engine
    jobs ran (their manifest.json)."""
    folder = Path(folder)
    folder = folder.parent if folder.suffix == ".csv" else folder
    what = []
    summary = folder / "summary.csv"
    if summary.exists():
        rows = pd.read_csv(summary, usecols=lambda c: c in ("build", "engine_version"))
        versions = rows[rows.build == build].engine_version.dropna().unique() if "build" in rows else []
        what += list(versions[:1])
    for manifest in sorted(folder.glob(f"**/{build}/manifest.json")):
        exe = json.loads(manifest.read_text()).get("executable")
        if exe:
            what.append(exe)
            break
    return f"{build} ({', '.join(what)})" if what else build


def build_title(baseline_folder, candidate_folder, baseline_build: str, candidate_build: str) -> str:
    """'Build comparison: <baseline build> (version, executable) → <candidate build> (...)'."""
    return (f"Build comparison: {describe_build(baseline_folder, baseline_build)} → "
            f"{describe_build(candidate_folder, candidate_build)}")


def write_comparison(comparison: pd.DataFrame, out_dir, baseline: str, candidate: str, factor: float,
                     noise_floor: float, title: str = "Comparison of two studies") -> None:
    """compare.csv, compare.md, compare.html and compare-junit.xml in `out_dir`; `title` heads
    the report ("Build comparison: <baseline build> (<version>, <executable>) -> <candidate> (...)"
    for two builds of one study)."""
    import markdown as md

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    text = markdown(comparison, baseline, candidate, factor, noise_floor, title)
    write_atomically(out / "compare.csv", comparison.to_csv(index=False, float_format="%.6g"))
    write_atomically(out / "compare.md", text)
    body = md.markdown(text, extensions=["tables"])
    write_atomically(out / "compare.html", html_page(title, body, "body{font-family:sans-serif;max-width:1300px;"
                                                     "margin:auto}table{border-collapse:collapse}td,th{border:1px "
                                                     "solid #ccc;padding:2px 6px;font-size:13px}"))
    write_junit_xml(junit_element(comparison), out / "compare-junit.xml")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m postprocess.compare", description=__doc__.split("\n\n")[0])
    parser.add_argument("baseline", help="results folder or summary.csv of the baseline study")
    parser.add_argument("candidate", help="results folder or summary.csv of the candidate study")
    parser.add_argument("--out", default="results/compare", help="folder for compare.{md,html,csv} and "
                                                                 "compare-junit.xml (default: results/compare)")
    parser.add_argument("--factor", type=float, default=2.0, help="error growth that counts as a regression")
    parser.add_argument("--noise-floor", type=float, default=1e-9, help="errors below it count as it")
    parser.add_argument("--builds", metavar="BASELINE_BUILD=CANDIDATE_BUILD",
                        help="compare this build of the baseline with that build of the candidate (they may be one "
                             "study), leaving the other builds out")
    parser.add_argument("--tolerance", type=float, nargs=3, metavar=("T", "A", "EPS"),
                        default=[DEFAULT_TOLERANCE[q] for q in GATED_QUANTITIES],
                        help="tolerances for a study given as a summary.csv")
    args = parser.parse_args(argv)
    if not (args.factor > 1 and args.noise_floor >= 0):
        parser.error("--factor must exceed 1 and --noise-floor must not be negative")
    tolerance = dict(zip(GATED_QUANTITIES, args.tolerance))
    try:
        base, cand = load_checks(args.baseline, tolerance), load_checks(args.candidate, tolerance)
        if args.builds:
            b, sep, c = args.builds.partition("=")
            if not (sep and b and c):
                raise CompareError(f"--builds {args.builds!r}: write it as BASELINE_BUILD=CANDIDATE_BUILD")
            base, cand = pair_builds(base, cand, b, c)
    except CompareError as err:
        print(f"compare: {err}", file=sys.stderr)
        return 2
    comparison = compare_checks(base, cand, args.factor, args.noise_floor)
    title = build_title(args.baseline, args.candidate, b, c) if args.builds else "Comparison of two studies"
    write_comparison(comparison, args.out, args.baseline, args.candidate, args.factor, args.noise_floor, title)
    regressions = comparison[comparison.status == "regression"]
    fixes = comparison[comparison.status == "fix"]
    print(f"{len(comparison)} checks: {len(regressions)} regressions, {len(fixes)} fixes; {args.out}/compare.md")
    for r in regressions.to_dict("records"):
        print(f"  REGRESSION {_verdict_line(r)}")
    for r in fixes.to_dict("records"):
        print(f"  fix        {_verdict_line(r)}")
    return 1 if len(regressions) else 0


if __name__ == "__main__":
    sys.exit(main())
