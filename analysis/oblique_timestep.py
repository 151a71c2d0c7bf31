r"""The time-step advisor for oblique impacts: how wrong are omega', e_t and the rebound angle at
the step I run, and which step do I need?

    python -m postprocess.timestep cases/oblique/chung_ooi_test4.yaml --model lammps:mindlin
        --impact-index 1 --tolerance 1e-3 [--dt 0.05T_R] [--json]

For one oblique impact of a case (`contact_model.Case.oblique_impacts`, by its index) and one
tangential model of the registry (`contact_model.tangential_models`, its form in the case's
geometry: `form_of`), it replays the engines' discrete map (`reference.oblique_engine_map`) at
`analysis.timestep.PHASES` phases of the contact's start on the step grid and sets each replay
against the model's own equation at dt -> 0 (`reference.solve_oblique`), with the errors formed
as the oblique gate forms them (`analysis.oblique.errors`):

    T, eps          relative: map / reference - 1
    vt_after        (map - reference) / V_s,   V_s = sqrt(v_n^2 + v_t^2) + R |w1|
    omega_after     (map - reference) R / V_s
    e_t             map - reference (undefined where the contact point does not slip at touching)
    rebound_angle   map - reference, in radians

For each it answers the band over the phases (min / median / max) at the user's dt (else at
dt_max), and dt_max: the largest dt keeping |error| within the tolerance at every phase, found as
`analysis.timestep.largest_step` finds it (`analysis.timestep.scan_grid`).

The normal law is the case's (`engines.oblique_plan.normal_law`: elastic for viscosity 0, else
viscoelastic; ``--law viscoelastic_clipped`` where the case has a viscosity), the tangential
damping ratio x_t is 0 (as the study's oblique runs), Mindlin's k_t0 = 8 G* of the bodies.

Only the sphere on a plane: the map of two spheres is not written (their line of centres turns,
`reference.oblique_engine_map`), and a case without a plane contact is refused naming it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contact_model.effective import effective_shear_modulus
from contact_model.tangential_models import TANGENTIAL_MODELS, NoReference, form_of, stiffness_constant
from engines.oblique_plan import normal_law
from reference import solve_oblique

from .oblique import errors, speed_scale
from .timestep import GAP_STEPS, MAX_STEPS, PHASES, AdvisorError, scan_grid

#: The quantities answered, in the order printed.
QUANTITIES = ("T", "eps", "vt_after", "omega_after", "e_t", "rebound_angle")
#: How each error is formed (`analysis.oblique.errors`).
ERROR_FORMS = {"T": "relative", "eps": "relative", "vt_after": "(v_t' - ref) / V_s",
               "omega_after": "(omega' - ref) R / V_s", "e_t": "absolute", "rebound_angle": "absolute [rad]"}
#: The units of each quantity's reference value.
UNITS = {"T": "s", "eps": "-", "vt_after": "m/s", "omega_after": "rad/s", "e_t": "-", "rebound_angle": "deg"}


@dataclass(frozen=True)
class ObliqueStep:
    """One oblique impact of a case under one tangential model, ready to be replayed.

    Attributes
    ----------
    model : str
        The tangential model's registry name (``lammps:mindlin``).
    geometry : str
        'sphere-plane'.
    law : str
        The normal law ('elastic', 'viscoelastic' or 'viscoelastic_clipped').
    impact_index : int
        The impact's index in `contact_model.Case.oblique_impacts`.
    impact : dict
        That impact (normal_velocity, tangential_velocity [m/s], spin [rad/s], angle [deg]).
    friction : float
        Coulomb's mu [-].
    arguments : dict
        `reference.solve_oblique`'s keyword arguments (SI), the map's too (without the plane's).
    reference : dict
        The reference's T [s], eps, vt_after [m/s], omega_after [rad/s], e_t, rebound_angle [deg],
        slip_before [m/s], phases (text).
    V_s : float
        The impact's speed scale [m/s] (`analysis.oblique.speed_scale`).
    T_R, T_e, delta_e : float
        The sphere's Rayleigh time [s], Hertz's contact time [s] and overlap [m] at v_n.
    """

    model: str
    geometry: str
    law: str
    impact_index: int
    impact: dict
    friction: float
    arguments: dict
    reference: dict
    V_s: float
    T_R: float
    T_e: float
    delta_e: float

    @property
    def e_t_defined(self) -> bool:
        """Whether the contact point slips at touching (else e_t = v_s'/v_s is undefined)."""
        return abs(self.reference["slip_before"]) > 1e-12 * self.V_s


def oblique_step(case, model: str, impact_index: int = 0, law: str | None = None) -> ObliqueStep:
    """The `ObliqueStep` of impact `impact_index` of `case` under tangential model `model`.

    Parameters
    ----------
    case : contact_model.Case
        An oblique case (`friction:` with angles, tangential velocities or spins).
    model : str
        A tangential model's registry name (``lammps:mindlin``).
    impact_index : int
        The impact, an index of `contact_model.Case.oblique_impacts`.
    law : str or None
        The normal law: None for the case's (`engines.oblique_plan.normal_law`);
        ``viscoelastic_clipped`` where the case has a viscosity.

    Returns
    -------
    ObliqueStep

    Raises
    ------
    AdvisorError
        Naming --model (a head-on case, an unknown model, one without the case's geometry or
        without a reference form), --impact-index (out of range), --law (a law the case does not
        run), or the case (two spheres only: not supported yet).
    """
    if not case.is_oblique:
        raise AdvisorError(f"--model {model}: {case.path} is a head-on case (no `friction:` and no oblique "
                           "`impact:` angle, tangential_velocity or spin): a tangential model needs an oblique case "
                           "(cases/oblique/*.yaml); for the normal quantities drop --model and give --law", "--model")
    if model not in TANGENTIAL_MODELS:
        raise AdvisorError(f"--model {model!r} is not a tangential model of the study; known: "
                           f"{', '.join(TANGENTIAL_MODELS)} (contact_model/tangential_models.yaml)", "--model")
    geometries = [p.geometry for p in case.pairs]
    if "sphere-plane" not in geometries:
        raise AdvisorError(f"{case.path}: the advisor's oblique map answers for a sphere on a plane only; this case "
                           f"has {', '.join(geometries)} contacts. Two spheres are not supported yet: their line of "
                           "centres turns while they slide (reference/oblique_engine_map.py)", "case", "geometries")
    geometry = "sphere-plane"
    entry = TANGENTIAL_MODELS[model]
    if geometry not in entry.geometries:
        raise AdvisorError(f"--model {model}: it has no {geometry} contact (contact_model/tangential_models.yaml "
                           f"gives it {', '.join(entry.geometries) or 'none'}), and the case's oblique impacts are "
                           f"of a {geometry}", "--model")
    try:
        form = form_of(model, geometry)
    except NoReference as err:
        raise AdvisorError(f"--model {model}: {err}", "--model") from None
    if form.stiffness != "mindlin":
        raise AdvisorError(f"--model {model}: its tangential stiffness is a user's constant k_t (linear), which a "
                           "case file does not give; the advisor answers for Mindlin's k_t = 8 G* a", "--model")
    impacts = case.oblique_impacts()
    if not 0 <= impact_index < len(impacts):
        raise AdvisorError(f"--impact-index {impact_index}: the case has {len(impacts)} oblique impacts (0 to "
                           f"{len(impacts) - 1}: {_list(impacts)})", "--impact-index")
    pair = case.pair(geometry)
    own = normal_law(case)
    allowed = (own, "viscoelastic_clipped") if pair.eta > 0 else (own,)
    law = own if law is None else law
    if law not in allowed:
        raise AdvisorError(f"--law {law} with --model: the case's normal law is {own} (its viscosity is "
                           f"{pair.eta:g} Pa s); give {' or '.join(allowed)}, or leave --law out", "--law")
    impact = impacts[impact_index]
    v_n, v_t, w1 = impact["normal_velocity"], impact["tangential_velocity"], impact["spin"]
    b1, b2 = pair.body_1, pair.body_2
    arguments = dict(geometry=geometry, R1=b1.radius, m1=b1.mass, E_star=pair.E,
                     G_star=effective_shear_modulus(b1, b2), R_star=pair.R, eta=pair.eta,
                     clipped=law == "viscoelastic_clipped", mu=case.friction, form=form, v_n=v_n, v_t=v_t, w1=w1,
                     k_t0=stiffness_constant(model, pair))
    r = solve_oblique(R2=math.inf, m2=math.inf, M_star=pair.M, **arguments)
    reference = {"T": r.T, "eps": r.eps, "vt_after": r.vt_after - r.vt2_after, "omega_after": r.omega_after,
                 "e_t": r.e_t, "rebound_angle": r.rebound_angle, "slip_before": v_t + b1.radius * w1,
                 "T_x0": r.T_x0, "phases": "; ".join(f"{kind} from {t:.6e} s" for kind, t in r.phases)}
    s = pair.scales(v_n)
    return ObliqueStep(model=model, geometry=geometry, law=law, impact_index=impact_index, impact=impact,
                       friction=case.friction, arguments=arguments, reference=reference,
                       V_s=speed_scale(v_n, v_t, w1, b1.radius), T_R=pair.rayleigh_time(), T_e=s["T_e"],
                       delta_e=s["delta_e"])


def _list(impacts: list[dict]) -> str:
    """The impacts as 'index: angle' (or v_t, spin), for a refusal's message."""
    return ", ".join(f"{i}: {x['angle']:.4g} deg (v_n {x['normal_velocity']:.4g} m/s, v_t "
                     f"{x['tangential_velocity']:.4g} m/s, spin {x['spin']:.4g} rad/s)" for i, x in enumerate(impacts))


def steps_for(o: ObliqueStep, dt: float) -> float:
    """The steps a replay of `o` at step dt [s] takes: the gap, the contact (the reference's T_x0)
    with 30 % to spare, and 10 more (inf for dt -> 0).

    Parameters
    ----------
    o : ObliqueStep
        The impact.
    dt : float
        The time step [s].
    """
    if not dt > 0:
        return math.inf
    return GAP_STEPS + 1 + math.ceil(min(1.3 * o.reference["T_x0"] / dt, 1e300)) + 10


def check_dt(o: ObliqueStep, dt: float, text: str) -> None:
    """Refuse (AdvisorError naming --dt) a step longer than T_e or needing more than MAX_STEPS steps.

    Parameters
    ----------
    o : ObliqueStep
        The impact.
    dt : float
        The time step [s].
    text : str
        The --dt argument as given, quoted in the message.
    """
    if dt > o.T_e:
        raise AdvisorError(f"--dt {text!r}: {dt:.3g} s is longer than the whole contact (T_e = {o.T_e:.3g} s, "
                           f"{o.T_e / o.T_R:.3g} T_R): give a step below T_e", "--dt")
    if steps_for(o, dt) > MAX_STEPS:
        finest = 1.3 * o.reference["T_x0"] / (MAX_STEPS - GAP_STEPS - 12)
        raise AdvisorError(f"--dt {text!r}: {dt:.3g} s needs {steps_for(o, dt):.3g} steps over the contact, more than "
                           f"the {MAX_STEPS:,} a replay may take; the finest step answered is {finest:.3g} s "
                           f"({finest / o.T_R:.3g} T_R)", "--dt")


def errors_at(o: ObliqueStep, dt: float, phases=None) -> dict[str, np.ndarray]:
    """Each quantity's error at step dt [s], one per start phase (`analysis.oblique.errors`).

    Parameters
    ----------
    o : ObliqueStep
        The impact.
    dt : float
        The time step [s].
    phases : array_like or None
        The contact's start phases on the step grid (fractions of a step); default PHASES of
        them, (k + 1/2) / PHASES.

    Returns
    -------
    dict of str to numpy.ndarray
        {quantity: error per phase} for `QUANTITIES` (e_t NaN where it is undefined).
    """
    from reference.oblique_engine_map import oblique_map  # numba: compiled when a collision is replayed

    phases = (np.arange(PHASES) + 0.5) / PHASES if phases is None else np.asarray(phases, dtype=float)
    ref = {**o.reference, "Ft_max": math.nan}
    out = {q: np.full(len(phases), np.nan) for q in QUANTITIES}
    a = o.arguments
    for k, phase in enumerate(phases):
        m = oblique_map(dt=dt, start_phase=float(phase), gap_steps=GAP_STEPS, max_steps=MAX_STEPS, **a)
        engine = {"T": m.T, "eps": m.eps, "vt_after": m.vt_after, "omega_after": m.omega_after, "e_t": m.e_t,
                  "rebound_angle": m.rebound_angle, "Ft_max": math.nan}
        e = errors(engine, ref, a["v_n"], a["v_t"], a["w1"], a["R1"])
        for q in QUANTITIES:
            out[q][k] = e[f"err_{q}"]
    return out


def largest_step(o: ObliqueStep, tolerance: float, cache: dict | None = None) -> dict[str, float]:
    """{quantity: dt_max / T_R}: the largest dt keeping |error| <= tolerance at every phase (0 where
    no step of the grid does; e_t left out where it is undefined), scanned as
    `analysis.timestep.largest_step` scans.

    Parameters
    ----------
    o : ObliqueStep
        The impact.
    tolerance : float
        The largest |error| allowed [-] (each quantity's error as `errors_at` forms it).
    cache : dict or None
        {dt / T_R: `errors_at`'s errors}, filled and reused (None: a new one).
    """
    cache = {} if cache is None else cache
    quantities = tuple(q for q in QUANTITIES if q != "e_t" or o.e_t_defined)

    def passes(x):
        if x not in cache:
            cache[x] = errors_at(o, x * o.T_R)
        return {q: bool(np.all(np.abs(cache[x][q]) <= tolerance)) for q in quantities}

    return scan_grid(passes, lambda x: steps_for(o, x * o.T_R) <= MAX_STEPS, quantities)


def advise(o: ObliqueStep, tolerance: float, dt_s: float | None) -> list[dict]:
    """The advisor's answer for one oblique impact: one row per quantity (the --json objects).

    Parameters
    ----------
    o : ObliqueStep
        The impact.
    tolerance : float
        The |error| [-] to hold at every start phase.
    dt_s : float or None
        The user's step [s] (checked by `check_dt`), or None: the errors are given at dt_max (or,
        where no step of the grid holds the tolerance, at the finest step scanned).

    Returns
    -------
    list of dict
        One row per quantity of `QUANTITIES`: model, geometry, law, impact_index, angle,
        normal_velocity, tangential_velocity, spin, friction, quantity, error_form, reference
        (its value, in `UNITS`), tolerance, dt_max_s, dt_max_over_T_R, dt_max_over_T_e, dt_s,
        err_min, err_median, err_max, err_spread (max - min: the phases' scatter), note, T_R_s,
        T_e_s, V_s. Values that do not exist are None, and ``note`` says why.
    """
    from .timestep import GRID_OVER_T_R

    cache: dict[float, dict] = {}
    largest = largest_step(o, tolerance, cache)
    within = [x for x in GRID_OVER_T_R if steps_for(o, x * o.T_R) <= MAX_STEPS]
    finest = float(min(within)) if within else None
    rows = []
    for q in QUANTITIES:
        note, x_max = None, None
        if q == "e_t" and not o.e_t_defined:
            note = "e_t = v_s'/v_s is undefined: the contact point does not slip at touching (v_s = 0)"
        elif largest[q] > 0:
            x_max = largest[q]
        else:
            note = (f"no step of the grid down to {finest:.3g} T_R ({finest * o.T_R:.3g} s) holds the tolerance"
                    if finest is not None else
                    f"no step of the grid is within the {MAX_STEPS:,} steps a replay may take")
        at = dt_s / o.T_R if dt_s is not None else x_max if x_max is not None else finest
        if q == "e_t" and not o.e_t_defined:
            e = np.full(PHASES, np.nan)
        else:
            if at is not None and at not in cache:
                cache[at] = errors_at(o, at * o.T_R)
            e = cache[at][q] if at is not None else np.full(PHASES, np.nan)
            if x_max is None and dt_s is None and at is not None:
                note += "; the errors are at that finest step"
        readable = bool(np.isfinite(e).all())
        band = {f"err_{w}": float(f(e)) if readable else None
                for w, f in (("min", np.min), ("median", np.median), ("max", np.max))}
        rows.append({"model": o.model, "geometry": o.geometry, "law": o.law, "impact_index": o.impact_index,
                     "angle": o.impact["angle"], "normal_velocity": o.impact["normal_velocity"],
                     "tangential_velocity": o.impact["tangential_velocity"], "spin": o.impact["spin"],
                     "friction": o.friction, "quantity": q, "error_form": ERROR_FORMS[q],
                     "reference": float(o.reference[q]) if math.isfinite(o.reference[q]) else None,
                     "tolerance": tolerance, "dt_max_s": x_max * o.T_R if x_max is not None else None,
                     "dt_max_over_T_R": x_max, "dt_max_over_T_e": x_max * o.T_R / o.T_e if x_max is not None else None,
                     "dt_s": dt_s if dt_s is not None else at * o.T_R if at is not None else None, **band,
                     "err_spread": band["err_max"] - band["err_min"] if readable else None, "note": note,
                     "T_R_s": o.T_R, "T_e_s": o.T_e, "V_s": o.V_s})
    return rows


def text(rows: list[dict], o: ObliqueStep, dt_given: bool) -> str:
    """The advisor's answer for one oblique impact as the command line prints it.

    Parameters
    ----------
    rows : list of dict
        `advise`'s rows.
    o : ObliqueStep
        The impact.
    dt_given : bool
        Whether the user gave --dt (the errors are at it), else they are at dt_max.
    """
    i = o.impact
    lines = [f"{o.geometry}, tangential model {o.model}, normal law {o.law}, impact {o.impact_index}: "
             f"{i['angle']:.4g} deg, v_n = {i['normal_velocity']:.6g} m/s, v_t = {i['tangential_velocity']:.6g} m/s, "
             f"spin {i['spin']:.6g} rad/s, mu = {o.friction:g}: T_R = {o.T_R:.6g} s, T_e = {o.T_e:.6g} s, "
             f"V_s = {o.V_s:.6g} m/s",
             f"  reference (dt -> 0): {o.reference['phases']}",
             f"  {'quantity':<14} {'reference':>12} {'dt_max [s]':>11} {'/T_R':>8} {'/T_e':>8}   error at "
             + ("your dt" if dt_given else "dt_max") + ": min / median / max over the start phases (scatter); form"]
    for r in rows:
        ref = "-" if r["reference"] is None else f"{r['reference']:.6g}"
        band = ("" if r["err_max"] is None else f"{r['err_min']:+.2e} / {r['err_median']:+.2e} / {r['err_max']:+.2e} "
                f"({r['err_spread']:.2e}); {r['error_form']}")
        band = "; ".join(b for b in (band, r["note"]) if b)
        if r["dt_max_s"] is None:
            lines.append(f"  {r['quantity']:<14} {ref:>12} {'none':>11} {'-':>8} {'-':>8}   {band}")
        else:
            lines.append(f"  {r['quantity']:<14} {ref:>12} {r['dt_max_s']:11.4g} {r['dt_max_over_T_R']:8.3g} "
                         f"{r['dt_max_over_T_e']:8.3g}   {band}")
    lines += ["", f"Tolerance {rows[0]['tolerance']:g} on each error as formed above (V_s = sqrt(v_n^2 + v_t^2) "
              f"+ R |w1|), at every one of {PHASES} start phases of the contact on the step grid; "
              "against the model's own equation at dt -> 0 (reference/oblique_collision.py), "
              "from the engines' discrete map (reference/oblique_engine_map.py: velocity Verlet, the history "
              "rescaled, advanced, capped and reset each step). The map of the sphere on a plane only; x_t = 0, as "
              "the study's oblique runs."]
    return "\n".join(lines)
