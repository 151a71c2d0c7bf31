"""ESyS-Particle 2.3.5 `HertzMindlin` oblique collisions (host side): two rotational spheres, or a sphere
and the plane's stand-in sphere, friction, no damping, `mpirun -np 2 esysparticle oblique_hertz_mindlin.py
job` (cases/decks/esys/oblique_hertz_mindlin.py), a per-step record of both bodies' positions, velocities
and spins.

Two uses of the one deck:

- the study's oblique driver, `run_esys_oblique_sweep` (`engines.codes`: ``oblique_driver``): the
  study's `ObliqueRun`s of ``esys:hertz_mindlin`` -> dumps of the 8 columns of
  `records.dump_file.OBLIQUE_COLUMNS`, gated against the model's own equations (force history, k_t0 =
  (16/3) G of E*, elastic cap, no torque, no spin in the slip: `reference.TangentialForm` with the
  arms ``"none"``);
- the tangential-defect checks (`EsysObliqueRun`, `run_esys_oblique`, `stick_stiffness`,
  `spins_after`): HertzMindlin's missing torque and its tangential stiffness (16/3) G a, measured on
  the engine itself (tests/test_engine_tangential_defects.py).

The plane: ESyS has no Hertzian wall (engines/esys.py), so the plane is a non-dynamic sphere of radius
OBLIQUE_WALL_RATIO R, its E scaled by sqrt(R / R*_esys) (`contact_model.engine_parameters.
esys_plane_as_sphere`): the normal force 4/3 E sqrt(R*_esys) delta^{3/2} and the tangential stiffness
(16/3) E/(2(1 + nu)) sqrt(R*_esys delta) are then the plane's, both ~E sqrt(R*), at every overlap. What
remains of its curvature: while the sphere slides a distance s over it, the line of centres turns by
s/(R + R_wall), and the sphere is pulled towards the stand-in at v_t^2/(R + R_wall). The reference follows
that geometry (`analysis.oblique.reference_of`, the registry's `oblique_plane_ratio`): it matters at
grazing incidence, where the pull changes eps by ~ v_t^2 T/(R_wall v_n): 2.4e-6 for Chung & Ooi's test 5
at 85 deg (R = 10 um, v_t = 57 m/s; measured: eps -2.37e-6 against a flat plane's reference, -6.6e-9
against the stand-in's). A larger ratio would shrink it, at a price: the wall's centre sits at x = R_wall,
so ESyS's overlap R + R_wall - |x2 - x1| is rounded by ~u R_wall (u = 2^-53): 5.6e-13 m for alumina
(R = 2.5 mm), ~5e-7 of its maximum overlap at 85 deg, which is why the ratio stays at 1e6.

The deck's contact (Model/HertzMindlinInteraction.cpp:118-160 in the 2.3.5 source,
danielfrascarelli/esys-particle@ced39b6), with E the number given to ESyS and R* = R1 R2/(R1 + R2)::

    F_n = 4/3 E sqrt(R*) delta^{3/2}                 [N]
    F_t <- F_t + k_t0 sqrt(R* delta) ds,  k_t0 = (16/3) E / (2 (1 + nu))   [Pa]
    ds = (v2 - v1) dt minus its normal part           [m] (spins do not enter)
    |F_t| <= mu F_n (scaled back to the cap)

so the host writes E = E* (the normal force is then the study's Hertz force, as engines/esys.py does
for the `default` law) and the tangential stiffness constant comes out as (8/3) E*/(1 + nu), against
Mindlin's 8 G*: for two spheres of one material (Young's E_Y, nu) E* = E_Y/(2(1 - nu^2)) and
8 G* = 2 E_Y/((2 - nu)(1 + nu)), a ratio (2/3)(2 - nu)/(1 - nu^2) (1.246 at nu = 0.23).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from contact_model.engine_parameters import esys_plane_as_sphere
from contact_model.tangential_models import stiffness_constant
from records.dump_file import OBLIQUE_COLUMNS, write_dump
from records.files import file_sha256

from .codes import CODES
from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import EngineRunFailed, require_executable
from .esys import EXECUTABLE, MPIRUN, WALL_MASS_RATIO, mpirun_command
from .oblique_record import deck_record, read_oblique_record
from .oblique_run import ObliqueJob, ObliqueRun

DECK = Path(__file__).resolve().parents[1] / "cases" / "decks" / "esys" / "oblique_hertz_mindlin.py"
COLUMNS = ("x1", "y1", "x2", "y2", "vx1", "vy1", "vx2", "vy2", "wx1", "wy1", "wz1", "wx2", "wy2", "wz2")
#: Steps of free flight before the touch (the bodies start this many steps apart, plus a half step so
#: that no sample falls at touching).
APPROACH_STEPS = 10.5


class EsysObliqueRun:
    """One oblique collision of two solid spheres of one material in ESyS's HertzMindlin. SI units.

    Parameters
    ----------
    name : str
        The run's name (file names).
    radius, density : float
        Each sphere's radius [m] and density [kg/m^3].
    young, poisson : float
        Young's modulus [Pa] and Poisson's ratio [-] of both spheres.
    friction : float
        Coulomb's mu [-].
    speed, angle : float
        Body 1's speed [m/s] and its angle to the line of centres [deg]; body 2 is at rest.
    time_step_factor : float
        dt = T_e / factor, T_e = delta_e / v_n (the Hertz overlap scale over the normal velocity).
    """

    engine = "esys"
    case = "esys-hertz-mindlin"

    def __init__(self, name: str, radius: float, density: float, young: float, poisson: float, friction: float,
                 speed: float, angle: float, time_step_factor: float):
        for field, value in (("radius", radius), ("density", density), ("young", young), ("speed", speed),
                             ("time_step_factor", time_step_factor)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"ESyS oblique run {name!r}: {field} must be a finite number > 0, got {value!r}")
        if not (0 <= poisson < 0.5 and 0 <= friction < math.inf and 0 <= angle < 90):
            raise ValueError(f"ESyS oblique run {name!r}: poisson must be in [0, 0.5), friction >= 0 and finite, "
                             f"angle in [0, 90) deg; got {poisson!r}, {friction!r}, {angle!r}")
        self.name, self.radius, self.density = name, radius, density
        self.young, self.poisson, self.friction = young, poisson, friction
        self.speed, self.angle, self.time_step_factor = speed, angle, time_step_factor

    @property
    def mass(self) -> float:
        return 4.0 / 3.0 * math.pi * self.radius ** 3 * self.density

    @property
    def E_star(self) -> float:
        """E* = E/(2(1 - nu^2)) [Pa] of two bodies of one material."""
        return self.young / (2.0 * (1.0 - self.poisson ** 2))

    @property
    def G_star(self) -> float:
        """Mindlin's G* = G/(2(2 - nu)) [Pa], G = E/(2(1 + nu)), of two bodies of one material."""
        return self.young / (2.0 * (1.0 + self.poisson)) / (2.0 * (2.0 - self.poisson))

    @property
    def R_star(self) -> float:
        return self.radius / 2.0

    @property
    def v_n(self) -> float:
        return self.speed * math.cos(math.radians(self.angle))

    @property
    def v_t(self) -> float:
        return self.speed * math.sin(math.radians(self.angle))

    @property
    def time_step(self) -> float:
        """dt = T_e / factor [s], T_e = delta_e / v_n, delta_e = (15 M* v_n^2 / (16 E* sqrt(R*)))^{2/5}."""
        delta_e = (15.0 * (self.mass / 2.0) * self.v_n ** 2 / (16.0 * self.E_star * math.sqrt(self.R_star))) ** 0.4
        return delta_e / self.v_n / self.time_step_factor

    def steps(self) -> int:
        """The approach and about 4 T_e of contact (a Hertz contact lasts 3.22 T_e) and a margin."""
        return int(APPROACH_STEPS + 4.5 * self.time_step_factor)

    def esys_stiffness(self) -> float:
        """k_t0 = (16/3) E/(2(1 + nu)) [Pa] with E = E*, as HertzMindlinInteraction.cpp:137 computes it."""
        return 16.0 / 3.0 * self.E_star / (2.0 * (1.0 + self.poisson))


