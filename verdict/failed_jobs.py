"""The jobs a workflow run lost, and the FAIL they force on the study's verdict.

A job can end without a verdict of its own: SLURM kills an engine job at its time or memory
limit, a user cancels it (`scancel`), a node fails, a script crashes. Snakemake then removes the
job's outputs, the gate never runs, and no check names what happened; a CI reading the JUnit XML
of an earlier run would even read its PASS. So the Snakefile's `onerror` hands Snakemake's log to
`record_failed_jobs`, which

- reads the failed jobs from it (its "Error in rule ..." blocks, less those a retry finished),
- asks SLURM (`sacct`) for each cluster job's state, time limit, memory and peak use,
- writes the verdict FAIL naming every lost job and why into verdict.json, junit.xml and
  report.md / report.html, merged with what this run's report wrote before the failure, and
- withdraws gate.txt (the PASS of a run that did not finish),

in the study's folder (results/) and, for a job of one case (its `case` wildcard: run_engine,
case_summary, case_verdict, ...), in that case's folder (results/<case>/) too, with that case's
lost jobs: `snakemake -j2 steel` gates on results/steel/gate.txt, which must not outlive a failed
case_verdict.

The rules whose failure *is* a verdict (the gates: they exit non-zero on FAIL, after writing it)
are not lost jobs and are left out.

Light (the standard library and engines.engine_process's log reading): the Snakefile imports it.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from engines.engine_process import log_tail
from records.files import write_atomically

from .verdict_files import (SUITE, backdate, html_page, is_stale, junit_suite, mark_stale, write_junit_xml,
                            write_verdict)

#: How long `sacct` may take for one job before its account is left out [s].
SACCT_TIMEOUT_S = 30
#: Lines of a local job's log quoted with its failure.
LOG_LINES = 8

_ERROR = re.compile(r"^Error in rule (?P<rule>\S+):$")
_FIELD = re.compile(r"^ {4}(?P<key>[a-z_-]+): (?P<value>.*)$")
_FINISHED = re.compile(r"^Finished jobid: (?P<jobid>\d+)\b")
_SLURM_FIELDS = ("JobID", "State", "ExitCode", "Elapsed", "Timelimit", "ReqMem", "MaxRSS", "Reason")


@dataclass
class FailedJob:
    """A job Snakemake reported failed: its rule, Snakemake's job id, the outputs it did not
    make, its logs (the rule's, then the cluster's), the executor's message and, for a cluster
    job, SLURM's job id."""

    rule: str
    jobid: str
    outputs: list[str] = field(default_factory=list)
    logs: list[str] = field(default_factory=list)
    message: str = ""
    external_jobid: str | None = None


def parse_failed_jobs(log_text: str) -> list[FailedJob]:
    """The jobs of a Snakemake log that failed and were not finished by a retry, in the order of
    their last failure. A job is keyed by Snakemake's job id, which a retry keeps."""
    failed: dict[str, FailedJob] = {}
    lines = log_text.splitlines()
    i = 0
    while i < len(lines):
        finished = _FINISHED.match(lines[i])
        if finished:
            failed.pop(finished["jobid"], None)
        error = _ERROR.match(lines[i])
        if not error:
            i += 1
            continue
        fields = {}
        i += 1
        while i < len(lines) and (m := _FIELD.match(lines[i])):
            fields[m["key"]] = m["value"]
            i += 1
        if "jobid" not in fields:
            continue
        logs = re.sub(r" \(check log file\(s\) for error details\)$", "", fields.get("log", ""))
        job = FailedJob(rule=error["rule"], jobid=fields["jobid"], outputs=_split(fields.get("output", "")),
                        logs=_split(logs), message=_message(fields.get("message", "")),
                        external_jobid=fields.get("external_jobid"))
        failed.pop(job.jobid, None)
        failed[job.jobid] = job
    return list(failed.values())


def _message(value: str) -> str:
    value = value.strip()
    return "" if value == "None" else value  # a local job's error has no message: Snakemake prints None


def _split(value: str) -> list[str]:
    return [v for v in value.split(", ") if v]


#: A wildcard in an output pattern: {name}, or {name,regex} once constraints are applied.
_WILDCARD = re.compile(r"\{\s*(\w+)\s*(?:,\s*((?:[^{}]|\{[^{}]*\})*))?\}")


