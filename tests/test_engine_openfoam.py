"""OpenFOAM v1912 (Debian's openfoam, `make openfoam`) as a code of the study, run for real.

The study's own driver (engines/openfoam.py: the case template, blockMesh and
icoUncoupledKinematicParcelFoam, the conversion to the study's dump) runs two ladders of the study's
plan (`engines.plan.plan_runs`, steel, K = 0.1): the law ``default`` (keyword ``openfoam:alpha``,
told alpha(e) for the viscoelastic reference eps at K = 0.1) between two spheres, and ``elastic``
(alpha = 0) on the plane. Their dumps go through the study's own gate (`analysis.comparison`,
`analysis.extrapolation`, `verdict.gate`) at the study's tolerances (1e-6 relative on T, A and eps,
|error| + resolution): PASS, every check. Measured here (2 shared cores): 7 runs, 6 184 steps in 57 s
wall, 12.4 s of OpenFOAM's CPU (2.0 ms a step) at load 7, its cases on a tmpfs; 523 s wall and 104 s
of CPU at load 14 with its cases on the disk, as before (the fixture prints wall and CPU); errors of
the limits (resolution): keyword T 1.6e-9 (2.9e-7), A 6.4e-9 (2.5e-7), eps 7.2e-9 (1e-8); elastic
T 2.1e-10 (1e-8), A 1.7e-10 (2.4e-8), eps 9.2e-10 (1e-8).

The cases run in a scratch folder of the sweep's own on a tmpfs (`openfoam.scratch_folder`); the
same run on the disk (no tmpfs: the work folder) writes the same dump, byte for byte.

Its failure paths: a law OpenFOAM cannot express and a run name that is no plain file name are
refused before anything starts (nothing outside the work folder removed); a run whose solver fails
(a case template with a broken dictionary) or that reaches its time limit fails alone, naming its
log, and leaves no dump and no scratch folder (in /dev/shm or the work folder).
"""

from __future__ import annotations

import hashlib
import os
import resource
import time
from pathlib import Path

import pandas as pd
import pytest

from analysis.comparison import comparison_rows
from analysis.extrapolation import extrapolated_rows
from contact_model import load_case
from contact_model.keywords import KEYWORDS, promised_restitution
from engine_cases import OPTIONAL_VERSIONS, missing, steel_pair
from engines import EngineRunFailed, RunSpec, openfoam
from engines.builds import Build, check_build
from engines.codes import CODES
from engines.plan import plan_runs
from records.collision_metrics import collision_metrics
from records.dump_file import read_dump
from verdict.gate import gate_checks, verdict_of

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = {"T": 1e-6, "A": 1e-6, "eps": 1e-6}  # config/config.yaml `tolerance:`
BUILD = Build("openfoam-v1912", "openfoam", openfoam.SOLVER)


def require_openfoam():
    import shutil

    if shutil.which(openfoam.SOLVER) is None or shutil.which("blockMesh") is None:
        missing(f"{openfoam.SOLVER} is not installed; {CODES['openfoam'].install_hint}")


@pytest.fixture(scope="module")
def ladders(tmp_path_factory, runs_engine):
    """The keyword's ladder between two spheres and elastic's on the plane, run by the study's
    driver in one sweep; {run name: (spec, dump)}, and the sweep's seconds per run."""
    require_openfoam()
    plan = plan_runs(load_case(ROOT / "cases" / "steel.yaml"), [BUILD], laws=["elastic", "default"], K_grid=[0.1])
    specs = [s for s in plan.runs if (s.law, s.pair.geometry) in {("default", "sphere-sphere"),
                                                                   ("elastic", "sphere-plane")}]
    assert len({s.ladder for s in specs}) == 2 and len(specs) == 7  # 4 keyword rungs, 3 elastic
    started, cpu = time.monotonic(), resource.getrusage(resource.RUSAGE_CHILDREN)
    sweep = openfoam.run_openfoam(specs, tmp_path_factory.mktemp("openfoam")).raise_first()
    seconds = time.monotonic() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)  # OpenFOAM's own CPU: what an idle machine pays
    cpu_s = after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime
    steps = sum(s.steps() for s in specs)
    print(f"openfoam: {len(specs)} runs, {steps} steps in {seconds:.1f} s wall ({1e3 * seconds / steps:.1f} ms/step), "
          f"{cpu_s:.1f} s CPU ({1e3 * cpu_s / steps:.2f} ms/step), load {os.getloadavg()[0]:.1f}")
    return {s.name: (s, sweep.dumps[s.name]) for s in specs}


