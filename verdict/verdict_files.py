"""The files that carry a verdict (gate.txt, verdict.json, junit.xml, checks.csv, the report):
marked stale before results change, the PASS stamp (gate.txt) withdrawn when a verdict is being
made anew, its text (`gate_text`), the tolerances a verdict may be made at (`tolerance_problems`,
`tolerance_warnings`), and the verdict of an interrupted run. Every verdict.json and JUnit XML of
the study is written by `write_verdict` and `write_junit_xml` here (the gate's `write_verdict_files`,
the lost jobs' FAIL, a stale mark, the comparison of two studies): one format, written with
`records.files.write_atomically` and tied to the summary they describe by its
`records.files.file_sha256`.

A rule that changes results marks the verdict of its folders *stale* (`mark_stale`), it does not
remove it: the user keeps reading the study's report while one case reruns, and nothing in it
still claims PASS for results it does not describe:

- gate.txt, the PASS stamp, goes, and so does checks.csv (a pass per check, which a CSV cannot
  mark);
- verdict.json says ``"verdict": "STALE"``, ``"pass": false``, with what the verdict was, since
  when, which job changed results and the command that gives a verdict again;
- junit.xml gains one failing test case, ``workflow.stale``, saying the same;
- report.md and report.html open with a banner saying the same; the rest is left as it was.

The rules that write a verdict (the checks, the reports, the gates) write it anew. A verdict file
written outside its rule (marked stale here, or the FAIL of a lost job, or an interrupted run's,
`verdict.failed_jobs`) is dated 1 January 1970 (`backdate`): older than any input, so that
the next run of any target that needs it reruns the rule that writes it, and everything upstream
that is missing, instead of taking it as up to date.

Kept apart from `verdict.gate` (which needs pandas) because every workflow rule imports it
first, through workflow/scripts/common.py: standard library only.
"""

from __future__ import annotations

import html
import json
import os
import re
import xml.etree.ElementTree as ET
from datetime import datetime, timezone
from pathlib import Path

from records.files import write_atomically
from records.quantities import gated_quantities  # the quantities a verdict judges, each with its tolerance

#: The files that carry a verdict; any rule that changes results marks them stale first.
VERDICT_FILES = ("gate.txt", "verdict.json", "junit.xml", "checks.csv", "report.md", "report.html")
#: The files marked stale by removal: what they say cannot carry a banner.
_REMOVED_WHEN_STALE = ("gate.txt", "checks.csv")
#: A relative tolerance above this is allowed, with a warning in the log, verdict.json, gate.txt
#: and the report: a PASS at it says little about an engine.
LOOSE_TOLERANCE = 1e-2
#: The JUnit test suite the study's gate writes (verdict.gate.junit_xml).
SUITE = "hertz-dem-gate"
#: The stale banner's markers in report.md and report.html: a new note replaces the old one.
_MD_BANNER = re.compile(r"<!-- stale -->.*?<!-- /stale -->\n\n", re.S)
_HTML_BANNER = re.compile(r"<section class='stale'>.*?</section>", re.S)


def write_verdict(verdict: dict, path) -> None:
    """verdict.json: `verdict` as JSON (indent 1, a final newline), atomically. The one writer of it."""
    write_atomically(path, json.dumps(verdict, indent=1) + "\n")


def junit_bytes(root: ET.Element) -> bytes:
    """A JUnit XML document `root` as the study writes it: UTF-8 with its XML declaration."""
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def write_junit_xml(root: ET.Element, path) -> None:
    """JUnit XML `root` (`junit_bytes`), atomically. The one writer of the study's JUnit files."""
    write_atomically(path, junit_bytes(root))


def html_page(title: str, body: str, css: str | None = None) -> str:
    """The study's HTML page around `body` (HTML): its head (UTF-8, `title` escaped, the style sheet
    `css` where given) and body. The one page shell of the study's pages (the report, a comparison
    of two studies, the verdict of lost jobs or of an interrupted run); here, below the reports,
    because the verdict's own writers (`verdict.failed_jobs`, `verdict.compare`) write pages too."""
    style = f"<style>{css}</style>" if css is not None else ""
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>{style}"
            f"</head><body>{body}</body></html>")


def withdraw_verdict(results_dir="results") -> list[str]:
    """Remove every file that carries a verdict from `results_dir` (the names removed). A file
    another job removed first is gone, which is what was asked, not an error."""
    removed = []
    for name in VERDICT_FILES:
        p = Path(results_dir) / name
        try:
            p.unlink()
        except FileNotFoundError:
            continue
        removed.append(str(p))
    return removed