def _pattern_regex(pattern: str) -> str:
    parts, pos, seen = [], 0, set()
    for m in _WILDCARD.finditer(pattern):
        parts.append(re.escape(pattern[pos:m.start()]))
        name = m[1]
        parts.append(f"(?P={name})" if name in seen else f"(?P<{name}>{m[2] or '[^/]+'})")
        seen.add(name)
        pos = m.end()
    return "".join(parts) + re.escape(pattern[pos:])


def wildcards_of(patterns, outputs) -> dict[str, str]:
    """The wildcards of a job, read from its first output that matches one of its rule's output
    `patterns` ('results/{case}/{build}/manifest.json' and 'results/steel/esys-2.3.5/manifest.json'
    give {'case': 'steel', 'build': 'esys-2.3.5'}; a constrained '{case,steel|glass}' too); empty
    when none matches."""
    for pattern in patterns:
        regex = _pattern_regex(str(pattern))
        for path in outputs:
            m = re.fullmatch(regex, path)
            if m:
                return m.groupdict()
    return {}


def describe(job: FailedJob, wildcards: dict[str, str]) -> str:
    """'run_engine (case steel, build esys-2.3.5)', or the rule and its first output."""
    if wildcards:
        return f"{job.rule} ({', '.join(f'{k} {v}' for k, v in wildcards.items())})"
    return f"{job.rule} ({job.outputs[0]})" if job.outputs else job.rule


def slurm_account(jobid: str, sacct: str | None = None) -> list[dict[str, str]]:
    """SLURM's account of a job (`sacct -j jobid`): one dict of _SLURM_FIELDS for the allocation,
    then one per step; empty when sacct is missing, fails or knows no such job."""
    sacct = sacct or shutil.which("sacct")
    if not sacct:
        return []
    try:
        out = subprocess.run([sacct, "-j", str(jobid), "-n", "-P", "-o", ",".join(_SLURM_FIELDS)],
                             capture_output=True, text=True, timeout=SACCT_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired):
        return []
    if out.returncode != 0:
        return []
    return [dict(zip(_SLURM_FIELDS, line.split("|"))) for line in out.stdout.splitlines() if line.count("|") >= 7]


def slurm_reason(rows: list[dict[str, str]], cluster_log=None) -> str:
    """What SLURM did to a job, from `slurm_account`'s rows (allocation first) and the job's
    SLURM log: 'SLURM job 61: TIMEOUT after 00:01:31, killed at its time limit 00:01:00', '...:
    FAILED after 00:00:04, killed for its memory: a step peaked at 2.9G, over the 1500M it
    requested', 'CANCELLED by 0 ...', with the first line SLURM wrote about it in `cluster_log`."""
    job = rows[0]
    state = job["State"]
    text = f"SLURM job {job['JobID']}: {state}" + (f" after {job['Elapsed']}" if job.get("Elapsed") else "")
    peak = max((r["MaxRSS"] for r in rows[1:] if r.get("MaxRSS")), key=_bytes, default="")
    if state == "TIMEOUT":
        text += f", killed at its time limit {job.get('Timelimit', '')}".rstrip()
    elif peak and job.get("ReqMem") and _bytes(peak) > _bytes(job["ReqMem"]):
        text += f", killed for its memory: a step peaked at {_human(peak)}, over the {job['ReqMem']} it requested"
    elif state.startswith("CANCELLED"):
        text += " (scancel, or SLURM on a user's or an administrator's request)"
    elif state == "NODE_FAIL":
        text += ": its node failed"
    if job.get("Reason") and job["Reason"] != "None":
        text += f"; reason: {job['Reason']}"
    exit_code = job.get("ExitCode", "")
    if exit_code and exit_code != "0:0":
        text += f"; exit code {exit_code} (status:signal)"
    said = _slurm_said(cluster_log)
    return f"{text}; SLURM: {said!r}" if said else text


#: What slurmstepd writes into a job's output when it stops it (time limit, memory, scancel).
_SLURM_SAYS = re.compile(r"slurmstepd.*(?:CANCELLED AT|DUE TO|exceeded memory limit|error:).*")


def _slurm_said(cluster_log) -> str:
    try:
        text = Path(cluster_log).read_text(errors="replace") if cluster_log else ""
    except OSError:
        return ""
    m = _SLURM_SAYS.search(text)
    return m.group(0).strip() if m else ""


