"""T, delta_max (hence A) and eps of one collision, from a sampled time series.

Pure functions on arrays (time [s], overlap [m], normal_velocity d(delta)/dt [m/s],
normal_force [N]); no engine and no file in sight.

- Contact start t_s: the overlap crosses zero upwards (linear interpolation between samples).
- Criterion x0: the overlap crosses zero downwards at t_x0; T_x0 = t_x0 - t_s,
  eps_x0 = -d(delta)/dt (t_x0) / V.
- Criterion F0: the normal force first drops to zero at t_F0 (after the contact started);
  T_F0 = t_F0 - t_s, eps_F0 = -d(delta)/dt (t_F0) / V.
- delta_max: the vertex of the parabola through the largest sample and its two neighbours
  (the sampled maximum alone is off by ~(dt/T)^2).

Crossings are interpolated linearly, which is second-order accurate in the sampling step. A force
clipped at exactly zero (an engine that forbids attraction) is extrapolated from the last three
positive samples instead (third order).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class ExtractionError(ValueError):
    """The series does not contain one complete collision."""


@dataclass(frozen=True)
class CollisionMetrics:
    """One collision's characteristics (SI). NaN where a criterion's end was not reached."""

    t_start: float
    delta_max: float
    t_max: float
    T_x0: float
    eps_x0: float
    T_F0: float
    eps_F0: float
    samples_in_contact: int


def _crossing(t, y, i):
    """Time where y crosses zero between samples i-1 and i (linear)."""
    t0, t1, y0, y1 = t[i - 1], t[i], y[i - 1], y[i]
    return t0 + (t1 - t0) * y0 / (y0 - y1)


def _extrapolated_zero(t3, y3, t_next):
    """Zero of the quadratic through three samples, in [t3[-1], t_next] (third order);
    the linear extrapolation of the last two where the quadratic has no zero there."""
    t0 = t3[-1]
    c2, c1, c0 = np.polyfit(t3 - t0, y3, 2)
    roots = np.roots([c2, c1, c0]) if c2 != 0 else np.roots([c1, c0])
    real = roots[np.isreal(roots)].real
    inside = real[(real >= 0) & (real <= t_next - t0)]
    if len(inside):
        return t0 + inside.min()
    slope = (y3[-1] - y3[-2]) / (t3[-1] - t3[-2])
    return min(t0 - y3[-1] / slope, t_next) if slope < 0 else t_next


def _interpolate(t, y, i, at):
    """y at time `at` between samples i-1 and i (linear)."""
    w = (at - t[i - 1]) / (t[i] - t[i - 1])
    return (1 - w) * y[i - 1] + w * y[i]


def _parabola_vertex(t, y, i):
    """(t, y) of the vertex of the parabola through samples i-1, i, i+1."""
    if i == 0 or i == len(y) - 1:
        return t[i], y[i]
    h0, h1 = t[i] - t[i - 1], t[i + 1] - t[i]
    # Divided differences of the interpolating quadratic.
    d1 = (y[i] - y[i - 1]) / h0
    d2 = (y[i + 1] - y[i]) / h1
    c = (d2 - d1) / (h0 + h1)
    if c >= 0:
        return t[i], y[i]
    b = d1 + c * h0  # slope at t[i] of p(t) = y_i + b (t - t_i) + c (t - t_i)^2
    s = -b / (2 * c)  # offset from t[i]
    return t[i] + s, y[i] + b * s + c * s * s


def collision_metrics(time, overlap, normal_velocity, normal_force, impact_velocity) -> CollisionMetrics:
    """Extract T, delta_max and eps under both criteria from one sampled collision."""
    t = np.asarray(time, float)
    d = np.asarray(overlap, float)
    v = np.asarray(normal_velocity, float)
    f = np.asarray(normal_force, float)
    if not (len(t) == len(d) == len(v) == len(f)) or len(t) < 3:
        raise ExtractionError("time, overlap, velocity and force must be equal-length series of 3 or more samples")
    if not np.all(np.isfinite(np.stack([t, d, v, f]))):
        raise ExtractionError("the series contains NaN or inf")
    if d[0] > 0:
        raise ExtractionError("the bodies overlap at the first sample: the run must start before contact")
    touching = np.nonzero(d > 0)[0]
    if len(touching) == 0:
        raise ExtractionError("the bodies never touch (the overlap never becomes positive)")
    i_s = touching[0]
    t_s = _crossing(t, d, i_s)

    after = np.nonzero(d[i_s:] <= 0)[0]
    if len(after) == 0:
        raise ExtractionError("the contact is still open when the series ends (overlap > 0 at the last sample)")
    i_x = i_s + after[0]
    t_x0 = _crossing(t, d, i_x)
    eps_x0 = -_interpolate(t, v, i_x, t_x0) / impact_velocity

    # F0: the first in-contact sample (overlap > 0) whose force is <= 0. Where the force stays
    # positive as long as the bodies overlap (an elastic contact, force ~ delta^{3/2}), the
    # force vanishes with the overlap and both criteria end together.
    drops = np.nonzero(f[i_s:i_x] <= 0)[0]
    if len(drops) == 0:
        t_f0, eps_f0 = t_x0, eps_x0
    elif drops[0] == 0:
        raise ExtractionError("the normal force is not positive at the first sample in contact")
    else:
        i_f = i_s + drops[0]
        if f[i_f] == 0 and i_f - 3 >= i_s:
            # The engine clipped the force at zero (F0 physics): the zero sample says nothing
            # of where the force crossed, so extrapolate the last three positive samples.
            t_f0 = _extrapolated_zero(t[i_f - 3:i_f], f[i_f - 3:i_f], t[i_f])
        else:
            t_f0 = _crossing(t, f, i_f)
        eps_f0 = -_interpolate(t, v, i_f, t_f0) / impact_velocity

    contact = slice(i_s, i_x)
    i_m = i_s + int(np.argmax(d[contact]))
    t_m, d_m = _parabola_vertex(t, d, i_m)
    return CollisionMetrics(
        t_start=float(t_s), delta_max=float(d_m), t_max=float(t_m),
        T_x0=float(t_x0 - t_s), eps_x0=float(eps_x0),
        T_F0=float(t_f0 - t_s), eps_F0=float(eps_f0), samples_in_contact=int(i_x - i_s),
    )
