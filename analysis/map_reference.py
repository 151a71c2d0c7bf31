"""The discrete reference of an engine run: the engines' own map (`reference.engine_map`) replayed
at the run's time step, beside the gate (which judges the ladders' limits against the ODE).

Every build of the study advances a collision with the same map, so a run that implements the
law exactly reproduces the map's replay at its own dt to round-off, at any dt: no extrapolation,
no time-step error to remove. The differences (`map_errors`: the engine's T, A and eps against
the replay's, relative) are a diagnostic, not a check: they show an implementation error of a
build at every rung (kn x (1 + 1e-5) moves T by 4e-6 at every dt), and how far each engine's
rounding (positions stored at the magnitude of the radius; ESyS's forces read back from velocity
jumps) takes it from the exact map.

Pure functions; the replay is in the reference solver's units (x = delta / delta_e,
tau = t V / delta_e), the engine's numbers are made dimensionless with its run's scales.
"""

from __future__ import annotations

import math

from contact_model.keywords import KEYWORDS
from contact_model.laws import DAMPING_POWER
from engines.codes import keyword_of
from engines.run_spec import GAP_STEPS
from reference.engine_map import replay

from records.collision_metrics import CollisionMetrics, ExtractionError, collision_metrics


def map_law(meta: dict) -> tuple[float, float, bool]:
    """(coefficient, damping power, clipped) of the map of the run of dump header `meta`: the
    viscoelastic model's K and x^{1/2} (clipped for viscoelastic_clipped), or an engine keyword's
    own coefficient, power and clip (`contact_model.keywords`) at the restitution it was told.

    Parameters
    ----------
    meta : dict
        The run's dump header: law, engine, K, and matched_restitution (the restitution an engine
        keyword was told [-]) for a keyword's run.
    """
    keyword = keyword_of(meta["law"], meta["engine"])
    if keyword is None:
        return float(meta["K"]), 0.5, meta["law"] == "viscoelastic_clipped"
    k = KEYWORDS[keyword]
    if meta.get("told_input") is not None:  # told its own input directly (yade:betan's beta)
        return k.b(float(meta["told_input"])), DAMPING_POWER[k.form], k.clipped
    return k.b(k.told_for(float(meta["matched_restitution"]))), DAMPING_POWER[k.form], k.clipped


def map_metrics(meta: dict, samples: int) -> CollisionMetrics:
    """The map's collision for the run of dump header `meta` (its law, time step and start
    phase), `samples` samples long, extracted like an engine's record (dimensionless).

    Parameters
    ----------
    meta : dict
        The run's dump header: law, engine, K (matched_restitution for a keyword), time_step [s],
        impact_velocity [m/s], delta_e [m], optionally start_phase (default 0.5).
    samples : int
        The length of the replay, in steps.
    """
    h = meta["time_step"] * meta["impact_velocity"] / meta["delta_e"]
    coefficient, power, clipped = map_law(meta)
    d = replay(coefficient, h, samples, start_phase=meta.get("start_phase", 0.5), gap_steps=GAP_STEPS,
               clipped=clipped, power=power)
    return collision_metrics(*d.T, impact_velocity=1.0)


def map_errors(meta: dict, m: CollisionMetrics, samples: int) -> dict:
    """{criterion: {'T', 'A', 'eps': the engine's value / the map's - 1}} of a run of any law
    (`map_law`: the model's or an engine keyword's force on the same map); empty where the map's
    collision cannot be extracted.

    Parameters
    ----------
    meta : dict
        The run's dump header, as for `map_metrics`, with represents (its criteria, 'x0' and/or 'F0').
    m : records.collision_metrics.CollisionMetrics
        The engine's collision, in SI units.
    samples : int
        The length of the map's replay, in steps.
    """
    try:
        ref = map_metrics(meta, samples)
    except ExtractionError:
        return {}
    to_t = meta["delta_e"] / meta["impact_velocity"]
    out = {}
    for criterion in meta["represents"]:
        T, T_map = (m.T_x0, ref.T_x0) if criterion == "x0" else (m.T_F0, ref.T_F0)
        eps, eps_map = (m.eps_x0, ref.eps_x0) if criterion == "x0" else (m.eps_F0, ref.eps_F0)
        out[criterion] = {"T": T / (T_map * to_t) - 1.0, "A": m.delta_max / (ref.delta_max * meta["delta_e"]) - 1.0,
                          "eps": eps / eps_map - 1.0 if eps_map != 0 else math.nan}
    return out
