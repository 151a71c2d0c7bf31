"""Engine drivers: `RunSpec`s in, study dumps (postprocess.dump_file) out."""

from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .errors import EngineMissing, EngineRunFailed
from .finish_run import Sweep
from .run_spec import GATED_LAWS, LAWS, RunSpec


def run_sweep(engine: str, specs, workdir, timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run `specs` in one process of `engine` ('liggghts', 'yade' or 'lammps'); a `Sweep`.

    The process is killed after a time limit scaled to the sweep's steps
    (`engines.engine_process.time_limit`), never less than `timeout_floor_s` seconds."""
    from .lammps import run_lammps
    from .liggghts import run_liggghts
    from .yade import run_yade

    runners = {"liggghts": run_liggghts, "yade": run_yade, "lammps": run_lammps}
    if engine not in runners:
        raise ValueError(f"unknown engine {engine!r}; known: {sorted(runners)}")
    return runners[engine](specs, workdir, timeout_floor_s=timeout_floor_s)


__all__ = ["EngineMissing", "EngineRunFailed", "GATED_LAWS", "LAWS", "RunSpec", "Sweep", "run_sweep"]