def job_entry(run: EsysObliqueRun, out: Path) -> dict:
    """The deck's numbers of one run (SI): E = E* (the normal force is Hertz's with the right E*)."""
    t0 = APPROACH_STEPS * run.time_step
    return {"name": run.name, "out": str(out), "R1": run.radius, "R2": run.radius, "m1": run.mass, "m2": run.mass,
            "E": run.E_star, "nu": run.poisson, "mu": run.friction, "dt": run.time_step, "steps": run.steps(),
            # the centres lie on the x axis when the spheres touch, t0 after the start
            "x1": -2.0 * run.radius - run.v_n * t0, "y1": -run.v_t * t0, "x2": 0.0,
            "vx1": run.v_n, "vy1": run.v_t}


def run_esys_oblique(runs: list[EsysObliqueRun], workdir, executable: str = EXECUTABLE, mpirun: str = MPIRUN,
                     timeout_s: float = 600.0) -> dict[str, dict[str, np.ndarray]]:
    """Run the collisions in one ESyS process; {run name: {column: values per step}}.

    Raises EngineMissing if esysparticle or mpirun is missing, EngineRunFailed (naming the log) if a
    run did not complete (an error in the deck, or ESyS stopped or killed at `timeout_s` [s]).
    """
    import json

    exe, mpi = require_executable("esys", executable), require_executable("esys", mpirun)
    files = prepare_sweep("esys", runs, workdir, job_entry)
    done = run_logged(mpirun_command(mpi, exe, DECK, str(files.job)), files.log, timeout_s, cwd=files.workdir,
                      env={"PYTHONUNBUFFERED": "1", "OMPI_MCA_mpi_yield_when_idle": "1"})
    status = json.loads(files.status.read_text()) if files.status.exists() else {"runs": {}}
    out = {}
    for run in runs:
        st = status["runs"].get(run.name)
        if done.returncode != 0 or not st or not st["ok"]:
            why = (st["error"] if st and not st["ok"] else
                   f"ESyS stopped at its time limit ({timeout_s:g} s)" if done.returncode is None else
                   f"ESyS ended with exit status {done.returncode}, no status for the run")
            raise EngineRunFailed(run.name, why, files.log, engine="esys", case=run.case)
        data = np.loadtxt(files.raws[run.name], delimiter=",", skiprows=1, ndmin=2)
        out[run.name] = {c: data[:, i] for i, c in enumerate(COLUMNS)}
    return out


