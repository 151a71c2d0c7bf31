"""ESyS-Particle driver (host side): many `RunSpec`s -> one `mpirun -np 2 esysparticle collisions.py job` -> dumps.

ESyS runs under MPI: one master (the Python script) and one worker (numWorkerProcesses=1). A
process takes about a second to start, so a whole sweep runs in one process: the deck
(cases/decks/esys/collisions.py) keeps one LsmMpi and gives every run its own particles and
tagged interaction group (a second LsmMpi after `exit()` is not possible: it waits forever for
the worker that has left). Every number the deck uses is written into the job file here, from
`contact_model.engine_parameters` (``esys_hertzian_viscoelastic``, ``esys_plane_as_sphere``).
ESyS's output is its log, streamed (PYTHONUNBUFFERED), under a time limit scaled to the sweep
(engines/engine_process.py); the process group is killed when it stops.

Laws: ``viscoelastic_clipped`` and ``elastic`` (HertzianViscoElasticPrms, A = 0 for elastic) and
``default`` (HertzMindlinViscoPrms with the restitution coefficient, as a user would set it).
``viscoelastic`` is not available: ESyS clips the force at zero (`engines.codes`).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path

from contact_model.engine_parameters import esys_plane_as_sphere

from .codes import law_unavailable
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, describe_exit, log_tail, run_logged, stop_message, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep, load_record, write_run_dump
from .run_spec import RunSpec

EXECUTABLE = "esysparticle"
MPIRUN = "mpirun"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "esys" / "collisions.py"
#: The plane's stand-in sphere is this many times heavier than the sphere hitting it (it does
#: not move: non-dynamic), so that M* = m1 m_wall / (m1 + m_wall) = m1 in doubles.
WALL_MASS_RATIO = 1e20


def driver_hash() -> str:
    return hashlib.sha256(DRIVER.read_bytes()).hexdigest()


def mpirun_command(mpirun: str, executable: str, script: Path, *args: str) -> list[str]:
    """`mpirun -np 2 ... <executable> <script> <args>`: one master and one worker. As root,
    Open MPI refuses to start without --allow-run-as-root; --oversubscribe lets the two ranks
    share fewer cores."""
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    return [mpirun, "-np", "2", *root, "--oversubscribe", executable, str(script), *args]


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the ESyS deck (SI)."""
    p = spec.pair
    params = p.engine_parameters("esys")
    state = spec.initial_state()
    # ESyS's force is read from the velocity jump of a step, which resolves no force below
    # M* ulp(v) / dt. A sample exactly at touching (the gap is a whole number of steps) would
    # carry a rounding-level overlap, positive or negative, whose force no velocity can show:
    # start half a step further apart, so that no sample falls at touching. The record keeps
    # its own times and overlaps; only the moment of first contact moves, by dt / 2.
    state["x1"] -= 0.5 * state["v1"] * state["dt"]
    if "x2" in state:
        state["x2"] -= 0.5 * state["v2"] * state["dt"]
    entry = {"name": spec.name, "geometry": p.geometry, "law": spec.law, "out": str(out), **state,
             "m1": p.body_1.mass}
    factor = 1.0
    if p.body_2.is_plane:
        wall = esys_plane_as_sphere(p.body_1.radius)
        factor = wall["modulus_factor"]
        entry.update(R_wall=wall["R_wall"], m_wall=WALL_MASS_RATIO * p.body_1.mass, modulus_factor=factor)
    else:
        entry["m2"] = p.body_2.mass
    if spec.law == "default":
        # Out of the box: HertzMindlinViscoPrms takes the restitution coefficient itself; its
        # normal force is 4/3 E sqrt(R*) delta^{3/2}, E standing for E*.
        entry.update(E=params["E_hertz_mindlin"] * factor, en=spec.matched_restitution)
    else:
        entry.update(E=params["E"] * factor, A=params["A"])  # elastic: the spec's eta is 0, so A = 0
    return entry