def withdraw_gate(folder) -> bool:
    """Remove the PASS stamp `folder`/gate.txt: the rules that make the verdict of `folder` anew
    (the checks, a case's verdict, the report) call this first, so that no PASS stands while they
    run or after they fail (killed, a full disk, a read-only folder). Whether there was one."""
    try:
        (Path(folder) / "gate.txt").unlink()
    except FileNotFoundError:
        return False
    return True


def tolerance_problems(tolerance: dict) -> list[str]:
    """Why `tolerance` (config `tolerance:`, {quantity: relative tolerance}) cannot judge a verdict,
    one message per bad value naming its key; empty when it can. A relative tolerance lies in
    (0, 1): at 1 or more, an engine whose T, A or eps is off by 100 % would pass.

    'tolerance.T = 10 is not a relative tolerance: it must lie in (0, 1) (1e-6 is one part in a
    million, the study's)'."""
    problems = []
    for q in gated_quantities():
        value = tolerance.get(q) if isinstance(tolerance, dict) else None
        if value is None:
            problems.append(f"tolerance.{q} is missing: give the relative tolerance of {q}, e.g. 1e-6")
        elif isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < 1:
            problems.append(f"tolerance.{q} = {value!r} is not a relative tolerance: it must lie in (0, 1) "
                            "(1e-6 is one part in a million, the study's)")
    return problems


def tolerance_warnings(tolerance: dict) -> list[str]:
    """One warning per tolerance above LOOSE_TOLERANCE (1e-2), naming its key:
    'tolerance.T = 0.05 is above 1e-2: a PASS at it allows T to be off by 5 %'."""
    return [f"tolerance.{q} = {tolerance[q]:g} is above 1e-2: a PASS at it allows {q} to be off by "
            f"{100 * tolerance[q]:g} %" for q in gated_quantities()
            if isinstance(tolerance.get(q), (int, float)) and tolerance[q] > LOOSE_TOLERANCE]


def tolerance_text(tolerance: dict) -> str:
    """'T 1e-06, A 1e-06, eps 1e-06': what a verdict was judged against."""
    return ", ".join(f"{q} {float(tolerance[q]):g}" for q in gated_quantities() if q in tolerance)


def gate_text(verdict: dict, summary_sha256: str) -> str:
    """gate.txt of a PASS `verdict` (`verdict.gate.verdict_of`): how many checks passed, the
    tolerances they were judged against, the summary they were computed from, then the verdict's
    warnings, one line each::

        PASS: 30 engine build x law x geometry x criterion x quantity checks within tolerance (relative:
        T 1e-06, A 1e-06, eps 1e-06; summary sha256 …)
    """
    lines = [f"PASS: {verdict['checked']} engine build x law x geometry x criterion x quantity checks within "
             f"tolerance (relative: {tolerance_text(verdict['tolerance'])}; summary sha256 {summary_sha256})"]
    lines += [f"Warning: {w}" for w in verdict.get("warnings", [])]
    return "\n".join(lines) + "\n"


def backdate(path) -> None:
    """Date `path` 1 January 1970 (mtime 0), so that Snakemake reruns the rule whose output it is
    (see the module's docstring); a file that is not there is left so."""
    try:
        os.utime(path, (0, 0))
    except FileNotFoundError:
        pass


def is_stale(results_dir="results") -> bool:
    """Whether the verdict in `results_dir` was marked stale (or is an interrupted run's)."""
    try:
        verdict = json.loads((Path(results_dir) / "verdict.json").read_text())
    except (OSError, ValueError):
        return False
    return isinstance(verdict, dict) and verdict.get("verdict") in ("STALE", "INTERRUPTED")


def mark_stale(results_dir, by: str, rerun: str = "snakemake -j2 all") -> list[str]:
    """Mark the verdict files of `results_dir` stale (see the module's docstring): results are
    about to change, by the job `by` ('run_engine (case steel, build lammps)'); `rerun` gives a
    verdict again. Idempotent: a folder already stale keeps when it went stale and what it was,
    and takes the newest note. Returns the files changed."""
    folder = Path(results_dir)
    changed = []
    for name in _REMOVED_WHEN_STALE:
        if (folder / name).exists():
            (folder / name).unlink(missing_ok=True)
            changed.append(str(folder / name))
    now = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    note = {"since": now, "by": by, "was": None, "rerun": rerun}
    path = folder / "verdict.json"
    if path.exists():
        try:
            verdict = json.loads(path.read_text())
            verdict = verdict if isinstance(verdict, dict) else {}
        except (OSError, ValueError):
            verdict = {}
        old = verdict.get("stale") if verdict.get("verdict") == "STALE" else None
        if old:
            note.update(since=old.get("since", now), was=old.get("was"))
        else:
            note["was"] = verdict.get("verdict")
        verdict.update(verdict="STALE", stale=note, **{"pass": False})
        write_verdict(verdict, path)
        changed.append(str(path))
    sentence = stale_sentence(note)
    if (folder / "junit.xml").exists():
        _junit_stale(folder / "junit.xml", sentence)
        changed.append(str(folder / "junit.xml"))
    for name, mark in (("report.md", _md_stale), ("report.html", _html_stale)):
        p = folder / name
        try:
            text = p.read_text()
        except OSError:
            continue
        write_atomically(p, mark(text, sentence))
        changed.append(str(p))
    for path in changed:
        backdate(path)
    return changed