def contact_forces(rec: dict, run: EsysObliqueRun) -> dict[str, np.ndarray]:
    """Per step n (in contact, all but the last row): the overlap delta_n [m], the unit normal n_n
    (from body 2 to body 1), the Hertz force F_n [N], the friction force on body 1 F_f [N] (a 2-vector:
    the total force m1 (v_{n+1} - v_n)/dt minus n_n F_n, symplectic Euler) and the tangential
    displacement increment ds_n = ((v2 - v1) dt)_tangential [m] the engine adds.

    Parameters
    ----------
    rec : dict
        `run_esys_oblique`'s record of `run`.
    run : EsysObliqueRun
    """
    dt = run.time_step
    d = np.stack([rec["x1"] - rec["x2"], rec["y1"] - rec["y2"]], axis=1)[:-1]
    dist = np.linalg.norm(d, axis=1)
    n = d / dist[:, None]
    delta = 2.0 * run.radius - dist
    inside = delta > 0
    F_n = 4.0 / 3.0 * run.E_star * math.sqrt(run.R_star) * np.clip(delta, 0.0, None) ** 1.5
    v1 = np.stack([rec["vx1"], rec["vy1"]], axis=1)
    v2 = np.stack([rec["vx2"], rec["vy2"]], axis=1)
    F_total = run.mass * np.diff(v1, axis=0) / dt
    F_f = F_total - n * F_n[:, None]
    ds = (v2 - v1)[:-1] * dt
    ds = ds - np.sum(ds * n, axis=1)[:, None] * n
    return {"delta": delta[inside], "n": n[inside], "F_n": F_n[inside], "F_f": F_f[inside], "ds": ds[inside]}


def stick_stiffness(rec: dict, run: EsysObliqueRun) -> np.ndarray:
    r"""The tangential stiffness constant the engine applied on each stick step [Pa]:

    .. math:: k_{t0} = \frac{(F_{f,n} - F_{f,n-1}) \cdot ds_n}{\sqrt{R^* \delta_n}\, |ds_n|^2}

    over the contact's steps n > first whose friction force is below the cap (|F_f| < mu F_n (1 - 1e-9)),
    the increment of HertzMindlin's incremental spring F_f += k_t0 sqrt(R* delta) ds.
    """
    c = contact_forces(rec, run)
    F_f, ds = c["F_f"], c["ds"]
    below = np.linalg.norm(F_f, axis=1) < run.friction * c["F_n"] * (1.0 - 1e-9)
    step = np.diff(F_f, axis=0)
    a = np.sqrt(run.R_star * c["delta"][1:])
    k = np.sum(step * ds[1:], axis=1) / (a * np.sum(ds[1:] ** 2, axis=1))
    return k[below[1:] & (np.sum(ds[1:] ** 2, axis=1) > 0)]


