"""LAMMPS (Debian 20220106, GRANULAR package): the deck variables of a run (cases/decks/lammps/).

pair_style granular / fix wall/gran granular with normal model `hertz` (kn = 4/3 E*) and
`damping viscoelastic` (eta_n = eta_n0 a m_eff, eta_n0 = 2 eta / M*): the exact Brilliantov
force, attractive tail kept. `limit_damping` clips the total force at zero (criterion F0).
The out-of-the-box law is `hertz/material` with `damping tsuji`, whose coefficient is the
restitution coefficient itself.

Two defects of the 2021 version, both fixed in 22 Jul 2025, are kept as regression cases run in
every LAMMPS build (`regression_cases`):

- ``wall-modulus``: fix wall/gran with `hertz/material E eta nu` uses E / (2 (1 - nu)) instead of
  E / (2 (1 - nu^2)) (src/GRANULAR/fix_wall_gran.cpp), so the study always gives the wall an
  explicit `hertz` kn;
- ``mixing``: with one `pair_coeff i i` line per atom type and the 1-2 contact left to mixing,
  pair_style granular does not carry the normal and damping models into the mixed pair, so the
  study gives every pair one `pair_coeff * *` line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from contact_model import Body, ContactPair
from contact_model.collision_scales import viscosity_for_dissipation
from contact_model.keywords import KEYWORDS

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .finish_run import Sweep
from .run_spec import RunSpec
from .script_engine import ScriptEngine, common_variables, number

DECK_OF_GEOMETRY = {"sphere-sphere": "two_spheres.in", "sphere-plane": "sphere_plane.in"}
TANGENTIAL = "tangential linear_nohistory 0 0"  # required by the granular styles; zero friction


#: Regression runs that need a deck of their own, by their RunSpec label.
DECK_OF_LABEL = {"per-type-coefficients": "two_spheres_two_types.in"}


def deck_files(spec: RunSpec) -> list[str]:
    return [DECK_OF_LABEL.get(spec.label) or DECK_OF_GEOMETRY[spec.pair.geometry]]


#: The damping words of LAMMPS's restitution keywords (contact_model.keywords).
DAMPING_OF_KEYWORD = {"lammps:tsuji": "tsuji", "lammps:coeff_restitution": "coeff_restitution",
                      "lammps:velocity": "velocity", "lammps:mass_velocity": "mass_velocity"}


def damping_coefficient(spec: RunSpec) -> float:
    """The number after E in `hertz/material E _ nu`: the restitution e for the restitution
    keywords; for the linear dashpots the eta_n that restitutes e at this run's velocity, from the
    dashpot's c of the run's reference row (contact_model.keywords.keyword_reference): c M* V /
    delta_e [N s/m] for `velocity`, c V / delta_e [1/s] for `mass_velocity`."""
    if spec.keyword not in ("lammps:velocity", "lammps:mass_velocity"):
        return spec.matched_restitution
    c = spec.reference["c"] if spec.reference and "c" in spec.reference else KEYWORDS[spec.keyword].told_for(
        spec.matched_restitution)
    rate = c * spec.velocity / spec.scales["delta_e"]
    return rate * spec.pair.M if spec.keyword == "lammps:velocity" else rate


def model_words(spec: RunSpec) -> str:
    """The granular model of a run, as pair_coeff / fix wall/gran words."""
    p = spec.pair
    if spec.keyword is not None:
        # hertz/material E e nu with a restitution damping: e is read as the restitution
        # coefficient. nu = 0 on both sides makes E* = E/2, and also sidesteps the wall's 1 - nu defect.
        return (f"hertz/material {number(2.0 * p.E)} {number(damping_coefficient(spec))} 0.0 "
                f"damping {DAMPING_OF_KEYWORD[spec.keyword]} {TANGENTIAL}")
    params = code("lammps").contact_parameters(p)
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


@dataclass(frozen=True)
class RegressionCase:
    """A known LAMMPS defect as a run: `run` is the contact written the way a user would write it,
    `control` the same contact written the way the study does (it must match the reference in
    every build, or the case proves nothing); each is run as a ladder of time steps
    (`engines.plan.rungs_of`), extrapolated like the gated runs. `overrides` replace deck
    variables of the user's ladder (by its name). `defect_err_T` is the relative error in T the
    defect gives, where it can be predicted (None: no closed form)."""

    name: str
    description: str
    user_writes: str
    run: RunSpec
    control: RunSpec
    overrides: dict
    defect_err_T: float | None


def regression_cases(build: str = "", young: float = 200e9, poisson: float = 0.3, radius: float = 0.005,
                     density: float = 7800.0, velocity: float = 1.0, K: float = 0.1) -> list[RegressionCase]:
    """The LAMMPS regression cases of build id `build`, steel-like spheres at `velocity` [m/s]:

    - ``wall-modulus``: an elastic sphere on a plane of its own material (E* = Y / (2 (1 - nu^2))),
      `hertz/material Y 0 nu` against an explicit `hertz` kn = 4/3 E*. A wall E* that is 1 + nu
      times too large (the 2021 defect) gives T off by (1 + nu)^(-2/5) - 1 (Hertz: T ~ E*^{-2/5}).
    - ``mixing``: two equal spheres, viscoelastic at dissipation parameter K, the model given per
      atom type (`pair_coeff 1 1`, `pair_coeff 2 2`, the 1-2 pair mixed) against `pair_coeff * *`.
    """
    sphere = Body(radius, density, young, poisson)
    wall = ContactPair.from_bodies(sphere, Body(math.inf, math.inf, young, poisson), 0.0)
    elastic_pair = ContactPair.from_bodies(sphere, sphere, 0.0)
    eta = viscosity_for_dissipation(elastic_pair.E, elastic_pair.R, elastic_pair.M, velocity, K)
    pair = ContactPair(elastic_pair.geometry, sphere, sphere, elastic_pair.E, eta)

    def spec(name, p, label=""):
        return RunSpec(f"lammps-{name}", "lammps", "viscoelastic", p, velocity, label=label, build=build)

    material = spec("wall-modulus", wall, "hertz-material")
    words = f"hertz/material {number(young)} 0.0 {number(poisson)} damping viscoelastic {TANGENTIAL}"
    mixed = spec("mixing", pair, "per-type-coefficients")
    return [
        RegressionCase("wall-modulus", "fix wall/gran hertz/material: the wall's E*",
                       "fix wall/gran granular hertz/material E 0 nu", material, spec("wall-modulus", wall),
                       {material.ladder: {"model": words}}, (1 + poisson) ** -0.4 - 1),
        RegressionCase("mixing", "pair_style granular: the mixed 1-2 pair of per-type coefficients",
                       "pair_coeff 1 1 hertz kn eta_n0 ...; pair_coeff 2 2 (the same)", mixed,
                       spec("mixing", pair), {}, None),
    ]


def run_regression_cases(workdir, executable: str = "lmp", build: str = "",
                         timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S):
    """Every regression case in the LAMMPS `executable`, each (its control's ladder, then its
    run's) in a process of its own, so that a defect that crashes the engine (the 2021 build's
    mixed pair can end in SIGSEGV) fails its own case only, in `workdir/<case>/`; returns
    (cases, sweep) with every case's runs."""
    from .plan import rungs_of

    cases = regression_cases(build)
    sweep = Sweep()
    for case in cases:
        one = run_lammps([*rungs_of(case.control), *rungs_of(case.run)], Path(workdir) / case.name, executable,
                         overrides=case.overrides, timeout_floor_s=timeout_floor_s)
        sweep.dumps.update(one.dumps)
        sweep.failures.update(one.failures)
        sweep.engine_seconds += one.engine_seconds
    return cases, sweep


def wall_modulus_regression(workdir, young: float = 200e9, poisson: float = 0.3, radius: float = 0.005,
                            density: float = 7800.0, velocity: float = 1.0, executable: str = "lmp",
                            build: str = ""):
    """The wall `hertz/material` case alone (see `regression_cases`): ((explicit, material), sweep).
    The 2021 build's wall gives the material run an error of (1 + nu)^(-2/5) - 1 in T; a build
    with the fix gives 0."""
    (case, _) = regression_cases(build, young, poisson, radius, density, velocity)
    sweep = run_lammps([case.control, case.run], workdir, executable, overrides=case.overrides)
    return (case.control, case.run), sweep
