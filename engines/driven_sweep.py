"""What a Python-driven engine's sweep left behind, run by run (YADE, ESyS-Particle, Kratos).

These engines run a driver script (cases/decks/<code>/collisions.py) that reads a job file,
prints 'RUN <name>' as each run starts, writes one raw record per run and, when it gets to the
end, a status file ({engine_version, runs: {name: {ok, error}}}). This module turns that, and
how the process ended, into a `Sweep`:

- the process stopped (its time limit, a crash, an exit before the status): the run in
  progress fails with the engine's last log lines, the runs after it are 'not run', and the
  runs before it land if their records are complete;
- otherwise every run lands, or fails with the error its driver reported.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

from records.files import file_sha256

from .engine_process import Finished, describe_exit, log_tail, stop_message
from .errors import EngineRunFailed
from .finish_run import Sweep, load_record, write_run_dump


@dataclass(frozen=True)
class SweepFiles:
    """The files of one driven sweep in its folder: the engine's log, the job file the driver
    reads, the status file it writes at the end, and each run's raw record (by run name)."""

    workdir: Path
    log: Path
    job: Path
    status: Path
    raws: dict
    entries: list


def prepare_sweep(engine: str, specs, workdir, job_entry, **more_files: Path) -> SweepFiles:
    """Check the runs (all of `engine`, names unique), clear what an earlier sweep left in
    `workdir` (dumps, raw records, status and `more_files`), and write the job file:
    {runs: [job_entry(spec, raw record path)], status: path, **more_files}."""
    if any(s.engine != engine for s in specs):
        raise ValueError(f"run_{engine} got runs for another engine")
    if len({s.name for s in specs}) != len(specs):
        raise ValueError(f"run_{engine} got two runs with the same name")
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    status = workdir / f"{engine}-status.json"
    for path in (status, *more_files.values()):
        Path(path).unlink(missing_ok=True)
    raws = {s.name: workdir / f"{s.name}.{engine}.csv" for s in specs}
    for s in specs:
        (workdir / f"{s.name}.csv").unlink(missing_ok=True)
        raws[s.name].unlink(missing_ok=True)
    entries = [job_entry(s, raws[s.name]) for s in specs]
    job = workdir / f"{engine}-job.json"
    job.write_text(json.dumps({"runs": entries, "status": str(status),
                               **{k: str(v) for k, v in more_files.items()}}, indent=1))
    return SweepFiles(workdir, workdir / f"{engine}.log", job, status, raws, entries)


def collect_sweep(engine: str, banner: str, exe: str, specs, files: SweepFiles, done: Finished, limit: float,
                  driver: Path, progress: str | None = None, make_dump=None) -> Sweep:
    """The `Sweep` of one driven engine process.

    Parameters
    ----------
    engine : str
        The code's name (in messages and dump headers).
    banner : str
        How the engine's version line starts in its log (e.g. 'YADE').
    exe, specs, files
        The executable, the runs and their files (`prepare_sweep`).
    done, limit
        How the process ended (`run_logged`) and its time limit [s].
    driver : Path
        The driver script (its name and sha256 go into every dump header).
    progress : str, optional
        Where the driver printed 'RUN <name>' / 'RUN FAILED <name>: <error>' lines; default the log.
    make_dump : callable, optional
        (engine, spec, entry, status, raw, workdir, log, version, driver) -> the dump's path, or
        EngineRunFailed; default the head-on dump (4 columns, `write_run_dump`). The oblique drivers
        (engines/yade_oblique.py) write their 8 columns with their own.
    """
    workdir, log, status_path, raws, entries = files.workdir, files.log, files.status, files.raws, files.entries
    sweep = Sweep(engine_seconds=done.seconds)
    make_dump = make_dump or _dump
    printed = log.read_text(errors="replace") if log.exists() else ""
    progress = printed if progress is None else progress
    status = json.loads(status_path.read_text()) if status_path.exists() else None
    stop = None
    if done.timed_out:
        stop = f"did not finish within its time limit of {limit:.3g} s and was killed"
    elif done.returncode != 0 or status is None:
        stop = f"exited with {describe_exit(done.returncode)}" + ("" if status else " before writing its status")
    build = re.search(rf"^{re.escape(banner)} .*$", printed, flags=re.M)
    build = build.group(0).strip() if build else None
    version = status["engine_version"] if status else build or f"{banner} (version not printed)"
    started = re.findall(r"^RUN (\S+)$", progress, flags=re.M)
    stopped_in = (started[-1] if started else specs[0].name) if stop else None
    reached_stop = False
    for spec, entry in zip(specs, entries):
        if spec.name == stopped_in:
            reached_stop = True
            problem = stop_message(engine, f"{build or 'no version line printed'}; {exe}", spec.case, spec.name,
                                   stop, log)
            sweep.failures[spec.name] = EngineRunFailed(spec.name, problem, log, engine=engine, case=spec.case,
                                                        log_tail=log_tail(log))
            continue
        if reached_stop:
            sweep.failures[spec.name] = EngineRunFailed(spec.name, f"not run: {engine} stopped in {stopped_in}", log)
            continue
        if status is not None:
            st = status["runs"].get(spec.name, {"ok": False, "error": "no status reported"})
        else:  # the engine stopped later: this run finished, and wrote its record unless it failed
            failed = re.search(rf"^RUN FAILED {re.escape(spec.name)}: (.*)$", progress, flags=re.M)
            st = {"ok": False, "error": failed.group(1)} if failed else {"ok": True}
        sweep.finish(spec, lambda: make_dump(engine, spec, entry, st, raws[spec.name], workdir, log, version, driver))
    return sweep


def _dump(engine, spec, entry, st, raw, workdir, log, version, driver: Path) -> Path:
    if not st["ok"]:
        raise EngineRunFailed(spec.name, f"{engine}: {st['error']}", log)
    data = load_record(spec, raw, log)
    meta = {"engine": engine, "engine_version": version, "deck": driver.name,
            "deck_sha256": file_sha256(driver), "engine_variables": {k: v for k, v in entry.items() if k != "out"}}
    dump = write_run_dump(spec, data, workdir / f"{spec.name}.csv", log, meta)
    raw.unlink()
    return dump