def slip_steps(rec: dict, run: EsysObliqueRun) -> tuple[int, int]:
    """(steps at the Coulomb cap, steps in contact) of a record."""
    c = contact_forces(rec, run)
    capped = np.linalg.norm(c["F_f"], axis=1) >= run.friction * c["F_n"] * (1.0 - 1e-9)
    return int(capped.sum()), len(capped)


def spins_after(rec: dict) -> float:
    """The largest |omega| component of either body over the whole record [rad/s]."""
    return float(max(np.max(np.abs(rec[c])) for c in ("wx1", "wy1", "wz1", "wx2", "wy2", "wz2")))


def tangential_impulse(rec: dict, run: EsysObliqueRun) -> float:
    """Body 1's change of y momentum over the record, m1 (v_y1,end - v_y1,start) [N s]."""
    return float(run.mass * (rec["vy1"][-1] - rec["vy1"][0]))


# --- the study's oblique driver -----------------------------------------------------------------------

#: The tangential models ESyS's oblique deck writes.
MODELS = ("esys:hertz_mindlin",)
#: R_wall / R of the plane's stand-in sphere in an oblique run (module docstring: its curvature, which the
#: reference follows, and its rounding), the code registry's one number (`engines.codes`).
OBLIQUE_WALL_RATIO = CODES["esys"].oblique_plane_ratio
#: A step of the oblique deck in head-on steps of ESyS's cost table: the state of both bodies (14
#: numbers) is fetched and formatted each step, where the head-on deck takes two (the time limit counts it).
STEP_COST = 2


def check_run(run: ObliqueRun) -> None:
    """Refuse, naming the run, an oblique run the ESyS deck cannot write: another engine's, another model,
    a normal law other than ``elastic`` (HertzMindlin has no normal damping), tangential damping, or two
    MPI ranks (ESyS's sweep is one master and one worker: its domain is not split).

    Raises
    ------
    ValueError
        Naming the run and what is wrong.
    """
    if run.normal.engine != "esys":
        raise ValueError(f"{run.name} is not an ESyS run (engine {run.normal.engine!r})")
    if run.model not in MODELS:
        raise ValueError(f"{run.name}: ESyS's oblique deck has no tangential model {run.model!r}; known: {MODELS}")
    if run.law != "elastic":
        raise ValueError(f"{run.name}: law {run.law!r}: ESyS's HertzMindlin has no normal damping, its oblique runs "
                         "are of the elastic law only")
    if run.damping_ratio:
        raise ValueError(f"{run.name}: HertzMindlin has no tangential damping (damping ratio {run.damping_ratio!r})")
    if run.ranks != 1:
        raise ValueError(f"{run.name}: ESyS's oblique sweep runs one worker (mpirun -np 2: a master and one "
                         f"worker); a processor boundary across the contact is not available (ranks {run.ranks})")


def deck_numbers(job: ObliqueJob) -> dict:
    """What the deck writes into HertzMindlinPrms (SI): E, nu and mu, with the sensitivity knobs.

    The deck writes E = E* (x the plane's `esys_plane_as_sphere` factor), so that the normal force is
    Hertz's; ESyS's k_t0 = (16/3) E/(2 (1 + nu)) (HertzMindlinInteraction.cpp:137) and nu enters nowhere
    else, so a `stiffness_factor` f is written as nu' = (1 + nu)/f - 1 (k_t0 x f, the normal force kept).
    """
    run = job.run
    p = run.pair
    nu = p.body_1.poisson
    stiffness_constant(run.model, p)  # refuses, naming the registry's field, bodies of two Poisson's ratios
    factor = esys_plane_as_sphere(p.body_1.radius, OBLIQUE_WALL_RATIO)["modulus_factor"] if p.body_2.is_plane \
        else 1.0
    return {"E": p.E * factor, "nu": (1.0 + nu) / job.stiffness_factor - 1.0, "mu": run.friction * job.friction_factor}


