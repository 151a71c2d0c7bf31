"""`snakemake oblique_reduced` end to end (issue 'Oblique impacts'): exit status, gate.txt,
verdict.json, junit.xml and the report, on PASS and on FAIL.

The FAIL is real: LAMMPS 22 Jul 2025's classic wall (`fix wall/gran hertz/history`, gamman = 0)
crashes (gammat / gamman = 0/0); the config declares it as a known defect, and without that
declaration the gate must fail, naming the build, the model and the engine's message."""

import json
import sys
import xml.etree.ElementTree as ET

import pytest

import processes
from engine_cases import require_default_builds
from workflow_copy import copy_workflow

SNAKEMAKE = [sys.executable, "-m", "snakemake", "-j2", "oblique_reduced"]
#: One impact (60 deg: gross sliding) and one build: a minute at most.
ONE = "oblique={cases: cases/oblique/*.yaml, builds: [%s], ladder: [1000, 2000, 4000], tolerance: 1.0e-6, " \
      "reduced: {cases: [cases/oblique/chung_ooi_test4.yaml], angles: [60.0]}, known_defects: %s}"
DECLARED = ("[{build: lammps-2025, model: 'lammps:hertz/history', fails: 'Non-numeric atom coords', "
            "reference: 'granular_model.cpp:221', description: 'classic wall, gamman = 0'}]")


@pytest.fixture
def project(tmp_path, runs_workflow):
    require_default_builds()
    return copy_workflow(tmp_path / "project")


def run(project, build, defects):
    return processes.run([*SNAKEMAKE, "--config", ONE % (build, defects)], cwd=project, capture_output=True,
                         text=True, timeout=600)


def test_a_passing_set_writes_its_gate_and_a_crash_fails_it_unless_declared(project):
    ok = run(project, "lammps-2021", "[]")
    assert ok.returncode == 0, ok.stderr[-3000:]
    folder = project / "results" / "oblique" / "reduced"
    verdict = json.loads((folder / "verdict.json").read_text())
    assert verdict["verdict"] == "PASS" and verdict["failed"] == 0 and verdict["checks"] >= 6 * 7
    assert (folder / "gate.txt").read_text().startswith("PASS")
    suite = ET.parse(folder / "junit.xml").getroot()
    assert int(suite.get("tests")) == verdict["checks"] and int(suite.get("failures")) == 0
    report = (folder / "report.md").read_text()
    assert "**Verdict: PASS**" in report and "lammps:mindlin" in report and "rigid-body closed form" in report

    failed = run(project, "lammps-2025", "[]")
    assert failed.returncode != 0
    assert "lammps-2025 lammps:hertz/history sphere-plane" in failed.stderr and "Non-numeric atom coords" in (
        folder / "checks.csv").read_text()
    assert not (folder / "gate.txt").exists()
    verdict = json.loads((folder / "verdict.json").read_text())
    assert verdict["verdict"] == "FAIL" and verdict["failed"] >= 1
    suite = ET.parse(folder / "junit.xml").getroot()
    assert int(suite.get("failures")) == verdict["failed"]
    assert "**Verdict: FAIL**" in (folder / "report.md").read_text()

    declared = run(project, "lammps-2025", DECLARED)
    assert declared.returncode == 0, declared.stderr[-3000:]
    verdict = json.loads((folder / "verdict.json").read_text())
    assert verdict["verdict"] == "PASS" and verdict["known_defects"] >= 1
    assert "KNOWN DEFECT" in (folder / "report.md").read_text()
