"""ESyS-Particle 2.3.5 `HertzMindlin` oblique collisions (host side), for the tangential-defect checks:
two rotational spheres, friction, no damping, `mpirun -np 2 esysparticle oblique_hertz_mindlin.py job`
(cases/decks/esys/oblique_hertz_mindlin.py), a per-step record of both bodies' positions, velocities
and spins; and what the record says (`stick_stiffness`, `spins_after`).

Not a study driver: the study does not gate ESyS oblique (it has no oblique ladder for it); this
runs the two suspected defects of docs/tangential.md, HertzMindlin's missing torque and its
tangential stiffness (16/3) G a, on the engine itself.

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

from .driven_sweep import prepare_sweep
from .engine_process import run_logged
from .errors import EngineRunFailed, require_executable
from .esys import EXECUTABLE, MPIRUN, mpirun_command

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