def study_entry(job: ObliqueJob, out: Path) -> dict:
    """The numbers of one study run for the deck (SI): the bodies, HertzMindlin's E, nu and mu
    (`deck_numbers`), the start (`engines.run_spec.RunSpec.initial_state`, `ObliqueRun.initial_velocities`
    and `initial_positions`: the centres on the x axis at touching), and for the plane its stand-in."""
    run = job.run
    p = run.pair
    state = run.normal.initial_state()
    v, y = run.initial_velocities(), run.initial_positions()
    # the farthest either body moves over the run [m]: the deck's Verlet distance exceeds it (no neighbour
    # rebuild inside the contact, which would reset HertzMindlin's friction force)
    speed = max(math.hypot(state["v1"], v["vy1"]), math.hypot(state.get("v2", 0.0), v["vy2"]))
    entry = {"name": run.name, "out": str(out), "R1": p.body_1.radius, "m1": p.body_1.mass, **deck_numbers(job),
             "dt": state["dt"], "steps": state["steps"], "x1": state["x1"], "y1": y["y1"], "vx1": state["v1"],
             "vy1": v["vy1"], "w1": v["w1"], "travel": speed * state["dt"] * state["steps"]}
    if p.body_2.is_plane:
        # the stand-in's surface at x = 0, where the plane is (RunSpec: the sphere touches x = 0)
        R_wall = esys_plane_as_sphere(p.body_1.radius, OBLIQUE_WALL_RATIO)["R_wall"]
        entry.update(R2=R_wall, m2=WALL_MASS_RATIO * p.body_1.mass, x2=R_wall, y2=0.0, vx2=0.0, vy2=0.0, fixed2=1)
    else:
        entry.update(R2=p.body_2.radius, m2=p.body_2.mass, x2=state["x2"], y2=y["y2"], vx2=state["v2"],
                     vy2=v["vy2"])
    return entry


def study_columns(rec: dict, R1: float, R2: float, m1: float, dt: float) -> np.ndarray:
    r"""The 8 columns of `records.dump_file.OBLIQUE_COLUMNS` from the deck's per-step state (pure).

    ESyS integrates with symplectic Euler (Model/Particle.cpp, CParticle::integrate): the force of step n
    is computed from x_n (and v_n), then v_{n+1} = v_n + F_n dt/m, x_{n+1} = x_n + v_{n+1} dt. Row n of the
    deck holds x_n and v_n before step n, so sample n (t_n = n dt) is::

        overlap        R1 + R2 - |r2 - r1|                         [m]
        normal_vel.    ((v1 - v2).x at n and n + 1) / 2            [m/s]   (the full-step rate)
        normal_force   -m1 (v1x_{n+1} - v1x_n)/dt                  [N]     (x force on body 2)
        tangential_v.  ((v1 - v2).y at n and n + 1) / 2            [m/s]
        omega_1, 2     (w_z at n and n + 1) / 2                    [rad/s]
        tang._force    m1 (v1y_{n+1} - v1y_n)/dt                   [N]     (y force on body 1)

    Parameters
    ----------
    rec : dict
        {column of `COLUMNS`: values per row} (steps + 1 rows).
    R1, R2 : float
        The radii [m] the deck gave (R2: the plane's stand-in's).
    m1 : float
        Body 1's mass [kg].
    dt : float
        The time step [s].

    Returns
    -------
    numpy.ndarray
        steps x 8.
    """
    x1, y1, x2, y2 = (np.asarray(rec[c], dtype=float) for c in ("x1", "y1", "x2", "y2"))
    overlap = R1 + R2 - np.hypot(x2 - x1, y2 - y1)
    rate = np.asarray(rec["vx1"]) - np.asarray(rec["vx2"])
    vt = np.asarray(rec["vy1"]) - np.asarray(rec["vy2"])

    def mid(a):
        a = np.asarray(a, dtype=float)
        return 0.5 * (a[:-1] + a[1:])

    n = len(overlap) - 1
    return np.column_stack([np.arange(n) * dt, overlap[:-1], mid(rate), -m1 * np.diff(rec["vx1"]) / dt, mid(vt),
                            mid(rec["wz1"]), mid(rec["wz2"]), m1 * np.diff(rec["vy1"]) / dt])


