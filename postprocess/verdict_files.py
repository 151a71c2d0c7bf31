"""The files that carry a verdict (gate.txt, verdict.json, junit.xml, the report): withdrawn
before results change. (They are written with `records.files.write_atomically` and tied to the
summary they describe by its `records.files.file_sha256`.)

Kept apart from `postprocess.gate` (which needs pandas) because every workflow rule imports it
first, through workflow/scripts/common.py: standard library only.
"""

from __future__ import annotations

from pathlib import Path

#: The files that carry a verdict; any rule that changes results withdraws them first.
VERDICT_FILES = ("gate.txt", "verdict.json", "junit.xml", "report.md", "report.html")


def withdraw_verdict(results_dir="results") -> list[str]:
    """Remove every file that carries a verdict from `results_dir` (the names removed).

    Called first by every rule that changes results: a rerun that fails or is interrupted
    then leaves no verdict beside results it does not describe. Jobs that start together (every
    case's summary) withdraw the same files at once: a file another job removed first is gone,
    which is what was asked, not an error.
    """
    removed = []
    for name in VERDICT_FILES:
        p = Path(results_dir) / name
        try:
            p.unlink()
        except FileNotFoundError:
            continue
        removed.append(str(p))
    return removed
