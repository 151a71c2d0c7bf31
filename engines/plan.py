"""From a case file and the study settings to the list of engine runs.

For every contact pair of the case (one per geometry) and every impact velocity (the case's
own, or those that give the study's K grid in that geometry):

- the viscoelastic law (tail kept: criteria x0 and F0 from one trajectory) in every engine;
- optionally the clipped viscoelastic law (criterion F0: the engines' own way of separating);
- optionally each engine's out-of-the-box law, its restitution matched once, at `match_K`,
  to the reference eps under the criterion that engine's default stands for; the same setting
  then runs at every velocity of the sweep, which shows how far it drifts.

A velocity whose Hertz overlap delta_e exceeds `max_overlap_ratio` R* is not run, with the
reason recorded: there the contact radius is no longer small against R* (Hertz's premise), and
the engines' contact geometry breaks down as delta approaches the radius (a sphere's centre
would cross the plane). It takes km/s impacts for the stiff materials at large K.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from contact_model import Case
from reference import solve_collision

from .run_spec import DEFAULT_LAW_CRITERION, LAWS, RunSpec


def matched_restitution(engine: str, match_K: float) -> float:
    """The reference eps at match_K under the criterion of the engine's default law."""
    r = solve_collision(match_K)
    return r["eps_x0"] if DEFAULT_LAW_CRITERION[engine] == "x0" else r["eps_F0"]


@dataclass
class Plan:
    """The runs of a case, and the (geometry, velocity) pairs not run with the reason."""

    runs: list[RunSpec] = field(default_factory=list)
    skipped: list[dict] = field(default_factory=list)


def plan_runs(case: Case, engines, laws=LAWS, K_grid=(0.01, 0.03, 0.1, 0.2, 0.3, 0.5),
              time_step_factor: float = 1000.0, match_K: float = 0.1,
              max_overlap_ratio: float = 0.5) -> Plan:
    """Every run of `case` for the given engines and laws, in a stable order."""
    unknown = set(laws) - set(LAWS)
    if unknown:
        raise ValueError(f"unknown contact law(s) {sorted(unknown)}; known: {LAWS}")
    plan = Plan()
    allowed = {}  # geometry -> the velocities that are run
    for pair in case.pairs:
        allowed[pair.geometry] = []
        for v in case.impact_velocities(pair, K_grid):
            ratio = pair.scales(v)["delta_e"] / pair.R
            if ratio <= max_overlap_ratio:
                allowed[pair.geometry].append(v)
            else:
                plan.skipped.append({
                    "case": case.name, "geometry": pair.geometry, "K": pair.dissipation_parameter(v),
                    "V": v, "delta_e/R*": ratio,
                    "reason": f"the Hertz overlap would be {ratio:.2g} R* (> {max_overlap_ratio:g} R*) at "
                              f"V = {v:.3g} m/s"})
    for engine in engines:
        for pair in case.pairs:
            for law in laws:
                if law != "viscoelastic" and pair.eta == 0:
                    continue  # an elastic contact never pulls (nothing to clip) and has no restitution to match
                e = matched_restitution(engine, match_K) if law == "default" else None
                plan.runs += [RunSpec(case.name, engine, law, pair, v, time_step_factor, matched_restitution=e)
                              for v in allowed[pair.geometry]]
    return plan


def plan_at_velocity(case: Case, engine: str, K_values, time_step_factors, velocity: float,
                     purpose: str) -> list[RunSpec]:
    """Runs of the case's material and geometries at one impact velocity, the viscosity set for
    each K (K = 0: elastic), at every time-step factor (the convergence study, the paper's
    Fig. 4). `purpose` tags the case name."""
    from contact_model import ContactPair
    from contact_model.collision_scales import viscosity_for_dissipation

    runs = []
    for pair in case.pairs:
        for K in K_values:
            eta = viscosity_for_dissipation(pair.E, pair.R, pair.M, velocity, K) if K > 0 else 0.0
            tuned = ContactPair(pair.geometry, pair.body_1, pair.body_2, pair.E, eta)
            runs += [RunSpec(f"{case.name}-{purpose}", engine, "viscoelastic", tuned, velocity, f)
                     for f in time_step_factors]
    return runs
