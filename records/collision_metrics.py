"""T, delta_max (hence A), F_max and eps of one collision, from a sampled time series.

Pure functions on arrays (time [s], overlap [m], normal_velocity d(delta)/dt [m/s],
normal_force [N]); no engine and no file in sight.

The events are read the way the motion allows, so that what the extraction adds to a run's error
is a smooth function of the time step (the ladder extrapolates it away, `engines.ladder`) and not
a jitter that depends on where an event falls between two samples:

- Contact start t_s: before contact the bodies fly freely, so the overlap is exactly the line
  through the last sample before contact with the velocity recorded there; t_s is its zero.
- Criterion x0 (the overlap returns to zero): after contact the bodies fly freely again, at the
  exit velocity; t_x0 is the zero of the free-flight line through the first sample after
  contact, and eps_x0 = -d(delta)/dt there / V, the engine's own exit velocity. Interpolating
  across the end, where the force (~ delta^{1/2} d(delta)/dt) is not smooth, would add an error
  of order dt^{3/2} that jumps with the end's phase on the step grid.
- Criterion F0 (the force first returns to zero): the zero of F / delta^{1/2}, which has the
  zero of F but is smooth near the overlap's zero (F ~ delta^{1/2} times a smooth function
  for Hertz with Kuwabara-Kono damping), on a cubic through four in-contact samples around the
  sign change, or through the last four when the zero lies in the last step before x0 (small K);
  eps_F0 = -d(delta)/dt at t_F0 / V on a cubic through the same samples.
  A force clipped at zero (the engine forbids attraction; it stays at zero while the bodies still
  overlap) ends the contact's dynamics: t_F0 is the zero of the cubic through the last four
  positive samples, extrapolated, and eps_F0 the exit velocity of the free flight that follows.
- delta_max: the maximum of the quartic through the five samples around the largest (the sampled
  maximum alone is off by ~(dt/T)^2); the force's maximum F_max the same way where it lies inside
  the contact, the sample itself where it is the first or the last (a dashpot that acts at once,
  LAMMPS's `damping velocity`, has its largest force at touching).
- The phases of the start and of the x0 end on the step grid (fraction of a step after a
  sample), for the ladder's alignment check (`engines.ladder.PHASE_TOLERANCE`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .quantities import QUANTITIES, derived_values

#: A force whose magnitude stays below this fraction of the maximum force while the bodies still
#: overlap is clipped at zero (an engine's rounding may leave 1e-20 instead of 0).
CLIPPED = 1e-9
#: Samples in a stencil: cubic crossings (4), the quartic around the maximum (5).
CROSSING_POINTS = 4
PEAK_POINTS = 5


class ExtractionError(ValueError):
    """The series does not contain one complete collision."""


@dataclass(frozen=True)
class CollisionMetrics:
    """One collision's characteristics (SI). NaN where a criterion's end was not reached.

    start_phase and end_phase: where the contact starts and where the x0 end falls on the step
    grid, as the fraction of a step after the sample before it, in [0, 1)."""

    t_start: float
    delta_max: float
    t_max: float
    T_x0: float
    eps_x0: float
    T_F0: float
    eps_F0: float
    samples_in_contact: int
    start_phase: float = math.nan
    end_phase: float = math.nan
    force_max: float = math.nan


def _cubic(t, y, t0):
    """Coefficients (highest first) of the polynomial through (t - t0, y)."""
    return np.polyfit(t - t0, y, len(t) - 1)


def _root_in(coefficients, t0, lo, hi) -> float | None:
    """The real root of the polynomial (in t - t0) in [lo, hi] nearest to lo, or None."""
    roots = np.roots(coefficients)
    real = roots[np.abs(roots.imag) <= 1e-9 * max(1.0, float(np.abs(roots).max()))].real + t0
    slack = 1e-9 * (hi - lo)
    inside = real[(real >= lo - slack) & (real <= hi + slack)]
    if not len(inside):
        return None
    return float(min(max(inside[np.argmin(np.abs(inside - lo))], lo), hi))


def _free_flight_zero(t, d, v, i) -> float:
    """Where the free-flight line through sample i (overlap d[i], velocity v[i]) crosses zero."""
    if v[i] == 0:
        raise ExtractionError(f"the bodies do not move at sample {i} (free flight at zero velocity)")
    return float(t[i] - d[i] / v[i])


def _phase(time, t0, dt) -> float:
    """The fraction of a step after the sample before `time` (samples at t0 + k dt)."""
    steps = (time - t0) / dt
    return float(steps - math.floor(steps))


def _f0_in_tail(t, i_s, i_x, drops):
    """The stencil of the F0 crossing of a force that keeps its tail (not clipped), its origin,
    and the interval [lo, hi] of the crossing (hi None: up to the x0 end): around the first
    non-positive sample `drops[0]`, or the last four in contact when every one is positive."""
    if len(drops):
        k = int(drops[0])
        lo, hi = t[k - 1], t[k]
        a = min(max(k - CROSSING_POINTS // 2, i_s), i_x - CROSSING_POINTS)
    else:  # positive at every in-contact sample: the zero, if any, lies in the last step
        lo, hi = t[i_x - 1], None
        a = i_x - CROSSING_POINTS
    stencil = slice(a, a + CROSSING_POINTS)
    t0 = t[a]
    return stencil, t0, lo, hi


def _peak(t, y, i_s, i_x, dt) -> tuple[float, float]:
    """(value, time) of the maximum of y over the contact [i_s, i_x): the quartic through the five
    samples around the largest, its maximum within a step of that sample."""
    i_m = i_s + int(np.argmax(y[i_s:i_x]))
    a = min(max(i_m - PEAK_POINTS // 2, i_s), i_x - PEAK_POINTS)
    peak = slice(a, a + PEAK_POINTS)
    t0 = t[i_m]
    quartic = np.polyfit(t[peak] - t0, y[peak], PEAK_POINTS - 1)
    candidates = [0.0] + [float(r.real) for r in np.roots(np.polyder(quartic))
                          if abs(r.imag) <= 1e-12 * dt and abs(r.real) <= dt]
    s_m = max(candidates, key=lambda s: np.polyval(quartic, s))
    return float(np.polyval(quartic, s_m)), float(t0 + s_m)


def collision_metrics(time, overlap, normal_velocity, normal_force, impact_velocity) -> CollisionMetrics:
    """Extract T, delta_max and eps under both criteria from one sampled collision (see the
    module's docstring for how each event is read).

    Parameters
    ----------
    time : array_like
        Sample times [s], one per step, increasing.
    overlap : array_like
        Overlap delta at each sample [m] (positive in contact).
    normal_velocity : array_like
        d(delta)/dt at each sample [m/s] (positive while approaching).
    normal_force : array_like
        Normal force at each sample [N] (positive repulsive).
    impact_velocity : float
        The approach speed V before contact [m/s].
    """
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
    i_s = int(touching[0])
    after = np.nonzero(d[i_s:] <= 0)[0]
    if len(after) == 0:
        raise ExtractionError("the contact is still open when the series ends (overlap > 0 at the last sample)")
    i_x = i_s + int(after[0])
    if i_x - i_s < PEAK_POINTS + 1:
        raise ExtractionError(f"the contact spans {i_x - i_s} samples, fewer than {PEAK_POINTS + 1}: the time step "
                              "is too coarse to resolve it")
    dt = (t[-1] - t[0]) / (len(t) - 1)
    t_s = _free_flight_zero(t, d, v, i_s - 1)
    t_x0 = _free_flight_zero(t, d, v, i_x)
    eps_x0 = -v[i_x] / impact_velocity

    contact = slice(i_s, i_x)
    if f[i_s] <= 0:
        raise ExtractionError("the normal force is not positive at the first sample in contact")
    scale = float(np.abs(f[contact]).max())
    g = f / np.sqrt(np.where(d > 0, d, np.nan))  # F / delta^{1/2}: smooth where F ~ delta^{1/2}
    # F0 comes after the force's maximum: search from there (the first samples in contact carry a
    # force that starts from zero, which is no end of anything).
    i_fmax = i_s + int(np.argmax(f[contact]))
    after_max = slice(i_fmax, i_x)
    drops = i_fmax + np.nonzero(f[after_max] <= CLIPPED * scale)[0]
    if len(drops) and np.all(np.abs(f[drops[0]:i_x]) <= CLIPPED * scale):
        # Clipped at zero: the dynamics of the contact end at F0, the rest is free flight.
        k = int(drops[0])
        if k - CROSSING_POINTS < i_s:
            raise ExtractionError("the force is clipped to zero before four samples in contact")
        stencil = slice(k - CROSSING_POINTS, k)
        t0 = t[k - CROSSING_POINTS]
        root = _root_in(_cubic(t[stencil], g[stencil], t0), t0, t[k - 1], t[k])
        t_f0 = t[k] if root is None else root
        eps_f0 = -v[k] / impact_velocity
    else:
        tail_drops = i_fmax + np.nonzero(f[after_max] <= 0)[0]
        stencil, t0, lo, hi = _f0_in_tail(t, i_s, i_x, tail_drops)
        root = _root_in(_cubic(t[stencil], g[stencil], t0), t0, lo, t_x0 if hi is None else hi)
        if root is None and not len(tail_drops):
            # The force vanishes with the overlap (Hertz alone, eta = 0): both criteria end together.
            t_f0, eps_f0 = t_x0, eps_x0
        else:
            t_f0 = lo if root is None else root
            eps_f0 = -float(np.polyval(_cubic(t[stencil], v[stencil], t0), t_f0 - t0)) / impact_velocity

    delta_max, t_max = _peak(t, d, i_s, i_x, dt)
    force_max = _peak(t, f, i_s, i_x, dt)[0] if 0 < i_fmax - i_s and i_fmax < i_x - 1 else float(f[i_fmax])
    return CollisionMetrics(
        t_start=float(t_s), delta_max=delta_max, t_max=t_max, force_max=force_max,
        T_x0=float(t_x0 - t_s), eps_x0=float(eps_x0),
        T_F0=float(t_f0 - t_s), eps_F0=float(eps_f0), samples_in_contact=int(i_x - i_s),
        start_phase=_phase(t_s, t[0], dt), end_phase=_phase(t_x0, t[0], dt),
    )


def quantities_of(m: CollisionMetrics, criterion: str, R: float, V: float) -> dict[str, float]:
    """Every quantity of the table (`records.quantities.QUANTITIES`, in its order) of one run under
    `criterion` ('x0' or 'F0'): those read off the collision by their entry's `extract`, the others
    derived from them with the effective radius R [m] and the impact velocity V [m/s].

    Parameters
    ----------
    m : CollisionMetrics
        One run's characteristics (`collision_metrics`).
    criterion : {'x0', 'F0'}
        The end-of-contact criterion: overlap back to zero, or force back to zero.
    R : float
        The effective radius R* [m].
    V : float
        The impact velocity [m/s].
    """
    return derived_values({name: q.extract(m, criterion) for name, q in QUANTITIES.items()
                           if q.derive is None and q.extract is not None}, R, V)