def stale_sentence(note: dict) -> str:
    """'STALE: results changed since this verdict (PASS) was written: run_engine (case steel,
    build lammps) started at 2026-11-26 05:08:56 UTC. For a verdict again: snakemake -j2 all.'"""
    was = f" ({note['was']})" if note.get("was") else ""
    return (f"STALE: results changed since this verdict{was} was written: {note['by']}, since {note['since']}. "
            f"For a verdict again: {note['rerun']}.")


def _md_stale(text: str, sentence: str) -> str:
    banner = f"<!-- stale -->\n> **{sentence.split(':', 1)[0]}**:{sentence.split(':', 1)[1]}\n<!-- /stale -->\n\n"
    text = _MD_BANNER.sub("", text, count=1)
    m = re.match(r"# [^\n]*\n\n", text)  # after the title
    return text[:m.end()] + banner + text[m.end():] if m else banner + text


def _html_stale(text: str, sentence: str) -> str:
    block = (f"<section class='stale'><p style='border:2px solid #b60;padding:.5em'><strong>STALE</strong>:"
             f"{html.escape(sentence.split(':', 1)[1])}</p></section>")
    text = _HTML_BANNER.sub("", text, count=1)
    return text.replace("<body>", f"<body>{block}", 1) if "<body>" in text else block + text


def junit_suite(path: Path) -> tuple[ET.Element, ET.Element]:
    """(root, the study's test suite) of the JUnit file `path`, or of a new empty one where it
    cannot be read: the verdict files written outside their rules add their test cases to it."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError):
        root = ET.Element("testsuites", name=SUITE, tests="0", failures="0", errors="0", skipped="0")
    suite = root.find("testsuite")
    if suite is None:
        suite = ET.SubElement(root, "testsuite", name=SUITE, tests="0", failures="0", errors="0", skipped="0")
    return root, suite


def _junit_stale(path: Path, sentence: str) -> None:
    root, suite = junit_suite(path)
    old = suite.find("testcase[@classname='workflow'][@name='stale']")
    if old is None:
        case = ET.SubElement(suite, "testcase", classname="workflow", name="stale", time="0")
        for element in (root, suite):
            element.set("tests", str(int(element.get("tests", "0")) + 1))
            element.set("failures", str(int(element.get("failures", "0")) + 1))
    else:
        case = old
        for child in list(case):
            case.remove(child)
    ET.SubElement(case, "failure", message=sentence, type="stale")
    ET.indent(root)
    write_junit_xml(root, path)


def verdict_line(results_dir="results") -> str:
    """The one line that ends a study's log: its verdict and where its report is.

    'PASS: 114 of 114 gated checks pass; report: results/report.html', 'FAIL: 2 of 114 ...',
    'STALE: ...', 'INTERRUPTED: ...', or that there is no verdict (the workflow stopped before one
    was written)."""
    folder = Path(results_dir)
    report = folder / "report.html"
    where = f"; report: {report}" if report.exists() else ""
    try:
        verdict = json.loads((folder / "verdict.json").read_text())
    except (OSError, ValueError):
        return f"no verdict: {folder / 'verdict.json'} was not written (see the log above){where}"
    kind = verdict.get("verdict", "?")
    if kind == "STALE":
        return stale_sentence(verdict["stale"]) + where
    if kind == "INTERRUPTED":
        return f"INTERRUPTED: continue with {verdict.get('continue')}{where}"
    checked, failed = verdict.get("checked", 0), verdict.get("failed", 0)
    lost = len(verdict.get("failed_jobs", []))
    text = f"{kind}: {checked - failed} of {checked} gated checks pass"
    judged = f" (tolerance, relative: {tolerance_text(verdict['tolerance'])})" if verdict.get("tolerance") else ""
    warnings = "".join(f"\nWarning: {w}" for w in verdict.get("warnings", []))
    return text + judged + (f", {lost} job(s) did not finish" if lost else "") + where + warnings


def main(argv=None) -> int:
    """`python -m postprocess.verdict_files [RESULTS]`: make study / make ci-study end their log with
    this line (`verdict_line`)."""
    import sys

    argv = sys.argv[1:] if argv is None else argv
    print(verdict_line(argv[0] if argv else "results"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
