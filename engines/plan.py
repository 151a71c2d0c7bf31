"""From a case file and the study settings to the list of engine runs.

For every contact pair of the case (one per geometry) and every impact velocity (the case's
own, or those that give the study's K grid in that geometry):

- the viscoelastic law (tail kept: criteria x0 and F0 from one trajectory) in every engine;
- optionally the clipped viscoelastic law (criterion F0: the engines' own way of separating);
- optionally the elastic law (eta = 0, at the same velocities: Hertz alone, exact);
- optionally each engine's out-of-the-box law (its restitution keyword, law ``default``) and the
  keyword laws (`contact_model.laws`: ``betan``, ``coeff_restitution``), each told the reference
  eps at `match_K` under the criterion the keyword's force allows (or the case's own
  restitution), at every velocity of the sweep. (Told the reference's eps at each velocity
  instead, the keywords' ladders no longer resolve 1e-6 at the ends of the K grid: e = 0.003
  at K = 5, where the x0 end creeps, and e = 0.99 at K = 0.01, where a clipped force's F0 falls
  next to x = 0.)

Each run of a gated law is a ladder of runs at several time steps (`ladder`: the factors of
T_e per kind of law, `engines.ladder`), extrapolated to dt -> 0 by the post-processing; the
out-of-the-box law's against its keyword's own equation. `time_step_factor` sets the probe run
that checks a velocity can be run.

A velocity whose Hertz overlap delta_e exceeds `max_overlap_ratio` R* is not run, with the
reason recorded: there the contact radius is no longer small against R* (Hertz's premise), and
the engines' contact geometry breaks down as delta approaches the radius (a sphere's centre
would cross the plane). It takes km/s impacts for the stiff materials at large K.

A law a build's code cannot express (`engines.codes`, ``unavailable``) is not run in that build;
the plan lists the cell (build, law, geometry) with the reason, for the report.

A case the engines cannot run honestly is refused here, before any engine starts, with a
`PlanError` (a `CaseError`: it names the case file and the field):

- a velocity, or a Hertz scale derived from it, that is not a finite positive double
  (extreme magnitudes overflow or underflow: V_D = M*^2 E*^3 / (R* eta^5) easily does);
- a velocity the case asks for (impact.velocity or impact.K) whose overlap is too small for
  double-precision positions to resolve at the gate's resolution (`ladder_roundoff`);
  velocities of the study's K grid that fail this are not run, with the reason, like the
  too-fast ones;
- an empty plan: nothing left to run once the too-fast and unresolvable velocities are out.

The keywords' promise table (`keyword_table_plan`, snakemake keywords) and the history
(`history_plan`, snakemake history) are planned here too, by the same helpers: a keyword told e
is refused where its code refuses what it is told for e (`keyword_refusal`), and laddered and
referenced as in the study (`keyword_ladder`); their Snakemake scripts only run and record.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

from contact_model.case_file import VELOCITY_MEANING, Case, CaseError
from contact_model.keywords import KEYWORDS, keyword_reference, missing_in
from contact_model.contact_pair import Body, ContactPair
from records.files import file_sha256
from reference import solve_collision, solve_collisions

from .codes import keyword_of, law_unavailable
from .ladder import ladder_roundoff as roundoff_of_ladder
from .ladder import powers_of, rung_factor
from contact_model import LAW_REGISTRY, LAWS, load_case
from contact_model.laws import KEYWORD_LAWS

from .run_spec import ENGINES, RunSpec

#: The largest round-off of positions a ladder of runs may carry into its extrapolated errors
#: (`ladder_roundoff`), relative: a fifth of the default tolerance (1e-6), so that round-off
#: cannot decide between a pass and a fail of a clean engine.
#:
#: Why: the engines store the centres as doubles of magnitude X = |x1| + |x2| ~ R, so every
#: position update is rounded by up to u |x| (u = 2^-53), and the overlap, a difference of
#: positions, carries that error; over N steps it adds up as a random walk, so each run carries
#: up to sqrt(N) u X / delta_max (`RunSpec.roundoff_floor`), and the extrapolation over a
#: ladder weighs its rungs' errors with its Richardson weights w_k (about 5 times the finest
#: rung's floor for the four-rung ladder). Soft materials at small K need the tiniest overlaps:
#: ice at K = 0.01 has delta_e / R = 1.7e-9, a floor of 3e-6 at T_e/2000.
ROUNDOFF_LIMIT = 2e-7
#: The ladders of the study's default settings: time-step factors of T_e per kind of law (the
#: dissipative ones refined by sqrt(K) above K = 1: `engines.ladder.rung_factor`).
DEFAULT_LADDER = {"dissipative": (250, 500, 1000, 2000), "elastic": (125, 250, 500)}


class PlanError(CaseError):
    """A case the engines cannot run honestly; the message names the case file and the field."""


def ladder_factors(ladder: dict, law: str, K: float, own_K: float | None = None) -> list[float]:
    """The time-step factors of the rungs of a run of `law` at dissipation parameter K: the
    ladder's 'elastic' factors for the elastic law (or K = 0), its 'dissipative' ones refined by
    `engines.ladder.rung_factor` for the viscoelastic laws, unrefined for an engine's keyword but
    one whose force is Brilliantov's (YADE's en + vn), refined by its own K `own_K`
    (`keyword_own_K`)."""
    if LAW_REGISTRY[law].is_keyword:  # an engine's keyword: its damping does not grow with the pair's K
        if own_K is None:
            return [float(f) for f in ladder["dissipative"]]
        return [float(rung_factor(f, own_K)) for f in ladder["dissipative"]]
    if law == "elastic" or K == 0:
        return [float(f) for f in ladder["elastic"]]
    return [float(rung_factor(f, K)) for f in ladder["dissipative"]]


def keyword_own_K(keyword: str | None, reference: dict | None) -> float | None:
    """The K of a keyword whose force is Brilliantov's (form 'half': its reference row's b), which
    refines its ladder as the viscoelastic law's; None for the others."""
    if keyword is None or not KEYWORDS[keyword].damping_form.is_viscoelastic or not reference:
        return None
    return float(reference["b"])


