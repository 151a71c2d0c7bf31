"""The verdict of a run that lost jobs (verdict.failed_jobs): Snakemake's log read, SLURM's
account put into words, and the FAIL merged into the verdict files a report already wrote.
End to end: tests/test_slurm.py (SLURM's kills and a cancel) and tests/test_study_failures.py (a
local job that failed)."""

import json
import xml.etree.ElementTree as ET

from engines import run_sweep
from engines.builds import Build
from verdict.failed_jobs import parse_failed_jobs, record_failed_jobs, slurm_reason, wildcards_of

LOG = """\
[Wed Nov 25 13:48:24 2026]
Error in rule run_engine:
    message: SLURM-job '35' failed, SLURM status is: 'TIMEOUT'. Reason: Unknown.
    jobid: 14
    input: cases/steel.yaml
    output: results/steel/esys/manifest.json, results/steel/esys/runs
    log: logs/steel/esys.log, /p/slurm_logs/35.log (check log file(s) for error details)
    external_jobid: 35
Trying to restart job 14.
[Wed Nov 25 13:48:25 2026]
Error in rule case_summary:
    message: None
    jobid: 4
    output: results/glass/summary.csv
    log: logs/glass/summary.log (check log file(s) for error details)
Trying to restart job 4.
[Wed Nov 25 13:49:00 2026]
Error in rule run_engine:
    message: SLURM-job '41' failed, SLURM status is: 'TIMEOUT'. Reason: Unknown.
    jobid: 14
    output: results/steel/esys/manifest.json, results/steel/esys/runs
    log: logs/steel/esys.log, /p/slurm_logs/41.log (check log file(s) for error details)
    external_jobid: 41
[Wed Nov 25 13:49:10 2026]
Finished jobid: 4 (Rule: case_summary)
Error in rule gate:
    message: None
    jobid: 1
    output: results/gate.txt
"""


def test_failed_jobs_are_read_from_the_log_once_each_with_their_last_attempt_and_retried_successes_dropped():
    jobs = parse_failed_jobs(LOG)
    assert [(j.rule, j.jobid, j.external_jobid) for j in jobs] == [("run_engine", "14", "41"), ("gate", "1", None)]
    engine = jobs[0]
    assert engine.outputs == ["results/steel/esys/manifest.json", "results/steel/esys/runs"]
    assert engine.logs == ["logs/steel/esys.log", "/p/slurm_logs/41.log"]
    assert "TIMEOUT" in engine.message and jobs[1].message == ""  # Snakemake's "None" is no message


def test_wildcards_come_from_the_output_pattern_also_with_the_constraints_snakemake_writes_into_it():
    assert wildcards_of(["results/{case}/{build}/manifest.json"], ["results/steel/esys-2.3.5/manifest.json"]) == \
        {"case": "steel", "build": "esys-2.3.5"}
    constrained = ["results/{case,steel|glass}/summary.csv"]
    assert wildcards_of(constrained, ["results/glass/summary.csv"]) == {"case": "glass"}
    assert wildcards_of(constrained, ["results/cork/summary.csv"]) == {}  # outside the constraint


def _rows(state, elapsed="00:01:20", limit="00:01:00", mem="1500M", peak="", exit_code="0:0"):
    return [{"JobID": "61", "State": state, "ExitCode": exit_code, "Elapsed": elapsed, "Timelimit": limit,
             "ReqMem": mem, "MaxRSS": "", "Reason": "None"},
            {"JobID": "61.batch", "State": state, "ExitCode": exit_code, "Elapsed": elapsed, "Timelimit": "",
             "ReqMem": "", "MaxRSS": "12168K", "Reason": ""},
            {"JobID": "61.0", "State": state, "ExitCode": exit_code, "Elapsed": elapsed, "Timelimit": "",
             "ReqMem": "", "MaxRSS": peak, "Reason": ""}]


