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
gated) and 'default' with the matched restitution (clipped at zero: criterion F0, compared).

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

import hashlib
import json
import re
from pathlib import Path

from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, describe_exit, log_tail, run_logged, stop_message, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep, load_record, write_run_dump
from .run_spec import RunSpec

#: The Kratos venv's interpreter (relative to the project; `make kratos-10.4`).
EXECUTABLE = str(Path(__file__).resolve().parents[1] / ".venv-kratos" / "bin" / "python")
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "kratos" / "collisions.py"
#: The environment of the Kratos process.
ENVIRONMENT = {"OMP_NUM_THREADS": "1", "PYTHONUNBUFFERED": "1"}


def driver_hash() -> str:
    return hashlib.sha256(DRIVER.read_bytes()).hexdigest()


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the Kratos driver (SI)."""
    if spec.law not in ("elastic", "default"):
        raise ValueError(f"kratos cannot run law {spec.law!r}: see engines.codes")
    p = spec.pair
    params = p.engine_parameters("kratos")
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
    if any(s.engine != "kratos" for s in specs):
        raise ValueError("run_kratos got runs for another engine")
    if len({s.name for s in specs}) != len(specs):
        raise ValueError("run_kratos got two runs with the same name")
    exe = require_executable("kratos", executable)
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    log = workdir / "kratos.log"
    status_path = workdir / "kratos-status.json"
    status_path.unlink(missing_ok=True)
    raws = {s.name: workdir / f"{s.name}.kratos.csv" for s in specs}
    for s in specs:
        (workdir / f"{s.name}.csv").unlink(missing_ok=True)
        raws[s.name].unlink(missing_ok=True)
    job = {"runs": [job_entry(s, raws[s.name]) for s in specs], "status": str(status_path)}
    job_path = workdir / "kratos-job.json"
    job_path.write_text(json.dumps(job, indent=1))
    cmd = [exe, str(DRIVER), str(job_path)]
    sweep = Sweep()
    limit = time_limit("kratos", specs, timeout_floor_s)
    done = run_logged(cmd, log, limit, cwd=workdir, env=ENVIRONMENT)
    sweep.engine_seconds = done.seconds
    printed = log.read_text(errors="replace") if log.exists() else ""
    status = json.loads(status_path.read_text()) if status_path.exists() else None
    stop = None
    if done.timed_out:
        stop = f"did not finish within its time limit of {limit:.3g} s and was killed"
    elif done.returncode != 0 or status is None:
        stop = f"exited with {describe_exit(done.returncode)}" + ("" if status else " before writing its status")
    build = re.search(r"^KratosMultiphysics .*$", printed, flags=re.M)
    build = build.group(0).strip() if build else None
    version = status["engine_version"] if status else build or "KratosMultiphysics (version not printed)"
    started = re.findall(r"^RUN (\S+)$", printed, flags=re.M)
    stopped_in = (started[-1] if started else specs[0].name) if stop else None
    reached_stop = False
    for spec, entry in zip(specs, job["runs"]):
        if spec.name == stopped_in:
            reached_stop = True
            problem = stop_message("kratos", f"{build or 'no version line printed'}; {exe}", spec.case, spec.name,
                                   stop, log)
            sweep.failures[spec.name] = EngineRunFailed(spec.name, problem, log, engine="kratos", case=spec.case,
                                                        log_tail=log_tail(log))
            continue
        if reached_stop:
            sweep.failures[spec.name] = EngineRunFailed(spec.name, f"not run: kratos stopped in {stopped_in}", log)
            continue
        if status is not None:
            st = status["runs"].get(spec.name, {"ok": False, "error": "no status reported"})
        else:  # Kratos stopped later: this run finished, and wrote its record unless it failed
            failed = re.search(rf"^RUN FAILED {re.escape(spec.name)}: (.*)$", printed, flags=re.M)
            st = {"ok": False, "error": failed.group(1)} if failed else {"ok": True}
        sweep.finish(spec, lambda: _kratos_dump(spec, entry, st, raws[spec.name], workdir, log, version))
    return sweep


def _kratos_dump(spec, entry, st, raw, workdir, log, version) -> Path:
    if not st["ok"]:
        raise EngineRunFailed(spec.name, f"kratos: {st['error']}", log)
    data = load_record(spec, raw, log)
    meta = {"engine": "kratos", "engine_version": version, "deck": DRIVER.name,
            "deck_sha256": driver_hash(), "engine_variables": {k: v for k, v in entry.items() if k != "out"}}
    dump = write_run_dump(spec, data, workdir / f"{spec.name}.csv", log, meta)
    raw.unlink()
    return dump
