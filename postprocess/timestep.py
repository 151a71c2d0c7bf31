r"""The time-step advisor: how wrong is a collision at the step I run, and which step do I need?

    python -m postprocess.timestep cases/mine.yaml --law <law> [--code <code>]
        [--restitution 0.8 | --K 0.1 | --velocity 2 m/s] --tolerance 1e-3 [--dt 0.2T_R] [--json]

For each geometry of the case and each quantity (T, A, delta_max, F_max, eps) it answers, from the
engines' discrete map (`reference.engine_map`, which every build of the study follows to its
rounding: docs/timestep.md) replayed at 32 phases of the contact's start on the step grid:

- the largest dt that keeps the quantity's relative error within the tolerance at *every* phase
  (``dt_max``), in seconds, as a fraction of the Rayleigh time T_R and of the Hertz time T_e;
- the error at the user's dt (``--dt``: seconds, or a multiple of T_R or T_e), else at dt_max, as
  min / median / max over the phases: a production run has every phase at once, so the band, not
  its middle, is the honest error bar.

T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766), G = Y / (2 (1 + nu)) of the sphere (body 1;
`contact_model.collision_scales.rayleigh_time`: Y = 2 E*, nu = 0 where the case gives only E*), and
T_e = tau_e delta_e / V, Hertz's contact time (tau_e = 2.9432...).

The laws are the study's (`contact_model.laws`) and the engines' keywords (`contact_model.keywords`,
by their registry name, e.g. ``lammps:tsuji``); ``default`` needs ``--code``. The model's laws take
the case's viscosity at ``--velocity`` (or at the velocity giving ``--K``), or the viscosity that
restitutes ``--restitution`` at the velocity; a keyword is told ``--restitution``.

``--json`` prints a list of objects, one per geometry and quantity, with the keys law, geometry,
quantity, criterion, tolerance, dt_max_s, dt_max_over_T_R, dt_max_over_T_e, dt_s, err_min,
err_median, err_max (the last three at ``dt_s``: the user's --dt, or dt_max_s without one), T_R_s,
T_e_s, V.
"""

from __future__ import annotations

import argparse
import difflib
import json
import math
import re
import sys
from dataclasses import dataclass

import numpy as np

from contact_model import CaseError, load_case
from contact_model.keywords import KEYWORDS, keyword_reference
from contact_model.laws import DAMPING_POWER, LAW_REGISTRY
from engines.codes import CODES, integrators, keyword_of
from records.collision_metrics import ExtractionError, collision_metrics
from reference import HERTZ_TAU, solve_collision
from reference.engine_map import replay

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


class AdvisorError(ValueError):
    """A request the advisor cannot answer; the message names the argument or the case field."""


@dataclass(frozen=True)
class Collision:
    """One geometry's collision in the map's units: its law's damping (power, coefficient, clip),
    the criterion its quantities end at, its reference characteristics, and the SI scales."""

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

    @property
    def tau_end(self) -> float:
        """Where the run must last to: the overlap's return (after a clipped force's free flight)."""
        r = self.reference
        return r.get("tau_return", r["tau_0"] if math.isfinite(r["tau_0"]) else r["tau_f"] + 1.0)


def errors_at(c: Collision, h: float, phases=None) -> dict[str, np.ndarray]:
    """The relative errors of each quantity at map step h (dt V / delta_e), one per phase (NaN
    where the collision cannot be read at that step: too few samples in contact)."""
    phases = (np.arange(PHASES) + 0.5) / PHASES if phases is None else np.asarray(phases)
    r = c.reference
    tau_ref = r["tau_0"] if c.criterion == "x0" else r["tau_f"]
    eps_ref = r["eps_x0"] if c.criterion == "x0" else r["eps_F0"]
    steps = int(GAP_STEPS + math.ceil(1.3 * c.tau_end / h) + 10)
    out = {q: np.full(len(phases), np.nan) for q in QUANTITIES}
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
    return out


