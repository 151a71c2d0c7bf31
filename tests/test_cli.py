"""`python -m reference` prints the reference values, as JSON lines or as a table."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run(*args):
    return subprocess.run([sys.executable, "-m", "reference", *args], cwd=ROOT,
                          capture_output=True, text=True)


def test_json_lines():
    out = run("0.1", "1", "--json")
    assert out.returncode == 0, out.stderr
    rows = [json.loads(line) for line in out.stdout.splitlines()]
    assert [r["K"] for r in rows] == [0.1, 1.0]
    for key in ("K", "x_max", "tau_max", "tau_f", "eps_F0", "tau_0", "eps_x0"):
        assert key in rows[0]
    assert rows[0]["x_max"] == pytest.approx(0.961532369910445, rel=1e-13)
    assert rows[1]["eps_x0"] == pytest.approx(0.380838630487197, rel=1e-13)


def test_table_and_series():
    out = run("0.1")
    assert out.returncode == 0 and "0.961532369910" in out.stdout
    out = run("--series", "--order", "3")
    assert out.returncode == 0
    assert "0.1009" in out.stdout and "0.100890978854" in out.stdout


def test_bad_K_is_a_usage_error():
    out = run("12")
    assert out.returncode == 2 and "K must lie in" in out.stderr
