r"""The time-step advisor: how wrong is a collision at the step I run, and which step do I need?

    python -m postprocess.timestep cases/mine.yaml --law <law> [--code <code>]
        [--restitution 0.8 | --K 0.1 | --velocity 2 m/s] --tolerance 1e-3 [--dt 0.2T_R] [--json]

For each geometry of the case and each quantity (T, A, delta_max, F_max, eps) it answers, from the
engines' discrete map (`reference.engine_map`, which every build of the study follows to its
rounding: docs/timestep.md) replayed at 24 phases of the contact's start on the step grid:

- the largest dt that keeps the quantity's relative error within the tolerance at *every* phase
  (``dt_max``), in seconds, as a fraction of the Rayleigh time T_R and of the Hertz time T_e;
- the error at the user's dt (``--dt``: seconds, or a multiple of T_R or T_e), else at dt_max, as
  min / median / max over the phases: a production run has every phase at once, so the band, not
  its middle, is the honest error bar.

For an oblique case, ``--model <tangential model> [--impact-index i]`` answers instead for one
oblique impact of the sphere on a plane: omega', e_t, the rebound angle, v_t', T and eps
(`analysis.oblique_timestep`; docs/timestep.md, "Oblique impacts").

T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766), G = Y / (2 (1 + nu)) of the sphere (body 1;
`contact_model.collision_scales.rayleigh_time`: Y = 2 E*, nu = 0 where the case gives only E*), and
T_e = tau_e delta_e / V, Hertz's contact time (tau_e = 2.9432...).

The laws are the study's (`contact_model.laws`) and the engines' keywords (`contact_model.keywords`,
by their registry name, e.g. ``lammps:tsuji``); ``default`` needs ``--code``. The model's laws take
the case's viscosity at ``--velocity`` (or at the velocity giving ``--K``), or the viscosity that
restitutes ``--restitution`` at the velocity; a keyword is told ``--restitution``.

``--json`` prints a list of objects, one per geometry and quantity, with the keys law, geometry,
quantity, criterion, tolerance, dt_max_s, dt_max_over_T_R, dt_max_over_T_e, dt_s, err_min,
err_median, err_max (the last three at ``dt_s``: the user's --dt, else dt_max_s, else the finest
step scanned), note, T_R_s, T_e_s, V. A value that does not exist is null (never NaN): dt_max_*
where no step of the scanned grid holds the tolerance, err_* where the collision cannot be read at
dt_s; ``note`` then says why (else null).

dt_max and err_* are against the law's own equation; for a keyword, that is what the keyword
restitutes as dt -> 0, not what it was told (LAMMPS's tsuji told 0.7 restitutes 0.7777). Its
promise is answered beside it: every row has keyword, eps_requested (what it was told) and
eps_delivered (its own equation's restitution, `contact_model.keywords.promised_restitution`); the
row of eps has promise_min, promise_median, promise_max (eps at dt_s over the phases, divided by
eps_requested, minus 1) and dt_max_for_request_s (_over_T_R, _over_T_e: the largest dt holding
|eps / eps_requested - 1| within the tolerance at every phase), null with request_note saying why
where none exists (where the promise alone exceeds the tolerance, no step meets the request). All
these keys are null for the model's laws, and the band's and the step's in the rows of T, A,
delta_max and F_max (a stable schema).

A request it cannot answer prints ``{"error": {"argument": ..., "message": ...}}`` (with ``file``
and ``field`` for a case file's mistake) and exits with status 2; the message goes to stderr too.

Refused, naming the argument (docs/timestep.md): --K outside (0, 10] or with --velocity (--K picks
the velocity); --restitution outside (0, 1), or one the law cannot restitute, or with the law
``elastic``; --velocity (or the one --K or the case gives) not positive and finite, or whose Hertz
overlap exceeds the study's ``max_overlap_ratio`` R* (config/config.yaml); --tolerance outside
[TOLERANCE_FLOOR, 1); --dt not positive and finite, longer than T_e, or needing more than
MAX_STEPS steps over the contact.
"""

from __future__ import annotations

import argparse
import difflib
import json
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from contact_model import CaseError, load_case
from contact_model.keywords import KEYWORDS, keyword_reference, promised_restitution
from contact_model.laws import LAW_REGISTRY
from engines.codes import CODES, integrators, keyword_of
from records.collision_metrics import ExtractionError, collision_metrics
from reference import HERTZ_TAU, solve_collision
from reference.collision_ode import K_RANGE

#: The quantities the advisor answers for (A = pi R* delta_max: its relative error is delta_max's).
QUANTITIES = ("T", "A", "delta_max", "F_max", "eps")
#: The start phases of the contact on the step grid: (k + 1/2) / PHASES.
PHASES = 24
#: The dt grid it scans, in units of T_R (log-spaced), before the bisection refines dt_max.
GRID_OVER_T_R = np.geomspace(1e-4, 0.6, 28)
GAP_STEPS = 3
#: Finer grid steps that must pass too before a passing step is taken as dt_max's lower bound
#: (the error need not shrink monotonically with dt at coarse steps), and the bisections after.
CONFIRM = 2
BISECTIONS = 5
#: The most steps one replay of a collision may take (its record is 32 bytes a step: 64 MB; the
#: PHASES replays of a step take a few seconds). A --dt that needs more is refused; the grid's
#: steps that would are not scanned.
MAX_STEPS = 2_000_000
#: The smallest tolerance answered: the reference solution is integrated to about 1e-12
#: (reference/collision_ode.py) and the map follows every build to 8e-13 (docs/timestep.md), so
#: below this their own errors would be a sizeable part of the error the advisor measures.
TOLERANCE_FLOOR = 1e-10
#: The study's config, whose `max_overlap_ratio` the advisor applies as the study does (engines.plan).
CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


