"""Engine drivers: a `RunSpec` in, a study dump (postprocess.dump_file) out."""

from .errors import EngineMissing, EngineRunFailed
from .run_spec import LAWS, RunSpec

__all__ = ["EngineMissing", "EngineRunFailed", "LAWS", "RunSpec"]
