"""Engine drivers: `RunSpec`s in, study dumps (postprocess.dump_file) out."""

from .errors import EngineMissing, EngineRunFailed
from .finish_run import Sweep
from .run_spec import GATED_LAWS, LAWS, RunSpec


def run_sweep(engine: str, specs, workdir) -> Sweep:
    """Run `specs` in one process of `engine` ('liggghts', 'yade' or 'lammps'); a `Sweep`."""
    from .lammps import run_lammps
    from .liggghts import run_liggghts
    from .yade import run_yade

    runners = {"liggghts": run_liggghts, "yade": run_yade, "lammps": run_lammps}
    if engine not in runners:
        raise ValueError(f"unknown engine {engine!r}; known: {sorted(runners)}")
    return runners[engine](specs, workdir)


__all__ = ["EngineMissing", "EngineRunFailed", "GATED_LAWS", "LAWS", "RunSpec", "Sweep", "run_sweep"]
