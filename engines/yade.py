"""YADE driver (host side): many `RunSpec`s -> one `yade -n -x collisions.py job=...` -> dumps.

YADE needs over a second to start, so a whole sweep runs in one process; the driver script
(cases/decks/yade/collisions.py) resets the scene between runs. Every number it uses is
written into the job file here, from `contact_model`. YADE's output is its log, streamed
(PYTHONUNBUFFERED), under a time limit scaled to the sweep (engines/engine_process.py).
"""

from __future__ import annotations

from pathlib import Path

from contact_model.keywords import KEYWORDS
from records.files import file_sha256

from .codes import code
from .driven_sweep import collect_sweep, prepare_sweep
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, run_logged, time_limit
from .errors import require_executable
from .finish_run import Sweep
from .run_spec import RunSpec

EXECUTABLE = "yade"
DRIVER = Path(__file__).resolve().parents[1] / "cases" / "decks" / "yade" / "collisions.py"


def driver_hash() -> str:
    return file_sha256(DRIVER)


def job_entry(spec: RunSpec, out: Path) -> dict:
    """The numbers of one run for the YADE driver (SI)."""
    p = spec.pair
    params = code("yade").contact_parameters(p)
    entry = {"name": spec.name, "geometry": p.geometry, "law": spec.law, "out": str(out),
             **spec.initial_state(), "M": p.M, "young": params["young"], "c": params["c"]}
    if spec.keyword == "yade:en":
        # Out of the box: the user asks Ip2_FrictMat_FrictMat_MindlinPhys for the restitution
        # coefficient itself (YADE turns en into betan with Thornton et al.'s 2013 fit).
        entry["en"] = spec.matched_restitution
    elif spec.keyword == "yade:en-vn":
        # Mueller & Poeschel's route (YADE 2024.02a and later): the restitution at the velocity vn the
        # user names, here the run's impact velocity; YADE solves its Pade for beta.
        entry["en"], entry["vn"] = spec.matched_restitution, spec.velocity
    elif spec.keyword == "yade:betan":
        # The damping ratio itself: the one its en would compute (contact_model.keywords).
        entry["betan"] = (spec.told_input if spec.told_input is not None
                          else KEYWORDS[spec.keyword].told_for(spec.matched_restitution))
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
    exe = require_executable("yade", executable)
    files = prepare_sweep("yade", specs, workdir, job_entry)
    cmd = [exe, "-n", "-x", str(DRIVER), f"job={files.job}"]
    limit = time_limit("yade", specs, timeout_floor_s)
    done = run_logged(cmd, files.log, limit, cwd=files.workdir, env={"PYTHONUNBUFFERED": "1"})
    return collect_sweep("yade", "YADE", exe, specs, files, done, limit, DRIVER)

