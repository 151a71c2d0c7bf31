"""Helpers shared by the workflow scripts: logging into the rule's log file, and marking the
study's verdict stale before a rule changes any result."""

import logging
import sys

from verdict.verdict_files import mark_stale


def log_to(path):
    """Send logging and uncaught exceptions of a rule's script to its log file (and stderr). An
    interruption (Ctrl-C: SIGINT reaches every process of the workflow) is one line, not a
    traceback: it is not a failure of the rule."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(message)s",
                        handlers=[logging.FileHandler(path, mode="w"), logging.StreamHandler(sys.stderr)])

    def excepthook(kind, value, tb):
        if issubclass(kind, KeyboardInterrupt):
            logging.error("interrupted (SIGINT): the rule stopped before it finished")
            return
        logging.error("%s: %s", kind.__name__, value, exc_info=(kind, value, tb))

    sys.excepthook = excepthook
    return logging.getLogger("study")


def job_name(smk) -> str:
    """'run_engine (case steel, build lammps)': the rule and its wildcards."""
    wildcards = dict(smk.wildcards.items())
    return smk.rule + (f" ({', '.join(f'{k} {v}' for k, v in wildcards.items())})" if wildcards else "")


def start_oblique_rule(smk):
    """log_to(the rule's log), after marking stale the verdict of its oblique set (results/oblique/
    <set>/) and, for the reduced set, which the study's report includes, the study's verdict too;
    see `start_rule`."""
    log = log_to(smk.log[0])
    reduced = smk.wildcards.set == "reduced"
    by = job_name(smk)
    folders = [("results", "snakemake -j2 all")] if reduced else []
    folders.append((f"results/oblique/{smk.wildcards.set}", "snakemake -j2 " + ("oblique_reduced" if reduced
                                                                                else "oblique")))
    for folder, rerun in folders:
        for path in mark_stale(folder, by, rerun):
            log.info("marked stale: %s", path)
    return log


def start_rule(smk, *also, results_dir="results"):
    """log_to(the rule's log), after marking stale (`verdict.verdict_files.mark_stale`) the
    verdict of the study (`results_dir`), of the rule's case (`results_dir/<case>`, for a rule with
    a case wildcard) and of the folders `also` (e.g. results/calibration, whose report the study's
    report includes).

    Every rule that writes results calls this first: a rerun that then fails or is interrupted
    leaves no PASS (or FAIL) beside results that it was not computed from, and the reports stay
    readable, marked stale. The checks, case_verdict and calibration_report rules write them anew
    from the finished results.
    """
    log = log_to(smk.log[0])
    case = dict(smk.wildcards.items()).get("case")
    by = job_name(smk)
    for folder, rerun in [(results_dir, "snakemake -j2 all"),
                          *([(f"{results_dir}/{case}", f"snakemake -j2 {case}")] if case else []),
                          *((f, f"snakemake -j2 {f.rstrip('/').rsplit('/', 1)[-1]}") for f in also)]:
        for path in mark_stale(folder, by, rerun):
            log.info("marked %s stale: results are about to change", path)
    return log
