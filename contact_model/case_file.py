"""Material case files (YAML) -> validated `Case` objects in SI units.

Two ways to describe the bodies (see cases/README.md for the full format):

1. One material, as in the paper's Table 1: ``effective_modulus`` (E* of two bodies of the
   material), ``radius`` and ``density`` of the sphere; ``geometries`` picks sphere-sphere
   (two identical spheres) and/or sphere-plane (a plane of the same material: same E*).
2. Explicit ``bodies``: a list of two, the first a sphere ``{radius, density, young, poisson}``,
   the second a sphere or a plane ``{plane: true, young, poisson}`` / ``{plane: rigid}``.

Both need ``viscosity`` (the effective eta). An optional ``impact`` block gives ``K`` (a list of
target dissipation parameters) or ``velocity`` (a list of impact velocities); without it the
study's K grid (config/config.yaml) applies. Quantities carry their
units as strings ("109 GPa", "6.7e5 P", "0.635 cm", "7800 kg/m^3", "1 m/s"), converted with pint.
Every error names the file and the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import pint
import yaml

from .contact_pair import GEOMETRIES, Body, ContactPair

UNITS = pint.UnitRegistry()

# field -> (pint dimensionality, SI unit)
DIMENSIONS = {
    "effective_modulus": ("[pressure]", "Pa"),
    "young": ("[pressure]", "Pa"),
    "viscosity": ("[pressure] * [time]", "Pa*s"),
    "radius": ("[length]", "m"),
    "density": ("[mass] / [length] ** 3", "kg/m^3"),
    "velocity": ("[length] / [time]", "m/s"),
}


class CaseError(ValueError):
    """A case file that cannot be used; the message names the file and the field."""

    def __init__(self, path, field_name: str, problem: str):
        self.path, self.field, self.problem = str(path), field_name, problem
        super().__init__(f"{path}: field '{field_name}': {problem}")


@dataclass(frozen=True)
class Case:
    """A validated case: its contact pairs (one per geometry) and impact conditions (SI)."""

    name: str
    path: str
    pairs: tuple[ContactPair, ...]
    K: tuple[float, ...] = ()
    velocities: tuple[float, ...] = ()
    description: str = ""
    extra: dict = field(default_factory=dict)

    def pair(self, geometry: str) -> ContactPair:
        for p in self.pairs:
            if p.geometry == geometry:
                return p
        raise KeyError(f"case {self.name!r} has no {geometry} contact")

    def impact_velocities(self, pair: ContactPair, K_grid=()) -> list[float]:
        """The impact velocities [m/s] of this case for one of its pairs: its own velocities,
        or those giving its own K list, or those giving `K_grid` (the study's)."""
        if self.velocities:
            return list(self.velocities)
        return [pair.velocity_for_dissipation(k) for k in (self.K or tuple(K_grid))]


def quantity(value, name: str, path) -> float:
    """Convert a '<number> <unit>' string (or a number with unit) to SI for field `name`."""
    dimension, si_unit = DIMENSIONS[name.split(".")[-1].split("[")[0]]
    if isinstance(value, bool) or value is None:
        raise CaseError(path, name, f"expected a quantity with a unit, e.g. '1 {si_unit}', got {value!r}")
    if isinstance(value, (int, float)):
        raise CaseError(path, name, f"{value!r} has no unit; write it as e.g. '{value} {si_unit}'")
    try:
        q = UNITS.Quantity(str(value))
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, ValueError,
            AttributeError, TypeError) as err:
        raise CaseError(path, name, f"cannot read {value!r} as a quantity ({err})")
    if not isinstance(q, pint.Quantity) or q.dimensionless:
        raise CaseError(path, name, f"{value!r} has no unit; expected a {dimension} such as '{si_unit}'")
    if not q.check(dimension):
        raise CaseError(path, name, f"{value!r} is a {q.dimensionality}, expected a {dimension} (e.g. {si_unit})")
    return float(q.to(si_unit).magnitude)


def _positive(value, name, path) -> float:
    x = quantity(value, name, path)
    if not (x > 0 and math.isfinite(x)):
        raise CaseError(path, name, f"must be positive and finite, got {value!r}")
    return x


def _poisson(value, name, path) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(path, name, f"must be a number (dimensionless), got {value!r}")
    if not -1.0 < value < 0.5:
        raise CaseError(path, name, f"Poisson's ratio must lie in (-1, 0.5), got {value}")
    return float(value)


