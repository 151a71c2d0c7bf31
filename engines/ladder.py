r"""The time-step ladder of a gated run: its rungs, where they put the contact on the step grid,
and the Richardson extrapolation of their results to dt -> 0.

Why a ladder
------------
Every engine of the study advances a collision with the same discrete map (LAMMPS and LIGGGHTS:
velocity Verlet, the force computed after the first half kick; YADE: leapfrog; ESyS and Kratos:
symplectic Euler; written on positions x_n and half-step velocities v_{n-1/2} they are one map)::

    F_n = F(x_n, v_{n-1/2}),   v_{n+1/2} = v_{n-1/2} + dt F_n / M*,   x_{n+1} = x_n + dt v_{n+1/2}

The dissipative force therefore sees a velocity half a step old, and the map is first-order in
dt for every law with eta > 0: at dt = T_e/1000 its error (2.4e-4 in T at K = 0.5) is the
study's own, not the engine's. One run at one dt cannot tell an engine error of 1e-6 from it.
A ladder of runs at several dt, extrapolated to dt -> 0, can.

The expansion in dt (h = dt/T_e)
-------------------------------
::

    dissipative (eta > 0):  e(h) = e0 + c_1 h + c_{3/2} h^{3/2} + c_2 h^2 + c_{5/2} h^{5/2} + ...
    elastic (eta = 0):      e(h) = e0 + c_2 h^2 + c_{5/2} h^{5/2} + c_{7/2} h^{7/2} + ...

- The integer powers are the map's smooth global error: first order with the lagged velocity;
  with eta = 0 the map is symmetric (time-reversible), which leaves even powers only.
- The half-integer powers come from where contact starts and ends: there the force is not
  smooth in time. The damping force grows as s^{1/2} (s the time from touching), the Hertz
  force as s^{3/2}; a step that straddles such a point integrates it with a rule that is exact
  only for smooth functions, and the generalised Euler-Maclaurin expansion (Navot) gives terms
  h^{3/2+k} (damping) and h^{5/2+k} (Hertz). A force clipped at zero (F0) has a kink there:
  a term in h^2.
- Their coefficients depend on the phase of that point on the step grid (through the Hurwitz
  zeta function, e.g. zeta(-1/2, theta)). A phase that changes from rung to rung makes them an
  oscillating error that no extrapolation removes; so every rung puts the contact at the same
  phases (`aligned_time_step`, `START_PHASE`).

tests/test_ladder.py measures these powers on the map itself (the orders of successive
differences of its results over eight halvings of dt), and checks the extrapolation on series
of known limit.

Error estimate
--------------
With n rungs the n - 1 leading powers are eliminated exactly. The estimate of what remains is
the difference from the same extrapolation on the finest n - 1 rungs with one power fewer:
about the error of that weaker extrapolation, which bounds the stronger one's. No estimate from
a ladder alone is a guaranteed bound: on random series of the expansion's form, coefficients
uniform in [-1, 1] (tests/test_ladder.py), it holds in 97 % of them (median margin 18); it fails
where the coefficient of h^2 (the first power the weaker extrapolation neglects) nearly
vanishes. On the engines' own map, at every K in 0.01 ... 5 and every quantity, it is 3 to 300
times the true error (below 1e-9 excepted, where round-off decides). The larger of the finest
and the coarsest sub-ladders' differences holds more often (98 %) but is 2 to 4 times wider:
it would put the resolution at the tolerance at K >= 1 with these rungs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from contact_model.damping_forms import DAMPING_FORMS
from contact_model.keywords import KEYWORDS
from contact_model.laws import LAW_REGISTRY

#: Where contact starts on the step grid: half a step after a sample, at every rung (no sample
#: falls at touching, where a rounding-level overlap would decide whether a force acts).
START_PHASE = 0.5
#: The powers of h in the expansion of each damping form (`contact_model.damping_forms`, which owns
#: them; named here for the tests and the docs). A damping force growing as s^{1/4} from touching (the
#: engines' restitution keywords, x^{1/4} x') gives h^{5/4 + k} where the viscoelastic law's s^{1/2}
#: gives h^{3/2 + k}; a linear dashpot whole powers and Hertz's h^{5/2}.
DISSIPATIVE_POWERS = DAMPING_FORMS["half"].ladder_powers()
ELASTIC_POWERS = DAMPING_FORMS["none"].ladder_powers()
QUARTER_POWERS = DAMPING_FORMS["quarter"].ladder_powers()
LINEAR_POWERS = DAMPING_FORMS["velocity"].ladder_powers()
#: Fewest steps a contact may take at a rung (T_e/10, the coarsest production step of the
#: convergence study, gives about 10): the event detections use stencils of up to five samples.
MIN_CONTACT_STEPS = 8
#: A rung whose contact starts further than this (in steps) from START_PHASE is misaligned.
PHASE_TOLERANCE = 1e-4
#: The smallest resolution a ladder claims: below ~3e-9 the estimate can fall short of the true
#: error (measured on the engines' map: 1.2e-9 against an estimate of 1.1e-10 for eps_x0 at
#: K = 0.03; 3.6e-9 against 1.1e-9 at most, at any K), where what remains is no longer a series in
#: dt but the extraction's and the rungs' own rounding. 1e-8 covers every such case with a margin.
RESOLUTION_FLOOR = 1e-8


def form_of(law: str, engine: str | None = None):
    """The damping form (`contact_model.damping_forms`) a run of `law` in `engine` runs: its
    keyword's (law ``default``: the engine's own keyword, `engines.codes.keyword_of`), else the law's.

    Raises
    ------
    ValueError
        For ``default`` without an engine: each code's keyword has its own form.
    """
    from .codes import keyword_of

    entry = LAW_REGISTRY[law]
    if entry.form is not None:
        return entry.form
    if engine is None:
        raise ValueError(f"law {law!r} runs each code's own keyword: name the engine to know its damping form")
    return KEYWORDS[keyword_of(law, engine)].damping_form


def powers_of(eta: float, law: str = "viscoelastic", engine: str | None = None) -> tuple[float, ...]:
    """The powers of h in the error expansion of a run of `law` (in `engine`, for ``default``) with
    viscosity `eta` [Pa s] (or any coefficient: only whether it is 0 matters): its damping form's
    (`form_of`, `contact_model.damping_forms.DampingForm.ladder_powers`)."""
    damped = LAW_REGISTRY[law].is_keyword or eta != 0  # a keyword's coefficient is its own, not eta
    return form_of(law, engine).ladder_powers(1.0 if damped else 0.0)


def rung_factor(factor: float, K: float) -> int:
    """The time-step factor of a rung at dissipation parameter K: `factor` x sqrt(max(1, K)),
    rounded to a whole number (the aligned step rounds again: only the ratios matter).

    The map's error grows with K (its coefficients roughly as K^{0.8} above K = 1: the damping
    time shrinks), so a ladder that reaches 1e-7 at K <= 1 is refined by sqrt(K) above it
    (measured on the map: the self-estimate at K = 5 falls from 1.5e-6 to 3e-7)."""
    return int(round(factor * math.sqrt(max(1.0, K))))


def aligned_time_step(event_time: float, T_e: float, factor: float) -> float:
    """The time step [s] nearest to T_e / factor that fits a whole number of steps into
    `event_time` [s] (the reference duration of the contact up to its singular end), so that the
    end falls at the same phase of the step grid as the start, at every rung:

        dt = event_time / N,   N = max(MIN_CONTACT_STEPS, round(factor event_time / T_e))
    """
    if not (event_time > 0 and T_e > 0 and factor > 0):
        raise ValueError(f"aligned_time_step needs positive times and factor, got {event_time}, {T_e}, {factor}")
    N = max(MIN_CONTACT_STEPS, round(factor * event_time / T_e))
    return event_time / N


def richardson_weights(h, powers) -> np.ndarray:
    """Weights w with sum_k w_k y_k = e0 for y_k = e0 + sum_j c_j h_k^{p_j} (exact for
    len(h) = len(powers) + 1; least squares for more rungs).

    Parameters
    ----------
    h : array_like
        The rungs' step sizes (any unit; only ratios matter), all distinct.
    powers : sequence of float
        The powers p_j to eliminate.
    """
    h = np.asarray(h, dtype=float)
    if len(powers) >= len(h):
        raise ValueError(f"{len(h)} rungs cannot eliminate {len(powers)} powers")
    if len(set(h.tolist())) != len(h):
        raise ValueError("the rungs' step sizes must be distinct")
    # A copy: the cached array is shared by every ladder of these steps.
    return _richardson_weights(tuple(h.tolist()), tuple(powers)).copy()


@lru_cache(maxsize=4096)
def _richardson_weights(h: tuple, powers: tuple) -> np.ndarray:
    """`richardson_weights` of checked rungs, once per (steps, powers): a case's summary
    extrapolates each ladder's T, A, eps, delta_max, F_max under two criteria, and every build
    runs the same ladders, so the same rungs come back some twenty times (a pseudo-inverse each,
    ~6 % of the rule's seconds). The same inputs give the same weights, bit for bit."""
    h = np.asarray(h, dtype=float)
    scale = h.max()
    A = np.column_stack([np.ones_like(h)] + [(h / scale) ** p for p in powers])
    return np.linalg.pinv(A)[0]


def ladder_roundoff(h, floors, powers) -> float:
    """The round-off a ladder's extrapolated value may carry, relative:

        sqrt(sum_k (w_k floor_k)^2),

    w the Richardson weights of the rungs' step sizes `h` eliminating the first len(h) - 1 of
    `powers`, floor_k each rung's own round-off (`RunSpec.roundoff_floor`; independent errors,
    propagated)."""
    h = np.asarray(h, dtype=float)
    w = richardson_weights(h, tuple(powers[: len(h) - 1]))
    return float(np.sqrt(np.sum((w * np.asarray(floors, dtype=float)) ** 2)))


@dataclass(frozen=True)
class Extrapolation:
    """A quantity extrapolated to dt -> 0 over a ladder.

    Attributes
    ----------
    value : float
        The limit dt -> 0 (all rungs, the len(rungs) - 1 leading powers eliminated).
    estimate : float
        |value - the same on the finest len(rungs) - 1 rungs with one power fewer|: the ladder's
        own estimate of its error.
    amplification : float
        sum |w_k|: how much a rung's own error (round-off) can grow in `value`.
    order : float
        The observed order: slope of log|y_k - value| against log h_k (NaN when the rungs sit
        within 100 ulp-level noise of the limit, or there are fewer than two rungs above it).
    """

    value: float
    estimate: float
    amplification: float
    order: float


def extrapolate(h, y, powers) -> Extrapolation:
    """Richardson extrapolation of the rung values `y` at step sizes `h` (at least 3 rungs),
    eliminating the first len(h) - 1 of `powers`; see the module's docstring."""
    h, y = np.asarray(h, dtype=float), np.asarray(y, dtype=float)
    if len(h) != len(y) or len(h) < 3:
        raise ValueError(f"a ladder needs 3 or more rungs with a value each, got {len(h)} and {len(y)}")
    order = np.argsort(h)[::-1]  # coarsest first
    h, y = h[order], y[order]
    used = tuple(powers[: len(h) - 1])
    w = richardson_weights(h, used)
    value = float(w @ y)
    finest = float(richardson_weights(h[1:], used[:-1]) @ y[1:])
    return Extrapolation(value=value, estimate=abs(value - finest), amplification=float(np.abs(w).sum()),
                         order=observed_order(h, y - value))


def observed_order(h, deviation, noise: float = 1e-13) -> float:
    """Least-squares slope of log|deviation| against log h over the rungs whose |deviation|
    exceeds `noise` (NaN with fewer than two)."""
    h, d = np.asarray(h, dtype=float), np.abs(np.asarray(deviation, dtype=float))
    keep = d > noise
    if keep.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(h[keep]), np.log(d[keep]), 1)[0])


def phase_of(time: float, dt: float) -> float:
    """Where `time` falls on the step grid: its fractional part in steps, in [0, 1)."""
    steps = time / dt
    return float(steps - math.floor(steps))


def phase_offset(phase: float, planned: float = START_PHASE) -> float:
    """The signed distance in steps from `planned` to `phase`, on the circle [-0.5, 0.5)."""
    return float((phase - planned + 0.5) % 1.0 - 0.5)
