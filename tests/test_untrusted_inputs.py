"""The audit's "Trust 3", end to end through Snakemake: case and measurement files (and config
values naming them) are data. A device, a FIFO or a huge file is refused before it is read, a
measurement path leading outside the project is refused unread and the text of a file that is no
case or measurement file is never repeated, too few measurements are refused before any job, data
the viscoelastic model contradicts are flagged in the fit's log and summary, and no string of a
config value runs in a shell. The loaders' own tests: tests/test_case_file.py and
tests/test_calibration.py."""

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from engine_cases import require_engine
from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow

ROOT = Path(__file__).resolve().parents[1]
#: One build (Debian's LAMMPS): parsing the workflow asks each build for its version.
BUILDS = "builds=[{id: lammps-2021, code: lammps, executable: lmp}]"
#: A line of /etc/passwd, which no message may repeat.
PASSWD_LINE = re.compile(r"root:[^:\s]*:0:0:")


def snakemake(project: Path, *args, timeout=300):
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=project, capture_output=True, text=True,
                          timeout=timeout)


@pytest.fixture
def project(tmp_path, runs_workflow):
    require_engine("lmp", "lammps")
    return copy_workflow(tmp_path / "project")


@pytest.mark.parametrize("kind", ["/dev/zero", "fifo", "huge"])
def test_a_case_path_that_is_no_small_regular_file_stops_the_workflow_in_seconds(project, kind):
    """`cases=/dev/zero` was read whole (80 s, 20 GB of memory) before any check: now it is refused
    before a byte is read, as are a FIFO (which would block the read) and a 2 MB case file."""
    if kind == "/dev/zero":
        path, said = "/dev/zero", "is a character device, not a regular file"
    elif kind == "fifo":
        path, said = str(project / "cases" / "pipe.yaml"), "is a named pipe (FIFO), not a regular file"
        os.mkfifo(path)
    else:
        path, said = str(project / "cases" / "huge.yaml"), "is 2000000 bytes; a case file is a few hundred bytes"
        with open(path, "wb") as fh:
            fh.truncate(2_000_000)
    start = time.monotonic()
    out = snakemake(project, "-n", "all", "--config", f"cases={path}", BUILDS, "extras=[]", timeout=120)
    assert time.monotonic() - start < 60
    assert out.returncode != 0
    assert f"  {path}: field '(file)': {said}" in out.stderr, out.stderr[-3000:]
    assert "Traceback" not in out.stderr and not (project / "results").exists()


def test_config_values_with_injection_strings_are_file_patterns_never_commands(project, tmp_path):
    """The audit's strings as the `cases` pattern: each matches no file or names files that are
    refused (their text not repeated); no marker file appears, no result is written."""
    markers = tmp_path / "markers"
    values = [f"$(touch {markers}/dollar)", f"`touch {markers}/backtick`", f"; touch {markers}/semicolon",
              f"| touch {markers}/pipe", "*", "../../etc/passwd", "/etc/passwd"]
    for value in values:
        out = snakemake(project, "-n", "all", "--config", f"cases={value}", BUILDS, "extras=[]", timeout=120)
        assert out.returncode != 0, value
        said = out.stdout + out.stderr
        assert "Traceback" not in said and not PASSWD_LINE.search(said), said[-3000:]
        if value == "/etc/passwd":  # a file, but no case file: refused without its text
            assert ("/etc/passwd: field '(top level)': a case file must be a YAML mapping of fields, got one text of "
                    in said), said[-3000:]
        elif value == "*":  # the project's own files and folders: each refused, none repeated
            assert "Snakefile: field '(file)': not valid YAML at line " in said, said[-3000:]
            assert "config: field '(file)': is a directory, not a regular file" in said
            assert "configfile:" not in said and "rule all" not in said
        else:
            assert f"config 'cases': no case file matches '{value}'" in said, said[-3000:]
    assert not markers.exists()
    assert not (project / "results").exists()


def _measured(project: Path, name: str, csv: str | None, measurements: str | None = None) -> Path:
    folder = project / "cases" / "calibration"
    folder.mkdir(exist_ok=True)
    if csv is not None:
        (folder / f"{name}.csv").write_text(csv)
    case = folder / f"{name}.yaml"
    case.write_text("effective_modulus: 70 GPa\nradius: 5 mm\ndensity: 2700 kg/m^3\nviscosity: 5e4 P\n"
                    f"geometries: [sphere-plane]\nmeasurements: {measurements or name + '.csv'}\n")
    return case


def test_bad_measurements_stop_the_calibration_before_any_job_naming_each_file(project):
    """A measurement path to /etc/passwd (read, its first line echoed, before), a 2-row file
    (ZeroDivisionError in the fit, before) and a file that is no measurement file: every one named
    at once, with its field, before any job; no line of /etc/passwd in the output."""
    evil = _measured(project, "evil", None, "../../../../../../../../../../../../etc/passwd")
    two = _measured(project, "two", "velocity [m/s],restitution\n1,0.9\n2,0.88\n")
    stray = _measured(project, "stray", Path("/etc/passwd").read_text() if Path("/etc/passwd").exists()
                      else "root:x:0:0:root:/root:/bin/bash\n")
    out = snakemake(project, "-n", "calibration", "--config", BUILDS)
    said = out.stdout + out.stderr
    assert out.returncode != 0
    assert "3 of the calibration's case files this target needs cannot be used" in said, said[-3000:]
    assert (f"{evil.relative_to(project)}: field 'measurements': '../../../../../../../../../../../../etc/passwd' "
            f"leads outside the project folder {project.resolve()} (symlinks followed)") in said, said[-3000:]
    assert (f"{two.with_suffix('.csv').relative_to(project)}: (file): has 2 data row(s); the calibration needs at "
            "least 3 rows at 2 or more distinct velocities") in said
    assert (f"{stray.with_suffix('.csv').relative_to(project)}: header (line 1), column 1: not a column name "
            in said)
    assert not PASSWD_LINE.search(said) and "/bin/bash" not in said
    assert not (project / "results").exists()


def test_restitution_rising_with_velocity_is_flagged_in_the_fits_log_and_summary(project):
    """The fit job of data whose eps rises with V: it writes its eta, flagged not to be used, in
    fit.json, and its log warns."""
    _measured(project, "rising", "velocity [m/s],restitution,restitution_uncertainty\n0.5,0.795,0.005\n"
                                 "1,0.806,0.005\n2,0.827,0.005\n4,0.84,0.005\n6,0.86,0.005\n")
    out = snakemake(project, "-j1", "results/calibration/rising/fit.json", "--config", BUILDS, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    summary = json.loads((project / "results" / "calibration" / "rising" / "fit.json").read_text())
    assert summary["restitution_trend"]["rising"] and summary["restitution_trend"]["p_rising"] < 1e-3
    assert len(summary["warnings"]) == 1
    assert summary["warnings"][0].startswith("the measured eps rises with the impact velocity (slope +0.0255 ")
    log = (project / "logs" / "calibration" / "rising" / "fit.log").read_text()
    assert re.search(r"WARNING rising \(cases/calibration/rising\.csv\): do not use the eta above: the measured eps "
                     r"rises with the impact velocity", log), log