def _require(data: dict, key: str, where: str, path):
    if key not in data:
        raise CaseError(path, where + key, "missing")
    return data[key]


def _body(spec, index: int, path) -> Body:
    where = f"bodies[{index}]"
    if not isinstance(spec, dict):
        raise CaseError(path, where, f"must be a mapping, got {spec!r}")
    plane = spec.get("plane", False)
    if plane not in (False, True, "rigid"):
        raise CaseError(path, where + ".plane", f"must be true, false or 'rigid', got {plane!r}")
    if plane and index == 0:
        raise CaseError(path, where + ".plane", "the first body must be a sphere")
    if plane == "rigid":
        return Body(math.inf, math.inf, math.inf, 0.0)
    young = _positive(_require(spec, "young", where + ".", path), where + ".young", path)
    poisson = _poisson(_require(spec, "poisson", where + ".", path), where + ".poisson", path)
    if plane:
        return Body(math.inf, math.inf, young, poisson)
    radius = _positive(_require(spec, "radius", where + ".", path), where + ".radius", path)
    density = _positive(_require(spec, "density", where + ".", path), where + ".density", path)
    return Body(radius, density, young, poisson)


def _impact(data: dict, path) -> tuple[tuple[float, ...], tuple[float, ...]]:
    if "impact" not in data:
        return (), ()  # the study's K grid applies
    impact = data["impact"]
    if not isinstance(impact, dict) or len(set(impact) & {"K", "velocity"}) != 1:
        raise CaseError(path, "impact", "give exactly one of 'K' (a list) or 'velocity' (a list)")
    if "K" in impact:
        ks = impact["K"] if isinstance(impact["K"], list) else [impact["K"]]
        for i, k in enumerate(ks):
            if isinstance(k, bool) or not isinstance(k, (int, float)) or not 0 < k <= 10:
                raise CaseError(path, f"impact.K[{i}]", f"must be a number in (0, 10], got {k!r}")
        return tuple(float(k) for k in ks), ()
    vs = impact["velocity"] if isinstance(impact["velocity"], list) else [impact["velocity"]]
    return (), tuple(_positive(v, f"impact.velocity[{i}]", path) for i, v in enumerate(vs))


def parse_case(data, path) -> Case:
    """Validate the parsed YAML `data` of case file `path` (used in messages)."""
    if not isinstance(data, dict):
        raise CaseError(path, "(top level)", "a case file must be a YAML mapping")
    name = data.get("name", Path(str(path)).stem)
    eta = quantity(_require(data, "viscosity", "", path), "viscosity", path)
    if not (eta >= 0 and math.isfinite(eta)):
        raise CaseError(path, "viscosity", f"must be non-negative, got {data['viscosity']!r}")

    if "bodies" in data:
        bodies = data["bodies"]
        if not isinstance(bodies, list) or len(bodies) != 2:
            raise CaseError(path, "bodies", "must be a list of exactly two bodies")
        pairs = (ContactPair.from_bodies(_body(bodies[0], 0, path), _body(bodies[1], 1, path), eta),)
    else:
        E = _positive(_require(data, "effective_modulus", "", path), "effective_modulus", path)
        radius = _positive(_require(data, "radius", "", path), "radius", path)
        density = _positive(_require(data, "density", "", path), "density", path)
        geometries = data.get("geometries", list(GEOMETRIES))
        if not isinstance(geometries, list) or not geometries or any(g not in GEOMETRIES for g in geometries):
            raise CaseError(path, "geometries", f"must be a list drawn from {list(GEOMETRIES)}, got {geometries!r}")
        sphere = Body(radius, density)
        other = {"sphere-sphere": sphere, "sphere-plane": Body(math.inf, math.inf)}
        pairs = tuple(ContactPair(g, sphere, other[g], E, eta) for g in geometries)

    K, velocities = _impact(data, path)
    if K and eta == 0:
        raise CaseError(path, "impact.K", "a target K needs a positive viscosity")
    known = {"name", "description", "viscosity", "bodies", "effective_modulus", "radius",
             "density", "geometries", "impact"}
    extra = {k: v for k, v in data.items() if k not in known}
    return Case(str(name), str(path), pairs, K, velocities, str(data.get("description", "")), extra)


def load_case(path) -> Case:
    """Read and validate a case file."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise CaseError(path, "(file)", f"cannot read: {err.strerror}")
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as err:
        raise CaseError(path, "(file)", f"not valid YAML: {err}")
    return parse_case(data, path)
