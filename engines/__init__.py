"""Engine drivers: `RunSpec`s in, study dumps (records.dump_file) out."""

from pathlib import Path

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .errors import EngineMissing, EngineRunFailed
from .finish_run import Sweep
from .run_spec import RunSpec


def run_sweep(build, specs, workdir, timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run `specs` in one process of `build` (an `engines.builds.Build`, or a code `engines.codes`,
    for its default executable); a `Sweep`.

    The process is killed after a time limit scaled to the sweep's steps
    (`engines.engine_process.time_limit`), never less than `timeout_floor_s` seconds. No runs
    (a build that can run none of the study's laws, as ESyS with `laws: [viscoelastic]`): no
    process, an empty `Sweep` in an empty `workdir`."""
    if not specs:
        # Started with nothing to do, ESyS waited until its time limit (60 s) killed it, and its
        # driver then had no run to name the stop in (IndexError): the job failed.
        Path(workdir).mkdir(parents=True, exist_ok=True)
        return Sweep()
    engine, executable = (build, None) if isinstance(build, str) else (build.code, build.executable)
    runner = code(engine).runner()
    if not isinstance(build, str) and any(s.build != build.id for s in specs):
        raise ValueError(f"build {build.id!r} got runs of another build")
    kw = {"executable": executable} if executable else {}
    return runner(specs, workdir, timeout_floor_s=timeout_floor_s, **kw)


__all__ = ["EngineMissing", "EngineRunFailed", "RunSpec", "Sweep", "run_sweep"]