def rungs_of(spec: RunSpec, ladder: dict | None = None) -> list[RunSpec]:
    """`spec` at every time step of its ladder (`ladder_factors`; default DEFAULT_LADDER)."""
    own = keyword_own_K(spec.keyword, spec.reference)
    return [replace(spec, time_step_factor=f) for f in ladder_factors(ladder or DEFAULT_LADDER, spec.law, spec.K, own)]


def ladder_roundoff(rungs: list[RunSpec]) -> float:
    """The round-off of positions that a ladder of runs may carry into its extrapolated errors,
    relative (`engines.ladder.ladder_roundoff` of the rungs' steps and floors; see ROUNDOFF_LIMIT)."""
    return roundoff_of_ladder([r.time_step / r.scales["T_e"] for r in rungs], [r.roundoff_floor() for r in rungs],
                              powers_of(rungs[0].pair.eta, rungs[0].law, rungs[0].engine))


def _velocity_meaning(field_name: str) -> str:
    """'; `velocity` is the relative normal velocity ...' for an error about a velocity the case
    file gives, '' otherwise."""
    return f" ({VELOCITY_MEANING})" if field_name.startswith("impact.velocity") else ""


def _velocities(case: Case, pair, K_grid) -> list[tuple[float, str, str, float | None]]:
    """(velocity, field, what it is, the target K or None) of every velocity of `pair`."""
    if case.velocities:
        return [(v, f"impact.velocity[{i}]", f"V = {v:.6g} m/s", None) for i, v in enumerate(case.velocities)]
    if pair.eta == 0:
        raise PlanError(case.path, "impact" if not case.K else "impact.K",
                        "an elastic case (viscosity 0) needs impact velocities: no K can give them")
    if case.K:
        targets = [(k, f"impact.K[{i}]", f"K = {k:g}") for i, k in enumerate(case.K)]
    else:
        targets = [(k, "impact", f"K = {k:g} of the study's K grid (the case has no impact block)")
                   for k in K_grid]
    out = []
    for k, where, what in targets:
        try:
            v = pair.velocity_for_dissipation(k)
        except (OverflowError, ZeroDivisionError, ValueError) as err:
            raise PlanError(case.path, where, f"{pair.geometry}: the velocity for {what} cannot be computed ({err})")
        out.append((v, where, what, k))
    return out