def test_slurm_reasons_are_said_in_words_with_the_limit_that_was_hit(tmp_path):
    log = tmp_path / "61.log"
    log.write_text("...\nslurmstepd-vm: error: *** STEP 61.0 ON vm CANCELLED AT 2026-11-25T14:04:45 DUE TO TIME "
                   "LIMIT ***\n")
    assert slurm_reason(_rows("TIMEOUT"), log) == (
        "SLURM job 61: TIMEOUT after 00:01:20, killed at its time limit 00:01:00; SLURM: "
        "'slurmstepd-vm: error: *** STEP 61.0 ON vm CANCELLED AT 2026-11-25T14:04:45 DUE TO TIME LIMIT ***'")
    # 1 624 752 128 B = 1.51 GiB over 1 500 MiB: SLURM's memory kill (jobacct_gather) leaves state FAILED
    oom = slurm_reason(_rows("FAILED", elapsed="00:00:09", peak="1586672K", exit_code="9:0"))
    assert oom == ("SLURM job 61: FAILED after 00:00:09, killed for its memory: a step peaked at 1.51G, over the "
                   "1500M it requested; exit code 9:0 (status:signal)")
    within = slurm_reason(_rows("FAILED", elapsed="00:00:09", peak="1400000K", exit_code="1:0"))
    assert "memory" not in within and within.endswith("exit code 1:0 (status:signal)")
    assert "scancel" in slurm_reason(_rows("CANCELLED by 0", elapsed="00:00:01"))


def test_the_fail_is_merged_into_the_verdict_files_a_report_already_wrote_and_a_pass_is_withdrawn(tmp_path):
    results = tmp_path / "results"
    results.mkdir()
    (results / "gate.txt").write_text("PASS: 6 checks\n")
    (results / "verdict.json").write_text(json.dumps({"verdict": "PASS", "pass": True, "checked": 6, "failed": 0,
                                                      "failures": [], "summary_sha256": "abc"}))
    (results / "junit.xml").write_text('<?xml version="1.0"?><testsuites name="hertz-dem-gate" tests="6" failures="0">'
                                       '<testsuite name="hertz-dem-gate" tests="6" failures="0"></testsuite>'
                                       '</testsuites>')
    (results / "report.md").write_text("# Hertz DEM comparison report\n\n**Verdict: PASS**\n")
    (results / "report.html").write_text("<html><body><p>PASS</p></body></html>")
    engine_log = tmp_path / "logs" / "steel" / "esys.log"
    engine_log.parent.mkdir(parents=True)
    engine_log.write_text("INFO steel: 4 runs of build esys\nTraceback (most recent call last):\n"
                          "  File x\nrecords.dump_file.DumpError: a dump is broken\n")
    log = tmp_path / "snakemake.log"
    log.write_text(LOG.replace("logs/steel/esys.log", str(engine_log)).replace("external_jobid: 41\n", ""))
    failures = record_failed_jobs([str(log)], results, {"run_engine": ["results/{case}/{build}/manifest.json"]},
                                  verdict_rules=("gate",), sacct="/nonexistent/sacct")
    assert [f["job"] for f in failures] == ["run_engine (case steel, build esys)"]
    assert "TIMEOUT" in failures[0]["reason"]  # no sacct here: the plugin's message
    assert not (results / "gate.txt").exists()
    verdict = json.loads((results / "verdict.json").read_text())
    assert (verdict["verdict"], verdict["pass"], verdict["checked"]) == ("FAIL", False, 6)
    assert verdict["failures"] == [f"run_engine (case steel, build esys) did not finish: {failures[0]['reason']}"]
    root = ET.parse(results / "junit.xml").getroot()
    assert (root.get("tests"), root.get("failures")) == ("7", "1")
    (case,) = root.iter("testcase")
    assert (case.get("classname"), case.get("name")) == ("workflow.run_engine", "case=steel, build=esys")
    assert "DumpError: a dump is broken" in case.find("failure").text
    report = (results / "report.md").read_text()
    assert report.index("## The workflow did not finish: FAIL") < report.index("**Verdict: PASS**")
    assert "The workflow did not finish" in (results / "report.html").read_text().split("<p>PASS</p>")[0]


def test_a_run_whose_only_failure_is_a_gate_records_nothing(tmp_path):
    log = tmp_path / "snakemake.log"
    log.write_text("Error in rule gate:\n    message: None\n    jobid: 1\n    output: results/gate.txt\n")
    assert record_failed_jobs(log, tmp_path / "results", verdict_rules=("gate",)) == []
    assert not (tmp_path / "results").exists()


def test_a_build_with_no_run_in_the_case_starts_no_engine(tmp_path):
    # ESyS with `laws: [viscoelastic]` has no run (its viscoelastic force is clipped): started with
    # nothing to do it waited out its 60 s time limit and its job failed. No process now, whatever
    # the executable (this one does not exist).
    sweep = run_sweep(Build("esys", "esys", "/nonexistent/esysparticle"), [], tmp_path / "runs")
    assert (sweep.dumps, sweep.failures, sweep.engine_seconds) == ({}, {}, 0.0)
    assert (tmp_path / "runs").is_dir()
