"""LAMMPS (Debian 20220106, GRANULAR package): the deck variables of a run (cases/decks/lammps/).

pair_style granular / fix wall/gran granular with normal model `hertz` (kn = 4/3 E*) and
`damping viscoelastic` (eta_n = eta_n0 a m_eff, eta_n0 = 2 eta / M*): the exact Brilliantov
force, attractive tail kept. `limit_damping` clips the total force at zero (criterion F0).
The out-of-the-box law is `hertz/material` with `damping tsuji`, whose coefficient is the
restitution coefficient itself.

Known defect of the 2021 version (fixed in 22 Jul 2025), kept as a regression case (`wall_modulus_regression`): fix
wall/gran with `hertz/material E eta nu` uses E / (2 (1 - nu)) instead of E / (2 (1 - nu^2))
(src/GRANULAR/fix_wall_gran.cpp), so the study always gives the wall an explicit `hertz` kn.
"""

from __future__ import annotations

import math
from pathlib import Path

from contact_model import Body, ContactPair

from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .run_spec import RunSpec
from .script_engine import ScriptEngine, common_variables, number

DECK_OF_GEOMETRY = {"sphere-sphere": "two_spheres.in", "sphere-plane": "sphere_plane.in"}
TANGENTIAL = "tangential linear_nohistory 0 0"  # required by the granular styles; zero friction


def deck_files(spec: RunSpec) -> list[str]:
    return [DECK_OF_GEOMETRY[spec.pair.geometry]]


def model_words(spec: RunSpec) -> str:
    """The granular model of a run, as pair_coeff / fix wall/gran words."""
    p = spec.pair
    if spec.law == "default":
        # hertz/material E e nu with tsuji damping: e is read as the restitution coefficient.
        # nu = 0 on both sides makes E* = E/2, and also sidesteps the wall's 1 - nu defect.
        return f"hertz/material {number(2.0 * p.E)} {number(spec.matched_restitution)} 0.0 damping tsuji {TANGENTIAL}"
    params = p.engine_parameters("lammps")
    words = f"hertz {number(params['kn'])} {number(params['eta_n0'])} damping viscoelastic {TANGENTIAL}"
    return words + (" limit_damping" if spec.law == "viscoelastic_clipped" else "")


def deck_variables(spec: RunSpec, out: Path, decks: Path) -> dict[str, str]:
    """The deck variables of one run (SI): the common ones, the diameters and the model."""
    var = {**common_variables(spec), "model": model_words(spec), "out": str(out)}
    for i, body in ((1, spec.pair.body_1), (2, spec.pair.body_2)):
        if not body.is_plane:
            var[f"d{i}"] = number(2 * body.radius)
    return var


LAMMPS = ScriptEngine(
    name="lammps", executable="lmp", version_prefix="LAMMPS",
    decks=Path(__file__).resolve().parents[1] / "cases" / "decks" / "lammps",
    variables=deck_variables, deck_files=deck_files, step0_in_record=True,
)


def run_lammps(specs: list[RunSpec], workdir, executable: str = "lmp",
               timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, **kw):
    """Run LAMMPS collisions in one process (see `ScriptEngine.run`); returns a `Sweep`.
    The process's time limit scales with the sweep, never below `timeout_floor_s` seconds."""
    return LAMMPS.run(specs, workdir, executable, timeout_floor_s=timeout_floor_s, **kw)


def wall_modulus_regression(workdir, young: float = 200e9, poisson: float = 0.3, radius: float = 0.005,
                            density: float = 7800.0, velocity: float = 1.0, executable: str = "lmp",
                            build: str = ""):
    """The wall `hertz/material` defect, measured: an elastic sphere on a plane of its own
    material (E* = Y / (2 (1 - nu^2))), once with an explicit `hertz` kn = 4/3 E* and once with
    `hertz/material Y 0 nu` as a user would write it, in the LAMMPS `executable` (build id
    `build` in the run names). Returns ((explicit, material), sweep).

    The 2021 build's wall gives the material run an error of (1 + nu)^(-2/5) - 1 in T (its wall
    E* is 1 + nu times too large); a build with the fix gives 0."""
    sphere = Body(radius, density, young, poisson)
    pair = ContactPair.from_bodies(sphere, Body(math.inf, math.inf, young, poisson), 0.0)
    spec = RunSpec("lammps-wall-modulus", "lammps", "viscoelastic", pair, velocity)
    spec = RunSpec("lammps-wall-modulus", "lammps", "viscoelastic", pair, velocity, build=build)
    material = RunSpec("lammps-wall-modulus", "lammps", "viscoelastic", pair, velocity, label="hertz-material",
                       build=build)
    words = f"hertz/material {number(young)} 0.0 {number(poisson)} damping viscoelastic {TANGENTIAL}"
    overrides = {material.name: {"model": words}}
    return (spec, material), run_lammps([spec, material], workdir, executable, overrides=overrides)
