"""The tangential results of one oblique collision, from a dump's eight columns
(`records.dump_file.OBLIQUE_COLUMNS`).

Conventions (engines/oblique_run.py): normal +x from body 1 to body 2, body 1 approaching with
v_n > 0, tangential +y, spins about +z; the contact point's slip velocity is

    v_s = (v_y1 + R1 w1) - (v_y2 - R2 w2) = v_t + R1 w1 + R2 w2    [m/s]

(v_t = v_y1 - v_y2; the plane: R2 w2 = 0). The values after separation are read from the free
flight that follows the contact (no gravity: every velocity and spin is constant there): the mean
of its last samples (up to `AFTER_SAMPLES`), which must agree to round-off (`ROUNDOFF`), else the
series is no single collision followed by free flight. The values before contact are the first
sample's (free flight too). The normal quantities are `records.collision_metrics.collision_metrics`'s.
"""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np

from .collision_metrics import PEAK_POINTS, ExtractionError, _peak, collision_metrics

#: Samples of the free flight after contact that are averaged (the last ones of the series).
AFTER_SAMPLES = 10
#: How far those samples may spread, relative to the quantity's scale (velocities: the larger of
#: the impact and the tangential speed; spins: that over the radius): round-off of a constant.
ROUNDOFF = 1e-12


def _constant_after(name: str, values: np.ndarray, scale: float, source: str) -> float:
    """The mean of `values` (free flight), checked constant to ROUNDOFF * scale."""
    spread = float(values.max() - values.min())
    if not spread <= ROUNDOFF * scale:
        raise ExtractionError(f"{source}: {name} is not constant after separation (spread {spread:.3g}, "
                              f"{spread / scale:.3g} of its scale {scale:.3g}): no free flight after the contact")
    return float(values.mean())


def oblique_metrics(columns: dict, meta: dict, source: str | None = None) -> dict:
    """The normal and tangential results of one oblique collision.

    Parameters
    ----------
    columns : dict
        The dump's columns (numpy arrays, `records.dump_file.read_dump(path, oblique=True)`):
        time [s], overlap [m], normal_velocity [m/s], normal_force [N], tangential_velocity
        v_y1 - v_y2 [m/s], omega_1 and omega_2 [rad/s], tangential_force [N] (on body 1).
    meta : dict
        The dump's header: impact_velocity v_n [m/s], radius_1 [m] and radius_2 [m] (None for a
        plane), the lever arms of the slip velocity.
    source : str, optional
        The file the columns come from, named in errors (default: ``meta["path"]`` or "the dump").

    Returns
    -------
    dict
        omega_after [rad/s]: body 1's spin after separation; omega_2_after [rad/s] (0 for a
        plane); vt_before, vt_after [m/s]: the centres' relative tangential velocity v_y1 - v_y2;
        vs_before, vs_after [m/s]: the contact point's slip velocity; e_t [-]: vs_after /
        vs_before (NaN when vs_before = 0); vn_after [m/s]: the normal separation speed
        (positive); rebound_angle [deg]: atan2(vs_after, vn_after); Ft_max [N]: the largest
        |tangential_force| over the contact (the maximum of the quartic through the five samples
        around the largest, inside the contact; the sample itself at its first or last sample);
        and every field of `records.collision_metrics.CollisionMetrics` (SI units).

    Raises
    ------
    ExtractionError
        No complete collision, or velocities and spins not constant after it; the message names
        `source`.
    """
    source = source or meta.get("path") or "the dump"
    t = np.asarray(columns["time"], float)
    d = np.asarray(columns["overlap"], float)
    vn = np.asarray(columns["normal_velocity"], float)
    vt = np.asarray(columns["tangential_velocity"], float)
    w1 = np.asarray(columns["omega_1"], float)
    w2 = np.asarray(columns["omega_2"], float)
    ft = np.asarray(columns["tangential_force"], float)
    V = float(meta["impact_velocity"])
    try:
        normal = collision_metrics(t, d, vn, columns["normal_force"], impact_velocity=V)
    except ExtractionError as err:
        raise ExtractionError(f"{source}: {err}") from err
    if not np.all(np.isfinite(np.stack([vt, w1, w2, ft]))):
        raise ExtractionError(f"{source}: the tangential columns contain NaN or inf")
    i_s = int(np.nonzero(d > 0)[0][0])
    i_x = i_s + int(np.nonzero(d[i_s:] <= 0)[0][0])
    after = slice(max(i_x, len(t) - AFTER_SAMPLES), len(t))
    if len(t) - i_x < 2:
        raise ExtractionError(f"{source}: fewer than 2 samples after separation")
    R1 = float(meta["radius_1"])
    R2 = meta.get("radius_2")
    R2 = 0.0 if R2 is None else float(R2)
    speed = max(V, abs(vt[0]), abs(vt[0] + R1 * w1[0] + R2 * w2[0]))
    vt_after = _constant_after("tangential_velocity", vt[after], speed, source)
    w1_after = _constant_after("omega_1", w1[after], speed / R1, source)
    w2_after = _constant_after("omega_2", w2[after], speed / (R2 or R1), source)
    vn_after = -_constant_after("normal_velocity", vn[after], speed, source)
    vs_before = float(vt[0] + R1 * w1[0] + R2 * w2[0])
    vs_after = vt_after + R1 * w1_after + R2 * w2_after
    magnitude = np.abs(ft)
    dt = (t[-1] - t[0]) / (len(t) - 1)
    i_m = i_s + int(np.argmax(magnitude[i_s:i_x]))
    if i_s < i_m < i_x - 1 and i_x - i_s >= PEAK_POINTS:
        ft_max = _peak(t, magnitude, i_s, i_x, dt)[0]
    else:
        ft_max = float(magnitude[i_m])
    return {
        "omega_after": w1_after, "omega_2_after": w2_after, "vt_before": float(vt[0]), "vt_after": vt_after,
        "vs_before": vs_before, "vs_after": vs_after,
        "e_t": vs_after / vs_before if vs_before != 0 else math.nan,
        "vn_after": vn_after, "rebound_angle": math.degrees(math.atan2(vs_after, vn_after)), "Ft_max": ft_max,
        **asdict(normal),
    }


def oblique_metrics_of_dump(path) -> dict:
    """`oblique_metrics` of the dump at `path` (an oblique one: eight columns).

    Parameters
    ----------
    path : str or os.PathLike
        The dump file.

    Returns
    -------
    dict
        See `oblique_metrics`.
    """
    from .dump_file import read_dump

    meta, columns = read_dump(path, oblique=True)
    return oblique_metrics(columns, meta, source=str(path))