def _checked(case: Case, pair, v: float, where: str, what: str, K_target, time_step_factor: float,
             solved: dict | None = None) -> tuple[dict, RunSpec]:
    """The scales at `v` and a probe run, refusing what is not a finite positive double.
    `solved` ({K: reference row}) spares the probe its own solve of the ODE (for its steps)."""
    def refuse(problem):
        raise PlanError(case.path, where, f"{pair.geometry}, {what}: {problem}; the engines cannot run it"
                                          f"{_velocity_meaning(where)}")

    if not (math.isfinite(v) and v > 0):
        refuse(f"the impact velocity would be {v:g} m/s (V_D = {pair.viscous_velocity:g} m/s)")
    try:
        scales = pair.scales(v)
        spec = RunSpec(case.name, ENGINES[0], "viscoelastic", pair, v, time_step_factor,
                       reference=(solved or {}).get(scales["K"]))
        derived = {**scales, "dt": spec.time_step, "gap": spec.initial_gap(), **spec.initial_state()}
    except (OverflowError, ZeroDivisionError, ValueError) as err:
        refuse(f"the Hertz scales overflow ({err})")
    for name, x in derived.items():
        if name in ("K", "V_D") and pair.eta == 0:
            continue  # K = 0 and V_D = inf: an elastic contact
        if isinstance(x, float) and not (math.isfinite(x) and x != 0):
            refuse(f"{name} = {x:g} is beyond double precision")
    if K_target is not None and not math.isclose(scales["K"], K_target, rel_tol=1e-9):
        refuse(f"the velocity {v:g} m/s gives K = {scales['K']:.12g}: precision lost")
    return scales, spec


def _with_solutions(Ks, solved: dict | None = None) -> dict:
    """`solved` ({K: reference row}) with the row of every K in `Ks` it lacks, those solved in
    one batch (`reference.solve_collisions`)."""
    solved = dict(solved or {})
    missing = sorted(set(Ks) - set(solved))
    if missing:
        solved.update(zip(missing, solve_collisions(missing).rows()))
    return solved


def _solved_in_one_batch(case: Case, velocities: dict) -> dict:
    """{K: reference row} of every velocity of the case whose K is a number the solver takes
    (0 <= K <= 10), solved in one batch; the others are refused or solved later, one by one."""
    Ks = set()
    for pair in case.pairs:
        for v, *_ in velocities[pair.geometry]:
            try:
                K = pair.dissipation_parameter(v)
            except (OverflowError, ZeroDivisionError, ValueError):
                continue
            if math.isfinite(K) and 0 <= K <= 10:
                Ks.add(K)
    return _with_solutions(Ks)


@functools.lru_cache(maxsize=64)
def told_restitution(keyword: str, match_K: float) -> float:
    """What a keyword is told when the case gives no restitution: the viscoelastic reference's
    eps at match_K under the criterion the keyword's force allows (x0 where it keeps the tail,
    F0 where it clips). Solved once per keyword and K: the plan asks at every run."""
    r = solve_collision(match_K)
    return float(r["eps_x0"] if KEYWORDS[keyword].criterion == "x0" else r["eps_F0"])


def keyword_refusal(keyword: str, e: float) -> str:
    """Why `keyword`'s code refuses to be asked for restitution `e` ('' when it takes it): what it
    is told, `Keyword.told_for(e)` (YADE's betan: Thornton's beta of e, 0 at e = 1), against the
    range its code takes. The study's plan, the keywords' promise and the history refuse by this
    alone (`keyword_promise_plan`)."""
    k = KEYWORDS[keyword]
    return k.refuses(k.told_for(e))


def keyword_ladder(case_name: str, engine: str, law: str, keyword: str, pair, velocity: float, e: float, K: float,
                   ladder: dict | None = None, build: str = "", direct: bool = False) -> list[RunSpec]:
    """The ladder of a run of `law`, `engine`'s keyword `keyword` asked for restitution `e` at
    `velocity` (K: the pair's there, which names and places the run): its reference row is the
    keyword's own equation (`keyword_reference`), its time steps `ladder_factors` (refined by its
    own K where its force is Brilliantov's, `keyword_own_K`). `direct`: `e` is no restitution but
    the code's own input (`RunSpec.told_input`, yade:betan's beta)."""
    row = keyword_reference(keyword, e, K, direct=direct)
    told = {"told_input": e} if direct else {"matched_restitution": e}
    return [RunSpec(case_name, engine, law, pair, velocity, f, reference=row, build=build, **told)
            for f in ladder_factors(ladder or DEFAULT_LADDER, law, row["K"], keyword_own_K(keyword, row))]


def build_codes(builds) -> dict[str, str]:
    """{build id: code} of `builds`: `engines.builds.Build`s, {id, code} mappings (the plan's
    settings), or bare codes (a build named as its code, e.g. in tests)."""
    out = {}
    for b in builds:
        if isinstance(b, str):
            out[b] = b
        elif isinstance(b, dict):
            out[b["id"]] = b["code"]
        else:
            out[b.id] = b.code
    return out