class AdvisorError(ValueError):
    """A request the advisor cannot answer; the message names the argument or the case field.

    Parameters
    ----------
    message : str
        What is wrong, starting with the argument and the value read.
    argument : str or None
        The command-line argument at fault ('--K', '--dt', ...), or 'case' for the case file.
    field : str or None
        The case file's field at fault, where the argument is 'case'.
    """

    def __init__(self, message: str, argument: str | None = None, field: str | None = None):
        super().__init__(message)
        self.argument, self.field = argument, field


def max_overlap_ratio() -> float:
    """The study's `max_overlap_ratio` (config/config.yaml): the largest Hertz overlap delta_e / R*
    it runs (engines.plan leaves faster impacts out); 0.5, engines.plan's default, where the
    checkout has no config or the config does not say."""
    try:
        text = CONFIG.read_text()
    except OSError:
        return 0.5
    return float((yaml.safe_load(text) or {}).get("max_overlap_ratio", 0.5))


@dataclass(frozen=True)
class Collision:
    """One geometry's collision in the map's units: its law's damping (power, coefficient, clip),
    the criterion its quantities end at, its reference characteristics, and the SI scales.

    For a keyword (a law told a restitution): its registry name (`keyword`), the restitution it
    was asked for (`requested`, [-]) and what its own equation restitutes for it as dt -> 0
    (`delivered`, [-]: `contact_model.keywords.promised_restitution`, under `criterion`); the
    three are None for the model's laws."""

    law: str
    geometry: str
    power: float
    coefficient: float
    clipped: bool
    criterion: str
    reference: dict
    V: float
    T_e: float
    T_R: float
    delta_e: float
    K: float
    keyword: str | None = None
    requested: float | None = None
    delivered: float | None = None

    @property
    def tau_end(self) -> float:
        """Where the run must last to: the overlap's return (after a clipped force's free flight)."""
        r = self.reference
        return r.get("tau_return", r["tau_0"] if math.isfinite(r["tau_0"]) else r["tau_f"] + 1.0)


def errors_at(c: Collision, h: float, phases=None) -> dict[str, np.ndarray]:
    """The relative errors of each quantity at map step h (dt V / delta_e), one per phase (NaN
    where the collision cannot be read at that step: too few samples in contact).

    Parameters
    ----------
    c : Collision
        The collision.
    h : float
        The map's step, dt V / delta_e [-].
    phases : array_like or None
        The contact's start phases on the step grid (fractions of a step); default PHASES of
        them, (k + 1/2) / PHASES.

    Returns
    -------
    dict of str to numpy.ndarray
        {quantity: error per phase} for `QUANTITIES`, each against the law's own equation (the
        reference row of `c`); for a keyword also ``eps_request``: eps / `Collision.requested`
        - 1, the restitution at that step against what the keyword was asked for [-].
    """
    phases = (np.arange(PHASES) + 0.5) / PHASES if phases is None else np.asarray(phases)
    r = c.reference
    tau_ref = r["tau_0"] if c.criterion == "x0" else r["tau_f"]
    eps_ref = r["eps_x0"] if c.criterion == "x0" else r["eps_F0"]
    from reference.engine_map import replay  # numba: imported when a collision is replayed, not for a refusal

    steps = steps_for(c, h)
    if steps > MAX_STEPS:
        raise AdvisorError(f"a step of {h:.3g} delta_e / V needs {steps:.3g} steps over the {c.geometry} contact, more "
                           f"than the {MAX_STEPS:,} the advisor replays", "--dt")
    out = {q: np.full(len(phases), np.nan) for q in QUANTITIES + (("eps_request",) if c.requested is not None else ())}
    for k, phase in enumerate(phases):
        rec = replay(c.coefficient, h, steps, start_phase=float(phase), gap_steps=GAP_STEPS, clipped=c.clipped,
                     power=c.power)
        try:
            m = collision_metrics(rec[:, 0], rec[:, 1], rec[:, 2], rec[:, 3], impact_velocity=1.0)
        except ExtractionError:
            continue
        T, eps = (m.T_x0, m.eps_x0) if c.criterion == "x0" else (m.T_F0, m.eps_F0)
        out["T"][k] = T / tau_ref - 1.0
        out["A"][k] = out["delta_max"][k] = m.delta_max / r["x_max"] - 1.0
        out["F_max"][k] = m.force_max / r["force_max"] - 1.0
        out["eps"][k] = eps / eps_ref - 1.0 if eps_ref > 0 else np.nan
        if c.requested is not None:
            out["eps_request"][k] = eps / c.requested - 1.0
    return out


def steps_for(c: Collision, h: float) -> float:
    """The steps one replay of `c` at map step h (dt V / delta_e) takes: the gap before contact, the
    contact (to `Collision.tau_end`) with 30 % to spare, and 10 more (a float: inf for h -> 0).

    Parameters
    ----------
    c : Collision
        The collision.
    h : float
        The map's step, dt V / delta_e [-].
    """
    if not h > 0:
        return math.inf
    return GAP_STEPS + math.ceil(min(1.3 * c.tau_end / h, 1e300)) + 10


