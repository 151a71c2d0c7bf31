"""YADE driver (host side): many `RunSpec`s -> one `yade -n -x collisions.py job=...` -> dumps.

YADE needs over a second to start, so a whole sweep runs in one process; the driver script
(cases/decks/yade/collisions.py) resets the scene between runs. Every number it uses is
written into the job file here, from `contact_model`. YADE's output is its log, streamed
(PYTHONUNBUFFERED), under a time limit scaled to the sweep (engines/engine_process.py).
"""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, describe_exit, log_tail, run_logged, stop_message, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep, load_record, write_run_dump
from .run_spec import RunSpec

EXECUTABLE = "yade"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "yade" / "collisions.py"


def driver_hash() -> str:
    return hashlib.sha256(DRIVER.read_bytes()).hexdigest()


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the YADE driver (SI)."""
    p = spec.pair
    params = p.engine_parameters("yade")
    entry = {"name": spec.name, "geometry": p.geometry, "law": spec.law, "out": str(out),
             **spec.initial_state(), "M": p.M, "young": params["young"], "c": params["c"]}
    if spec.law == "default":
        # Out of the box: the user asks Ip2_FrictMat_FrictMat_MindlinPhys for the restitution
        # coefficient itself (YADE turns en into betan with Thornton et al.'s 2013 fit).
        entry["en"] = spec.matched_restitution
    return entry


def run_yade(specs: list[RunSpec], workdir, executable: str = EXECUTABLE,
             timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run every spec in one YADE process; write `workdir/<spec.name>.csv` for each.

    Raises EngineMissing if YADE is not installed. A run that fails is an EngineRunFailed
    (naming the log) in the returned `Sweep`. If YADE itself stops (an error, a crash, or its
    time limit: `engine_process.time_limit`, at least `timeout_floor_s`), the run in progress
    fails with YADE's last log lines, the runs after it are not run, and the runs before it
    land if their records are complete.
    """
    if any(s.engine != "yade" for s in specs):
        raise ValueError("run_yade got runs for another engine")
    if len({s.name for s in specs}) != len(specs):
        raise ValueError("run_yade got two runs with the same name")
    exe = require_executable("yade", executable)
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    log = workdir / "yade.log"
    status_path = workdir / "yade-status.json"
    status_path.unlink(missing_ok=True)
    raws = {s.name: workdir / f"{s.name}.yade.csv" for s in specs}
    for s in specs:
        (workdir / f"{s.name}.csv").unlink(missing_ok=True)
        raws[s.name].unlink(missing_ok=True)
    job = {"runs": [job_entry(s, raws[s.name]) for s in specs], "status": str(status_path)}
    job_path = workdir / "yade-job.json"
    job_path.write_text(json.dumps(job, indent=1))
    cmd = [exe, "-n", "-x", str(DRIVER), f"job={job_path}"]
    sweep = Sweep()
    limit = time_limit("yade", specs, timeout_floor_s)
    done = run_logged(cmd, log, limit, cwd=workdir, env={"PYTHONUNBUFFERED": "1"})
    sweep.engine_seconds = done.seconds
    printed = log.read_text(errors="replace") if log.exists() else ""
    status = json.loads(status_path.read_text()) if status_path.exists() else None
    stop = None
    if done.timed_out:
        stop = f"did not finish within its time limit of {limit:.3g} s and was killed"
    elif done.returncode != 0 or status is None:
        stop = f"exited with {describe_exit(done.returncode)}" + ("" if status else " before writing its status")
    build = re.search(r"^YADE .*$", printed, flags=re.M)
    build = build.group(0).strip() if build else None
    version = status["engine_version"] if status else build or "YADE (version not printed)"
    started = re.findall(r"^RUN (\S+)$", printed, flags=re.M)
    stopped_in = (started[-1] if started else specs[0].name) if stop else None
    reached_stop = False
    for spec, entry in zip(specs, job["runs"]):
        if spec.name == stopped_in:
            reached_stop = True
            problem = stop_message("yade", f"{build or 'no version line printed'}; {exe}", spec.case, spec.name,
                                   stop, log)
            sweep.failures[spec.name] = EngineRunFailed(spec.name, problem, log, engine="yade", case=spec.case,
                                                        log_tail=log_tail(log))
            continue
        if reached_stop:
            sweep.failures[spec.name] = EngineRunFailed(spec.name, f"not run: yade stopped in {stopped_in}", log)
            continue
        if status is not None:
            st = status["runs"].get(spec.name, {"ok": False, "error": "no status reported"})
        else:  # YADE stopped later: this run finished, and wrote its record unless it failed
            failed = re.search(rf"^RUN FAILED {re.escape(spec.name)}: (.*)$", printed, flags=re.M)
            st = {"ok": False, "error": failed.group(1)} if failed else {"ok": True}
        sweep.finish(spec, lambda: _yade_dump(spec, entry, st, raws[spec.name], workdir, log, version))
    return sweep


def _yade_dump(spec, entry, st, raw, workdir, log, version) -> Path:
    if not st["ok"]:
        raise EngineRunFailed(spec.name, f"yade: {st['error']}", log)
    data = load_record(spec, raw, log)
    meta = {"engine": "yade", "engine_version": version, "deck": DRIVER.name,
            "deck_sha256": driver_hash(), "engine_variables": {k: v for k, v in entry.items() if k != "out"}}
    dump = write_run_dump(spec, data, workdir / f"{spec.name}.csv", log, meta)
    raw.unlink()
    return dump