@dataclass
class Plan:
    """The runs of a case, and the (geometry, velocity) pairs not run with the reason."""

    runs: list[RunSpec] = field(default_factory=list)
    skipped: list[dict] = field(default_factory=list)
    #: (build, law, geometry) cells a build's code cannot express, with the reason (engines.codes).
    not_available: list[dict] = field(default_factory=list)
    #: What a reader of the plan must know about what runs (e.g. that an elastic case runs one law).
    notes: list[str] = field(default_factory=list)


def plan_runs(case: Case, engines, laws=LAWS, K_grid=(0.01, 0.03, 0.1, 0.2, 0.3, 0.5),
              time_step_factor: float = 1000.0, match_K: float = 0.1,
              max_overlap_ratio: float = 0.5, roundoff_limit: float = ROUNDOFF_LIMIT,
              ladder: dict | None = None, told: float | None = None, told_input: float | None = None) -> Plan:
    """Every run of `case` for the given engine builds (see `build_codes`) and laws, in a
    stable order: every build runs the same pairs, velocities, laws and time steps. A gated law
    runs a ladder of time steps (`ladder`, default DEFAULT_LADDER; `ladder_factors`); a keyword
    law is told the restitution `told`, else the reference's at match_K (`told_restitution`).
    A told restitution the keyword's code refuses (`Keyword.refuses`: LIGGGHTS wants e > 0.05)
    is not run there, listed in `Plan.not_available` with the reason. `told_input`: a keyword law is
    told that value in its code's own input instead (`Keyword.told`: yade:betan's beta; the
    conformance kit's --beta), with no restitution asked.

    A case with restitutions (`impact: restitution`) is planned once per restitution
    (`contact_model.case_file.restitution_variants`) at each impact velocity: its contacts' eta
    set to restitute it there, the out-of-the-box law told it.

    Raises `PlanError` (naming the case file and the field) for a case the engines cannot run
    honestly: see the module's docstring."""
    if case.restitutions:
        return _plan_restitutions(case, engines, laws, K_grid, time_step_factor, match_K, max_overlap_ratio,
                                  roundoff_limit, ladder)
    unknown = set(laws) - set(LAWS)
    if unknown:
        raise ValueError(f"unknown contact law(s) {sorted(unknown)}; known: {LAWS}")
    ladder = ladder or DEFAULT_LADDER
    plan = Plan()
    allowed = {}  # geometry -> the velocities that are run
    velocities = {pair.geometry: _velocities(case, pair, K_grid) for pair in case.pairs}
    solved = _solved_in_one_batch(case, velocities)
    for pair in case.pairs:
        allowed[pair.geometry] = []
        for v, where, what, K_target in velocities[pair.geometry]:
            scales, probe = _checked(case, pair, v, where, what, K_target, time_step_factor, solved)
            ratio = scales["delta_e"] / pair.R
            skip = {"case": case.name, "geometry": pair.geometry, "K": scales["K"], "V": v, "delta_e/R*": ratio}
            if ratio > max_overlap_ratio:
                plan.skipped.append({**skip, "reason": f"the Hertz overlap would be {ratio:.2g} R* "
                                                       f"(> {max_overlap_ratio:g} R*) at V = {v:.3g} m/s"})
                continue
            error = ladder_roundoff(_probe_ladder(probe, ladder, laws))
            if error > roundoff_limit:
                reason = (f"the Hertz overlap {ratio:.2g} R* at V = {v:.3g} m/s is too small for double-precision "
                          f"positions: round-off would limit the extrapolated errors to about {error:.1g} "
                          f"(> {roundoff_limit:g}); see engines.plan.ROUNDOFF_LIMIT")
                if where == "impact":  # the study's grid: not this case's request
                    plan.skipped.append({**skip, "reason": reason})
                    continue
                raise PlanError(case.path, where, f"{pair.geometry}, {what}: {reason}{_velocity_meaning(where)}")
            allowed[pair.geometry].append(v)
    if not any(allowed.values()):
        field_name = "impact.velocity" if case.velocities else "impact.K" if case.K else "impact"
        reasons = "; ".join(f"{s['geometry']} K = {s['K']:.3g}: {s['reason']}" for s in plan.skipped)
        raise PlanError(case.path, field_name, f"nothing to run: every velocity is left out ({reasons})"
                                               f"{_velocity_meaning(field_name)}")
    # The reference solution of every K of the case, solved in one batch: the runs carry their row
    # (RunSpec.reference), and plan.json hands it on to the engine jobs and the summary.
    # Every K run was solved for the probes above (`solved`); the elastic K = 0 joins them here.
    keys = [(pair.geometry, v) for pair in case.pairs for v in allowed[pair.geometry]]
    Ks = {key: case.pair(key[0]).dissipation_parameter(key[1]) for key in keys}
    solved = _with_solutions({*Ks.values(), 0.0}, solved)
    reference, elastic = {key: solved[K] for key, K in Ks.items()}, solved[0.0]
    builds = build_codes(engines)
    for build, engine in builds.items():
        for pair in case.pairs:
            for law in laws:
                if pair.eta == 0 and law != "elastic":
                    continue  # an elastic contact: the law 'elastic' is all there is to run
                reason = law_unavailable(engine, law)
                if reason is not None:
                    plan.not_available.append({"build": build, "engine": engine, "law": law,
                                               "geometry": pair.geometry, "reason": reason})
                    continue
                keyword = keyword_of(law, engine)
                for v in allowed[pair.geometry]:
                    row = elastic if law == "elastic" else reference[(pair.geometry, v)]
                    e = None
                    if keyword is not None:  # the engine's keyword, against its own equation
                        e = told if told is not None else told_restitution(keyword, match_K)
                        what = "e"
                        if told_input is not None:  # its own input, as the user gives it (no restitution)
                            e, what = told_input, KEYWORDS[keyword].told
                        refused = (KEYWORDS[keyword].refuses(e) if told_input is not None
                                   else keyword_refusal(keyword, e))
                        if refused:
                            plan.not_available.append({
                                "build": build, "engine": engine, "law": law, "geometry": pair.geometry,
                                "reason": f"told {what} = {e:.6g} at V = {v:.6g} m/s: {refused}"})
                            continue
                        plan.runs += keyword_ladder(case.name, engine, law, keyword, pair, v, e, row["K"], ladder,
                                                    build, direct=told_input is not None)
                        continue
                    plan.runs += [RunSpec(case.name, engine, law, pair, v, f, reference=row, build=build)
                                  for f in ladder_factors(ladder, law, row["K"])]
    left_out = [law for law in laws if law != "elastic"]
    if left_out and any(pair.eta == 0 for pair in case.pairs):
        plan.notes.append(f"{case.name}: the viscosity is 0, an elastic contact: only the law 'elastic' runs; "
                          f"{', '.join(left_out)} left out (give a positive `viscosity:` to run them)")
    if not plan.runs:
        raise PlanError(case.path, "viscosity" if all(p.eta == 0 for p in case.pairs) else "laws",
                        f"nothing to run with the laws {', '.join(laws)} in the builds {', '.join(builds)}")
    return plan


