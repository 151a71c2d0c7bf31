"""The benchmarks' own refusals (their figures are printed by `make bench`, never asserted)."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_reference_solver_benchmark_refuses_an_unknown_baseline_naming_it():
    run = subprocess.run([sys.executable, "-m", "benchmarks.reference_solver", "--baseline", "no-such-rev"],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode != 0
    assert "--baseline no-such-rev: not a git revision" in run.stderr
    assert "Traceback" not in run.stderr
