"""The last step of every engine run: check the engine's record and write the study dump."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from records.collision_metrics import ExtractionError, collision_metrics
from records.dump_file import write_dump
from records.text_rows import read_rows

from .errors import EngineRunFailed
from .run_spec import RunSpec


def load_record(spec: RunSpec, raw: Path, log) -> np.ndarray:
    """An engine's per-step record (time, overlap, normal velocity, normal force; one header
    line) as an array, or EngineRunFailed."""
    try:
        data = read_rows(raw, delimiter=None if raw.suffix == ".txt" else ",", skiprows=1)
    except (OSError, ValueError) as err:
        raise EngineRunFailed(spec.name, f"unreadable engine record {raw}: {err}", log)
    if data.shape[0] < 3 or data.shape[1] != 4:
        raise EngineRunFailed(spec.name, f"engine record {raw} has {data.shape[0]} rows of {data.shape[1]} columns",
                              log)
    return data


def write_run_dump(spec: RunSpec, data: np.ndarray, dump: Path, log, meta: dict) -> Path:
    """Check that `data` holds one complete, finite collision, then write the dump.

    Raises EngineRunFailed (naming the engine log) for NaN, bodies that never touch or a
    contact still open at the end; nothing is written then.
    """
    if not np.all(np.isfinite(data)):
        row = int(np.nonzero(~np.all(np.isfinite(data), axis=1))[0][0])
        raise EngineRunFailed(spec.name, f"the engine produced NaN or inf (record row {row + 1})", log)
    try:
        collision_metrics(*data.T, impact_velocity=spec.velocity)
    except ExtractionError as err:
        raise EngineRunFailed(spec.name, str(err), log)
    write_dump(dump, {**meta, **spec.metadata()}, data)
    return dump


@dataclass
class Sweep:
    """What an engine process made of a list of runs: a dump or a failure for each run.

    `engine_seconds` is the wall time of the engine process itself.
    """

    dumps: dict[str, Path] = field(default_factory=dict)
    failures: dict[str, EngineRunFailed] = field(default_factory=dict)
    engine_seconds: float = 0.0

    def failed_runs(self, runs) -> list[dict]:
        """The manifest's `failed` entries (run, law, problem, log) of the failed ones among
        `runs` (RunSpec), in the order they failed."""
        law = {r.name: r.law for r in runs}
        return [{"run": n, "law": law[n], "problem": e.problem, "log": e.log_path} for n, e in self.failures.items()]

    def raise_first(self) -> "Sweep":
        """Raise the first failure, if any; otherwise return self."""
        if self.failures:
            raise next(iter(self.failures.values()))
        return self

    def finish(self, spec: RunSpec, make_dump) -> None:
        """Record make_dump()'s path for spec, or its EngineRunFailed."""
        try:
            self.dumps[spec.name] = make_dump()
        except EngineRunFailed as err:
            self.failures[spec.name] = err