def _human(size: str) -> str:
    """'599664K' -> '586M' (binary units, as sacct's)."""
    value = _bytes(size)
    for unit in "KMGT":
        value /= 1024
        if value < 1024:
            return f"{value:.3g}{unit}"
    return size


def _bytes(size: str) -> float:
    """'1536K' -> 1572864.0 (sacct's MaxRSS)."""
    m = re.fullmatch(r"([\d.]+)([KMGTP]?)", size.strip())
    if not m:
        return 0.0
    return float(m[1]) * 1024 ** " KMGTP".index(m[2] or " ")


#: The line a Python traceback ends with ('records.dump_file.DumpError: ...').
_EXCEPTION = re.compile(r"^(?:[\w.]+\.)?(\w*(?:Error|Exception|Exit|Interrupt))(?:: (.*))?$")


def _error_line(logs) -> str:
    """The last exception a job's logs name ('DumpError: ... the dump changed ...'); '' if none."""
    for path in logs:
        for line in reversed(log_tail(path, 200)):
            m = _EXCEPTION.match(line.strip())
            if m:
                return f"{m[1]}: {m[2]}" if m[2] else m[1]
    return ""


def job_failure(job: FailedJob, wildcards: dict[str, str], sacct: str | None = None) -> dict:
    """One lost job as the verdict records it: what it was, why it failed, where its logs are."""
    reason = job.message or _error_line(job.logs) or "its job failed (see its log)"
    if job.external_jobid:
        rows = slurm_account(job.external_jobid, sacct)
        if rows:
            reason = slurm_reason(rows, next((p for p in job.logs if p.endswith(f"/{job.external_jobid}.log")), None))
    # The rule's own log says where the job was; a cluster job that died before its rule's log
    # (e.g. in the workflow's start inside the job) left it in its SLURM log.
    tail = next((t for t in (log_tail(p, LOG_LINES) for p in job.logs) if t), [])
    return {"job": describe(job, wildcards), "rule": job.rule, "wildcards": wildcards, "reason": reason,
            "slurm_job": job.external_jobid, "logs": job.logs, "log_tail": tail}


def failure_markdown(failures: list[dict]) -> str:
    lines = ["## The workflow did not finish: FAIL", "",
             f"{len(failures)} job(s) failed, so no verdict covers their results; the gate did not judge "
             "the study. Each failed job, why, and its logs:", ""]
    for f in failures:
        lines.append(f"- **{f['job']}**: {f['reason']}. Logs: {', '.join(f'`{p}`' for p in f['logs']) or 'none'}")
        lines += [f"      {line}" for line in f["log_tail"]]
    return "\n".join(lines) + "\n"


def _merge_verdict(path: Path, failures: list[dict]) -> None:
    try:
        verdict = json.loads(path.read_text())
    except (OSError, ValueError):
        verdict = {"checked": 0, "failed": 0, "failures": [], "summary_sha256": None}
    verdict.update(verdict="FAIL", **{"pass": False})
    verdict["failures"] = [*verdict.get("failures", []),
                           *(f"{f['job']} did not finish: {f['reason']}" for f in failures)]
    verdict["failed_jobs"] = failures
    write_verdict(verdict, path)


def _merge_junit(path: Path, failures: list[dict]) -> None:
    root, suite = junit_suite(path)
    for f in failures:
        name = ", ".join(f"{k}={v}" for k, v in f["wildcards"].items()) or "job"
        case = ET.SubElement(suite, "testcase", classname=f"workflow.{f['rule']}", name=name, time="0")
        failure = ET.SubElement(case, "failure", message=f"{f['job']} did not finish: {f['reason']}", type="job")
        failure.text = "\n".join([f"logs: {', '.join(f['logs'])}", *f["log_tail"]])
    for element in (root, suite):
        element.set("tests", str(int(element.get("tests", "0")) + len(failures)))
        element.set("failures", str(int(element.get("failures", "0")) + len(failures)))
    ET.indent(root)
    write_junit_xml(root, path)


