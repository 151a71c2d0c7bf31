"""Kratos Multiphysics DEM driver (host side): many `RunSpec`s -> one Kratos Python process -> dumps.

Kratos 10.4 (PyPI ``KratosMultiphysics`` + ``KratosDEMApplication``, installed into
.venv-kratos/ by ``make kratos-10.4``) is a Python package, so a build's executable is the
Python interpreter of the environment that has it. One process runs a whole sweep: the driver
script cases/decks/kratos/collisions.py writes each run's Kratos inputs (no GiD) and runs a
`DEMAnalysisStage` on a fresh `Model` per run. Every number it uses is written into the job
file here, from `contact_model` (`contact_model.engine_parameters.kratos_hertz`).

The normal law is ``DEM_D_Hertz_viscous_Coulomb`` (Kratos source:
applications/DEMApplication/custom_constitutive/DEM_D_Hertz_viscous_Coulomb_CL.cpp, the
damping coefficient gamma from the restitution coefficient in
applications/DEMApplication/python_scripts/sphere_strategy.py, GammaForHertzThornton):

    F = max(0, (4/3) Y* sqrt(R*) delta^{3/2} + 2 gamma sqrt(M* kn) d(delta)/dt),
    kn = 2 Y* sqrt(R* delta)  [N/m],

a dissipative force proportional to delta^{1/4} d(delta)/dt. Every other Hertz-type normal law
of the 10.4 DEMApplication (DEM_D_Hertz_viscous_Coulomb_Nestle, _DMT, _JKR, DEM_D_Hertz_confined,
DEM_D_Conical_damage, DEM_D_Stress_Dependent_Cohesive) damps with the same 2 gamma sqrt(M* kn),
kn the law's own stiffness (DEM_D_*_CL.cpp, CalculateViscoDampingForce); none has the
viscoelastic delta^{1/2} d(delta)/dt force, and the dissipative force cannot be added from
Python inside the force loop. So the laws 'viscoelastic' and 'viscoelastic_clipped' are not
available (`engines.codes`); 'elastic' runs the law with restitution 1 (gamma = 0: Hertz alone,
gated) and 'default' with the matched restitution (clipped at zero: criterion F0, gated against its own
equation).

The process runs with OMP_NUM_THREADS=1 (a two-body problem; with more threads Kratos's OpenMP
loops spin and a run takes ten times longer) and PYTHONUNBUFFERED, its output streamed to
kratos.log under a time limit scaled to the sweep (engines/engine_process.py).

Time integration: Kratos's default Symplectic_Euler
(applications/DEMApplication/custom_strategies/schemes/symplectic_euler_scheme.cpp):
v_{n+1} = v_n + F(x_n) dt / m, x_{n+1} = x_n + v_{n+1} dt. After a step a node holds x_{n+1}
and the force F(x_n), so the driver pairs each position with the force computed from it, and
records the full-step rate d(delta)/dt (t_n) = r(t_n + dt/2) + F_n dt / (2 M*) [m/s].
"""

from __future__ import annotations

from pathlib import Path

from .codes import code, law_unavailable
from records.files import file_sha256

from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import require_executable
from .finish_run import Sweep
from .run_spec import RunSpec

#: The Kratos venv's interpreter (relative to the project; `make kratos-10.4`).
EXECUTABLE = str(Path(__file__).resolve().parents[1] / ".venv-kratos" / "bin" / "python")
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "kratos" / "collisions.py"
#: The environment of the Kratos process.
ENVIRONMENT = {"OMP_NUM_THREADS": "1", "PYTHONUNBUFFERED": "1"}


def driver_hash() -> str:
    return file_sha256(DRIVER)


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the Kratos driver (SI)."""
    if law_unavailable("kratos", spec.law):
        raise ValueError(f"kratos cannot run law {spec.law!r}: {law_unavailable('kratos', spec.law)}")
    p = spec.pair
    params = code("kratos").contact_parameters(p)
    # 'elastic': restitution 1 -> DAMPING_GAMMA = 0. 'default': the restitution the user asks for
    # (Kratos turns it into gamma with Thornton et al.'s fit).
    restitution = 1.0 if spec.law == "elastic" else spec.matched_restitution
    return {"name": spec.name, "geometry": p.geometry, "law": spec.law, "out": str(out), **spec.initial_state(),
            "M": p.M, "young": params["young"], "poisson": params["poisson"], "restitution": restitution}


def run_kratos(specs: list[RunSpec], workdir, executable: str = EXECUTABLE,
               timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run every spec in one Kratos process; write `workdir/<spec.name>.csv` for each.

    Raises EngineMissing if the executable is missing. A run that fails is an EngineRunFailed
    (naming the log) in the returned `Sweep`. If the Kratos process itself stops (an error, a
    crash, or its time limit: `engine_process.time_limit`, at least `timeout_floor_s`), the run
    in progress fails with the last log lines, the runs after it are not run, and the runs before
    it land if their records are complete.
    """
    exe = require_executable("kratos", executable)
    files = prepare_sweep("kratos", specs, workdir, job_entry)
    cmd = [exe, str(DRIVER), str(files.job)]
    limit = time_limit("kratos", specs, timeout_floor_s)
    done = run_logged(cmd, files.log, limit, cwd=files.workdir, env=ENVIRONMENT)
    return collect_sweep("kratos", "KratosMultiphysics", exe, specs, files, done, limit, DRIVER)