def finest_step(c: Collision) -> float | None:
    """The finest step of `GRID_OVER_T_R` [T_R] a replay of `c` takes within MAX_STEPS (None: not one).

    Parameters
    ----------
    c : Collision
        The collision (its T_R [s], V [m/s], delta_e [m] and reference).
    """
    to_h = c.T_R * c.V / c.delta_e
    within = [x for x in GRID_OVER_T_R if steps_for(c, x * to_h) <= MAX_STEPS]
    return float(min(within)) if within else None


def largest_step(c: Collision, tolerance: float, phases=None, cache: dict | None = None,
                 quantities: tuple[str, ...] = QUANTITIES) -> dict[str, float]:
    """{quantity: dt_max / T_R}: the largest dt keeping |error| <= tolerance at every phase. The
    grid `GRID_OVER_T_R` is scanned from its coarsest step down (a step that cannot be read
    fails); dt_max lies between the first step that passes, with the next CONFIRM finer steps
    passing too, and the step above it, and is refined there by bisection in log dt. 0 where not
    even the finest step of the grid passes (steps needing more than MAX_STEPS are not scanned:
    `finest_step`). `phases` (default: PHASES of them) and `cache` ({dt /
    T_R: errors}, shared by calls for several tolerances) are passed on to `errors_at`;
    `quantities`: the keys of `errors_at` answered (``("eps_request",)``: a keyword's restitution
    against what it was asked for, instead of against its own equation).

    Parameters
    ----------
    c : Collision
        The collision.
    tolerance : float
        The largest relative |error| allowed [-].
    phases : array_like or None
        The contact's start phases on the step grid (fractions of a step); None: PHASES of them.
    cache : dict or None
        {dt / T_R: `errors_at`'s errors}, filled and reused across calls (None: a new one).
    quantities : tuple of str
        The keys of `errors_at` answered (default `QUANTITIES`).
    """
    to_h = c.T_R * c.V / c.delta_e  # dt / T_R -> h
    cache = {} if cache is None else cache

    def passes(x):
        if x not in cache:
            cache[x] = errors_at(c, x * to_h, phases)
        e = cache[x]
        return {q: bool(np.all(np.abs(e[q]) <= tolerance)) for q in quantities}

    return scan_grid(passes, lambda x: steps_for(c, x * to_h) <= MAX_STEPS, quantities)


def scan_grid(passes, fits, quantities: tuple[str, ...]) -> dict[str, float]:
    """{quantity: dt_max / T_R} from a pass/fail test of each step: the scan of `largest_step`.

    `GRID_OVER_T_R` is scanned from its coarsest step down to the finest that `fits`; dt_max lies
    between the first step that passes, with the next CONFIRM finer steps passing too, and the step
    above it, and is refined there by BISECTIONS bisections in log dt (0 where no step passes).

    Parameters
    ----------
    passes : callable
        passes(x) -> {quantity: bool}: whether the step x T_R holds the tolerance at every phase.
    fits : callable
        fits(x) -> bool: whether a replay at x T_R is within its step budget (the scan stops at
        the first that is not).
    quantities : tuple of str
        The quantities answered.
    """
    found: dict[str, tuple[float, float | None]] = {}
    candidate: dict[str, tuple[float, float | None, int]] = {}  # q -> (x, the failing step above, passes so far)
    above = None
    for x in GRID_OVER_T_R[::-1]:
        if not fits(x):
            break
        ok = passes(x)
        for q in quantities:
            if q in found:
                continue
            if not ok[q]:
                candidate.pop(q, None)
            elif q in candidate:
                top, fail, n = candidate[q]
                candidate[q] = (top, fail, n + 1)
            else:
                candidate[q] = (x, above, 1)
            if q in candidate and candidate[q][2] > CONFIRM:
                found[q] = candidate[q][:2]
        if len(found) == len(quantities):
            break
        above = x
    out = {}
    for q in quantities:
        good, bad = found.get(q) or (candidate[q][:2] if q in candidate else (None, None))
        if good is None:
            out[q] = 0.0
            continue
        for _ in range(BISECTIONS if bad is not None else 0):
            mid = math.sqrt(good * bad)
            if passes(mid)[q]:
                good = mid
            else:
                bad = mid
        out[q] = float(good)
    return out