def largest_step(c: Collision, tolerance: float, phases=None, cache: dict | None = None) -> dict[str, float]:
    """{quantity: dt_max / T_R}: the largest dt keeping |error| <= tolerance at every phase. The
    grid `GRID_OVER_T_R` is scanned from its coarsest step down (a step that cannot be read
    fails); dt_max lies between the first step that passes, with the next CONFIRM finer steps
    passing too, and the step above it, and is refined there by bisection in log dt. 0 where not
    even the finest step of the grid passes. `phases` (default: PHASES of them) and `cache` ({dt /
    T_R: errors}, shared by calls for several tolerances) are passed on to `errors_at`."""
    to_h = c.T_R * c.V / c.delta_e  # dt / T_R -> h
    cache = {} if cache is None else cache

    def passes(x):
        if x not in cache:
            cache[x] = errors_at(c, x * to_h, phases)
        e = cache[x]
        return {q: bool(np.all(np.abs(e[q]) <= tolerance)) for q in QUANTITIES}

    found: dict[str, tuple[float, float | None]] = {}
    candidate: dict[str, tuple[float, float | None, int]] = {}  # q -> (x, the failing step above, passes so far)
    above = None
    for x in GRID_OVER_T_R[::-1]:
        ok = passes(x)
        for q in QUANTITIES:
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
        if len(found) == len(QUANTITIES):
            break
        above = x
    out = {}
    for q in QUANTITIES:
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
    """A time step from '0.2T_R', '0.2 T_R', '0.01 T_e', '1e-7', '1e-7 s' or '50 ns' -> seconds."""
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(T_R|T_e|s|ms|us|µs|ns)?\s*", text)
    try:
        value = float(m.group(1)) if m else math.nan
    except ValueError:
        value = math.nan
    if not (m and math.isfinite(value) and value > 0):
        raise AdvisorError(f"--dt {text!r}: give a positive step in seconds (1e-7, 50 ns) or as a multiple of the "
                           "Rayleigh or Hertz time (0.2T_R, 0.01T_e)")
    unit = m.group(2) or "s"
    factor = {"T_R": T_R, "T_e": T_e, "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9}[unit]
    return value * factor


def _velocity(text: str) -> float:
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(m/s)?\s*", text)
    try:
        v = float(m.group(1)) if m else math.nan
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise AdvisorError(f"--velocity {text!r}: give the relative impact velocity in m/s, e.g. 2 or '2 m/s'")
    return v


def collisions(case, law: str, code: str | None, restitution: float | None, K: float | None,
               velocity: float | None) -> list[Collision]:
    """One `Collision` per geometry of `case` under `law` (see the module's docstring)."""
    keyword = _keyword(law, code)
    if restitution is not None and not 0 < restitution < 1:
        raise AdvisorError(f"--restitution {restitution:g}: a restitution coefficient lies in (0, 1)")
    out = []
    for pair in case.pairs:
        V = velocity
        if V is None and K is not None:
            if pair.eta == 0:
                raise AdvisorError(f"{case.path}: field 'viscosity': 0, so no --K gives a velocity; give --velocity")
            V = pair.velocity_for_dissipation(K)
        if V is None and case.velocities:
            V = case.velocities[0]
        if V is None and case.K and pair.eta > 0:
            V = pair.velocity_for_dissipation(case.K[0])
        if V is None:
            raise AdvisorError(f"{case.path}: no impact velocity: give --velocity (or --K), or `impact:` in the case")
        s = pair.scales(V)
        common = dict(geometry=pair.geometry, V=V, T_e=s["T_e"], T_R=pair.rayleigh_time(), delta_e=s["delta_e"])
        if keyword is not None:
            k = KEYWORDS[keyword]
            told = restitution if restitution is not None else (case.restitutions[0] if case.restitutions else None)
            if told is None:
                raise AdvisorError(f"--law {law}: a keyword is told a restitution: give --restitution (e.g. 0.8)")
            refused = k.refuses(k.told_for(told))
            if refused:
                raise AdvisorError(f"--restitution {told:g}: {refused}")
            row = keyword_reference(keyword, told, 0.0)
            out.append(Collision(law=law, power=DAMPING_POWER[k.form] if k.form != "half" else 0.5,
                                 coefficient=row["b"], clipped=k.clipped, criterion=k.criterion, reference=row,
                                 K=math.nan, **common))
            continue
        entry = LAW_REGISTRY[law]
        if entry.damping == "none":
            Kv = 0.0
        elif restitution is not None:
            from reference.dissipation_for_restitution import dissipation_for_restitution

            Kv = dissipation_for_restitution(restitution, entry.aligned_end)
        else:
            Kv = s["K"]
            if not 0 < Kv <= 10:
                raise AdvisorError(f"{case.path}: K = {Kv:.3g} at V = {V:g} m/s, outside (0, 10] where the reference "
                                   "is solved; give --K or --restitution")
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
        raise AdvisorError(f"--law {law!r} is not a law of the study{guess}; known: {', '.join(known)}")
    if law == "default":
        if code not in CODES:
            raise AdvisorError(f"--law default is each code's own keyword: name the code with --code "
                               f"({', '.join(CODES)})")
        return keyword_of(law, code)
    return LAW_REGISTRY[law].keyword


def advise(c: Collision, tolerance: float, dt_s: float | None) -> list[dict]:
    """The advisor's answer for one geometry: one row per quantity (the --json objects)."""
    largest = largest_step(c, tolerance)
    rows = []
    for q in QUANTITIES:
        dt_max = largest[q] * c.T_R
        at = dt_s if dt_s is not None else dt_max
        e = errors_at(c, at * c.V / c.delta_e)[q] if at > 0 else np.full(PHASES, np.nan)
        finite = e[np.isfinite(e)]
        unread = len(finite) < len(e)
        rows.append({"law": c.law, "geometry": c.geometry, "quantity": q, "criterion": c.criterion,
                     "tolerance": tolerance, "dt_max_s": dt_max, "dt_max_over_T_R": largest[q],
                     "dt_max_over_T_e": dt_max / c.T_e, "dt_s": at,
                     "err_min": float(finite.min()) if len(finite) and not unread else math.nan,
                     "err_median": float(np.median(finite)) if len(finite) and not unread else math.nan,
                     "err_max": float(finite.max()) if len(finite) and not unread else math.nan,
                     "T_R_s": c.T_R, "T_e_s": c.T_e, "V": c.V})
    return rows


def _text(rows: list[dict], cs: list[Collision], dt_given: bool) -> str:
    lines = []
    for c in cs:
        lines.append(f"{c.geometry}, law {c.law} (criterion {c.criterion}), V = {c.V:.6g} m/s"
                     + (f", K = {c.K:.6g}" if math.isfinite(c.K) else "")
                     + f": T_R = {c.T_R:.6g} s (pi R sqrt(rho/G) / (0.1631 nu + 0.8766)), "
                     f"T_e = {c.T_e:.6g} s (Hertz's contact time, {HERTZ_TAU:.6g} delta_e / V)")
        head = f"  {'quantity':<10} {'dt_max [s]':>12} {'/T_R':>8} {'/T_e':>8}   error at " + \
               ("your dt" if dt_given else "dt_max") + ": min / median / max over the start phases"
        lines.append(head)
        for r in rows:
            if r["geometry"] != c.geometry:
                continue
            band = ("not readable at that step (fewer than 6 samples in contact)" if math.isnan(r["err_max"])
                    else f"{r['err_min']:+.2e} / {r['err_median']:+.2e} / {r['err_max']:+.2e}")
            lines.append(f"  {r['quantity']:<10} {r['dt_max_s']:12.4g} {r['dt_max_over_T_R']:8.3g} "
                         f"{r['dt_max_over_T_e']:8.3g}   {band}")
        lines.append("")
    lines.append(f"Tolerance {rows[0]['tolerance']:g} (relative), at every one of {PHASES} start phases of the contact "
                 f"on the step grid. Every build of the study advances a collision with one discrete map "
                 f"(reference/engine_map.py): {integrators(CODES)}; the map is checked against each build's runs "
                 "at production steps (tests/test_engine_timestep.py).")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m postprocess.timestep", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", help="a case file (cases/*.yaml)")
    parser.add_argument("--law", required=True, help="a law of the study (contact_model/laws.py) or a keyword "
                                                     "(contact_model/keywords.py, e.g. lammps:tsuji)")
    parser.add_argument("--code", help="the engine code whose keyword the law `default` is")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--restitution", type=float, help="the restitution told to a keyword, or restituted by "
                                                          "the viscoelastic law at the velocity")
    which.add_argument("--K", type=float, help="the viscoelastic law's dissipation parameter")
    parser.add_argument("--velocity", help="the relative impact velocity [m/s]")
    parser.add_argument("--tolerance", type=float, default=1e-3, help="relative error to hold (default 1e-3)")
    parser.add_argument("--dt", help="your time step: seconds (1e-7, '50 ns') or a multiple of T_R or T_e (0.2T_R)")
    parser.add_argument("--json", action="store_true", help="print the answer as JSON (a list of objects)")
    args = parser.parse_args(argv)
    try:
        if not 0 < args.tolerance < 1:
            raise AdvisorError(f"--tolerance {args.tolerance:g}: give a relative error in (0, 1), e.g. 1e-3")
        case = load_case(args.case)
        velocity = _velocity(args.velocity) if args.velocity is not None else None
        cs = collisions(case, args.law, args.code, args.restitution, args.K, velocity)
        rows = []
        for c in cs:
            dt_s = parse_dt(args.dt, c.T_R, c.T_e) if args.dt else None
            rows += advise(c, args.tolerance, dt_s)
    except (AdvisorError, CaseError, OSError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(json.dumps(rows, indent=1) if args.json else _text(rows, cs, bool(args.dt)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
