"""Engine drivers: `RunSpec`s in, study dumps (postprocess.dump_file) out."""

from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .errors import EngineMissing, EngineRunFailed
from .finish_run import Sweep
from .run_spec import GATED_LAWS, LAWS, RunSpec


def run_sweep(build, specs, workdir, timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run `specs` in one process of `build` (an `engines.builds.Build`, or a code 'liggghts',
    'yade' or 'lammps' for its default executable); a `Sweep`.

    The process is killed after a time limit scaled to the sweep's steps
    (`engines.engine_process.time_limit`), never less than `timeout_floor_s` seconds."""
    from .lammps import run_lammps
    from .liggghts import run_liggghts
    from .yade import run_yade

    runners = {"liggghts": run_liggghts, "yade": run_yade, "lammps": run_lammps}
    engine, executable = (build, None) if isinstance(build, str) else (build.code, build.executable)
    if engine not in runners:
        raise ValueError(f"unknown engine {engine!r}; known: {sorted(runners)}")
    if not isinstance(build, str) and any(s.build != build.id for s in specs):
        raise ValueError(f"build {build.id!r} got runs of another build")
    kw = {"executable": executable} if executable else {}
    return runners[engine](specs, workdir, timeout_floor_s=timeout_floor_s, **kw)


__all__ = ["EngineMissing", "EngineRunFailed", "GATED_LAWS", "LAWS", "RunSpec", "Sweep", "run_sweep"]