def run_esys(specs: list[RunSpec], workdir, executable: str = EXECUTABLE,
             timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, mpirun: str = MPIRUN) -> Sweep:
    """Run every spec in one ESyS process (`mpirun -np 2`); write `workdir/<spec.name>.csv` for each.

    Raises EngineMissing if esysparticle (or mpirun) is not installed. A run that fails is an
    EngineRunFailed (naming the log) in the returned `Sweep`. If ESyS itself stops (an error, a
    crash, or its time limit: `engine_process.time_limit`, at least `timeout_floor_s`), the run
    in progress fails with ESyS's last log lines, the runs after it are not run, and the runs
    before it land if their records are complete.
    """
    if any(s.engine != "esys" for s in specs):
        raise ValueError("run_esys got runs for another engine")
    if len({s.name for s in specs}) != len(specs):
        raise ValueError("run_esys got two runs with the same name")
    for s in specs:
        if law_unavailable("esys", s.law):
            raise ValueError(f"run_esys got a run of law {s.law!r} ({s.name}), which ESyS cannot express: "
                             f"{law_unavailable('esys', s.law)}")
    exe = require_executable("esys", executable)
    mpi = require_executable("esys", mpirun)
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    log = workdir / "esys.log"
    status_path = workdir / "esys-status.json"
    progress_path = workdir / "esys-progress.txt"
    for path in (status_path, progress_path):
        path.unlink(missing_ok=True)
    raws = {s.name: workdir / f"{s.name}.esys.csv" for s in specs}
    for s in specs:
        (workdir / f"{s.name}.csv").unlink(missing_ok=True)
        raws[s.name].unlink(missing_ok=True)
    job = {"runs": [job_entry(s, raws[s.name]) for s in specs], "status": str(status_path),
           "progress": str(progress_path)}
    job_path = workdir / "esys-job.json"
    job_path.write_text(json.dumps(job, indent=1))
    cmd = mpirun_command(mpi, exe, DRIVER, str(job_path))
    sweep = Sweep()
    limit = time_limit("esys", specs, timeout_floor_s)
    # Open MPI's ranks spin while they wait for each other: yielding lets the other engine job
    # of a two-core study use the core (steel sweep alone: 3.6 -> 2.9 CPU s, 2.2 -> 1.8 s wall).
    done = run_logged(cmd, log, limit, cwd=workdir, env={"PYTHONUNBUFFERED": "1", "OMPI_MCA_mpi_yield_when_idle": "1"})
    sweep.engine_seconds = done.seconds
    printed = log.read_text(errors="replace") if log.exists() else ""
    status = json.loads(status_path.read_text()) if status_path.exists() else None
    stop = None
    if done.timed_out:
        stop = f"did not finish within its time limit of {limit:.3g} s and was killed"
    elif done.returncode != 0 or status is None:
        stop = f"exited with {describe_exit(done.returncode)}" + ("" if status else " before writing its status")
    build = re.search(r"^ESyS-Particle .*$", printed, flags=re.M)
    build = build.group(0).strip() if build else None
    version = status["engine_version"] if status else build or "ESyS-Particle (version not printed)"
    # The run in progress: from the deck's progress file, not the log, where mpirun forwards
    # the ranks' stdout and stderr in chunks that can splice a crash's backtrace into a line.
    progress = progress_path.read_text(errors="replace") if progress_path.exists() else ""
    started = re.findall(r"^RUN (\S+)$", progress, flags=re.M)
    stopped_in = (started[-1] if started else specs[0].name) if stop else None
    reached_stop = False
    for spec, entry in zip(specs, job["runs"]):
        if spec.name == stopped_in:
            reached_stop = True
            problem = stop_message("esys", f"{build or 'no version line printed'}; {exe}", spec.case, spec.name,
                                   stop, log)
            sweep.failures[spec.name] = EngineRunFailed(spec.name, problem, log, engine="esys", case=spec.case,
                                                        log_tail=log_tail(log))
            continue
        if reached_stop:
            sweep.failures[spec.name] = EngineRunFailed(spec.name, f"not run: esys stopped in {stopped_in}", log)
            continue
        if status is not None:
            st = status["runs"].get(spec.name, {"ok": False, "error": "no status reported"})
        else:  # ESyS stopped later: this run finished, and wrote its record unless it failed
            failed = re.search(rf"^RUN FAILED {re.escape(spec.name)}: (.*)$", progress, flags=re.M)
            st = {"ok": False, "error": failed.group(1)} if failed else {"ok": True}
        sweep.finish(spec, lambda: _esys_dump(spec, entry, st, raws[spec.name], workdir, log, version))
    return sweep


def _esys_dump(spec, entry, st, raw, workdir, log, version) -> Path:
    if not st["ok"]:
        raise EngineRunFailed(spec.name, f"esys: {st['error']}", log)
    data = load_record(spec, raw, log)
    meta = {"engine": "esys", "engine_version": version, "deck": DRIVER.name,
            "deck_sha256": driver_hash(), "engine_variables": {k: v for k, v in entry.items() if k != "out"}}
    dump = write_run_dump(spec, data, workdir / f"{spec.name}.csv", log, meta)
    raw.unlink()
    return dump
