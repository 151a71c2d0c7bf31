"""A run with another build list beside a study (the README's "your own build" on a case of the study):
it writes the case's report of its own builds, says under its verdict that the folders of the builds it
does not have are stale and lists none of their runs, and withdraws the study's verdict those folders
were part of (no PASS of seven builds stands beside a report of two)."""

import json
import sys

import pytest

import processes
from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow

CASE = """name: steel
effective_modulus: 109 GPa
radius: 0.635 cm
viscosity: 6.7e5 P
density: 7800 kg/m^3
geometries: [sphere-plane]
impact:
  K: [0.1]
"""
TWO = ("builds=[{id: lammps-2021, code: lammps, executable: lmp}, "
       "{id: liggghts-3.8, code: liggghts, executable: liggghts}]")
ONE = "builds=[{id: lammps-2021, code: lammps, executable: lmp}]"


def study(project, target, builds):
    return processes.run([sys.executable, "-m", "snakemake", "-j2", target, "--config", builds, "laws=[viscoelastic]",
                          "extras=[]", "compare_builds=[]"], cwd=project, capture_output=True, text=True, timeout=900)


def test_a_run_with_fewer_builds_marks_the_others_stale_and_withdraws_the_studys_pass(tmp_path):
    for engine in ("lmp", "liggghts"):
        if processes.run(["which", engine], capture_output=True).returncode != 0:
            pytest.skip(f"{engine} is not installed (apt-get install lammps liggghts)")
    project = copy_workflow(tmp_path / "study", CASE)
    first = study(project, "all", TWO)
    assert first.returncode == 0, first.stderr[-3000:]
    assert (project / "results" / "gate.txt").read_text().startswith("PASS: ")
    second = study(project, "steel", ONE)
    assert second.returncode == 0, second.stderr[-3000:]
    report = (project / "results" / "steel" / "report.md").read_text()
    assert "**Stale folders**: `results/steel/liggghts-3.8` beside this report are from an earlier run" in report
    assert "(lammps-2021)" in report
    table = report.split("**Stale folders**")[1]
    assert "liggghts-3.8 viscoelastic" not in table and "| liggghts-3.8 |" not in table  # none of its runs
    # the study's PASS of two builds does not stand beside a case report of one
    assert not (project / "results" / "gate.txt").exists()
    assert json.loads((project / "results" / "verdict.json").read_text())["verdict"] == "STALE"
    # the case's own verdict is of its one build
    verdict = json.loads((project / "results" / "steel" / "verdict.json").read_text())
    assert verdict["verdict"] == "PASS" and all(c.startswith("lammps-2021") for c in verdict.get("passed", [])), verdict
