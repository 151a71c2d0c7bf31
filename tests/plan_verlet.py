"""The velocity-Verlet integrator the kit's tests run an exported plan with (`conformance export`'s
plan.json runs): written here from the plan's SI numbers, not the project's `reference.engine_map`,
so that a PASS of the kit's gate is a PASS against an independent integration."""

from __future__ import annotations

import numpy as np


def integrate(run: dict, force) -> dict[str, np.ndarray]:
    """Velocity Verlet of one plan run (the force after the first half kick, with the velocity of
    that half step, as LAMMPS integrates), one sample per step.

    Parameters
    ----------
    run : dict
        One run of plan.json: ``body_1``, ``body_2`` (radius_m, mass_kg, plane), ``initial``
        (x1_m, v1_m_s, x2_m, v2_m_s), ``dt_s`` and ``steps``.
    force : callable
        ``force(delta, rate)`` [N], the contact force (repulsive positive) at overlap delta > 0 [m]
        and overlap rate d(delta)/dt [m/s]; 0 is used where delta <= 0.

    Returns
    -------
    dict of numpy.ndarray
        Per sample: time [s], x1, x2 [m], v1, v2 [m/s], overlap [m], rate [m/s], force [N].
    """
    plane = run["body_2"]["plane"]
    R1, R2 = run["body_1"]["radius_m"], 0.0 if plane else run["body_2"]["radius_m"]
    m1 = run["body_1"]["mass_kg"]
    inv2 = 0.0 if plane else 1.0 / run["body_2"]["mass_kg"]
    init = run["initial"]
    x1, v1, x2, v2 = init["x1_m"], init["v1_m_s"], init["x2_m"], init["v2_m_s"]
    dt, n = run["dt_s"], run["steps"] + 1
    out = {k: np.empty(n) for k in ("x1", "v1", "x2", "v2", "force")}

    def overlap(x1, x2):
        return R1 + x1 if plane else R1 + R2 - (x2 - x1)

    def f(x1, x2, rate):
        d = overlap(x1, x2)
        return force(d, rate) if d > 0 else 0.0

    F = f(x1, x2, v1 - v2)
    for i in range(n):
        out["x1"][i], out["v1"][i], out["x2"][i], out["v2"][i], out["force"][i] = x1, v1, x2, v2, F
        v1 -= 0.5 * dt * F / m1
        v2 += 0.5 * dt * F * inv2
        x1 += dt * v1
        x2 += dt * v2
        F = f(x1, x2, v1 - v2)
        v1 -= 0.5 * dt * F / m1
        v2 += 0.5 * dt * F * inv2
    out["time"] = np.arange(n) * dt
    out["overlap"] = overlap(out["x1"], out["x2"])
    out["rate"] = out["v1"] - out["v2"]
    return out
