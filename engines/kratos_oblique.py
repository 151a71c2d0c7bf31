"""Kratos DEM 10.4 oblique collisions (host side): many `ObliqueRun`s -> one Kratos Python process
(cases/decks/kratos/oblique.py) -> dumps of the 8 columns of `records.dump_file.OBLIQUE_COLUMNS`.

The head-on driver's machinery (engines/kratos.py, engines/driven_sweep.py: one process per sweep,
OMP_NUM_THREADS=1, its time limit, its log, a failed run's error) with the oblique deck, which runs
``DEM_D_Hertz_viscous_Coulomb`` (contact_model/tangential_models.yaml, ``kratos:hertz_viscous_coulomb``)
with rotation and Coulomb friction:

- normal: F_n = (4/3) E* sqrt(R*) delta^{3/2} [N], E* from each body's own Young's modulus and Poisson's
  ratio (the head-on driver's Y = 2 E*, nu = 0 gives the same E* but G* = E*/4, not the bodies' G*, which
  the tangential stiffness needs). R* = R1 R2/(R1 + R2), or R at the wall. Restitution 1: DAMPING_GAMMA
  = 0, so no normal and no tangential dashpot (the oblique cases are elastic, `viscosity: 0 P`; every
  other normal law is refused, `check_run`);
- tangential: the incremental force F_t <- F_t sqrt(delta/delta_prev) (where delta fell) - k_t du_t,
  k_t = 8 G* a, a = sqrt(R* delta), G* = 1/((2 - nu1)/G1 + (2 - nu2)/G2) (Kratos's and
  `contact_model.effective.effective_shear_modulus`'s), capped at mu F_n (F_n clipped at zero);
  STATIC_FRICTION = DYNAMIC_FRICTION = mu, so the friction decay exp(-c |v_s|) multiplies zero.

Restitution 1 is no damping: the sphere strategy sets DAMPING_GAMMA = GammaForHertzThornton(e), which
returns 0 for e > 0.999 (KratosDEMApplication 10.4.4 wheel, DEMApplication/sphere_strategy.py:617-622,
850), and the law's dashpots are 2 gamma sqrt(M* k_n) and 2 gamma sqrt(M* k_t)
(DEM_D_Hertz_viscous_Coulomb_CL.cpp, CalculateViscoDampingForce).

A Kratos sphere-plane contact is a sphere against one RigidFace3D3N triangle of the FEM model part
(the head-on deck's wall), with the plane's own Young's modulus and Poisson's ratio. The lever arms
(decided by running, tests/test_engine_kratos_oblique.py): R - delta at the wall, for the torque and
the slip; between spheres R_i - delta E_j/(E_i + E_j) (spheric_particle.cpp, ComputeMoments).

The tangential increment du_t is the contact point's displacement over the step before the force
(symplectic Euler), so the tangential results converge at first order in dt: the five rungs of
config ``oblique.ladder`` resolve the sticking impacts, four do not (docs/tangential.md, "Kratos").

Kratos's DEM runs in one process here (its MPI build is not the PyPI one): no two-rank runs
(`check_run` refuses them; config ``oblique.ranks`` lists none for kratos).
"""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path

from contact_model.effective import effective_shear_modulus
from records.dump_file import write_dump
from records.files import file_sha256

from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep
from .kratos import ENVIRONMENT, EXECUTABLE
from .oblique_record import read_oblique_record
from .oblique_run import ObliqueJob, ObliqueRun

DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "kratos" / "oblique.py"
#: The head-on deck the oblique one runs for its functions (its hash is part of the oblique dump's).
HEAD_ON_DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "kratos" / "collisions.py"
MODELS = ("kratos:hertz_viscous_coulomb",)
#: A step of the oblique deck in head-on steps of the cost table (engines.codes: 500 us): Kratos's
#: stock solution loop with rotation, and a record of both bodies' 9 values read through
#: GetSolutionStepValue (the head-on deck's fast loop records the normal columns only). Measured: the
#: reduced set's 20 runs (156 005 steps) in 107-122 s on the 2 shared cores, 0.69-0.78 ms a step.
STEP_COST = 3


def _material(body, which: str) -> tuple[float, float]:
    if body.young is None or body.poisson is None:
        raise ValueError(f"an oblique Kratos run needs {which}'s Young's modulus and Poisson's ratio (G* needs "
                         "them); the case gives E* alone")
    if not math.isfinite(body.young):
        raise ValueError(f"Kratos's DEM_D_Hertz_viscous_Coulomb cannot express a rigid {which} (Young's modulus "
                         "inf): give it its own modulus")
    return body.young, body.poisson


