"""The oblique runs of a build: every oblique case's impacts, in each geometry of the case, with
each tangential model the build's release has (`contact_model.tangential_models`), a ladder of
time steps each.

A model the release lacks is not run: it is listed in `ObliquePlan.refused` with the reason, so
that the report can say so beside the cell (never an empty cell that reads as PASS).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from contact_model.tangential_models import models_for

from .oblique_run import ObliqueRun
from .run_spec import RunSpec


@dataclass
class ObliquePlan:
    """The runs of one build and what was left out.

    Attributes
    ----------
    runs : list of ObliqueRun
        Every rung of every ladder.
    refused : dict
        {(case, model): why} for the build's code's models its release lacks, or the case's normal law
        its oblique driver cannot run.
    build : str
        The build id.
    """

    runs: list[ObliqueRun] = field(default_factory=list)
    refused: dict = field(default_factory=dict)
    build: str = ""


def normal_law(case) -> str:
    """The normal law of an oblique case: ``elastic`` for viscosity 0, else ``viscoelastic``."""
    return "elastic" if all(p.eta == 0 for p in case.pairs) else "viscoelastic"


def finer_ladder(entries, case: str, contact_angle: float, model: str):
    """The time-step factors config ``oblique.finer_ladders`` gives an impact, or None.

    Parameters
    ----------
    entries : sequence of dict
        {case, angles, ladder, models?}: the case's name, the contact-point incidences [deg] of the
        impacts (`ObliqueRun.contact_angle`, to 1e-6 deg), their factors (three or more, > 0), and
        the tangential models they apply to (default: every model).
    case, contact_angle, model
        The impact's case name, incidence [deg] and tangential model.

    Raises
    ------
    ValueError
        An entry without its fields, naming the entry and the field.
    """
    for i, e in enumerate(entries or ()):
        where = f"config oblique.finer_ladders[{i}]"
        if not isinstance(e, dict) or not {"case", "angles", "ladder"} <= set(e):
            raise ValueError(f"{where}: needs the fields case, angles and ladder, got {e!r}")
        ladder = e["ladder"]
        if not (isinstance(ladder, list) and len(ladder) >= 3
                and all(isinstance(f, (int, float)) and f > 0 for f in ladder)):
            raise ValueError(f"{where}.ladder: three or more positive time-step factors, got {ladder!r}")
        if not (isinstance(e["angles"], list) and all(isinstance(a, (int, float)) for a in e["angles"])):
            raise ValueError(f"{where}.angles: a list of incidences in degrees, got {e['angles']!r}")
        if e["case"] != case or (e.get("models") is not None and model not in e["models"]):
            continue
        if any(abs(contact_angle - a) <= 1e-6 for a in e["angles"]):
            return [float(f) for f in ladder]
    return None


def oblique_plan(cases, code: str, build: str, banner: str, factors, ranks=(1,), finer=()) -> ObliquePlan:
    """The oblique runs of `build` (of engine `code`, whose version line is `banner`).

    Parameters
    ----------
    cases : sequence of contact_model.Case
        Oblique cases (`Case.is_oblique`); head-on ones are skipped.
    code, build, banner : str
        The engine code, the build id and the build's version line.
    factors : sequence of float
        The ladder's time-step factors (dt ~ T_e / factor), each rung aligned (`RunSpec.time_step`).
    ranks : sequence of int
        The MPI process counts to run: 1, every rung of every ladder; 2, the coarsest rung of
        each again on two ranks (the processor-boundary check).
    finer : sequence of dict
        Config ``oblique.finer_ladders`` (`finer_ladder`): impacts whose ladder takes other factors
        than `factors` (those whose default rungs are short of their asymptotic range: data, so
        that the plan names them and the report costs them).

    Returns
    -------
    ObliquePlan
    """
    from .codes import CODES

    plan = ObliquePlan(build=build)
    models, missing = models_for(code, banner)
    for case in cases:
        if not case.is_oblique:
            continue
        for name, why in missing.items():
            plan.refused[(case.name, name)] = why
        law = normal_law(case)
        if law in CODES[code].oblique_unavailable:
            for model in models:
                plan.refused[(case.name, model.name)] = f"{law}: {CODES[code].oblique_unavailable[law]}"
            continue
        for pair in case.pairs:
            for impact in case.oblique_impacts():
                for model in models:
                    if pair.geometry not in model.geometries:
                        plan.refused[(case.name, f"{model.name} ({pair.geometry})")] = (
                            f"{model.name} has no {pair.geometry} contact")
                        continue
                    probe = ObliqueRun(RunSpec(case.name, code, law, pair, impact["normal_velocity"],
                                               time_step_factor=float(factors[0]), build=build),
                                       model.name, case.friction, impact["tangential_velocity"], impact["spin"])
                    ladder = finer_ladder(finer, case.name, probe.contact_angle, model.name) or factors
                    for n in ranks:
                        # Two ranks check that crossing a processor boundary changes nothing (bitwise,
                        # `analysis.oblique.processor_boundary_checks`): one rung does, the coarsest.
                        for f in (ladder if n == 1 else ladder[:1]):
                            normal = RunSpec(case.name, code, law, pair, impact["normal_velocity"],
                                             time_step_factor=float(f), build=build)
                            plan.runs.append(ObliqueRun(normal, model.name, case.friction,
                                                        impact["tangential_velocity"], impact["spin"],
                                                        ranks=n))
    return plan
