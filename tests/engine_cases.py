"""Shared set-up of the engine integration tests: the issue's steel accuracy case.

Steel spheres, R = 0.635 cm, E* = 109 GPa, density 7800 kg/m^3, V = 1 m/s, eta chosen so that
K = 0.1 in each geometry (K depends on R* and M*, so the two geometries get different eta).
"""

import math
import shutil

import pytest

from contact_model import Body, ContactPair
from contact_model.collision_scales import viscosity_for_dissipation
from reference import HERTZ_TAU, solve_collision

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
    from postprocess.collision_metrics import collision_metrics
    from postprocess.dump_file import read_dump

    meta, c = read_dump(path)
    return meta, collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                                   impact_velocity=meta["impact_velocity"])


def require_engine(executable: str, package: str):
    if shutil.which(executable) is None:
        pytest.skip(f"{executable} is not installed; install it with: sudo apt-get install {package}"
                    " (make test does this)")