def gated(ladders) -> tuple[pd.DataFrame, dict]:
    """The study's gate over the ladders' dumps: its checks and verdict (as workflow/scripts does)."""
    rows = []
    for name, (spec, dump) in ladders.items():
        meta, c = read_dump(dump)
        m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"], spec.velocity)
        rows += [{**row, "run": name, "dump": str(dump)} for row in comparison_rows(meta, m, spec.reference)]
    table = pd.DataFrame(rows)
    table = pd.concat([table, extrapolated_rows(table)], ignore_index=True)
    planned = pd.DataFrame([{"case": s.case, "name": s.name, "engine": s.engine, "build": s.build, "law": s.law,
                             "geometry": s.pair.geometry, "represents": list(s.represents), "ladder": s.ladder}
                            for s, _ in ladders.values()])
    checks = gate_checks(table, planned, pd.DataFrame(), TOLERANCE)
    return checks, verdict_of(checks, "0" * 64, TOLERANCE)


def test_both_ladders_pass_the_studys_gate(ladders):
    checks, verdict = gated(ladders)
    print(checks[["law", "geometry", "criterion", "quantity", "max_rel_error", "resolution", "pass"]].to_string())
    assert verdict["verdict"] == "PASS" and verdict["failed"] == 0, checks.to_string()
    assert set(checks.law) == {"elastic", "default"} and len(checks) == 6  # T, A, eps of each (x0)
    for r in checks.itertuples():
        assert abs(r.max_rel_error) + r.resolution <= TOLERANCE[r.quantity], r


def test_the_dumps_say_what_ran(ladders):
    """The keyword's rungs ran alpha(e) = sqrt(5) |beta(e)| (its own equation restitutes e, exactly),
    elastic's alpha = 0; the version is OpenFOAM's Build line, the force free of -0.0 outside contact."""
    for spec, dump in ladders.values():
        meta, c = read_dump(dump)
        assert meta["engine"] == "openfoam" and meta["engine_version"].startswith("OpenFOAM OPENFOAM=1912")
        alpha = meta["engine_variables"]["alpha"]
        if spec.law == "elastic":
            assert alpha == 0.0 and meta["represents"] == ["x0"]
        else:
            e = spec.matched_restitution
            assert alpha == KEYWORDS["openfoam:alpha"].told_for(e)
            assert promised_restitution("openfoam:alpha", e) == pytest.approx(e, abs=1e-14)
        assert (c["normal_force"][c["overlap"] < 0] == 0).all()


def test_the_build_reports_openfoams_version():
    require_openfoam()
    assert check_build(BUILD) == OPTIONAL_VERSIONS[BUILD.id]


def test_laws_openfoam_cannot_express_and_unsafe_names_are_refused_before_it_starts(tmp_path):
    spec = RunSpec("steel", "openfoam", "viscoelastic", steel_pair("sphere-plane"), 1.0)
    with pytest.raises(ValueError, match=r"openfoam cannot run law 'viscoelastic': .*delta\^\(1/4\)"):
        openfoam.run_openfoam([spec], tmp_path)
    assert openfoam.name_problem("../victim") and openfoam.name_problem("a/b") and not openfoam.name_problem("x-1.5")
    victim = tmp_path / "victim"
    victim.mkdir()
    with pytest.raises(ValueError, match="not inside"):
        openfoam.remove_case(victim, tmp_path / "work")
    assert victim.exists() and not list((tmp_path).glob("*.case"))


def test_a_solver_that_fails_fails_that_run_alone_and_names_its_log(tmp_path, monkeypatch, runs_engine):
    """A template with a broken dictionary (no `deltaT`): OpenFOAM's solver exits with its FATAL
    ERROR; the run fails naming its log (which keeps the error), no dump, no case folder left."""
    require_openfoam()
    broken = tmp_path / "decks"
    broken.mkdir()
    for name in openfoam.TEMPLATE_FILES:
        text = (openfoam.DECKS / name).read_text()
        (broken / name).write_text(text.replace("deltaT          ${dt};", "") if name == "controlDict" else text)
    monkeypatch.setattr(openfoam, "DECKS", broken)
    spec = RunSpec("steel", "openfoam", "elastic", steel_pair("sphere-plane"), 1.0, time_step_factor=125)
    work = tmp_path / "work"
    sweep = openfoam.run_openfoam([spec], work)
    with pytest.raises(EngineRunFailed, match=r"exited with status 1") as failed:
        sweep.raise_first()
    assert "deltaT" in Path(failed.value.log_path).read_text()
    assert not (work / f"{spec.name}.csv").exists() and not (work / f"{spec.name}.case").exists()
    assert_no_scratch_left(Path(failed.value.log_path), work)


