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


def oblique_plan(cases, code: str, build: str, banner: str, factors, ranks=(1,)) -> ObliquePlan:
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
                    for n in ranks:
                        # Two ranks check that crossing a processor boundary changes nothing (bitwise,
                        # `analysis.oblique.processor_boundary_checks`): one rung does, the coarsest.
                        for f in (factors if n == 1 else factors[:1]):
                            normal = RunSpec(case.name, code, law, pair, impact["normal_velocity"],
                                             time_step_factor=float(f), build=build)
                            plan.runs.append(ObliqueRun(normal, model.name, case.friction,
                                                        impact["tangential_velocity"], impact["spin"],
                                                        ranks=n))
    return plan