def _merge_report(results: Path, section: str) -> None:
    md, page_path = results / "report.md", results / "report.html"
    try:
        old = md.read_text()
    except OSError:
        old = ""
    write_atomically(md, (f"# Hertz DEM comparison report\n\n{section}" if not old else
                          re.sub(r"\A(# [^\n]*\n\n)?", lambda m: f"{m.group(0)}{section}\n", old, count=1)))
    items = "".join(f"<li>{html.escape(line[2:])}</li>" for line in section.splitlines() if line.startswith("- "))
    block = (f"<section class='lost-jobs'><h2>The workflow did not finish: FAIL</h2><p>"
             f"{html.escape(section.splitlines()[2])}</p><ul>{items}</ul></section>")
    try:
        page = page_path.read_text()
    except OSError:
        page = ""
    if "<body>" in page:
        page = page.replace("<body>", f"<body>{block}", 1)
    else:
        page = html_page("Hertz DEM comparison report", block)
    write_atomically(page_path, page)


def record_failed_jobs(log_path, results_dir="results", output_patterns: dict | None = None,
                       verdict_rules=(), sacct: str | None = None, command: str | None = None) -> list[dict]:
    """Read the failed jobs of the Snakemake log `log_path` (a path, or a list of them) and write
    the FAIL they force into `results_dir` (see the module's docstring). `output_patterns` maps each rule to its output
    patterns (to name a job by its wildcards); the jobs of `verdict_rules` are left out. An
    interrupted workflow (Ctrl-C) is no failure: `record_interruption`, with `command` (the one
    that continues it). Returns the failures written, or the interrupted jobs (each with
    reason 'interrupted ...'); none: nothing written."""
    paths = [log_path] if isinstance(log_path, (str, Path)) else list(log_path or [])
    text = ""
    for path in paths:  # Snakemake 9 hands `onerror` a list: one file per log handler
        try:
            text += Path(path).read_text(errors="replace")
        except OSError:
            continue
    jobs = [j for j in parse_failed_jobs(text) if j.rule not in set(verdict_rules)]
    if not jobs:
        return []
    patterns = output_patterns or {}
    results = Path(results_dir)
    if was_interrupted(text, jobs):
        return record_interruption(jobs, patterns, results, command)
    failures = [job_failure(j, wildcards_of(patterns.get(j.rule, ()), j.outputs), sacct) for j in jobs]
    results.mkdir(parents=True, exist_ok=True)
    write_failures(results, failures)
    for case in dict.fromkeys(f["wildcards"]["case"] for f in failures if "case" in f["wildcards"]):
        if (results / case).is_dir():
            write_failures(results / case, [f for f in failures if f["wildcards"].get("case") == case])
    return failures


def write_failures(folder: Path, failures: list[dict]) -> None:
    """The FAIL of the lost jobs `failures` (`job_failure`) in the verdict files of `folder`: gate.txt
    withdrawn; verdict.json, junit.xml, report.md and report.html merged with what is there (or,
    when that is stale, a verdict about earlier results, replacing it) and dated 1970, so that the
    next run rewrites them."""
    (folder / "gate.txt").unlink(missing_ok=True)
    if is_stale(folder):  # a verdict about earlier results: this run's FAIL replaces it, not joins it
        for name in ("verdict.json", "junit.xml", "report.md", "report.html"):
            (folder / name).unlink(missing_ok=True)
    _merge_verdict(folder / "verdict.json", failures)
    _merge_junit(folder / "junit.xml", failures)
    _merge_report(folder, failure_markdown(failures))
    for name in ("verdict.json", "junit.xml", "report.md", "report.html"):
        backdate(folder / name)  # written outside their rules: the next run rewrites them


#: What Snakemake logs when the user stops it (Ctrl-C, SIGINT), and how a job's script or shell
#: reports the signal.
_USER_STOP = "Terminating processes on user request"
_SIGINT = re.compile(r"KeyboardInterrupt|interrupted \(SIGINT\)|Signals\.SIGINT|signal 2\b")


def was_interrupted(log_text: str, jobs: list[FailedJob]) -> bool:
    """Whether the workflow was stopped by its user (Ctrl-C) rather than by a failure: Snakemake
    says so in its log, or every failed job died of SIGINT."""
    if _USER_STOP in log_text:
        return True
    return bool(jobs) and all(_SIGINT.search(j.message or _error_line(j.logs)) for j in jobs)


def continue_command(argv) -> str:
    """The command that continues an interrupted workflow: the user's, with --rerun-incomplete
    ('snakemake -j2 steel --rerun-incomplete')."""
    import shlex

    args = [a for a in list(argv)[1:]]
    if not any(a in ("--rerun-incomplete", "--ri") for a in args):
        args.append("--rerun-incomplete")
    return shlex.join(["snakemake", *args])