def check_run(run: ObliqueRun) -> None:
    """Refuse, before any engine starts, a run the deck cannot write: another code's model, another
    engine's run, a normal law other than 'elastic' (Kratos damps with delta^{1/4} d(delta)/dt, not the
    study's law: engines/kratos.py), a tangential damping ratio, or two MPI ranks."""
    if run.model not in MODELS:
        raise ValueError(f"{run.name}: Kratos's oblique deck has no tangential model {run.model!r}; known: {MODELS}")
    if run.normal.engine != "kratos":
        raise ValueError(f"{run.name} is not a Kratos run (engine {run.normal.engine!r})")
    if run.law != "elastic":
        raise ValueError(f"{run.name}: Kratos's oblique deck runs the elastic normal law only (restitution 1), "
                         f"not {run.law!r}")
    if run.damping_ratio:
        raise ValueError(f"{run.name}: Kratos's tangential dashpot follows its restitution (2 gamma sqrt(M* k_t)); "
                         f"an elastic run has none, so damping ratio {run.damping_ratio!r} cannot be told")
    if run.ranks != 1:
        raise ValueError(f"{run.name}: the Kratos DEM of PyPI runs on one process; {run.ranks} ranks cannot be run")


def job_entry(job: ObliqueJob, out: Path, friction_factor: float = 1.0) -> dict:
    """The numbers of one oblique run for the deck (SI). `friction_factor` (a check's knob, not a
    study run's): mu told to Kratos multiplied by it."""
    run = job.run
    check_run(run)
    p = run.pair
    young1, poisson1 = _material(p.body_1, "body 1")
    young2, poisson2 = _material(p.body_2, "the plane" if p.body_2.is_plane else "body 2")
    return {"name": run.name, "geometry": p.geometry, "law": run.law, "out": str(out), **run.normal.initial_state(),
            "M": p.M, "young1": young1, "poisson1": poisson1, "young2": young2, "poisson2": poisson2,
            "restitution": 1.0, "friction": friction_factor * run.friction, "y2": 0.0,
            **run.initial_velocities(), **run.initial_positions()}


def _oblique_dump(engine, job: ObliqueJob, entry, st, raw: Path, workdir: Path, log, version, driver: Path) -> Path:
    run = job.run
    if not st["ok"]:
        raise EngineRunFailed(run.name, f"{engine}: {st['error']}", log)
    data = read_oblique_record(raw, run, log)
    meta = {"engine": engine, "engine_version": version, "deck": driver.name, "deck_sha256": file_sha256(driver),
            "head_on_deck_sha256": file_sha256(HEAD_ON_DRIVER),
            "engine_variables": {k: v for k, v in entry.items() if k != "out"},
            "tangential_stiffness": 8.0 * effective_shear_modulus(run.pair.body_1, run.pair.body_2),
            "tangential_stiffness_unit": "Pa (times a: N/m)"}
    dump = workdir / f"{run.name}.csv"
    write_dump(dump, {**meta, **run.metadata()}, data)
    raw.unlink()
    return dump


def run_kratos_oblique(runs: list[ObliqueRun], workdir, executable: str = EXECUTABLE,
                       timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, friction_factor: float = 1.0) -> Sweep:
    """Run every oblique run in one Kratos process; write `workdir/<run.name>.csv` (8 columns) for each.

    Parameters
    ----------
    runs : list of ObliqueRun
        The collisions (names unique), each of model ``kratos:hertz_viscous_coulomb``, law 'elastic',
        one rank.
    workdir : str or os.PathLike
        Where the job file, the log and the dumps go.
    executable : str
        The Python of the Kratos environment.
    timeout_floor_s : float
        The least time limit of the Kratos process [s].
    friction_factor : float
        mu told to Kratos is multiplied by it (1: the case's own; a sensitivity check).

    Raises
    ------
    EngineMissing
        Where the executable is missing.
    ValueError
        Before any engine starts, for a run `check_run` refuses or bodies without Young's modulus and
        Poisson's ratio. A run that fails in Kratos is an EngineRunFailed in the returned `Sweep`.
    """
    for run in runs:
        check_run(run)
    exe = require_executable("kratos", executable)
    specs = [ObliqueJob(r, STEP_COST, friction_factor=friction_factor) for r in runs]
    files = prepare_sweep("kratos", specs, workdir, partial(job_entry, friction_factor=friction_factor))
    cmd = [exe, str(DRIVER), str(files.job)]
    limit = time_limit("kratos", specs, timeout_floor_s)
    done = run_logged(cmd, files.log, limit, cwd=files.workdir, env=ENVIRONMENT)
    return collect_sweep("kratos", "KratosMultiphysics", exe, specs, files, done, limit, DRIVER,
                         make_dump=_oblique_dump)