def _plan_restitutions(case: Case, engines, laws, K_grid, time_step_factor, match_K, max_overlap_ratio,
                       roundoff_limit, ladder) -> Plan:
    """`plan_runs` of a case with restitutions: one plan per restitution, joined in order."""
    from contact_model.case_file import restitution_variants

    plan = Plan()
    for r, variant in restitution_variants(case):  # one per restitution and velocity, each its own eta
        V = variant.velocities[0]
        sub = plan_runs(variant, engines, laws, K_grid, time_step_factor, match_K, max_overlap_ratio, roundoff_limit,
                        ladder, told=r)
        names = {run.name for run in plan.runs}
        plan.runs += [run for run in sub.runs if run.name not in names]  # Hertz alone (K = 0) runs once
        plan.skipped += [row for row in sub.skipped if row not in plan.skipped]
        plan.not_available += [n for n in sub.not_available if n not in plan.not_available]
        plan.notes += [n for n in sub.notes if n not in plan.notes]
        plan.notes.append(f"{case.name}: restitution {r:g} under {case.restitution_criterion} at V = {V:.6g} m/s: "
                          + "; ".join(f"{p.geometry} eta = {p.eta:.10g} Pa s (K = {p.dissipation_parameter(V):.8g})"
                                      for p in variant.pairs)
                          + f"; the out-of-the-box laws are told {r:g}")
    return plan


def _probe_ladder(probe: RunSpec, ladder: dict, laws) -> list[RunSpec]:
    """The rungs of the gated law of `laws` with the longest runs (the tail kept, then clipped,
    then elastic; elastic alone for an elastic contact) at the probe's velocity: the ladder whose
    round-off decides whether the velocity can be run."""
    law = next((lw for lw in ("viscoelastic", "viscoelastic_clipped", "elastic") if lw in laws), "viscoelastic")
    if probe.pair.eta == 0:
        law = "elastic"
    return rungs_of(replace(probe, law=law), ladder)


