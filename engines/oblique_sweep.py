"""Run oblique collisions (`engines.oblique_run.ObliqueRun`) in a build: its code's oblique
driver (`engines.codes.Code.oblique_driver`), one engine process per tangential model, geometry and
MPI rank count, so that a model that crashes its engine in one geometry (LAMMPS 22 Jul 2025's
classic wall) fails its own ladders alone."""

from __future__ import annotations

from pathlib import Path

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .finish_run import Sweep


def run_oblique_sweep(build, runs, workdir, timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run `runs` in `build` (an `engines.builds.Build`); a `Sweep` of all of them.

    Parameters
    ----------
    build : engines.builds.Build
        The build; every run must be its own.
    runs : list of ObliqueRun
        The runs, in any order; those of each model, geometry and rank count go to one process.
    workdir : str or os.PathLike
        Where the engine works and the dumps are written (a subfolder per process).
    timeout_floor_s : float
        The least time an engine process is given [s].
    """
    Path(workdir).mkdir(parents=True, exist_ok=True)
    if any(r.build != build.id for r in runs):
        raise ValueError(f"build {build.id!r} got runs of another build")
    runner = code(build.code).runner(oblique=True) if runs else None
    sweep = Sweep()
    for model, geometry, ranks in sorted({(r.model, r.pair.geometry, r.ranks) for r in runs}):
        part = [r for r in runs if r.ranks == ranks and r.model == model and r.pair.geometry == geometry]
        folder = Path(workdir) / f"{model.replace(':', '-').replace('/', '_')}-{geometry}-np{ranks}"
        one = runner(part, folder, executable=build.executable, timeout_floor_s=timeout_floor_s)
        sweep.dumps.update(one.dumps)
        sweep.failures.update(one.failures)
        sweep.engine_seconds += one.engine_seconds
    return sweep
