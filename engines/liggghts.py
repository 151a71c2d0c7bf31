"""LIGGGHTS-PUBLIC 3.8.0: the deck variables of a run (cases/decks/liggghts/).

The decks hold only LIGGGHTS syntax; every number is set here, from the contact pair through
`contact_model`. The sweep mechanics are shared with LAMMPS (engines/script_engine.py).
"""

from __future__ import annotations

from pathlib import Path

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .run_spec import RunSpec
from .script_engine import ScriptEngine, common_variables, number

DECK_OF_GEOMETRY = {"sphere-sphere": "two_spheres.in", "sphere-plane": "sphere_plane.in"}
PROPERTIES_OF_LAW = {"viscoelastic": "properties_viscoelastic.in",
                     "viscoelastic_clipped": "properties_viscoelastic.in",
                     "elastic": "properties_viscoelastic.in",  # with gamman = 0 (the pair's eta is 0)
                     "default": "properties_default.in"}


def deck_files(spec: RunSpec) -> list[str]:
    return [DECK_OF_GEOMETRY[spec.pair.geometry], PROPERTIES_OF_LAW[spec.law]]


def deck_variables(spec: RunSpec, out: Path, decks: Path) -> dict[str, str]:
    """The deck variables of one run (SI): the common ones, the law's property file and model."""
    p = spec.pair
    var = {
        **common_variables(spec),
        "properties": str(decks / PROPERTIES_OF_LAW[spec.law]),
        "model_tail": "limitForce " + ("on" if spec.law == "viscoelastic_clipped" else "off"),
        "out": str(out),
    }
    if spec.keyword is not None:  # its one keyword: model hertz with coefficientRestitution
        var["model_head"] = "model hertz tangential no_history"
        var["young"] = number(2.0 * p.E)  # poisson 0 on both: Y* = Y/2 = E*
        var["restitution"] = number(spec.matched_restitution)
    else:
        params = code("liggghts").contact_parameters(p)
        var["model_head"] = "model hertz/stiffness tangential no_history"
        var["kn"], var["gamman"] = number(params["kn"]), number(params["gamman"])
    return var


LIGGGHTS = ScriptEngine(
    name="liggghts", executable="liggghts", version_prefix="LIGGGHTS",
    decks=Path(__file__).resolve().parents[1] / "cases" / "decks" / "liggghts",
    variables=deck_variables, deck_files=deck_files, step0_in_record=False,
)


def run_liggghts(specs: list[RunSpec], workdir, executable: str = "liggghts",
                 timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, **kw):
    """Run LIGGGHTS collisions in one process (see `ScriptEngine.run`); returns a `Sweep`.
    The process's time limit scales with the sweep, never below `timeout_floor_s` seconds."""
    return LIGGGHTS.run(specs, workdir, executable, timeout_floor_s=timeout_floor_s, **kw)