def _body(body) -> dict:
    return {"radius": body.radius, "density": body.density, "young": body.young, "poisson": body.poisson}


def plan_listing(case: Case, plan: Plan) -> dict:
    """The plan as plain data (plan.json): the case's contact pairs, every run with what it
    needs and its reference row, and the sha256 of the case file it was made from."""
    return {"case": case.name, "file": case.path, "case_sha256": file_sha256(case.path),
            "pairs": {p.geometry: {"body_1": _body(p.body_1), "body_2": _body(p.body_2), "E": p.E, "eta": p.eta}
                      for p in case.pairs},
            "runs": [{"name": r.name, "ladder": r.ladder, "build": r.build, "engine": r.engine, "law": r.law,
                      "geometry": r.pair.geometry,
                      "represents": list(r.represents), "velocity": r.velocity, "K": r.K,
                      "time_step_factor": r.time_step_factor, "time_step": r.time_step, "steps": r.steps(),
                      "matched_restitution": r.matched_restitution, "eta": r.pair.eta, "reference": r.reference}
                     for r in plan.runs],
            "not_run": plan.skipped, "not_available": plan.not_available, "notes": plan.notes}


def without_missing_keywords(listing: dict, banners: dict[str, str]) -> dict:
    """The plan listing without the runs of keywords their build's release lacks
    (`contact_model.keywords.missing_in`: LAMMPS 29 Sep 2021 has no ``coeff_restitution``),
    each such (build, law, geometry) listed in ``not_available`` with the reason; `banners`
    {build id: version banner} (`engines.builds.check_build`). The rest is unchanged."""
    missing = {}
    for run in listing["runs"]:
        keyword = keyword_of(run["law"], run["engine"])
        banner = banners.get(run["build"])
        if keyword is not None and banner is not None and missing_in(keyword, banner):
            missing[(run["build"], run["law"], run["geometry"])] = (run["engine"], missing_in(keyword, banner))
    if not missing:
        return listing
    cells = [{"build": b, "engine": engine, "law": law, "geometry": g, "reason": reason}
             for (b, law, g), (engine, reason) in missing.items()]
    return {**listing, "runs": [r for r in listing["runs"] if (r["build"], r["law"], r["geometry"]) not in missing],
            "not_available": listing["not_available"] + cells}


def build_part(listing: dict, build: str) -> dict:
    """The part of a plan listing (plan_listing) that one build runs: its runs and its cells not
    available; the case, its pairs and the velocities not run as they are.

    Parameters
    ----------
    listing : dict
        A case's plan listing (results/<case>/plan.json).
    build : str
        A build's id.
    """
    return {**listing, "runs": [r for r in listing["runs"] if r["build"] == build],
            "not_available": [c for c in listing["not_available"] if c.get("build") == build]}


def runs_from_listing(case: Case | None, listing: dict, build: str) -> list[RunSpec]:
    """The runs of build `build` (its id) in a plan listing (plan_listing), rebuilt with their reference rows,
    so that no later rule solves the ODE again. A listing that does not match the case (a run
    whose name comes out different) is an error: the plan is stale.

    With `case` None the contact pairs come from the listing itself, and the case file it
    names must still have the sha256 it was planned from: an engine job then reads no case
    file and no units (pint), which was a third of its own time."""
    if case is None:
        if file_sha256(listing["file"]) != listing["case_sha256"]:
            raise ValueError(f"{listing['file']} changed after its plan was made: the plan is stale: rerun the study")
        pairs = {g: ContactPair(g, Body(**p["body_1"]), Body(**p["body_2"]), p["E"], p["eta"])
                 for g, p in listing["pairs"].items()}
        name = listing["case"]
    else:
        pairs, name = {p.geometry: p for p in case.pairs}, case.name
    runs = []
    for entry in listing["runs"]:
        if entry["build"] != build:
            continue
        pair = pairs[entry["geometry"]]
        if "eta" in entry and entry["eta"] != pair.eta:  # a case with restitutions: each its own eta
            pair = replace(pair, eta=entry["eta"])
        spec = RunSpec(name, entry["engine"], entry["law"], pair, entry["velocity"],
                       entry["time_step_factor"], matched_restitution=entry["matched_restitution"],
                       reference=entry["reference"], build=build)
        if spec.name != entry["name"]:
            raise ValueError(f"{listing['file']}: the plan lists run {entry['name']!r} but the case gives "
                             f"{spec.name!r}; "
                             "the plan is stale: rerun the study")
        runs.append(spec)
    return runs


