"""The files the config names outside `cases:` are refused by the key that names them, by the targets
that read them, before any job (workflow/rules/config_files.smk); the other targets run, warned.
A path outside the project, or one that is not a regular file, is never read."""

import subprocess
import sys

import pytest

from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow

BUILD = "builds=[{id: lammps-2021, code: lammps, executable: lmp}]"
CONVERGENCE = ("convergence={{case: {case}, velocity: 1.0, K: [0.1], time_step_factors: [10, 20, 50], "
               "thresholds: [1e-2]}}")
KEYWORDS = "keywords={{case: {case}, geometry: sphere-sphere, velocity: 1.0, restitution: [0.5], measured: {measured}}}"
HISTORY = ("history={{cases: [{case}], K: [0.1], laws: [viscoelastic], restitution: [0.5], promise_tolerance: 1e-3, "
           "builds: [lammps-2021], releases: {{}}}}")


def dry_run(project, target, *config):
    return subprocess.run([sys.executable, "-m", "snakemake", "-n", target, "--config", BUILD, "extras=[convergence]",
                           "laws=[viscoelastic]", *config], cwd=project, capture_output=True, text=True, timeout=300)


def test_a_file_the_config_names_is_refused_by_its_key(tmp_path):
    if subprocess.run(["which", "lmp"], capture_output=True).returncode != 0:
        pytest.skip("Debian's LAMMPS is not installed (apt-get install lammps)")
    project = copy_workflow(tmp_path / "project")
    missing = CONVERGENCE.format(case="cases/nope.yaml")
    out = dry_run(project, "all", missing)
    assert out.returncode != 0 and "Traceback" not in out.stderr
    assert "config 'convergence.case': cases/nope.yaml does not exist" in out.stderr, out.stderr[-2000:]
    out = dry_run(project, "steel", missing)  # the case's own target does not read it: warned, it runs
    assert out.returncode == 0, out.stderr[-2000:]
    assert "Warning: config 'convergence.case': cases/nope.yaml does not exist" in out.stderr
    # outside the project, or not a regular file: refused unread
    out = dry_run(project, "keywords", KEYWORDS.format(case="../../../../etc/passwd", measured="/dev/zero"))
    assert out.returncode != 0
    assert "config 'keywords.case': ../../../../etc/passwd is outside the project folder" in out.stderr
    assert "config 'keywords.measured': /dev/zero is outside the project folder" in out.stderr
    assert "root:" not in out.stderr  # nothing of the file is echoed
    (project / "cases" / "folder.yaml").mkdir()
    out = dry_run(project, "history", HISTORY.format(case="cases/folder.yaml"))
    assert out.returncode != 0 and "config 'history.cases[0]': cases/folder.yaml is not a regular file" in out.stderr
    out = dry_run(project, "history", HISTORY.format(case="cases/gone.yaml"))
    assert out.returncode != 0 and "config 'history.cases[0]': cases/gone.yaml does not exist" in out.stderr
