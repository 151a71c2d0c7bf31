r"""Oblique impacts: from the rungs of each engine ladder to its limit dt -> 0, against the
tangential model's own equation, and the gate's checks.

An oblique run (`engines.oblique_run.ObliqueRun`) is a rung of a ladder of runs that differ in
their time step alone (the head-on run's ladder: its contact starts half a step after a sample at
every rung). For each rung, `rung_row` reads the engine's dump (`records.oblique_metrics`) and
sets it against the reference of the model's own equation (`reference.solve_oblique`, solved once
per ladder); `limit_rows` extrapolates every quantity's error to dt -> 0 (`engines.ladder`) and
`oblique_checks` gates it: a check passes when |error| + resolution <= tolerance.

Errors (``err_<q>``), each dimensionless, in the form that stays meaningful where the quantity
itself vanishes (no spin after a frictionless impact, a slip that stops):

    T, eps, Ft_max    relative: engine / reference - 1;
    vt_after          (engine - reference) / V_s, with V_s = sqrt(v_n^2 + v_t^2) + R1 |w1| the
                      impact's speed scale [m/s];
    omega_after       (engine - reference) R1 / V_s;
    e_t               engine - reference (a ratio of order 1; left out where the contact point
                      does not slip at the start, v_s = 0: e_t is then undefined);
    rebound_angle     (engine - reference) in radians.

The limit: an oblique contact's tangential force depends on the slip velocity, which the engines'
map sees half a step late, and on where stick and slip meet, which falls anywhere on the step
grid: there the rungs' errors are no series in dt (measured, alumina at 10 deg in LAMMPS: omega'
off by 3.3e-6, 6.0e-7, 4.6e-7, 5.7e-8 at T_e/250 ... T_e/2000). Each quantity's limit
(`oblique_limit`) is one of three candidates: the Richardson extrapolation over the dissipative
expansion's powers (1, 3/2, 2, ...; `engines.ladder.extrapolate`), the first-order limit of the two
finest rungs (its estimate: its distance from the same limit of the next two), or the finest rung
itself (its estimate: the finest two rungs' difference over r^p - 1, which bounds what remains at
order p in [1/2, 1]). Each candidate must earn its estimate on the ladder itself:

- the Richardson extrapolation is refused where the finest three rungs converge more slowly than
  its first power (observed order below 1 - ORDER_SLACK), in this quantity or in any other
  tangential quantity of the contact (`ladder_order`: one force history makes them all): it would
  claim an order the rungs do not show;
- each candidate's estimate is checked one and two rungs coarser: the same method on the ladder
  without its finest rung (and without its finest two) claims v' +- est'; where the full ladder's
  value lies further, |v - v'| > est', the estimate is widened by the worse miss, est |v - v'| / est'
  (the method understated its error on this ladder by that factor a rung coarser; nothing says it
  does better a rung finer);
- the finest rung's and the first-order limit's estimates are the tails of their last moves at the
  slowest order the finest rungs show (`slowest_order`, in [1/2, 1], the contact's other tangential
  quantities included), a geometric series.

Of the candidates left, the one with the smallest (checked) estimate gives the limit, that estimate
its resolution; ``method_<q>`` says which (the series wins in gross sliding and in the normal half,
where it holds). Why the checks (docs/tangential.md, "The full set", finding 1): the force-history
models at Chung & Ooi's test 5, 20 deg, converge at an observed order that rises from 0.83 at
T_e/1000 to 0.98 at T_e/2048000 (not yet the asymptotic first order at the default rungs); over
T_e/1000 ... /16000 the unchecked minimum of the candidates claimed e_t = +4.0e-6 +- 2.0e-6 in LAMMPS
and +4.9e-6 +- 1.6e-6 in YADE, where the finest five of twelve rungs put the limit at -1.8e-11 and
-7.0e-11 (tests/test_oblique_resolution.py).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd

from contact_model.effective import effective_shear_modulus
from contact_model.tangential_models import form_of, stiffness_constant
from engines.codes import CODES
from engines.ladder import RESOLUTION_FLOOR, extrapolate
from records.dump_file import DumpError, read_dump
from records.oblique_metrics import oblique_metrics
from reference import rigid_body_sliding, solve_oblique

#: The gated quantities of an oblique impact and how their error is formed (module docstring).
OBLIQUE_QUANTITIES = ("T", "eps", "vt_after", "omega_after", "e_t", "rebound_angle", "Ft_max")
#: Reported beside them, not gated.
OBLIQUE_REPORTED = ("delta_max", "F_max")
#: Powers of h = dt / T_e eliminated by the extrapolation, in order.
OBLIQUE_POWERS = (1.0, 1.5, 2.0, 2.5, 3.0)
#: How far below the expansion's first power the finest three rungs' observed order may fall before
#: the Richardson extrapolation is refused (`oblique_limit`). A series of the expansion's form shows
#: orders between 1 and 3/2 ahead of its asymptotic range, or just below 1 where its h and h^{3/2}
#: terms oppose (e.g. h - h^{3/2} at h = 0.01: 0.94); the force-history models at test 5, 20 deg
#: show 0.86 at T_e/16000 (module docstring). In the full set of 27 Nov 2026, 100 of 901 ladders show
#: an order below 0.9 in some tangential quantity: those and the stick-slip ladders whose rungs are no
#: series (erratic orders, where the finest rung or the first-order limit was already the tighter).
ORDER_SLACK = 0.1


def speed_scale(v_n: float, v_t: float, spin: float, R1: float) -> float:
    """V_s = sqrt(v_n^2 + v_t^2) + R1 |w1| [m/s]: the speed that scales the tangential errors.

    Parameters
    ----------
    v_n, v_t : float
        The impact's normal and tangential velocity [m/s].
    spin : float
        Body 1's initial spin [rad/s].
    R1 : float
        Body 1's radius [m].
    """
    return math.hypot(v_n, v_t) + R1 * abs(spin)


def errors(engine: dict, ref: dict, v_n: float, v_t: float, spin: float, R1: float) -> dict:
    """The errors ``err_<q>`` of one run's values against the reference's (module docstring).

    Parameters
    ----------
    engine, ref : dict
        The quantities of `OBLIQUE_QUANTITIES` [SI; rebound_angle in degrees], each of the engine
        run and of the reference; ``slip_before`` [m/s] in `ref` says whether e_t is defined.
    v_n, v_t, spin, R1 : float
        The impact (`speed_scale`).

    Returns
    -------
    dict
        err_<q> for every quantity of OBLIQUE_QUANTITIES (NaN where undefined).
    """
    V = speed_scale(v_n, v_t, spin, R1)
    out = {}
    for q in ("T", "eps", "Ft_max"):
        out[f"err_{q}"] = engine[q] / ref[q] - 1.0 if ref[q] != 0 else engine[q] - ref[q]
    out["err_vt_after"] = (engine["vt_after"] - ref["vt_after"]) / V
    out["err_omega_after"] = (engine["omega_after"] - ref["omega_after"]) * R1 / V
    defined = abs(ref.get("slip_before", 1.0)) > 1e-12 * V
    out["err_e_t"] = engine["e_t"] - ref["e_t"] if defined else math.nan
    out["err_rebound_angle"] = math.radians(engine["rebound_angle"] - ref["rebound_angle"])
    return out


def reference_of(run, tangential_stiffness: float | None = None) -> dict:
    """The reference of an oblique run's own equations (`reference.solve_oblique`), in the
    quantities of `records.oblique_metrics` (relative tangential velocity of the centres). Two
    spheres: the planar motion with the turning line of centres, every quantity of the lab frame
    as the dump records it (eps and F_max along x, vt_after and Ft_max along y); the rigid-body
    values, of a normal that does not turn, are then an approximation (to ~delta/R). A plane that the
    code represents by a fixed sphere (`engines.codes.Code.oblique_plane_ratio`: ESyS) is that sphere.

    Parameters
    ----------
    run : engines.oblique_run.ObliqueRun
        The run (any rung of its ladder: the reference does not depend on dt).
    tangential_stiffness : float, optional
        k_t [N/m] of a linear tangential spring (the dump's ``tangential_stiffness``); Mindlin's
        k_t0 follows from the bodies: 8 G*, or the model's own rule
        (`contact_model.tangential_models.stiffness_constant`: ESyS's (16/3) G of E*).

    Returns
    -------
    dict
        T [s], eps, delta_max [m], F_max [N], vt_after [m/s], omega_after [rad/s], e_t,
        rebound_angle [deg], Ft_max [N], slip_before [m/s], slides_throughout (bool), phases (text),
        and rigid_vt_after [m/s], rigid_omega_after [rad/s] where the contact slides throughout.
    """
    p = run.pair
    b1, b2 = p.body_1, p.body_2
    form = form_of(run.model, p.geometry)
    G_star = effective_shear_modulus(b1, b2)
    v = run.initial_velocities()
    v_n, v_t = run.normal.velocity, run.tangential_velocity
    geometry = dict(geometry=p.geometry, R2=b2.radius, m2=b2.mass)
    ratio = CODES[run.normal.engine].oblique_plane_ratio
    if p.geometry == "sphere-plane" and math.isfinite(ratio):
        # the code's plane is a fixed sphere of ratio R (ESyS): the planar motion over it, whose line of
        # centres turns and pulls the sphere in at v_t^2/(R + R_wall); the contact's stiffnesses stay the
        # plane's (its deck scales E so that E sqrt(R*) is the plane's), hence R* and M* of the plane
        geometry = dict(geometry="sphere-sphere", R2=ratio * b1.radius, m2=math.inf, I2=math.inf)
    r = solve_oblique(**geometry, R1=b1.radius, m1=b1.mass, E_star=p.E,
                      G_star=G_star, R_star=p.R, M_star=p.M, eta=p.eta, clipped=run.law == "viscoelastic_clipped",
                      mu=run.friction, form=form, v_n=v_n, v_t=v_t, w1=v["w1"],
                      k_t0=tangential_stiffness if form.stiffness == "linear" else stiffness_constant(run.model, p),
                      x_t=run.damping_ratio, young_1=b1.young, young_2=b2.young)
    out = {"T": r.T, "eps": r.eps, "delta_max": r.delta_max, "F_max": r.F_max, "vt_after": r.vt_after - r.vt2_after,
           "omega_after": r.omega_after, "e_t": r.e_t, "rebound_angle": r.rebound_angle, "Ft_max": r.Ft_max,
           "slip_before": v_t + b1.radius * v["w1"],
           "slides_throughout": len(r.phases) == 1 and r.phases[0][0] == "slip",
           "phases": "; ".join(f"{kind} from {t:.6e} s" for kind, t in r.phases)}
    if out["slides_throughout"]:
        rigid = rigid_body_sliding(v_n, r.eps, run.friction, b1.radius, b1.mass, 0.4 * b1.mass * b1.radius ** 2,
                                   v_s=out["slip_before"], R2=b2.radius, m2=b2.mass,
                                   I2=0.4 * b2.mass * b2.radius ** 2)
        out["rigid_vt_after"] = v_t + rigid["dv1"] - rigid["dv2"]
        out["rigid_omega_after"] = v["w1"] + rigid["dw1"]
    return out


def rung_rows(runs, sweep, known_defects=()) -> pd.DataFrame:
    """One row per landed run: its description, the engine's values, the reference's
    (``<q>_ref``), the errors (``err_<q>``, `errors`), and the rigid-body values where the
    contact slides throughout; runs whose dump cannot be read get ``problem``.

    Parameters
    ----------
    runs : list of engines.oblique_run.ObliqueRun
        The planned runs.
    sweep : engines.finish_run.Sweep
        Their dumps (and failures, which have no row here: `oblique_checks` names them).
    known_defects : sequence of dict
        Config ``oblique.known_defects``: {build, model, reference, description, max_error?,
        fails?}; with ``max_error``, a ladder of that build and model carries the text in
        ``known_defect`` and its size in ``known_defect_max_error``.
    """
    refs, rows = {}, []
    for run in runs:
        path = sweep.dumps.get(run.name)
        if path is None:
            continue
        try:
            meta, columns = read_dump(path, oblique=True)
            engine = oblique_metrics(columns, meta, source=str(path))
        except (DumpError, ValueError) as err:  # ExtractionError is a ValueError
            rows.append({"run": run.name, "ladder": run.ladder, "build": run.build, "problem": str(err)})
            continue
        if run.ladder not in refs:
            refs[run.ladder] = reference_of(run, meta.get("tangential_stiffness"))
        ref = refs[run.ladder]
        # The normal half under the law's criterion: F0 where the force is clipped, x0 otherwise.
        end = "F0" if run.law == "viscoelastic_clipped" else "x0"
        engine = {**engine, "T": engine[f"T_{end}"], "eps": engine[f"eps_{end}"], "F_max": engine["force_max"]}
        T_e = run.normal.scales["T_e"]
        row = {"case": run.normal.case, "build": run.build, "engine": run.normal.engine, "model": run.model,
               "geometry": run.pair.geometry, "law": run.law, "friction": run.friction, "angle": run.angle,
               "spin": run.spin, "normal_velocity": run.normal.velocity, "tangential_velocity": run.tangential_velocity,
               "radius_1": run.pair.body_1.radius, "mass_1": run.pair.body_1.mass,
               "radius_2": run.pair.body_2.radius, "mass_2": run.pair.body_2.mass, "ladder": run.ladder,
               "run": run.name, "dump": str(path),
               "dt": run.normal.time_step, "h": run.normal.time_step / T_e,
               "time_step_factor": run.normal.time_step_factor, "ranks": run.ranks,
               "engine_version": meta.get("engine_version", "")}
        for q in OBLIQUE_QUANTITIES + OBLIQUE_REPORTED:
            row[q], row[f"{q}_ref"] = engine[q], ref[q]
        row.update(errors(engine, ref, run.normal.velocity, run.tangential_velocity, run.spin,
                          run.pair.body_1.radius))
        for q in ("delta_max", "F_max"):
            row[f"err_{q}"] = engine[q] / ref[q] - 1.0
        row.update(slides_throughout=ref["slides_throughout"], phases=ref["phases"],
                   rigid_vt_after=ref.get("rigid_vt_after", math.nan),
                   rigid_omega_after=ref.get("rigid_omega_after", math.nan))
        d = declared_defect(known_defects, run.build, run.model, run.pair.geometry)
        if d and d.get("max_error") is not None:
            row.update(known_defect=f"{d['description']} ({d['reference']})",
                       known_defect_max_error=float(d["max_error"]))
        rows.append(row)
    return pd.DataFrame(rows)


def slowest_order(h, y, ladder_order: float = math.inf) -> float:
    """The slower of the orders the finest four rungs show (`rung_order` of the finest three and of
    the three before; the finest three alone for a ladder of three), taken in [1/2, 1]: the order
    at which what remains beyond the finest rung is bounded (a damped oblique contact converges as
    slowly as h^{1/2} where stick and slip alternate: measured, alumina at K = 0.1, 10 deg; orders
    above 1 are bounded at 1, which the series' own terms then only tighten). 1/2 where the rungs
    show no order (a difference of 0).

    Parameters
    ----------
    h : array_like
        The rungs' steps dt / T_e [-], coarsest first, at least three.
    y : array_like
        The quantity's error at each rung [-], in the same order.
    ladder_order : float, optional
        The slowest order another quantity of the same contact shows (`ladder_order`, `limit_rows`);
        it bounds this one too. Default: none.

    Returns
    -------
    float
        The order [-], in [1/2, 1].
    """
    orders = [rung_order(h[:k], y[:k]) for k in ((len(y), len(y) - 1) if len(y) >= 4 else (len(y),))]
    if not all(math.isfinite(p) for p in orders):
        return 0.5
    return min(1.0, max(0.5, min(orders + [ladder_order])))


def _tail(step: float, ratio: float, p: float) -> float:
    """What a sequence still moves after its last `step`, at order p with steps shrinking by
    `ratio` each (a geometric series): |step| / (ratio^p - 1)."""
    return abs(step) / (ratio ** p - 1.0)


def _finest_bound(h, y, ladder_order: float = math.inf) -> float:
    """What the finest rung's error may still hold: the tail (`_tail`) of its difference from the
    next coarser rung at the slowest order the rungs show (`slowest_order`)."""
    return _tail(y[-1] - y[-2], h[-2] / h[-1], slowest_order(h, y, ladder_order))


def _first_order(h, y) -> float:
    """The limit h -> 0 of a + b h through two rungs (h, y)."""
    return float(y[1] + (y[1] - y[0]) * h[1] / (h[0] - h[1]))


def rung_order(h, y) -> float:
    """The order the finest three rungs show: log(|y[-2] - y[-3]| / |y[-1] - y[-2]|) / log(h[-2] / h[-1]).

    Parameters
    ----------
    h : array_like
        The rungs' steps dt / T_e [-], coarsest first, at least three.
    y : array_like
        The quantity at each rung [-], in the same order.

    Returns
    -------
    float
        The observed order [-]; NaN where a difference is 0.
    """
    d1, d2 = abs(y[-2] - y[-3]), abs(y[-1] - y[-2])
    if d1 == 0 or d2 == 0:
        return math.nan
    return math.log(d1 / d2) / math.log(h[-2] / h[-1])


def _candidates(h, y, ladder_order: float = math.inf) -> list[tuple[str, float, float]]:
    """(method, value, estimate) of each limit candidate of the rungs (h, y), coarsest first
    (module docstring): the Richardson extrapolation, the finest rung and the first-order limit."""
    e = extrapolate(h, y, OBLIQUE_POWERS)
    # The first-order limits of successive pairs converge at the rungs' own order where that is
    # below 1 (the h^p term survives the elimination of h): their last move's tail bounds them.
    first = [_first_order(h[k:k + 2], y[k:k + 2]) for k in (len(y) - 2, len(y) - 3)]
    p = slowest_order(h, y, ladder_order)
    return [("extrapolated", e.value, e.estimate), ("finest rung", float(y[-1]), _finest_bound(h, y, ladder_order)),
            ("first order", first[0], _tail(first[0] - first[1], h[-2] / h[-1], p))]


def oblique_limit(h, y, ladder_order: float = math.inf) -> dict:
    r"""One quantity's limit h -> 0 over a ladder and its resolution (module docstring).

    Candidates (m, v_m, est_m): Richardson over OBLIQUE_POWERS, the finest rung, the first-order
    limit of the two finest rungs. Richardson is refused where the rungs are above round-off
    (|y_n - y_{n-1}| > RESOLUTION_FLOOR) and the finest three converge at an observed order
    p_obs < 1 - ORDER_SLACK (`rung_order`). With four or more rungs each candidate is checked on the
    ladders without the finest rung and (five or more) without the finest two, which claim
    v^(k)_m +- est^(k)_m, k = 1, 2:

        est_m <- est_m max(1, max_k |v_m - v^(k)_m| / max(est^(k)_m, RESOLUTION_FLOOR)).

    The candidate of the smallest checked estimate is the limit.

    Parameters
    ----------
    h : array_like
        The rungs' steps dt / T_e [-], distinct, at least three.
    y : array_like
        The quantity's error at each rung [-], in the same order.
    ladder_order : float, optional
        The slowest order the finest three rungs of the contact's other tangential quantities show
        (`ladder_order`): one tangential force makes them all, and where one shows the ladder short
        of its asymptotic range, so is this quantity's (measured, test 5 at 20 deg: e_t at 0.86,
        while F_t,max shows 1.2 and its Richardson limit misses by 2.0e-6). Default: none.

    Returns
    -------
    dict
        value (the limit [-]), estimate (its checked estimate [-], before RESOLUTION_FLOOR), method,
        order (the Richardson extrapolation's observed order), rung_order (p_obs) and widened (the
        factor the check put on the chosen estimate; 1: none).
    """
    h, y = np.asarray(h, dtype=float), np.asarray(y, dtype=float)
    order = np.argsort(h)[::-1]  # coarsest first
    h, y = h[order], y[order]
    p_obs = rung_order(h, y)
    shown = min(p_obs if math.isfinite(p_obs) and abs(y[-1] - y[-2]) > RESOLUTION_FLOOR else math.inf, ladder_order)
    slow = shown < OBLIQUE_POWERS[0] - ORDER_SLACK
    # The same methods on the ladder without its finest rung, and without its finest two: their
    # claims, checked against this ladder's values.
    coarser = [{m: (v, est) for m, v, est in _candidates(h[:-k], y[:-k], ladder_order)} for k in (1, 2)
               if len(y) - k >= 3]
    kept = []
    for method, value, estimate in _candidates(h, y, ladder_order):
        if method == "extrapolated" and slow:
            continue  # it would claim an order the rungs do not show
        widened = max([1.0] + [abs(value - c[method][0]) / max(c[method][1], RESOLUTION_FLOOR) for c in coarser])
        kept.append((estimate * widened, value, method, widened))
    estimate, value, method, widened = min(kept, key=lambda c: c[0])
    return {"value": value, "estimate": estimate, "method": method, "widened": widened,
            "order": extrapolate(h, y, OBLIQUE_POWERS).order, "rung_order": p_obs}


#: The quantities one tangential force history makes: a ladder short of its asymptotic range in one
#: of them is short in all (`ladder_order`).
TANGENTIAL_QUANTITIES = ("vt_after", "omega_after", "e_t", "rebound_angle", "Ft_max")


def ladder_order(h, columns) -> float:
    """The slowest order (`rung_order`) the finest three rungs show among `columns`, counting those
    whose finest difference is above RESOLUTION_FLOOR (below it the order is round-off's).

    Parameters
    ----------
    h : array_like
        The rungs' steps dt / T_e [-], coarsest first.
    columns : iterable of array_like
        The tangential quantities' errors at each rung [-], each in the order of `h`.

    Returns
    -------
    float
        The slowest order [-]; inf where no column shows one.
    """
    orders = [rung_order(h, y) for y in columns if len(y) >= 3 and abs(y[-1] - y[-2]) > RESOLUTION_FLOOR]
    return min([p for p in orders if math.isfinite(p)], default=math.inf)


def limit_rows(rungs: pd.DataFrame) -> pd.DataFrame:
    """One row per ladder (column ``ladder``): every gated error extrapolated to dt -> 0, with its
    resolution, order and rungs.

    Parameters
    ----------
    rungs : DataFrame
        One row per landed run, with the columns ladder, h (dt / T_e, the rung's step) and
        err_<q> for q in OBLIQUE_QUANTITIES, and the run's description (case, build, model, ...).

    Returns
    -------
    DataFrame
        The finest rung's description, dt = 0, rungs, and for each q (`oblique_limit`): err_<q>
        (the limit), estimate_<q>, resolution_<q> = max(estimate, RESOLUTION_FLOOR), method_<q>,
        order_<q>, rung_order_<q>, widened_<q> and rungs_<q>; ladders of fewer than three rungs are
        left out.
    """
    out = []
    if not len(rungs) or "ladder" not in rungs:
        return pd.DataFrame()
    if "problem" in rungs:  # a dump that could not be read has no values: its rung did not land
        rungs = rungs[rungs.problem.isna()]
    for _, g in rungs.groupby("ladder", sort=False):
        if len(g) < 3:
            continue
        g = g.sort_values("h", ascending=False)  # coarsest first
        row = g.iloc[-1].to_dict()
        row.update(dt=0.0, h=0.0, rungs=len(g), dump="")
        h = g.h.to_numpy(dtype=float)
        tangential = [g[f"err_{q}"].to_numpy(dtype=float) for q in TANGENTIAL_QUANTITIES
                      if f"err_{q}" in g and g[f"err_{q}"].notna().all()]
        slowest = ladder_order(h, tangential)
        row["ladder_order"] = slowest
        for q in OBLIQUE_QUANTITIES + OBLIQUE_REPORTED:
            column = f"err_{q}"
            if column not in g or not g[column].notna().all():
                row.update({column: math.nan, f"resolution_{q}": math.nan})
                continue
            y = g[column].to_numpy(dtype=float)
            lim = oblique_limit(h, y, slowest if q in TANGENTIAL_QUANTITIES else math.inf)
            row.update({column: lim["value"], f"estimate_{q}": lim["estimate"], f"order_{q}": lim["order"],
                        f"method_{q}": lim["method"], f"rung_order_{q}": lim["rung_order"],
                        f"widened_{q}": lim["widened"], f"resolution_{q}": max(lim["estimate"], RESOLUTION_FLOOR),
                        f"rungs_{q}": ";".join(f"{x:.6e}" for x in y)})
        out.append(row)
    return pd.DataFrame(out)


#: How far a rung run on two MPI ranks may differ from the same rung on one, relative to each
#: quantity's scale: round-off (measured: bitwise identical in LAMMPS 29 Sep 2021 and 22 Jul 2025).
RANKS_TOLERANCE = 1e-12


def processor_boundary_checks(rungs: pd.DataFrame, planned=None, failures=None, known_defects=()) -> pd.DataFrame:
    """One check per rung run on two MPI ranks: its values equal the one-rank run's to round-off.

    The two-rank runs split the domain at the contact (engines/oblique_run.py,
    `ObliqueRun.initial_positions`), so that the pair and its tangential history cross ranks while
    the contact lasts.

    Parameters
    ----------
    rungs : DataFrame
        `rung_rows`' rows (columns run, ranks and the quantities).
    planned : engines.oblique_plan.ObliquePlan, optional
        The plan: a two-rank run without a row fails, named (KNOWN DEFECT where its one-rank twin
        failed as a declared defect says).
    failures : dict, optional
        {run name: EngineRunFailed} of the sweep.
    known_defects : sequence of dict, optional
        Config ``oblique.known_defects`` (`oblique_checks`).

    Returns
    -------
    DataFrame
        CHECK_COLUMNS, quantity 'ranks 1 vs 2', error the largest relative difference over the
        quantities of OBLIQUE_QUANTITIES and OBLIQUE_REPORTED.
    """
    rows = []
    failures = failures or {}
    landed = set(rungs.run) if len(rungs) and "run" in rungs else set()
    for run in (planned.runs if planned is not None else ()):
        if run.ranks != 2 or run.name in landed:
            continue
        why = failure_reason(run.name, failures) if run.name in failures else "its dump did not land"
        twin = run.name.removesuffix("-np2")
        twin_why = failure_reason(twin, failures) if twin in failures else ""
        defect = declared_defect(known_defects, run.build, run.model, run.pair.geometry)
        # On two ranks the rank that meets an error may not be the one whose output is the log: the
        # one-rank twin's failure says what it was.
        known = bool(defect and defect.get("fails") and defect["fails"] in why + twin_why)
        rows.append({"build": run.build, "case": run.normal.case, "model": run.model, "geometry": run.pair.geometry,
                     "angle": run.angle, "spin": run.spin, "ranks": 2,
                     "quantity": f"ranks 1 vs 2 (dt = T_e/{run.normal.time_step_factor:g})", "error": math.nan,
                     "resolution": math.nan, "status": "KNOWN DEFECT" if known else "FAIL",
                     "detail": (f"known defect ({defect['reference']}), as on one rank: " if known else "")
                               + f"the two-rank run failed: {why}"})
    if not len(rungs) or "ranks" not in rungs:
        return pd.DataFrame(rows, columns=CHECK_COLUMNS)
    one = {r.run: r for r in rungs[rungs.ranks == 1].itertuples()}
    for r in rungs[rungs.ranks == 2].itertuples():
        twin = one.get(r.run.removesuffix("-np2"))
        worst, which = 0.0, ""
        if twin is not None:
            # The difference in the form each error is gated in (`errors`): relative, or scaled by the
            # impact's speed, or absolute for e_t and the angle.
            two = {q: getattr(r, q) for q in OBLIQUE_QUANTITIES}
            one_values = {q: getattr(twin, q) for q in OBLIQUE_QUANTITIES}
            diffs = errors(two, {**one_values, "slip_before": r.tangential_velocity + r.radius_1 * r.spin},
                           r.normal_velocity, r.tangential_velocity, r.spin, r.radius_1)
            for column, d in diffs.items():
                if np.isfinite(d) and not abs(d) <= worst:
                    worst, which = abs(d), column.removeprefix("err_")
        ok = twin is not None and worst <= RANKS_TOLERANCE
        sign = "<=" if ok else ">"
        detail = ("no one-rank twin ran" if twin is None else
                  f"largest difference {worst:.3g} ({which or 'none'}) {sign} {RANKS_TOLERANCE:g}")
        rows.append({"build": r.build, "case": r.case, "model": r.model, "geometry": r.geometry, "angle": r.angle,
                     "spin": r.spin, "ranks": 2, "quantity": f"ranks 1 vs 2 (dt = T_e/{r.time_step_factor:g})",
                     "error": worst, "resolution": 0.0, "status": "PASS" if ok else "FAIL", "detail": detail})
    return pd.DataFrame(rows, columns=CHECK_COLUMNS)


CHECK_COLUMNS = ["build", "case", "model", "geometry", "angle", "spin", "ranks", "quantity", "error", "resolution",
                 "status", "detail"]


def failure_reason(name: str, failures: dict) -> str:
    """Why run `name` failed: its own problem, and where an earlier run stopped the engine ("not
    run: lammps stopped in <run>"), that run's problem as well.

    Parameters
    ----------
    name : str
        The run.
    failures : dict
        {run name: EngineRunFailed} of the sweep.
    """
    problem = failures[name].problem
    stopped = re.search(r"stopped in (\S+)", problem) if problem.startswith("not run") else None
    if stopped and stopped[1] in failures and stopped[1] != name:
        problem = f"{problem}, which failed: {failures[stopped[1]].problem}"
    return problem


def declared_defect(known_defects, build: str, model: str, geometry: str | None = None) -> dict | None:
    """The config's known defect of `build`, `model` and `geometry` (``oblique.known_defects``; an
    entry without a geometry covers both), if any.

    Parameters
    ----------
    known_defects : sequence of dict
        Config entries {build, model, geometry?, reference, description, max_error?, fails?}.
    build, model : str
        The ladder's build id and tangential model.
    geometry : str, optional
        The ladder's geometry.
    """
    return next((d for d in known_defects or () if d["build"] == build and d["model"] == model
                 and d.get("geometry", geometry) == geometry), None)


def oblique_checks(limits: pd.DataFrame, tolerance: float, planned=None, failures=None,
                   known_defects=()) -> pd.DataFrame:
    """The gate's checks of the oblique ladders: one per ladder and gated quantity, and one per
    planned ladder that did not land (a failed run, or fewer than three rungs).

    A check passes when |error| + resolution <= tolerance. One that does not, of a ladder with a
    declared known defect (``known_defect``), is 'KNOWN DEFECT' while |error| stays within the
    declared size (``known_defect_max_error``), and FAIL beyond it: a declared defect is never
    passed silently, and a defect that grows is news.

    Parameters
    ----------
    limits : DataFrame
        `limit_rows`' rows.
    tolerance : float
        The largest |error| + resolution a check passes with [-] (1e-6 as the head-on gate's).
    planned : engines.oblique_plan.ObliquePlan, optional
        The plan: its ladders without a limit row fail, named.
    failures : dict, optional
        {run name: EngineRunFailed} of the sweep: the reason given for those ladders.
    known_defects : sequence of dict, optional
        Config ``oblique.known_defects``: a ladder that did not land is a KNOWN DEFECT where one
        is declared for its build and model with ``fails``, text its failure contains (the engine
        crash it is known for); any other failure of it fails.

    Returns
    -------
    DataFrame
        CHECK_COLUMNS; status 'PASS', 'FAIL' or 'KNOWN DEFECT'.
    """
    rows = []
    for _, r in limits.iterrows():
        defect = str(r.get("known_defect", "") or "") if pd.notna(r.get("known_defect", None)) else ""
        size = float(r.get("known_defect_max_error", math.nan)) if defect else math.nan
        for q in OBLIQUE_QUANTITIES:
            err, res = r.get(f"err_{q}", math.nan), r.get(f"resolution_{q}", math.nan)
            if q == "e_t" and not np.isfinite(err):
                continue  # no slip at the start: e_t undefined, nothing to check
            ok = bool(np.isfinite(err) and np.isfinite(res) and abs(err) + res <= tolerance)
            known = not ok and defect and np.isfinite(err) and abs(err) <= size
            status = "PASS" if ok else ("KNOWN DEFECT" if known else "FAIL")
            detail = f"|{err:.3g}| + {res:.3g} {'<=' if ok else '>'} {tolerance:g}"
            if not ok and np.isfinite(err) and abs(err) <= res:  # not shown wrong: not shown right either
                detail += " (unresolved: the ladder cannot tell this error from 0 at the tolerance; finer rungs can)"
            if defect and not ok:
                detail += (f"; known defect within its declared size {size:g}: {defect}" if known else
                           f"; beyond the known defect's declared size {size:g}: {defect}")
            rows.append({"build": r["build"], "case": r["case"], "model": r["model"], "geometry": r["geometry"],
                         "angle": r["angle"], "spin": r["spin"], "ranks": r.get("ranks", 1), "quantity": q,
                         "error": err, "resolution": res, "status": status, "detail": detail})
    if planned is not None:
        landed = set(limits.ladder) if len(limits) else set()
        ladder_of = {r.name: r.ladder for r in planned.runs}
        problems = {}
        failures = failures or {}
        for name in failures:
            # A run left undone because an earlier one stopped the engine fails for that one's reason.
            problems.setdefault(ladder_of.get(name), failure_reason(name, failures))
        for run in planned.runs:
            if run.ladder in landed or run.ranks != 1:  # two ranks: processor_boundary_checks
                continue
            landed.add(run.ladder)
            why = problems.get(run.ladder, "fewer than three rungs landed")
            defect = declared_defect(known_defects, run.build, run.model, run.pair.geometry)
            known = bool(defect and defect.get("fails") and defect["fails"] in why)
            detail = f"the ladder did not land: {why}"
            if known:
                detail = f"known defect ({defect['reference']}): {defect['description']}; {detail}"
            rows.append({"build": run.build, "case": run.normal.case, "model": run.model,
                         "geometry": run.pair.geometry, "angle": run.angle, "spin": run.spin, "ranks": run.ranks,
                         "quantity": "run", "error": math.nan, "resolution": math.nan,
                         "status": "KNOWN DEFECT" if known else "FAIL", "detail": detail})
    for (case, model), why in (planned.refused.items() if planned is not None else ()):
        rows.append({"build": getattr(planned, "build", ""), "case": case, "model": model, "geometry": "any",
                     "angle": math.nan, "spin": math.nan, "ranks": 1, "quantity": "run", "error": math.nan,
                     "resolution": math.nan, "status": "NOT AVAILABLE", "detail": why})
    return pd.DataFrame(rows, columns=CHECK_COLUMNS)