def own_scratch_folders() -> list[Path]:
    """The scratch folders of this process's sweeps still in the tmpfs (their names carry its pid)."""
    return [p for parent in openfoam.SCRATCH_PARENTS
            for p in parent.glob(f"{openfoam.SCRATCH_PREFIX}{os.getpid()}-*")]


def assert_no_scratch_left(log: Path, work: Path) -> None:
    """The run's log names its case folder in the tmpfs; that folder's scratch folder is gone, and no
    other of this process's is left there or in the work folder."""
    note = log.read_text().splitlines()[-1]
    assert note.startswith("hertz study: case folder ") and "(tmpfs /dev/shm)" in note, note
    case = Path(note.split()[4])
    assert case.parent.parent == Path("/dev/shm") and case.parent.name.startswith(openfoam.SCRATCH_PREFIX)
    assert not case.parent.exists() and not own_scratch_folders()
    assert not list(work.glob(f"{openfoam.SCRATCH_PREFIX}*"))


def test_a_run_stopped_at_its_time_limit_fails_alone_and_leaves_no_scratch(tmp_path, monkeypatch, runs_engine):
    """A limit of 0.2 s (the module's `time_limit`, replaced: the real limit of a run is a minute or
    more): blockMesh or the solver is killed, the run fails saying so, naming its log; nothing stays."""
    require_openfoam()
    monkeypatch.setattr(openfoam, "time_limit", lambda *args: 0.2)
    spec = RunSpec("steel", "openfoam", "elastic", steel_pair("sphere-plane"), 1.0, time_step_factor=125)
    work = tmp_path / "work"
    sweep = openfoam.run_openfoam([spec], work)
    with pytest.raises(EngineRunFailed, match=r"did not finish within its time limit of 0.2 s") as failed:
        sweep.raise_first()
    assert not (work / f"{spec.name}.csv").exists()
    assert_no_scratch_left(Path(failed.value.log_path), work)


def test_the_scratch_folder_goes_on_an_error_and_falls_back_to_the_work_folder(tmp_path, monkeypatch):
    """`scratch_folder` makes its own folder (mode 0700) in the tmpfs, else in the work folder when no
    tmpfs is writable or has the room asked, and removes it, its contents too, when the block raises."""
    with pytest.raises(RuntimeError, match="in the middle"):
        with openfoam.scratch_folder(tmp_path) as (scratch, where):
            assert where == "tmpfs /dev/shm" and scratch.parent == Path("/dev/shm")
            assert scratch.stat().st_mode & 0o777 == 0o700
            (scratch / "a.case" / "0").mkdir(parents=True)
            raise RuntimeError("in the middle")
    assert not scratch.exists()
    with openfoam.scratch_folder(tmp_path, need_bytes=10**18) as (scratch, where):  # no tmpfs holds an exabyte
        assert where == "work folder" and scratch.parent == tmp_path
    assert not scratch.exists()
    monkeypatch.setattr(openfoam, "SCRATCH_PARENTS", (tmp_path / "no-tmpfs",))
    with openfoam.scratch_folder(tmp_path) as (scratch, where):
        assert where == "work folder" and scratch.parent == tmp_path
    assert not scratch.exists() and list(tmp_path.iterdir()) == []


def test_a_run_on_the_disk_writes_the_same_dump_byte_for_byte(ladders, tmp_path, monkeypatch):
    """The plane's shortest rung again with no tmpfs (its cases in the work folder, on the disk, as
    before the scratch folder): its dump is the tmpfs run's, byte for byte (sha256)."""
    spec, dump = min((v for v in ladders.values() if v[0].pair.geometry == "sphere-plane"),
                     key=lambda v: v[0].steps())
    monkeypatch.setattr(openfoam, "SCRATCH_PARENTS", ())
    work = tmp_path / "disk"
    on_disk = openfoam.run_openfoam([spec], work).raise_first().dumps[spec.name]
    assert "(work folder)" in (work / f"{spec.name}.openfoam.log").read_text()
    assert hashlib.sha256(on_disk.read_bytes()).hexdigest() == hashlib.sha256(dump.read_bytes()).hexdigest()
    assert sorted(work.iterdir()) == sorted([on_disk, work / f"{spec.name}.openfoam.log"])  # no scratch left