def record_interruption(jobs: list[FailedJob], patterns: dict, results: Path, command: str | None) -> list[dict]:
    """An interrupted workflow: not an engine failure, and no FAIL. Each interrupted job's partial
    outputs are removed (Snakemake removed them before the job started, so what is there is the
    job's unfinished work: dumps half written, an engine's scratch folders). The folder of each
    interrupted case job (results/<case>) gets the verdict INTERRUPTED, naming the jobs and the
    command that continues; so does the study's folder for a job of no case; every other verdict
    is only marked stale, with the interruption as its note. Returns the interrupted jobs."""
    command = command or "snakemake -j2 all --rerun-incomplete"
    interrupted = []
    for job in jobs:
        wildcards = wildcards_of(patterns.get(job.rule, ()), job.outputs)
        removed = [p for p in job.outputs if _remove(Path(p))]
        interrupted.append({"job": describe(job, wildcards), "rule": job.rule, "wildcards": wildcards,
                            "removed": removed, "logs": job.logs,
                            "reason": "interrupted (SIGINT) before it finished"})
    names = ", ".join(j["job"] for j in interrupted)
    folders = {results / j["wildcards"]["case"] if "case" in j["wildcards"] else results for j in interrupted}
    for folder in sorted(folders):
        mine = [j for j in interrupted if (results / j["wildcards"]["case"] if "case" in j["wildcards"]
                                           else results) == folder]
        _write_interrupted(folder, mine, command)
    if results not in folders and results.exists():
        mark_stale(results, f"the run was interrupted in {names}", "snakemake -j2 all")
    return interrupted


def _remove(path: Path) -> bool:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
        return True
    try:
        path.unlink()
        return True
    except FileNotFoundError:
        return False


def _write_interrupted(folder: Path, jobs: list[dict], command: str) -> None:
    """verdict.json, junit.xml, report.md and report.html of an interrupted run (no gate.txt)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "gate.txt").unlink(missing_ok=True)
    names = ", ".join(j["job"] for j in jobs)
    sentence = f"INTERRUPTED: {names} did not finish (stopped by the user). Continue with: {command}"
    verdict = {"verdict": "INTERRUPTED", "pass": False, "checked": 0, "failed": 0, "failures": [],
               "interrupted_jobs": jobs, "continue": command, "summary_sha256": None}
    write_verdict(verdict, folder / "verdict.json")
    root = ET.Element("testsuites", name=SUITE, tests=str(len(jobs)), failures="0", errors=str(len(jobs)),
                      skipped="0")
    suite = ET.SubElement(root, "testsuite", name=SUITE, tests=str(len(jobs)), failures="0",
                          errors=str(len(jobs)), skipped="0")
    for j in jobs:
        name = ", ".join(f"{k}={v}" for k, v in j["wildcards"].items()) or "job"
        case = ET.SubElement(suite, "testcase", classname=f"workflow.{j['rule']}", name=name, time="0")
        ET.SubElement(case, "error", message=f"{j['job']} was interrupted; continue with: {command}",
                      type="interrupted")
    ET.indent(root)
    write_junit_xml(root, folder / "junit.xml")
    lines = ["# Hertz DEM comparison report", "", "## The run was interrupted: no verdict", "",
             f"The workflow was stopped by its user (Ctrl-C) before {len(jobs)} job(s) finished; their unfinished "
             "outputs were removed. No check was judged, and nothing here is an engine failure. Continue with:", "",
             f"    {command}", ""]
    lines += [f"- **{j['job']}**: interrupted; logs: {', '.join(f'`{p}`' for p in j['logs']) or 'none'}" for j in jobs]
    write_atomically(folder / "report.md", "\n".join(lines) + "\n")
    items = "".join(f"<li><strong>{html.escape(j['job'])}</strong>: interrupted</li>" for j in jobs)
    write_atomically(folder / "report.html",
                     html_page("Hertz DEM comparison report", "<h1>Hertz DEM comparison report</h1><h2>The run was "
                               f"interrupted: no verdict</h2><p>{html.escape(sentence)}</p><ul>{items}</ul>"))
    for name in ("verdict.json", "junit.xml", "report.md", "report.html"):
        backdate(folder / name)  # written outside their rules: the next run rewrites them
