"""From a case file and the study settings to the list of engine runs.

For every contact pair of the case (one per geometry) and every impact velocity (the case's
own, or those that give the study's K grid in that geometry):

- the viscoelastic law (tail kept: criteria x0 and F0 from one trajectory) in every engine;
- optionally the clipped viscoelastic law (criterion F0: the engines' own way of separating);
- optionally each engine's out-of-the-box law, its restitution matched once, at `match_K`,
  to the reference eps under the criterion that engine's default stands for; the same setting
  then runs at every velocity of the sweep, which shows how far it drifts.
"""

from __future__ import annotations

from contact_model import Case
from reference import solve_collision

from .run_spec import DEFAULT_LAW_CRITERION, LAWS, RunSpec


def impact_velocities(case: Case, pair, K_grid) -> list[float]:
    """The case's velocities, or those giving each K of the grid (case's own K first)."""
    if case.velocities:
        return list(case.velocities)
    Ks = case.K or tuple(K_grid)
    return [pair.velocity_for_dissipation(k) for k in Ks]


def matched_restitution(engine: str, match_K: float) -> float:
    """The reference eps at match_K under the criterion of the engine's default law."""
    r = solve_collision(match_K)
    return r["eps_x0"] if DEFAULT_LAW_CRITERION[engine] == "x0" else r["eps_F0"]


def plan_runs(case: Case, engines, laws=LAWS, K_grid=(0.01, 0.03, 0.1, 0.2, 0.3, 0.5),
              time_step_factor: float = 1000.0, match_K: float = 0.1) -> list[RunSpec]:
    """Every run of `case` for the given engines and laws, in a stable order."""
    unknown = set(laws) - set(LAWS)
    if unknown:
        raise ValueError(f"unknown contact law(s) {sorted(unknown)}; known: {LAWS}")
    runs = []
    for engine in engines:
        for pair in case.pairs:
            velocities = impact_velocities(case, pair, K_grid)
            for law in laws:
                if law == "viscoelastic" or law == "viscoelastic_clipped":
                    if pair.eta == 0 and law == "viscoelastic_clipped":
                        continue  # an elastic contact never pulls: nothing to clip
                    runs += [RunSpec(case.name, engine, law, pair, v, time_step_factor) for v in velocities]
                elif law == "default":
                    if pair.eta == 0:
                        continue
                    e = matched_restitution(engine, match_K)
                    runs += [RunSpec(case.name, engine, law, pair, v, time_step_factor, matched_restitution=e)
                             for v in velocities]
    return runs