def plan_at_velocity(case: Case, engine: str, K_values, time_step_factors, velocity: float,
                     purpose: str, build: str = "", solved: dict | None = None,
                     every_law: bool = False) -> list[RunSpec]:
    """Runs of the case's material and geometries at one impact velocity, the viscosity set for
    each K, at every time-step factor (the convergence study, the paper's Fig. 4). `purpose` tags
    the case name. K = 0 runs the law 'elastic' (Hertz alone) in every code; K > 0 runs the
    model under test, 'viscoelastic', or, in a code that cannot keep the attractive tail
    (`engines.codes`, ``unavailable``, e.g. ESyS), 'viscoelastic_clipped' (criterion F0 only);
    with `every_law`, every viscoelastic law the code can express. A code that cannot express
    the viscoelastic force at all (e.g. Kratos) runs K = 0 alone.

    Every run carries the reference at its own K (`RunSpec.reference`), solved in one batch;
    `solved` ({K: reference row}, `references_of` an earlier plan of the same runs) spares the
    solve, and with it the compiled kernel's load (~1 s), in a job whose workflow has solved them."""
    from contact_model import ContactPair
    from contact_model.collision_scales import viscosity_for_dissipation

    laws = [lw for lw in ("viscoelastic", "viscoelastic_clipped") if law_unavailable(engine, lw) is None]
    laws = laws if every_law else laws[:1]
    runs = []
    for pair in case.pairs:
        for K in K_values:
            eta = viscosity_for_dissipation(pair.E, pair.R, pair.M, velocity, K) if K > 0 else 0.0
            tuned = ContactPair(pair.geometry, pair.body_1, pair.body_2, pair.E, eta)
            runs += [RunSpec(f"{case.name}-{purpose}", engine, law, tuned, velocity, f, build=build)
                     for law in (laws if K > 0 else ["elastic"]) for f in time_step_factors]
    # The reference at every run's own K in one batch, handed on as run_engine's plan does: a
    # run solved its K itself each time it was asked for its steps (72 one-K solves for the
    # 36 runs of a convergence sweep). K > 10 and K = 0 need none (RunSpec.steps).
    needed = {r.K for r in runs if 0.0 < r.K <= 10.0}
    solved = _with_solutions(needed, solved)
    return [replace(r, reference=solved[r.K]) if r.K in needed else r for r in runs]


def references_of(runs: list[RunSpec]) -> dict:
    """{K: reference row} of the runs that carry one: what `plan_at_velocity(..., solved=)`
    takes, to hand a plan's solutions on to a job (a Snakemake param) instead of solving again."""
    return {r.K: r.reference for r in runs if r.reference is not None}


# The keywords' promise (snakemake keywords) and the history (snakemake history): their runs come
# from here, by the helpers the study's plan uses (`keyword_refusal`, `keyword_ladder`,
# `ladder_factors`), so that the three refuse and ladder alike.


def promise_keywords(code: str, banner: str = "") -> tuple[dict[str, str], dict[str, str]]:
    """({keyword: its law}, {keyword: why the release lacks it}) of `code`'s restitution keywords
    (told e: their promise is eps = e; and its own keyword told a value computed from e, OpenFOAM's
    alpha(e): the study's map and the code together promise eps = e) that are laws of the code
    (`contact_model.laws.KEYWORD_LAWS`: the code's own, law ``default``, and the others that are laws
    of their own, e.g. LAMMPS's ``coeff_restitution``), each under its first law; a keyword the
    release whose version banner is `banner` predates (`missing_in`) is in the second ('': a release
    not known, none left out)."""
    laws, missing = {}, {}
    for law in KEYWORD_LAWS:
        name = keyword_of(law, code)
        own_from_e = law == "default" and name is not None and KEYWORDS[name].from_restitution is not None  # OpenFOAM
        if (name is None or law_unavailable(code, law) is not None or (KEYWORDS[name].told != "e" and not own_from_e)
                or name in laws or name in missing):
            continue
        why = missing_in(name, banner) if banner else None
        if why:
            missing[name] = why
        else:
            laws[name] = law
    return laws, missing


