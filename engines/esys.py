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

import os
from pathlib import Path

from contact_model.engine_parameters import esys_plane_as_sphere

from .codes import code, law_unavailable
from records.files import file_sha256

from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import require_executable
from .finish_run import Sweep
from .run_spec import RunSpec

EXECUTABLE = "esysparticle"
MPIRUN = "mpirun"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "esys" / "collisions.py"
#: The plane's stand-in sphere is this many times heavier than the sphere hitting it (it does
#: not move: non-dynamic), so that M* = m1 m_wall / (m1 + m_wall) = m1 in doubles.
WALL_MASS_RATIO = 1e20


def driver_hash() -> str:
    return file_sha256(DRIVER)


def mpirun_command(mpirun: str, executable: str, script: Path, *args: str) -> list[str]:
    """`mpirun -np 2 ... <executable> <script> <args>`: one master and one worker. As root,
    Open MPI refuses to start without --allow-run-as-root; --oversubscribe lets the two ranks
    share fewer cores."""
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    return [mpirun, "-np", "2", *root, "--oversubscribe", executable, str(script), *args]


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the ESyS deck (SI)."""
    p = spec.pair
    params = code("esys").contact_parameters(p)
    # No sample falls at touching (a rounding-level overlap whose force, read from a velocity
    # jump, no velocity could show): every run starts half a step off the grid
    # (engines.ladder.START_PHASE).
    state = spec.initial_state()
    entry = {"name": spec.name, "geometry": p.geometry, "law": spec.law, "out": str(out), **state,
             "m1": p.body_1.mass}
    factor = 1.0
    if p.body_2.is_plane:
        wall = esys_plane_as_sphere(p.body_1.radius)
        factor = wall["modulus_factor"]
        entry.update(R_wall=wall["R_wall"], m_wall=WALL_MASS_RATIO * p.body_1.mass, modulus_factor=factor)
    else:
        entry["m2"] = p.body_2.mass
    if spec.keyword is not None:  # its one keyword
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
    for s in specs:
        if law_unavailable("esys", s.law):
            raise ValueError(f"run_esys got a run of law {s.law!r} ({s.name}), which ESyS cannot express: "
                             f"{law_unavailable('esys', s.law)}")
    exe = require_executable("esys", executable)
    mpi = require_executable("esys", mpirun)
    progress_path = Path(workdir).resolve() / "esys-progress.txt"
    files = prepare_sweep("esys", specs, workdir, job_entry, progress=progress_path)
    cmd = mpirun_command(mpi, exe, DRIVER, str(files.job))
    limit = time_limit("esys", specs, timeout_floor_s)
    # Open MPI's ranks spin while they wait for each other: yielding lets the other engine job
    # of a two-core study use the core (steel sweep alone: 3.6 -> 2.9 CPU s, 2.2 -> 1.8 s wall).
    done = run_logged(cmd, files.log, limit, cwd=files.workdir,
                      env={"PYTHONUNBUFFERED": "1", "OMPI_MCA_mpi_yield_when_idle": "1"})
    # The run in progress: from the deck's progress file, not the log, where mpirun forwards
    # the ranks' stdout and stderr in chunks that can splice a crash's backtrace into a line.
    return collect_sweep("esys", "ESyS-Particle", exe, specs, files, done, limit, DRIVER,
                         progress=progress_path.read_text(errors="replace") if progress_path.exists() else "")

