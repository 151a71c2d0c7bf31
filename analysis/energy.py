"""The energy partition of a sampled collision (a dump), as fractions of (1/2) M* V^2.

    kinetic     (d(delta)/dt / V)^2
    elastic     (delta / delta_e)^{5/2}                      (= (8/15) E* R*^{1/2} delta^{5/2} / ((1/2) M* V^2))
    dissipated  int F_d d(delta)/dt dt / ((1/2) M* V^2),      F_d = F - (4/3) E* R*^{1/2} delta^{3/2}

The dissipated work is integrated from the recorded force (trapezoids), not inferred from the
other two, so kinetic + elastic + dissipated = 1 checks the engine's energy bookkeeping to the
order of its time step.
"""

from __future__ import annotations

import numpy as np


def energy_partition(meta: dict, c: dict) -> dict[str, np.ndarray]:
    """tau (from first contact, units of delta_e/V), kinetic, elastic, dissipated, total.

    Parameters
    ----------
    meta : dict
        The dump header: effective_modulus E* [Pa], effective_radius R* [m], effective_mass M* [kg],
        impact_velocity V [m/s], delta_e [m].
    c : dict
        The dump's columns, arrays of equal length: time [s], overlap delta [m], normal_velocity
        d(delta)/dt [m/s], normal_force F [N].
    """
    E, R, M = meta["effective_modulus"], meta["effective_radius"], meta["effective_mass"]
    V, delta_e = meta["impact_velocity"], meta["delta_e"]
    t, d, v, F = c["time"], c["overlap"], c["normal_velocity"], c["normal_force"]
    inside = d > 0
    elastic_force = np.where(inside, 4 / 3 * E * np.sqrt(R) * np.clip(d, 0, None) ** 1.5, 0.0)
    power = (F - elastic_force) * v
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t))])
    i0 = int(np.argmax(inside))
    t_start = t[i0 - 1] - d[i0 - 1] * (t[i0] - t[i0 - 1]) / (d[i0] - d[i0 - 1]) if i0 > 0 else t[0]
    scale = 0.5 * M * V**2
    out = {"tau": (t - t_start) * V / delta_e, "kinetic": (v / V) ** 2,
           "elastic": np.clip(d / delta_e, 0, None) ** 2.5, "dissipated": work / scale}
    out["total"] = out["kinetic"] + out["elastic"] + out["dissipated"]
    return out