def parse_dt(text: str, T_R: float, T_e: float) -> float:
    """A time step from '0.2T_R', '0.2 T_R', '0.01 T_e', '1e-7', '1e-7 s' or '50 ns'.

    Parameters
    ----------
    text : str
        The --dt argument.
    T_R, T_e : float
        The Rayleigh and the Hertz time [s], the units of 'T_R' and 'T_e'.

    Returns
    -------
    float
        The step [s], positive and finite; AdvisorError naming --dt otherwise.
    """
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(T_R|T_e|s|ms|us|µs|ns)?\s*", text)
    try:
        value = float(m.group(1)) if m else math.nan
    except ValueError:
        value = math.nan
    factor = {"T_R": T_R, "T_e": T_e, "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9}[m.group(2) or "s"] \
        if m else math.nan
    dt = value * factor
    if not (m and math.isfinite(value) and value > 0 and math.isfinite(dt) and dt > 0):
        raise AdvisorError(f"--dt {text!r}: give a positive step in seconds (1e-7, 50 ns) or as a multiple of the "
                           "Rayleigh or Hertz time (0.2T_R, 0.01T_e)", "--dt")
    return dt


def check_dt(c: Collision, dt: float, text: str) -> None:
    """Refuse (AdvisorError naming --dt) a step `dt` [s] the map cannot answer for `c`: longer than
    the Hertz time T_e (no step would fall within the contact), or needing more than MAX_STEPS
    steps over the contact (the finest step it answers for is named).

    Parameters
    ----------
    c : Collision
        The collision (its T_e, T_R [s], V [m/s], delta_e [m]).
    dt : float
        The time step [s].
    text : str
        The --dt argument as given, quoted in the message.
    """
    if dt > c.T_e:
        raise AdvisorError(f"--dt {text!r}: {dt:.3g} s is longer than the whole {c.geometry} contact (T_e = "
                           f"{c.T_e:.3g} s, {c.T_e / c.T_R:.3g} T_R): no step would fall within it; give a step "
                           "below T_e", "--dt")
    steps = steps_for(c, dt * c.V / c.delta_e)
    if steps > MAX_STEPS:
        finest = 1.3 * c.tau_end / (MAX_STEPS - GAP_STEPS - 11) * c.delta_e / c.V
        raise AdvisorError(f"--dt {text!r}: {dt:.3g} s needs {steps:.3g} steps over the {c.geometry} contact, more "
                           f"than the {MAX_STEPS:,} a replay of the map may take (32 bytes a step, {PHASES} start "
                           f"phases); the finest step answered is {finest:.3g} s ({finest / c.T_R:.3g} T_R)", "--dt")


def _velocity(text: str) -> float:
    """The --velocity argument ('2', '2 m/s') [m/s]: positive and finite, else AdvisorError."""
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(m/s)?\s*", text)
    try:
        v = float(m.group(1)) if m else math.nan
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise AdvisorError(f"--velocity {text!r}: give the relative impact velocity in m/s, e.g. 2 or '2 m/s'",
                           "--velocity")
    return v


def collisions(case, law: str, code: str | None, restitution: float | None, K: float | None,
               velocity: float | None) -> list[Collision]:
    """One `Collision` per geometry of `case` under `law` (see the module's docstring).

    Parameters
    ----------
    case : contact_model.Case
        The case (its pairs, viscosity and `impact:`).
    law, code : str, str or None
        A law of the study or a keyword's registry name; the code of the law ``default``.
    restitution : float or None
        The restitution [-] told a keyword, or restituted by a model's law at the velocity.
    K : float or None
        The dissipation parameter [-]: picks the velocity at which the case's viscosity gives it.
    velocity : float or None
        The relative impact velocity [m/s].

    Raises
    ------
    AdvisorError
        Naming the argument (or the case's field) of a request it cannot answer.
    """
    keyword = _keyword(law, code)
    if restitution is not None and not 0 < restitution < 1:
        raise AdvisorError(f"--restitution {restitution:g}: a restitution coefficient lies in (0, 1)", "--restitution")
    if K is not None and not (math.isfinite(K) and K_RANGE[0] < K <= K_RANGE[1]):
        raise AdvisorError(f"--K {K:g}: the dissipation parameter must lie in ({K_RANGE[0]:g}, {K_RANGE[1]:g}], where "
                           "the reference solves the collision (reference/collision_ode.py); for no dissipation "
                           "use --law elastic", "--K")
    if K is not None and velocity is not None:
        raise AdvisorError(f"--K {K:g} and --velocity {velocity:g}: give one of them. --K picks the impact velocity at "
                           "which the case's viscosity gives that K, so with --velocity it would be ignored; for "
                           f"K = {K:g} at {velocity:g} m/s set the case's viscosity to the one that gives it "
                           "(python -m contact_model.viscosity_for_k), or give --restitution", "--K")
    if keyword is None and restitution is not None and LAW_REGISTRY[law].damping == "none":
        raise AdvisorError(f"--restitution {restitution:g}: the law {law!r} has no damping (it restitutes 1); "
                           "drop --restitution or choose a dissipative law", "--restitution")
    limit = max_overlap_ratio()
    out = []
    for pair in case.pairs:
        V, source = velocity, ("--velocity", None)
        if V is None and K is not None:
            if pair.eta == 0:
                raise AdvisorError(f"--K {K:g}: the case's viscosity is 0 ({case.path}), so no velocity gives a K; "
                                   "give --velocity", "--K")
            V, source = pair.velocity_for_dissipation(K), ("--K", None)
        if V is None and case.velocities:
            V, source = case.velocities[0], ("case", "impact.velocity")
        if V is None and case.K and pair.eta > 0:
            V, source = pair.velocity_for_dissipation(case.K[0]), ("case", "impact.K")
        if V is None:
            raise AdvisorError(f"{case.path}: no impact velocity: give --velocity (or --K), or `impact:` in the case",
                               "--velocity")
        where = (f"--velocity {V:g}" if source[0] == "--velocity" else f"--K {K:g} (V = {V:.3g} m/s)"
                 if source[0] == "--K" else f"{case.path}: field '{source[1]}' (V = {V:.3g} m/s)")
        s = pair.scales(V)
        ratio = s["delta_e"] / pair.R
        if not ratio <= limit:
            raise AdvisorError(f"{where}: the {pair.geometry} Hertz overlap would be {ratio:.3g} R* (> {limit:g} R*, "
                               "max_overlap_ratio in config/config.yaml): beyond Hertz's premise of a small contact, "
                               "so the study does not run it; give a lower velocity", *source)
        common = dict(geometry=pair.geometry, V=V, T_e=s["T_e"], T_R=pair.rayleigh_time(), delta_e=s["delta_e"])
        if keyword is not None:
            k = KEYWORDS[keyword]
            told, told_by = restitution, ("--restitution", None)
            if told is None and case.restitutions:
                told, told_by = case.restitutions[0], ("case", "impact.restitution")
            if told is None:
                raise AdvisorError(f"--law {law}: a keyword is told a restitution: give --restitution (e.g. 0.8)",
                                   "--restitution")
            refused = k.refuses(k.told_for(told))
            if refused:
                what = f"--restitution {told:g}" if told_by[0] != "case" else f"{case.path}: field 'impact.restitution'"
                raise AdvisorError(f"{what}: {refused}", *told_by)
            row = keyword_reference(keyword, told, 0.0)
            out.append(Collision(law=law, power=k.damping_form.power,
                                 coefficient=row["b"], clipped=k.clipped, criterion=k.criterion, reference=row,
                                 K=math.nan, keyword=keyword, requested=float(told),
                                 delivered=promised_restitution(keyword, told), **common))
            continue
        entry = LAW_REGISTRY[law]
        if entry.damping == "none":
            Kv = 0.0
        elif restitution is not None:
            from reference.dissipation_for_restitution import dissipation_for_restitution

            try:
                Kv = dissipation_for_restitution(restitution, entry.aligned_end)
            except ValueError as err:
                raise AdvisorError(f"--restitution {restitution:g}: the law {law!r} cannot restitute it: {err}",
                                   "--restitution") from None
        elif K is not None:
            Kv = K
        else:
            Kv = s["K"]
            if not K_RANGE[0] < Kv <= K_RANGE[1]:
                raise AdvisorError(f"{where}: K = {Kv:.3g} in {pair.geometry}, outside ({K_RANGE[0]:g}, "
                                   f"{K_RANGE[1]:g}] where the reference is solved; give --K or --restitution",
                                   *source)
        row = solve_collision(Kv)
        out.append(Collision(law=law, power=0.5, coefficient=Kv, clipped=bool(entry.clipped),
                             criterion=entry.aligned_end, reference=row, K=Kv, **common))
    return out


def _keyword(law: str, code: str | None) -> str | None:
    """The keyword a law runs (None for the model's laws); AdvisorError for an unknown law."""
    if law in KEYWORDS:
        return law
    if law not in LAW_REGISTRY:
        known = list(LAW_REGISTRY) + list(KEYWORDS)
        close = difflib.get_close_matches(law, known, n=1, cutoff=0.6)
        guess = f" (did you mean {close[0]!r}?)" if close else ""
        raise AdvisorError(f"--law {law!r} is not a law of the study{guess}; known: {', '.join(known)}", "--law")
    if law == "default":
        if code not in CODES:
            raise AdvisorError(f"--law default is each code's own keyword: name the code with --code "
                               f"({', '.join(CODES)})", "--code")
        return keyword_of(law, code)
    return LAW_REGISTRY[law].keyword


def _unreadable(c: Collision, h: float) -> str:
    """Why the collision cannot be read at map step h: the first start phase's extraction error."""
    from reference.engine_map import replay

    for phase in (np.arange(PHASES) + 0.5) / PHASES:
        rec = replay(c.coefficient, h, int(steps_for(c, h)), start_phase=float(phase), gap_steps=GAP_STEPS,
                     clipped=c.clipped, power=c.power)
        try:
            collision_metrics(rec[:, 0], rec[:, 1], rec[:, 2], rec[:, 3], impact_velocity=1.0)
        except ExtractionError as err:
            return f"not readable at that step ({err})"
    return "not readable at that step (the reference restitution is 0)"


def _percent(x: float) -> str:
    """A relative difference as a signed percentage of three significant digits ('+11.1 %')."""
    return f"{100.0 * x:+.3g} %"


def promise_note(c: Collision, tolerance: float, offset_at: float | None = None) -> str | None:
    """Why no time step meets `tolerance` on the restitution `c` was asked for: its own equation
    restitutes `Collision.delivered` as dt -> 0, further from the request than the tolerance.

    Parameters
    ----------
    c : Collision
        A keyword's collision (else None is returned).
    tolerance : float
        The relative error [-] of eps against the request.
    offset_at : float or None
        A step [T_R] at which the map's own error happens to bring eps within the tolerance of
        the request at every start phase (named as the cancellation it is), or None.

    Returns
    -------
    str or None
        The note; None where the promise is within the tolerance (or `c` is not a keyword).
    """
    if c.requested is None or abs(c.delivered / c.requested - 1.0) <= tolerance:
        return None
    head = (f"the keyword's own equation restitutes {c.delivered:.4g} when told {c.requested:g} "
            f"({_percent(c.delivered / c.requested - 1.0)}): ")
    if offset_at is None:
        return f"{head}no time step meets a tolerance of {tolerance:g} on the request"
    return (f"{head}as dt -> 0 no time step meets a tolerance of {tolerance:g} on the request; at {offset_at:.3g} T_R "
            "the step's own error happens to offset the promise at every start phase, a cancellation that finer "
            "steps undo")


def request_step(c: Collision, tolerance: float, cache: dict | None = None) -> tuple[float | None, str | None]:
    """The largest dt keeping a keyword's restitution within `tolerance` of what it was asked for.

    Parameters
    ----------
    c : Collision
        A keyword's collision (`Collision.requested` set).
    tolerance : float
        The relative error [-] of eps against the request, to hold at every start phase.
    cache : dict or None
        {dt / T_R: `errors_at`'s answer}, shared with `largest_step` (and the user's step).

    Returns
    -------
    (float or None, str or None)
        dt_max / T_R [-] against the request (None where none exists), and why it does not, else
        None. Where the promise alone exceeds the tolerance the error tends to it as dt -> 0 and
        no step is sought (`promise_note`; a step of `cache` where the map's own error happens
        to offset it at every phase is named as such); otherwise the grid is scanned as for
        `largest_step`.
    """
    cache = {} if cache is None else cache
    if promise_note(c, tolerance) is not None:
        offset = [x for x, e in cache.items() if np.all(np.abs(e["eps_request"]) <= tolerance)]  # NaN: not held
        return None, promise_note(c, tolerance, max(offset) if offset else None)
    x = largest_step(c, tolerance, cache=cache, quantities=("eps_request",))["eps_request"]
    if x > 0:
        return x, None
    finest = finest_step(c)
    return None, (f"no step of the grid down to {finest:.3g} T_R ({finest * c.T_R:.3g} s) holds the tolerance on "
                  "the request" if finest is not None else
                  f"no step of the grid is within the {MAX_STEPS:,} steps a replay may take")


def advise(c: Collision, tolerance: float, dt_s: float | None) -> list[dict]:
    """The advisor's answer for one geometry: one row per quantity (the --json objects).

    Parameters
    ----------
    c : Collision
        The geometry's collision.
    tolerance : float
        The relative error [-] to hold at every start phase.
    dt_s : float or None
        The user's step [s] (checked by `check_dt`), or None: the errors are given at dt_max (or,
        where no step of the grid holds the tolerance, at the finest step scanned).

    Returns
    -------
    list of dict
        One row per quantity; dt_max_* and err_* are None where they do not exist, ``note`` says why.
        dt_max_* and err_* are against the law's own equation (a keyword's: what it restitutes as dt
        -> 0). For a keyword every row names it (``keyword``) and gives ``eps_requested`` (what it
        was asked for) and ``eps_delivered`` (its own equation's restitution,
        `contact_model.keywords.promised_restitution`); the row of eps also ``promise_min``,
        ``promise_median``, ``promise_max`` (eps at ``dt_s`` over the phases / eps_requested - 1)
        and ``dt_max_for_request_s`` (``_over_T_R``, ``_over_T_e``: the largest dt holding
        |eps / eps_requested - 1| <= tolerance at every phase, `request_step`), with
        ``request_note`` saying why it is None. These keys are None in every other row and for
        the model's laws.
    """
    to_h = c.V / c.delta_e  # seconds -> map step
    cache: dict[float, dict] = {}
    largest = largest_step(c, tolerance, cache=cache)
    finest = finest_step(c)

    def errors(x):  # at dt = x T_R, cached with largest_step's scan
        if x not in cache:
            cache[x] = errors_at(c, x * c.T_R * to_h)
        return cache[x]

    def band(e, key):  # min / median / max of the phases' values, None where any phase is unreadable
        readable = bool(np.isfinite(e).all())
        return {f"{key}_{w}": float(f(e)) if readable else None
                for w, f in (("min", np.min), ("median", np.median), ("max", np.max))}

    rows = []
    for q in QUANTITIES:
        x_max = largest[q] if largest[q] > 0 else None
        note = None
        if x_max is None:
            note = (f"no step of the grid down to {finest:.3g} T_R ({finest * c.T_R:.3g} s) holds the tolerance"
                    if finest is not None else
                    f"no step of the grid is within the {MAX_STEPS:,} steps a replay may take")
        at = dt_s / c.T_R if dt_s is not None else x_max if x_max is not None else finest  # [T_R]
        e = errors(at)[q] if at is not None else np.full(PHASES, np.nan)
        readable = bool(np.isfinite(e).all())
        if at is not None and not readable:
            unread = _unreadable(c, at * c.T_R * to_h)
            note = f"{note}; {unread}" if note else unread
        elif x_max is None and dt_s is None and at is not None:
            note += "; the errors are at that finest step"
        request = {"keyword": c.keyword, "eps_requested": c.requested, "eps_delivered": c.delivered,
                   "promise_min": None, "promise_median": None, "promise_max": None, "dt_max_for_request_s": None,
                   "dt_max_for_request_over_T_R": None, "dt_max_for_request_over_T_e": None, "request_note": None}
        if q == "eps" and c.requested is not None:
            request.update(band(errors(at)["eps_request"] if at is not None else np.full(PHASES, np.nan), "promise"))
            x_req, request["request_note"] = request_step(c, tolerance, cache)
            if x_req is not None:
                request.update(dt_max_for_request_s=x_req * c.T_R, dt_max_for_request_over_T_R=x_req,
                               dt_max_for_request_over_T_e=x_req * c.T_R / c.T_e)
        rows.append({"law": c.law, "geometry": c.geometry, "quantity": q, "criterion": c.criterion,
                     "tolerance": tolerance, "dt_max_s": x_max * c.T_R if x_max is not None else None,
                     "dt_max_over_T_R": x_max, "dt_max_over_T_e": x_max * c.T_R / c.T_e if x_max is not None else None,
                     "dt_s": dt_s if dt_s is not None else at * c.T_R if at is not None else None,
                     **band(e, "err"), "note": note, "T_R_s": c.T_R, "T_e_s": c.T_e, "V": c.V, **request})
    return rows


def _request_lines(r: dict, dt_given: bool) -> list[str]:
    """The text of a keyword's promise: the eps row `r`'s request keys, as `_text` prints them."""
    told, own = r["eps_requested"], r["eps_delivered"]
    lines = [f"  dt_max and the errors above are against the keyword's own equation ({r['keyword']}: what it "
             "restitutes as dt -> 0), not against what it was told.",
             f"  restitution told {told:g}; its own equation restitutes {own:.6g} as dt -> 0 "
             f"({_percent(own / told - 1.0)} of what it was told)"]
    where = "your dt" if dt_given else f"dt_max ({r['dt_s']:.4g} s)"
    if r["promise_max"] is None:
        lines.append(f"  eps / {told:g} - 1 at {where}: not readable at that step")
    else:
        lines.append(f"  eps / {told:g} - 1 at {where}: {r['promise_min']:+.3e} / {r['promise_median']:+.3e} / "
                     f"{r['promise_max']:+.3e} (min / median / max over the start phases: what the collision "
                     "delivers against what it was told)")
    head = f"  largest dt for the request (|eps / {told:g} - 1| <= {r['tolerance']:g} at every start phase): "
    if r["dt_max_for_request_s"] is None:
        lines.append(f"{head}none: {r['request_note']}")
    else:
        lines.append(f"{head}{r['dt_max_for_request_s']:.4g} s = {r['dt_max_for_request_over_T_R']:.3g} T_R = "
                     f"{r['dt_max_for_request_over_T_e']:.3g} T_e")
    return lines


def _text(rows: list[dict], cs: list[Collision], dt_given: bool) -> str:
    lines = []
    for c in cs:
        named = f" = {c.keyword}" if c.keyword is not None and c.keyword != c.law else ""
        lines.append(f"{c.geometry}, law {c.law}{named} (criterion {c.criterion}), V = {c.V:.6g} m/s"
                     + (f", K = {c.K:.6g}" if math.isfinite(c.K) else "")
                     + f": T_R = {c.T_R:.6g} s (pi R sqrt(rho/G) / (0.1631 nu + 0.8766)), "
                     f"T_e = {c.T_e:.6g} s (Hertz's contact time, {HERTZ_TAU:.6g} delta_e / V)")
        head = f"  {'quantity':<10} {'dt_max [s]':>12} {'/T_R':>8} {'/T_e':>8}   error " + \
               ("against its own equation " if c.keyword is not None else "") + "at " + \
               ("your dt" if dt_given else "dt_max") + ": min / median / max over the start phases"
        lines.append(head)
        for r in rows:
            if r["geometry"] != c.geometry:
                continue
            band = ("" if r["err_max"] is None
                    else f"{r['err_min']:+.2e} / {r['err_median']:+.2e} / {r['err_max']:+.2e}")
            band = "; ".join(b for b in (band, r["note"]) if b)
            if r["dt_max_s"] is None:
                lines.append(f"  {r['quantity']:<10} {'none':>12} {'-':>8} {'-':>8}   {band}")
            else:
                lines.append(f"  {r['quantity']:<10} {r['dt_max_s']:12.4g} {r['dt_max_over_T_R']:8.3g} "
                             f"{r['dt_max_over_T_e']:8.3g}   {band}")
        lines += [line for r in rows if r["geometry"] == c.geometry and r["quantity"] == "eps"
                  and r["eps_requested"] is not None for line in _request_lines(r, dt_given)]
        lines.append("")
    lines.append(f"Tolerance {rows[0]['tolerance']:g} (relative), at every one of {PHASES} start phases of the contact "
                 f"on the step grid. Every build of the study advances a collision with one discrete map "
                 f"(reference/engine_map.py): {integrators(CODES)}; the map is checked against each build's runs "
                 "at production steps (tests/test_engine_timestep.py).")
    return "\n".join(lines)


class _Parser(argparse.ArgumentParser):
    """argparse's parser, whose mistakes are raised as AdvisorError naming the argument (so that
    --json can answer them as JSON) instead of exiting."""

    def error(self, message):
        named = re.match(r"argument ([^\s:/]+)", message) or re.search(r"required: ([^\s,]+)", message)
        raise AdvisorError(message, named.group(1) if named else None)


def _wants_json(argv: list[str]) -> bool:
    """Whether the command line asks for --json (argparse also takes its abbreviations, --j ...)."""
    words = argv[:argv.index("--")] if "--" in argv else argv
    return any(len(w) >= 3 and "--json".startswith(w) for w in words)


def _error_json(err: Exception) -> str:
    """The --json answer to a refused request: {"error": {"argument", "message"[, "file", "field"]}}."""
    if isinstance(err, CaseError):
        error = {"argument": "case", "message": str(err), "file": err.path, "field": err.field}
    elif isinstance(err, AdvisorError):
        error = {"argument": err.argument, "message": str(err)}
        if err.field is not None:
            error["field"] = err.field
    elif isinstance(err, OSError):
        error = {"argument": "case", "message": str(err)}
    else:
        error = {"argument": None, "message": f"internal error: {type(err).__name__}: {err}"}
    return json.dumps({"error": error}, indent=1, allow_nan=False)


def main(argv=None) -> int:
    """The command line (see the module's docstring); the exit status: 0 answered, 2 refused.

    Parameters
    ----------
    argv : list of str or None
        The command line's arguments (None: ``sys.argv[1:]``).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    as_json = _wants_json(argv)
    parser = _Parser(prog="python -m postprocess.timestep", description=__doc__.split("\n\n")[0],
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", help="a case file (cases/*.yaml)")
    parser.add_argument("--law", help="a law of the study (contact_model/laws.py) or a keyword "
                                      "(contact_model/keywords.py, e.g. lammps:tsuji); required without --model")
    parser.add_argument("--code", help="the engine code whose keyword the law `default` is")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--restitution", type=float, help="the restitution told to a keyword, or restituted by "
                                                          "the viscoelastic law at the velocity; in (0, 1)")
    which.add_argument("--K", type=float, help="the viscoelastic law's dissipation parameter, in (0, 10]: picks the "
                                               "velocity at which the case's viscosity gives it (not with --velocity)")
    parser.add_argument("--velocity", help="the relative impact velocity [m/s]")
    parser.add_argument("--tolerance", type=float, default=1e-3,
                        help=f"relative error to hold, in [{TOLERANCE_FLOOR:g}, 1) (default 1e-3)")
    parser.add_argument("--dt", help="your time step: seconds (1e-7, '50 ns') or a multiple of T_R or T_e (0.2T_R)")
    parser.add_argument("--model", help="an oblique case: a tangential model (contact_model/tangential_models.yaml, "
                                        "e.g. lammps:mindlin); answers omega', e_t, the rebound angle, v_t', T and "
                                        "eps of one impact (--impact-index) against the model's own equation")
    parser.add_argument("--impact-index", type=int, default=0,
                        help="with --model: which of the case's oblique impacts (default 0)")
    parser.add_argument("--json", action="store_true", help="print the answer as JSON (a list of objects; "
                                                            "{\"error\": {...}} when refused)")
    try:
        try:
            args = parser.parse_args(argv)
        except AdvisorError:
            if not as_json:
                parser.print_usage(sys.stderr)
            raise
        if not 0 < args.tolerance < 1:
            raise AdvisorError(f"--tolerance {args.tolerance:g}: give a relative error in (0, 1), e.g. 1e-3",
                               "--tolerance")
        if args.tolerance < TOLERANCE_FLOOR:
            raise AdvisorError(f"--tolerance {args.tolerance:g}: below {TOLERANCE_FLOOR:g}, what the advisor answers "
                               "for: the reference solution is integrated to about 1e-12 and the map follows the "
                               "engines' runs to 8e-13, so their own errors would be a sizeable part of the error it "
                               "measures", "--tolerance")
        if args.model is None and args.law is None:
            raise AdvisorError("the following arguments are required: --law (or --model for an oblique case)",
                               "--law")
        if args.model is not None:
            for name, value in (("--code", args.code), ("--restitution", args.restitution), ("--K", args.K),
                                ("--velocity", args.velocity)):
                if value is not None:
                    raise AdvisorError(f"{name} with --model: an oblique impact's velocities are the case's "
                                       "(--impact-index picks one) and its normal law is the case's viscosity; "
                                       f"drop {name}", name)
        if args.dt:
            parse_dt(args.dt, 1.0, 1.0)  # its form, before the case is read (its value in T_R, T_e: below)
        case = load_case(args.case)
        if args.model is not None:
            from analysis import oblique_timestep

            o = oblique_timestep.oblique_step(case, args.model, args.impact_index, args.law)
            dt_s = parse_dt(args.dt, o.T_R, o.T_e) if args.dt else None
            if dt_s is not None:
                oblique_timestep.check_dt(o, dt_s, args.dt)
            rows = oblique_timestep.advise(o, args.tolerance, dt_s)
            answer = (json.dumps(rows, indent=1, allow_nan=False) if args.json
                      else oblique_timestep.text(rows, o, bool(args.dt)))
        else:
            velocity = _velocity(args.velocity) if args.velocity is not None else None
            cs = collisions(case, args.law, args.code, args.restitution, args.K, velocity)
            steps = []
            for c in cs:  # every step checked before any is answered
                dt_s = parse_dt(args.dt, c.T_R, c.T_e) if args.dt else None
                if dt_s is not None:
                    check_dt(c, dt_s, args.dt)
                steps.append(dt_s)
            rows = [row for c, dt_s in zip(cs, steps) for row in advise(c, args.tolerance, dt_s)]
            answer = json.dumps(rows, indent=1, allow_nan=False) if args.json else _text(rows, cs, bool(args.dt))
    except (AdvisorError, CaseError, OSError) as err:
        print(f"error: {err}", file=sys.stderr)
        if as_json:
            print(_error_json(err))
        return 2
    except Exception as err:
        if as_json:  # a defect of the advisor: still JSON on stdout, and the traceback on stderr
            print(_error_json(err))
        raise
    print(answer)
    return 0


if __name__ == "__main__":
    sys.exit(main())
