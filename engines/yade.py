"""YADE driver (host side): many `RunSpec`s -> one `yade -n -x collisions.py job=...` -> dumps.

YADE needs over a second to start, so a whole sweep runs in one process; the driver script
(cases/decks/yade/collisions.py) resets the scene between runs. Every number it uses is
written into the job file here, from `contact_model`.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import time
from pathlib import Path

from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep, load_record, write_run_dump
from .run_spec import RunSpec

EXECUTABLE = "yade"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "yade" / "collisions.py"
TIMEOUT_S = 1800


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


def run_yade(specs: list[RunSpec], workdir, executable: str = EXECUTABLE) -> Sweep:
    """Run every spec in one YADE process; write `workdir/<spec.name>.csv` for each.

    Raises EngineMissing if YADE is not installed. A run that fails is an EngineRunFailed
    (naming the log) in the returned `Sweep`; if YADE itself fails, every run fails.
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
    started = time.perf_counter()
    with open(log, "w") as out:
        try:
            done = subprocess.run(cmd, cwd=workdir, stdout=out, stderr=subprocess.STDOUT,
                                  stdin=subprocess.DEVNULL, timeout=TIMEOUT_S)
            stop = None
            if done.returncode != 0 or not status_path.exists():
                tail = log.read_text(errors="replace").strip().splitlines()[-1:] or ["no output"]
                stop = f"yade exited with status {done.returncode}: {tail[0]}"
        except subprocess.TimeoutExpired:
            stop = f"yade did not finish within {TIMEOUT_S} s"
    sweep.engine_seconds = time.perf_counter() - started
    status = json.loads(status_path.read_text()) if stop is None else {"runs": {}}
    for spec, entry in zip(specs, job["runs"]):
        if stop is not None:
            sweep.failures[spec.name] = EngineRunFailed(spec.name, stop, log)
            continue
        st = status["runs"].get(spec.name, {"ok": False, "error": "no status reported"})
        sweep.finish(spec, lambda: _yade_dump(spec, entry, st, raws[spec.name], workdir, log,
                                              status["engine_version"]))
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
