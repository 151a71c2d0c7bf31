"""Helpers shared by the workflow scripts: logging into the rule's log file."""

import logging
import sys


def log_to(path):
    """Send logging and uncaught exceptions of a rule's script to its log file (and stderr)."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(message)s",
                        handlers=[logging.FileHandler(path, mode="w"), logging.StreamHandler(sys.stderr)])

    def excepthook(kind, value, tb):
        logging.error("%s: %s", kind.__name__, value, exc_info=(kind, value, tb))

    sys.excepthook = excepthook
    return logging.getLogger("study")
