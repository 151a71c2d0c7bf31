"""YADE's oblique driver (host side): many `ObliqueRun`s -> one `yade -n -x oblique.py job=...` -> dumps.

The head-on driver's machinery (engines/yade.py, engines/driven_sweep.py: one process per sweep, its
time limit, its log, a failed run's error) with the deck cases/decks/yade/oblique.py, which runs
Hertz-Mindlin with its tangential law (Ip2_FrictMat_FrictMat_MindlinPhys + Law2_ScGeom_MindlinPhys_Mindlin)
and records the 8 columns of `records.dump_file.OBLIQUE_COLUMNS` per step. What YADE does differently
from the study's contact (the sphere-wall R*, the lever arm, the averaged G and nu of two materials, the
elastic normal law only) is the deck's docstring's.
"""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path

import numpy as np

from records.collision_metrics import ExtractionError, collision_metrics
from records.dump_file import OBLIQUE_COLUMNS, write_dump
from records.files import file_sha256

from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep
from .oblique_record import deck_record
from .oblique_run import ObliqueJob, ObliqueRun

EXECUTABLE = "yade"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "yade" / "oblique.py"
#: The deck records 8 columns where the head-on one records 4: its steps cost about twice as much
#: (the time limit counts them so).
STEP_COST = 2


def _material(body, which: str) -> tuple[float, float]:
    if body.young is None or body.poisson is None:
        raise ValueError(f"an oblique YADE run needs {which}'s Young's modulus and Poisson's ratio (G* needs "
                         f"them); the case gives E* alone")
    if not math.isfinite(body.young):
        raise ValueError(f"YADE's Hertz-Mindlin cannot express a rigid {which} (Young's modulus inf): give it "
                         f"its own modulus")
    return body.young, body.poisson


def job_entry(spec: ObliqueJob, out: Path, stiffness_scale: float | None = None, wall_hertzian: bool = True) -> dict:
    """The numbers of one oblique run for the deck (SI); `stiffness_scale` (a check's knob, not a
    study run's): YADE's tangential stiffness k_so multiplied by it; `wall_hertzian` False (a check's
    knob too): YADE's default wall, Ig2_Wall_Sphere_ScGeom(hertzian=False), whose radius is the
    sphere's, R* = R/2 (the study's runs: True, R* = R)."""
    run = spec.run
    normal = run.normal
    p = normal.pair
    state = normal.initial_state()
    young1, poisson1 = _material(p.body_1, "body 1")
    young2, poisson2 = _material(p.body_2, "the plane" if p.body_2.is_plane else "body 2")
    turn = run.initial_velocities()
    # Two spheres' centres lie on the x axis when they touch (ObliqueRun.initial_positions).
    entry = {"name": run.name, "geometry": p.geometry, "law": normal.law, "out": str(out), **state,
             "young1": young1, "poisson1": poisson1, "young2": young2, "poisson2": poisson2,
             "friction": run.friction, "betas": run.damping_ratio, **turn, "y2": 0.0,
             **run.initial_positions(), "M": p.M}
    if stiffness_scale is not None:
        entry["kso_scale"] = stiffness_scale
    if not wall_hertzian:
        entry["wall_hertzian"] = False
    return entry


def _oblique_dump(engine, spec: ObliqueJob, entry, st, raw: Path, workdir: Path, log, version, driver: Path) -> Path:
    run = spec.run
    data = deck_record(engine, run, st, raw, log)
    if data.shape[0] < 3 or data.shape[1] != len(OBLIQUE_COLUMNS):
        raise EngineRunFailed(run.name, f"engine record {raw} has {data.shape[0]} rows of {data.shape[1]} columns",
                              log)
    if not np.all(np.isfinite(data)):
        row = int(np.nonzero(~np.all(np.isfinite(data), axis=1))[0][0])
        raise EngineRunFailed(run.name, f"the engine produced NaN or inf (record row {row + 1})", log)
    try:
        collision_metrics(*data[:, :4].T, impact_velocity=run.normal.velocity)
    except ExtractionError as err:
        raise EngineRunFailed(run.name, str(err), log)
    meta = {"engine": engine, "engine_version": version, "deck": driver.name, "deck_sha256": file_sha256(driver),
            "engine_variables": {k: v for k, v in entry.items() if k != "out"}}
    dump = workdir / f"{run.name}.csv"
    write_dump(dump, {**meta, **run.metadata()}, data)
    raw.unlink()
    return dump


def run_yade_oblique(runs: list[ObliqueRun], workdir, executable: str = EXECUTABLE,
                     timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, stiffness_scale: float | None = None,
                     wall_hertzian: bool = True) -> Sweep:
    """Run every oblique run in one YADE process; write `workdir/<run.name>.csv` (8 columns) for each.

    Raises EngineMissing if YADE is not installed, ValueError for a run YADE's deck cannot express
    (bodies without Young's modulus and Poisson's ratio, a rigid plane). A run that fails (a normal law
    other than `elastic`, no collision, NaN) is an EngineRunFailed in the returned `Sweep`; a YADE that
    stops fails the run in progress as `engines.yade.run_yade` does. `stiffness_scale` (for the checks
    that the deck's stiffness reaches the result): every run's k_so times it, the contact created before
    the bodies touch so that it holds from the first step (None: YADE's own, the contact created by
    the collider). `wall_hertzian` False (the check of YADE's default wall, R* = R/2): the plane's
    Ig2_Wall_Sphere_ScGeom without hertzian=True (pkg/dem/Ig2_Facet_Sphere_ScGeom.hpp:103).
    """
    exe = require_executable("yade", executable)
    specs = [ObliqueJob(r, STEP_COST) for r in runs]
    files = prepare_sweep("yade", specs, workdir, partial(job_entry, stiffness_scale=stiffness_scale,
                                                                     wall_hertzian=wall_hertzian))
    cmd = [exe, "-n", "-x", str(DRIVER), f"job={files.job}"]
    limit = time_limit("yade", specs, timeout_floor_s)
    done = run_logged(cmd, files.log, limit, cwd=files.workdir, env={"PYTHONUNBUFFERED": "1"})
    return collect_sweep("yade", "YADE", exe, specs, files, done, limit, DRIVER, make_dump=_oblique_dump)
