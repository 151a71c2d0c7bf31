"""Helpers shared by the workflow scripts: logging into the rule's log file, and withdrawing the
study's verdict before a rule changes any result."""

import logging
import sys

from postprocess.verdict_files import withdraw_verdict


def log_to(path):
    """Send logging and uncaught exceptions of a rule's script to its log file (and stderr)."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(message)s",
                        handlers=[logging.FileHandler(path, mode="w"), logging.StreamHandler(sys.stderr)])

    def excepthook(kind, value, tb):
        logging.error("%s: %s", kind.__name__, value, exc_info=(kind, value, tb))

    sys.excepthook = excepthook
    return logging.getLogger("study")


def start_rule(smk, *also, results_dir="results"):
    """log_to(the rule's log), after removing the verdict files of the study (`results_dir`), of
    the rule's case (`results_dir/<case>`, for a rule with a case wildcard) and of the folders
    `also` (e.g. results/calibration, whose report the study's report includes).

    Every rule that writes results calls this first: a rerun that then fails or is killed leaves
    no PASS (or FAIL), and no report, beside results that it was not computed from. The report,
    case_verdict and calibration_report rules write them anew from the finished results.
    """
    log = log_to(smk.log[0])
    case = dict(smk.wildcards.items()).get("case")
    for folder in [results_dir, *([f"{results_dir}/{case}"] if case else []), *also]:
        for path in withdraw_verdict(folder):
            log.info("withdrew %s: results are about to change", path)
    return log