@dataclass
class PromisePlan:
    """The runs of keywords told restitutions: a ladder per (keyword, e), and the (keyword, e) its
    code refuses (`keyword_refusal`) with the reason, not run (the engine would stop the sweep)."""

    ladders: dict[tuple[str, float], list[RunSpec]] = field(default_factory=dict)
    refused: dict[tuple[str, float], str] = field(default_factory=dict)

    @property
    def runs(self) -> list[RunSpec]:
        return [r for rungs in self.ladders.values() for r in rungs]

    def of(self, keyword: str) -> dict[float, list[RunSpec]]:
        """{e: ladder} of one keyword."""
        return {e: rungs for (name, e), rungs in self.ladders.items() if name == keyword}


def keyword_promise_plan(case_name: str, engine: str, keywords: dict[str, str], pair, velocity: float,
                         restitutions, ladder: dict | None = None, build: str = "") -> PromisePlan:
    """Every keyword of `keywords` ({keyword: law}, `promise_keywords`) of `engine` told every e of
    `restitutions` in the contact `pair` at `velocity`, a ladder each (`keyword_ladder`), but
    what its code refuses (`keyword_refusal`, as the study's plan refuses it)."""
    plan = PromisePlan()
    K = pair.dissipation_parameter(velocity)
    for name, law in keywords.items():
        for e in map(float, restitutions):
            refused = keyword_refusal(name, e)
            if refused:
                plan.refused[(name, e)] = refused
            else:
                plan.ladders[(name, e)] = keyword_ladder(case_name, engine, law, name, pair, velocity, e, K, ladder,
                                                         build)
    return plan


def keyword_table_plan(keywords_settings: dict, engine: str, banner: str, ladder: dict | None = None,
                       build: str = "") -> tuple[dict[str, str], PromisePlan]:
    """The keywords' promise table of one build (config `keywords:`: its case, geometry, velocity
    and restitutions): ({keyword: law} of the build's restitution keywords its release has, their
    `keyword_promise_plan`, named 'keywords')."""
    keywords, _ = promise_keywords(engine, banner)
    pair = load_case(keywords_settings["case"]).pair(keywords_settings["geometry"])
    return keywords, keyword_promise_plan("keywords", engine, keywords, pair, float(keywords_settings["velocity"]),
                                          keywords_settings["restitution"], ladder, build)


@dataclass
class HistoryPlan:
    """The runs of one release's checks in the history: a ladder of the viscoelastic laws per
    check ({check: (criterion, ladder)}), the restitution keywords' promise, and the keywords
    the release lacks ({keyword: why})."""

    ladders: dict[str, tuple[str, list[RunSpec]]] = field(default_factory=dict)
    keywords: dict[str, str] = field(default_factory=dict)
    promise: PromisePlan = field(default_factory=PromisePlan)
    missing: dict[str, str] = field(default_factory=dict)

    @property
    def runs(self) -> list[RunSpec]:
        return [r for _, rungs in self.ladders.values() for r in rungs] + self.promise.runs


def history_plan(history: dict, engine: str, banner: str = "", ladder: dict | None = None,
                 build: str = "") -> HistoryPlan:
    """The runs of a release of `engine` in the history (config `history:`): each reduced case's
    laws (those the code can express) at the case's own impacts, else at `history.K`, a ladder
    each, criterion x0 with the tail kept, F0 clipped; its restitution keywords (`promise_keywords`)
    told `history.restitution` in the first case's first contact at its first velocity
    (`keyword_promise_plan`, named 'history')."""
    plan = HistoryPlan()
    cases = [load_case(path) for path in history["cases"]]
    for case in cases:
        for pair in case.pairs:
            for law in history["laws"]:
                if law_unavailable(engine, law) is not None:
                    continue
                velocities = case.impact_velocities(pair, history["K"])  # a case's own impacts, else history.K
                for V in velocities:
                    K = pair.dissipation_parameter(V)
                    check = f"{law} {pair.geometry}" + (f" {case.name} K={K:.3g}"
                                                         if len(cases) + len(velocities) > 2 else "")
                    plan.ladders[check] = (LAW_REGISTRY[law].criteria[0],  # x0 with the tail kept, F0 clipped
                                           [RunSpec(case.name, engine, law, pair, V, f, build=build)
                                            for f in ladder_factors(ladder or DEFAULT_LADDER, law, K)])
    plan.keywords, plan.missing = promise_keywords(engine, banner)
    pair = cases[0].pairs[0]
    V = cases[0].impact_velocities(pair, history["K"])[0]
    plan.promise = keyword_promise_plan("history", engine, plan.keywords, pair, V, history["restitution"], ladder,
                                        build)
    return plan