def _study_dump(engine, job: ObliqueJob, entry, st, raw: Path, workdir: Path, log, version, driver: Path) -> Path:
    """A landed run's dump: the deck's state rows -> the 8 columns (`study_columns`), checked as every
    oblique record is (`engines.oblique_record.read_oblique_record`), under the run's metadata."""
    run = job.run
    data = deck_record(engine, run, st, raw, log)
    if data.shape[0] < 4 or data.shape[1] != len(COLUMNS):
        raise EngineRunFailed(run.name, f"engine record {raw} has {data.shape[0]} rows of {data.shape[1]} columns, "
                              f"not {len(COLUMNS)}", log)
    columns = study_columns({c: data[:, i] for i, c in enumerate(COLUMNS)}, entry["R1"], entry["R2"], entry["m1"],
                            entry["dt"])
    table = raw.with_suffix(".columns")
    np.savetxt(table, columns, header=" ".join(OBLIQUE_COLUMNS), comments="", fmt="%.17g")
    data = read_oblique_record(table, run, log)
    k_t0 = stiffness_constant(run.model, run.pair)
    meta = {"engine": engine, "engine_version": version, "deck": driver.name, "deck_sha256": file_sha256(driver),
            "engine_variables": {k: v for k, v in entry.items() if k != "out"},
            "tangential_stiffness": job.stiffness_factor * k_t0, "tangential_stiffness_unit": "Pa (times a: N/m)",
            **run.metadata()}
    dump = workdir / f"{run.name}.csv"
    write_dump(dump, meta, data)
    raw.unlink()
    table.unlink()
    return dump


def run_esys_oblique_sweep(runs: list[ObliqueRun], workdir, executable: str = EXECUTABLE,
                           timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, mpirun: str = MPIRUN,
                           stiffness_factor: float = 1.0, friction_factor: float = 1.0,
                           verlet_distance: float | None = None):
    """Run the study's oblique ESyS collisions in one `mpirun -np 2 esysparticle` process; each landed
    run's dump is `workdir/<run.name>.csv` (8 columns, records.dump_file.OBLIQUE_COLUMNS, header
    `ObliqueRun.metadata()` and the engine's).

    Parameters
    ----------
    runs : list of ObliqueRun
        The collisions (names unique), each of ``esys:hertz_mindlin``, the elastic law, one rank.
    workdir : str or os.PathLike
        Where the job, the log and the dumps go.
    executable, mpirun : str
        ESyS's interpreter and the MPI launcher.
    timeout_floor_s : float
        The least time limit of the process [s] (`engines.engine_process.time_limit`).
    stiffness_factor : float
        k_t0 is multiplied by it in the generated deck (through nu, `deck_numbers`; 1: ESyS's own; a
        sensitivity check).
    friction_factor : float
        mu is multiplied by it in the generated deck (1: the case's own; a sensitivity check).
    verlet_distance : float, optional
        ESyS's Verlet distance [m] (a check's knob: the neighbour rebuild that resets HertzMindlin's
        friction force); None: twice the farthest a body travels in a run, so that no rebuild falls
        inside a contact.

    Returns
    -------
    engines.finish_run.Sweep

    Raises
    ------
    ValueError
        Before ESyS starts, for a run the deck cannot write (`check_run`).
    EngineMissing
        Where esysparticle or mpirun is not installed.
    """
    for run in runs:
        check_run(run)
    exe, mpi = require_executable("esys", executable), require_executable("esys", mpirun)
    jobs = [ObliqueJob(r, STEP_COST, stiffness_factor, friction_factor) for r in runs]
    entry = study_entry if verlet_distance is None else (
        lambda job, out: {**study_entry(job, out), "verlet": float(verlet_distance)})
    files = prepare_sweep("esys", jobs, workdir, entry)
    limit = time_limit("esys", jobs, timeout_floor_s)
    # Open MPI's ranks spin while they wait: yielding lets another engine job use the core (engines/esys.py).
    done = run_logged(mpirun_command(mpi, exe, DECK, str(files.job)), files.log, limit, cwd=files.workdir,
                      env={"PYTHONUNBUFFERED": "1", "OMPI_MCA_mpi_yield_when_idle": "1"})
    return collect_sweep("esys", "ESyS-Particle", exe, jobs, files, done, limit, DECK, make_dump=_study_dump)
