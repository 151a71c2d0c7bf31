r"""The discrete map every engine of the study advances a collision with, replayed exactly.

LAMMPS and LIGGGHTS (velocity Verlet, ``fix nve/sphere``: the force is computed after the first
half kick), YADE (leapfrog: the driver damps with the velocity of the last half step), ESyS and
Kratos (symplectic Euler) all advance the head-on collision with one map on positions x_n and
half-step velocities w_{n-1/2} (engines/ladder.py says why it is first-order in dt). In the
reference solver's units (x = delta / delta_e, tau = t V / delta_e, forces in M* V^2 / delta_e)::

    f_n       = x_n^{1/2} ((5/4) x_n + K w_{n-1/2})   where x_n > 0, else 0   (clipped: max(f_n, 0))

(or (5/4) x_n^{3/2} + c x_n^p w_{n-1/2} for a law of damping power p: `replay`'s ``power``)
    w_{n+1/2} = w_{n-1/2} - h f_n
    x_{n+1}   = x_n + h w_{n+1/2}

with h = dt V / delta_e. The contact starts at x = 0 moving at w = 1, `start_phase` of a step after
sample `gap_steps`. A sample's record is what the engines record: (tau_n, x_n, the full-step rate
w_n = w_{n-1/2} - (h/2) f_n, f_n).

Two uses: the tests measure on it the powers of the error expansion (`engines.ladder`), and the
size of the rounding of positions stored at their magnitude (`RunSpec.roundoff_floor`); and
replayed at an engine run's own dt it is the discrete reference of that run: an engine that
implements the law exactly differs from it by round-off alone, at any dt.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def _advance(c, power, h, steps, x, w, clipped, offset):
    """The map's steps with the damping c x^power x' (power 1/2: the viscoelastic law, computed as
    x^{1/2} ((5/4) x + K w) so that its records stay bit for bit what they were; 1/4: the
    restitution keywords; 0: a linear dashpot, whose force jumps to c w at touching)."""
    out = np.empty((steps + 1, 4))
    for n in range(steps + 1):
        overlap = x + offset
        f = 0.0
        if overlap > 0.0:
            root = math.sqrt(overlap)
            if power == 0.5:
                f = root * (1.25 * overlap + c * w)
            else:
                f = 1.25 * overlap * root + c * overlap**power * w
            if clipped and f < 0.0:
                f = 0.0
        out[n, 0] = n * h
        out[n, 1] = overlap
        out[n, 2] = w - 0.5 * h * f
        out[n, 3] = f
        w = w - h * f
        x = x + h * w
    return out


def replay(K: float, h: float, steps: int, start_phase: float = 0.5, gap_steps: int = 20,
           clipped: bool = False, position_scale: float = 0.0, power: float = 0.5) -> np.ndarray:
    """The map's record of a collision: an array (steps + 1, 4) of (tau, x, rate, force) in the
    reference's units.

    Parameters
    ----------
    K : float
        The damping coefficient c of c x^p x' (0: Hertz alone): for p = 1/2 the dissipation
        parameter K [-].
    h : float
        The step dt V / delta_e [-].
    steps : int
        Steps to take after the first sample [-].
    start_phase : float
        Contact starts `start_phase` of a step after sample `gap_steps` [-].
    gap_steps : int
        The samples before the contact starts [-].
    clipped : bool
        Clip the force at zero (the law 'viscoelastic_clipped') [-].
    position_scale : float
        0: the overlap is the stored coordinate itself (no rounding beyond the overlap's own).
        X > 0: the coordinate is stored as a centre at -X - (gap) and the overlap formed as
        X + centre, as the engines store centres of magnitude R (X = R / delta_e): their rounding
        [delta_e].
    power : float
        The damping's power p of x^p x' (`contact_model.laws.DAMPING_POWER`): 1/2 the
        viscoelastic law (K), 1/4 the restitution keywords (b), 0 a linear dashpot (c) [-].

    Returns
    -------
    numpy.ndarray
        Shape (steps + 1, 4): tau [delta_e/V], x [delta_e], the full-step rate w_n [V] and the
        force f_n [M* V^2/delta_e].

    Raises
    ------
    ValueError
        For a step h or a step count that is not positive.
    """
    if not (h > 0 and steps > 0 and math.isfinite(h)):
        raise ValueError(f"replay needs a positive step and step count, got h = {h}, steps = {steps}")
    start = -(gap_steps + start_phase) * h
    return _advance(float(K), float(power), float(h), int(steps), start - position_scale, 1.0, bool(clipped),
                    float(position_scale))
