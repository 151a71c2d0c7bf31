"""LIGGGHTS-PUBLIC driver: a `RunSpec` -> `liggghts -in deck -var ...` -> a study dump.

The decks (cases/decks/liggghts/) hold only LIGGGHTS syntax; every number is passed with -var
from here, derived from the contact pair by `contact_model`. One process per run: LIGGGHTS starts
in well under a second.
"""

from __future__ import annotations

import hashlib
import subprocess
from functools import lru_cache
from pathlib import Path

import numpy as np

from .errors import EngineRunFailed, require_executable
from .finish_run import load_record, write_run_dump
from .run_spec import RunSpec

EXECUTABLE = "liggghts"
DECKS = Path(__file__).resolve().parents[1] / "cases" / "decks" / "liggghts"
DECK_OF_GEOMETRY = {"sphere-sphere": "two_spheres.in", "sphere-plane": "sphere_plane.in"}
PROPERTIES_OF_LAW = {"viscoelastic": "properties_viscoelastic.in",
                     "viscoelastic_clipped": "properties_viscoelastic.in",
                     "default": "properties_default.in"}
TIMEOUT_S = 600


@lru_cache(maxsize=None)
def liggghts_version(executable: str = EXECUTABLE) -> str:
    """The version line LIGGGHTS prints at start-up, e.g.
    'LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled ...)'."""
    exe = require_executable("liggghts", executable)
    out = subprocess.run([exe, "-log", "none"], input="", capture_output=True, text=True, timeout=60)
    for line in out.stdout.splitlines():
        if line.startswith("LIGGGHTS"):
            return line.strip()
    return "LIGGGHTS (version line not found)"


def deck_hash(spec: RunSpec) -> str:
    """sha256 of the deck and the property file the run includes."""
    h = hashlib.sha256()
    for name in (DECK_OF_GEOMETRY[spec.pair.geometry], PROPERTIES_OF_LAW[spec.law]):
        h.update((DECKS / name).read_bytes())
    return h.hexdigest()


def deck_variables(spec: RunSpec, out: Path) -> dict[str, str]:
    """The -var values of one run (SI, %.17g so that nothing is rounded)."""
    p = spec.pair
    g = lambda x: f"{x:.17g}"  # noqa: E731
    R1 = p.body_1.radius
    gap = spec.initial_gap()
    v1, v2 = spec.initial_velocities()
    size = 3.0 * max(R1, p.body_2.radius if not p.body_2.is_plane else R1) + gap
    var = {
        "R1": g(R1), "rho1": g(p.body_1.density), "v1": g(v1),
        "dt": g(spec.time_step), "steps": str(spec.steps()),
        "box": g(size), "skin": g(0.25 * R1),
        "properties": str(DECKS / PROPERTIES_OF_LAW[spec.law]),
        "model_tail": "limitForce " + ("on" if spec.law == "viscoelastic_clipped" else "off"),
        "out": str(out),
    }
    if p.body_2.is_plane:
        var["x1"] = g(-(R1 + gap))
    else:
        var.update({"R2": g(p.body_2.radius), "rho2": g(p.body_2.density), "v2": g(v2),
                    "x1": g(-(R1 + gap / 2)), "x2": g(p.body_2.radius + gap / 2)})
    if spec.law == "default":
        var["model_head"] = "model hertz tangential no_history"
        var["young"] = g(2.0 * p.E)  # poisson 0 on both: Y* = Y/2 = E*
        var["restitution"] = g(spec.matched_restitution)
    else:
        params = p.engine_parameters("liggghts")
        var["model_head"] = "model hertz/stiffness tangential no_history"
        var["kn"], var["gamman"] = g(params["kn"]), g(params["gamman"])
    return var


def _last_error(log: Path) -> str:
    try:
        lines = log.read_text(errors="replace").splitlines()
    except OSError:
        return "no log written"
    errors = [l for l in lines if "ERROR" in l]
    return errors[-1].strip() if errors else (lines[-1].strip() if lines else "empty log")


def run_liggghts(spec: RunSpec, workdir, executable: str = EXECUTABLE) -> Path:
    """Run one collision in LIGGGHTS and write its dump `workdir/<spec.name>.csv`.

    Raises EngineMissing if LIGGGHTS is not installed, EngineRunFailed (with the log path) if it
    fails, produces NaN, or the bodies never touch or are still in contact at the end.
    """
    if spec.engine != "liggghts":
        raise ValueError(f"run_liggghts got a run for {spec.engine!r}")
    exe = require_executable("liggghts", executable)
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    raw = workdir / f"{spec.name}.liggghts.txt"
    log = workdir / f"{spec.name}.liggghts.log"
    dump = workdir / f"{spec.name}.csv"
    dump.unlink(missing_ok=True)
    raw.unlink(missing_ok=True)
    var = deck_variables(spec, raw)
    cmd = [exe, "-in", str(DECKS / DECK_OF_GEOMETRY[spec.pair.geometry]), "-log", str(log),
           "-screen", "none"]
    for k, v in var.items():
        cmd += ["-var", k, v]
    try:
        done = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise EngineRunFailed(spec.name, f"liggghts did not finish within {TIMEOUT_S} s", log)
    if done.returncode != 0:
        raise EngineRunFailed(spec.name, f"liggghts exited with status {done.returncode}: {_last_error(log)}", log)
    data = load_record(spec, raw, log)
    # fix print starts at step 1: prepend the initial state (free flight, no force).
    v1, v2 = spec.initial_velocities()
    data = np.vstack([[0.0, -spec.initial_gap(), v1 - v2, 0.0], data])
    meta = {"engine": "liggghts", "engine_version": liggghts_version(executable),
            "deck": DECK_OF_GEOMETRY[spec.pair.geometry], "deck_sha256": deck_hash(spec),
            "engine_variables": {k: v for k, v in var.items() if k != "out"}}
    write_run_dump(spec, data, dump, log, meta)
    raw.unlink()
    return dump
