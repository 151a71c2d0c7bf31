"""Material case files (YAML) -> validated `Case` objects in SI units.

Two ways to describe the bodies (docs/case_files.md gives the full format):

1. One material, as in the paper's Table 1: ``effective_modulus`` (E* of two bodies of the
   material), ``radius`` and ``density`` of the sphere; ``geometries`` picks sphere-sphere
   (two identical spheres) and/or sphere-plane (a plane of the same material: same E*).
2. Explicit ``bodies``: a list of two, the first a sphere ``{radius, density, young, poisson}``,
   the second a sphere or a plane ``{plane: true, young, poisson}`` / ``{plane: rigid}``.

Both need ``viscosity`` (the effective eta). An optional ``impact`` block gives ``K`` (a list of
target dissipation parameters) or ``velocity`` (a list of impact velocities); without it the
study's K grid (config/config.yaml) applies.

An optional ``measurements`` key names a CSV file of measured restitution coefficients
(`contact_model.measurement_file`), its path relative to the folder of the case file (so that a
case and its data move together and the path does not depend on the working directory). The file
is read and checked when the case is loaded. A case with measurements describes exactly one
contact (one geometry, or explicit bodies): the data belong to one pair. For such a case
``viscosity`` is the starting value only; the calibration fits it.

The file is read strictly, so that it cannot say one thing and run another:

- a quantity is exactly one plain number, one space and a unit ("109 GPa", "6.7e5 P",
  "0.635 cm", "7800 kg/m^3", "1 m/s"); comma decimals, digit groups, a second number, an
  expression or any other text is an error, and so is a number beyond double precision;
- the structure is checked against `case_file.schema.yaml`: unknown keys, contradictory blocks
  (``bodies`` with ``effective_modulus``, a rigid plane with a modulus), empty or repeated lists
  are errors; documentation keys are allowed only by name (description, note,
  <field>_source, <field>_note);
- the YAML is plain data: duplicated keys, anchors and aliases, explicit tags, YAML 1.1 number
  and boolean spellings (0.3_0, 010, 1:30, yes) and deep nesting are errors.

Every error is a `CaseError` naming the file and the field.
"""

from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import yaml

from .contact_pair import GEOMETRIES, Body, ContactPair
from .quantities import CaseError, not_a_quantity, quantity, written_unit
from .strict_yaml import PLAIN_FLOAT, join_field, read_utf8, scan_plain_yaml

#: What `impact.velocity` means, said wherever a velocity is refused: Chung & Ooi's test 1, written
#: as 10 m/s per sphere instead of 20 m/s between them, gives T off by 15 %.
VELOCITY_MEANING = ("`velocity` is the relative normal velocity of the two bodies at impact: two spheres each "
                    "moving at 10 m/s towards the other collide at 20 m/s; a sphere on a plane at rest, at its own "
                    "speed")



SCHEMA_PATH = Path(__file__).with_name("case_file.schema.yaml")

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
    measurements: object = None  # a measurement_file.Measurements, or None
    #: The unit `viscosity:` is written in ('P', 'mPa*s'): the calibration answers in it too.
    viscosity_unit: str = "Pa*s"
    #: `impact: restitution`: the restitution coefficients to run at the first impact velocity,
    #: and the end of contact they refer to ('F0' or 'x0'). The pairs' eta restitutes the first;
    #: `restitution_variants` gives one case per restitution.
    restitutions: tuple[float, ...] = ()
    restitution_criterion: str = "F0"

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


def _positive(value, name, path) -> float:
    x = quantity(value, name, path)
    if not (x > 0 and math.isfinite(x)):
        raise CaseError(path, name, f"must be positive and finite, got {value!r}")
    return x


def _poisson(value, name, path) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(path, name, f"must be a number (dimensionless), got {value!r}")
    if not -1.0 < value < 0.5:  # also refuses nan
        raise CaseError(path, name, f"Poisson's ratio must lie in (-1, 0.5), got {value}")
    return float(value)


# ------------------------------------------------------------------------------ the schema
_SCHEMA = None


def _validator():
    global _SCHEMA
    if _SCHEMA is None:
        schema = yaml.safe_load(SCHEMA_PATH.read_text(encoding="utf-8"))
        import jsonschema  # here: only reading a case file needs it

        jsonschema.Draft202012Validator.check_schema(schema)
        _SCHEMA = jsonschema.Draft202012Validator(schema)
    return _SCHEMA


def _field(where) -> str:
    out = ""
    for part in where:
        out = f"{out}[{part}]" if isinstance(part, int) else join_field(out, part)
    return out or "(top level)"


#: The order in which to report schema errors at the same depth: a misspelt or missing key
#: first (it usually explains the rest), the 'exactly one of' summaries last.
_PRIORITY = {"additionalProperties": 0, "required": 1, "not": 2, "const": 3, "type": 4, "oneOf": 9}


def _schema_problem(err, data) -> tuple[str, str]:
    """(field, readable problem) of a jsonschema error on `data`."""
    where = list(err.absolute_path)
    schema = err.schema if isinstance(err.schema, dict) else {}
    messages = schema.get("x-messages", {})
    instance = err.instance
    if err.validator == "required":
        missing = [k for k in err.validator_value if k not in instance]
        hint = " (or describe the contact by 'bodies')" if not where and missing[0] in (
            "effective_modulus", "radius", "density") else ""
        return _field(where + [missing[0]]), "missing" + hint
    if err.validator == "additionalProperties":
        known = schema.get("properties", {})
        patterns = list(schema.get("patternProperties", {}))
        extra = sorted(str(k) for k in instance if k not in known and not any(re.search(p, str(k)) for p in patterns))
        docs = "description, note, <field>_source, <field>_note" if not where else "note, <field>_source, <field>_note"
        close = difflib.get_close_matches(extra[0], list(known), n=1, cutoff=0.7)
        guess = f"did you mean '{close[0]}'? " if close else "a typo? "
        return (_field(where + [extra[0]]),
                f"unknown field ({guess}known here: {', '.join(known)}; documentation: {docs})")
    if schema.get("x-parent"):  # an item error better said about its list
        where, instance = where[:-1], data
        for part in where:
            instance = instance[part]
    if err.validator in messages:
        problem = messages[err.validator].replace("{instance!r}", repr(instance))
    elif schema.get("x-kind") == "quantity" and err.validator == "type":
        return _field(where), not_a_quantity(instance, _field(where))
    else:
        problem = err.message
    if err.validator == "type" and isinstance(instance, str) and PLAIN_FLOAT.fullmatch(instance.strip()):
        problem += f" (YAML 1.1 reads {instance!r} as text: write the exponent with a dot and a sign, e.g. 1.0e-1)"
    return _field(where), problem


def _check_schema(data, path) -> None:
    errors = list(_validator().iter_errors(data))
    if not errors:
        return
    errors.sort(key=lambda e: (len(e.absolute_path), _PRIORITY.get(e.validator, 5), _field(e.absolute_path)))
    field_name, problem = _schema_problem(errors[0], data)
    raise CaseError(path, field_name, problem)


# ------------------------------------------------------------------------------ building the case
def _body(spec: dict, index: int, path) -> Body:
    """A body from its (schema-checked) mapping. SI units."""
    where = f"bodies[{index}]"
    plane = spec.get("plane", False)
    if plane == "rigid":
        return Body(math.inf, math.inf, math.inf, 0.0)
    young = _positive(spec["young"], where + ".young", path)
    poisson = _poisson(spec["poisson"], where + ".poisson", path)
    if plane:
        return Body(math.inf, math.inf, young, poisson)
    radius = _positive(spec["radius"], where + ".radius", path)
    density = _positive(spec["density"], where + ".density", path)
    return Body(radius, density, young, poisson)


def _impact(data: dict, path) -> tuple[tuple[float, ...], tuple[float, ...]]:
    if "impact" not in data:
        return (), ()  # the study's K grid applies
    impact = data["impact"]
    if "K" in impact:
        ks = []
        for i, k in enumerate(impact["K"]):
            if isinstance(k, bool) or not isinstance(k, (int, float)) or not 0 < k <= 10:
                raise CaseError(path, f"impact.K[{i}]", f"must be a number in (0, 10], got {k!r}")
            if float(k) in ks:
                raise CaseError(path, f"impact.K[{i}]", f"gives K = {k} a second time (impact.K[{ks.index(float(k))}])")
            ks.append(float(k))
        return tuple(ks), ()
    vs = []
    for i, v in enumerate(impact["velocity"]):
        x = _positive(v, f"impact.velocity[{i}]", path)
        for j, y in enumerate(vs):
            if math.isclose(x, y, rel_tol=1e-12):
                raise CaseError(path, f"impact.velocity[{i}]",
                                f"{v!r} is the velocity of impact.velocity[{j}] again ({y:g} m/s)")
        vs.append(x)
    return (), tuple(vs)


def _check_finite(pair: ContactPair, fields: dict, path) -> None:
    """E*, R*, M* must be positive, finite doubles (extreme inputs can overflow or underflow)."""
    for symbol, attribute, unit in (("E*", "E", "Pa"), ("R*", "R", "m"), ("M*", "M", "kg")):
        try:
            value = getattr(pair, attribute)
        except (OverflowError, ZeroDivisionError) as err:  # e.g. radius**3 in the mass
            raise CaseError(path, fields[symbol], f"{symbol} ({pair.geometry}) cannot be computed in double "
                                                  f"precision ({err})")
        if not (math.isfinite(value) and value > 0):
            raise CaseError(path, fields[symbol], f"gives {symbol} = {value:g} {unit} ({pair.geometry}): "
                                                  "beyond double precision")


def parse_case(data, path) -> Case:
    """Validate the parsed YAML `data` of case file `path` (used in messages)."""
    if not isinstance(data, dict):
        got = "nothing (an empty file)" if data is None else f"a {type(data).__name__}: {data!r:.60}"
        raise CaseError(path, "(top level)", f"a case file must be a YAML mapping of fields, got {got}")
    impact = data.get("impact")
    if isinstance(impact, dict) and "restitution" in impact and "velocity" not in impact:
        _restitution(data, path)  # refuses it naming impact.restitution, before the schema's 'K or velocity'
    _check_schema(data, path)
    name = data.get("name", Path(str(path)).stem)
    restitutions, criterion = _restitution(data, path)
    if restitutions and "viscosity" in data:
        raise CaseError(path, "viscosity", "the impact's restitution sets the viscosity (the eta that restitutes it "
                                           "at the impact velocity): leave `viscosity:` out, or give K or velocity "
                                           "alone")
    if not restitutions and "viscosity" not in data:
        raise CaseError(path, "viscosity", "missing (or give `impact: {restitution: [...], velocity: [...]}`, "
                                           "which sets it)")
    eta = quantity(data["viscosity"], "viscosity", path) if not restitutions else 0.0  # set below
    if not (eta >= 0 and math.isfinite(eta)):
        raise CaseError(path, "viscosity", f"must be non-negative, got {data['viscosity']!r}")

    if "bodies" in data:
        bodies = data["bodies"]
        pairs = (ContactPair.from_bodies(_body(bodies[0], 0, path), _body(bodies[1], 1, path), eta),)
        fields = {"E*": "bodies", "R*": "bodies", "M*": "bodies"}
    else:
        E = _positive(data["effective_modulus"], "effective_modulus", path)
        radius = _positive(data["radius"], "radius", path)
        density = _positive(data["density"], "density", path)
        geometries = data.get("geometries", list(GEOMETRIES))
        sphere = Body(radius, density)
        other = {"sphere-sphere": sphere, "sphere-plane": Body(math.inf, math.inf)}
        pairs = tuple(ContactPair(g, sphere, other[g], E, eta) for g in geometries)
        fields = {"E*": "effective_modulus", "R*": "radius", "M*": "radius"}  # M* = (4/3) pi R^3 rho
    for pair in pairs:
        _check_finite(pair, fields, path)

    K, velocities = _impact(data, path)
    if K and eta == 0:
        raise CaseError(path, "impact.K", "a target K needs a positive viscosity")
    if restitutions:  # the eta that restitutes the first restitution at the first velocity, per contact
        pairs = tuple(replace(p, eta=_viscosity_for_restitution(p, velocities[0], restitutions[0], criterion, 0,
                                                                path)) for p in pairs)
        for i, r in enumerate(restitutions[1:], start=1):
            _viscosity_for_restitution(pairs[0], velocities[0], r, criterion, i, path)  # reachable?
    measurements = _measurements(data, pairs, path)
    known = {"name", "description", "viscosity", "bodies", "effective_modulus", "radius",
             "density", "geometries", "impact", "measurements"}
    extra = {k: v for k, v in data.items() if k not in known}  # the documentation keys
    return Case(str(name), str(path), pairs, K, velocities, str(data.get("description", "")), extra,
                measurements, viscosity_unit=written_unit(data["viscosity"]) if "viscosity" in data else "Pa*s",
                restitutions=restitutions, restitution_criterion=criterion)


def _restitution(data: dict, path) -> tuple[tuple[float, ...], str]:
    """The case's restitution coefficients and the criterion they refer to ((), 'F0' without)."""
    impact = data.get("impact") or {}
    if "criterion" in impact and "restitution" not in impact:
        raise CaseError(path, "impact.criterion", "names the end of contact a restitution refers to: give it with "
                                                  "`restitution:`")
    if "restitution" not in impact:
        return (), "F0"
    if "velocity" not in impact:
        raise CaseError(path, "impact.restitution", "needs the impact velocity it holds at: add `velocity: [...]` "
                                                    f"beside it ({VELOCITY_MEANING}), not K")
    return tuple(float(r) for r in impact["restitution"]), str(impact.get("criterion", "F0"))


def _viscosity_for_restitution(pair, V: float, eps: float, criterion: str, i: int, path) -> float:
    """The eta [Pa s] whose viscoelastic collision of `pair` at V restitutes eps under `criterion`;
    a CaseError naming impact.restitution[i] when no eta does."""
    from reference.dissipation_for_restitution import dissipation_for_restitution

    from .collision_scales import viscosity_for_dissipation

    try:
        K = dissipation_for_restitution(eps, criterion)
    except ValueError as err:
        raise CaseError(path, f"impact.restitution[{i}]", f"no viscoelastic law can reach it: {err}") from None
    return viscosity_for_dissipation(pair.E, pair.R, pair.M, V, K)


def restitution_variants(case: Case) -> list[tuple[float, Case]]:
    """(restitution, the case with each contact's eta set to restitute it at the first impact
    velocity under the case's criterion) for every restitution of the case, in order; the
    variants have no restitutions of their own. A case without restitutions: []."""
    out = []
    for i, r in enumerate(case.restitutions):
        pairs = tuple(replace(p, eta=_viscosity_for_restitution(p, case.velocities[0], r, case.restitution_criterion,
                                                                i, case.path)) for p in case.pairs)
        out.append((r, replace(case, pairs=pairs, restitutions=())))
    return out


def _measurements(data: dict, pairs, path):
    """The case's measurement file, read (its path relative to the case file's folder), or None."""
    if "measurements" not in data:
        return None
    from .measurement_file import load_measurements  # it imports this module

    if len(pairs) != 1:
        raise CaseError(path, "measurements", f"measurements belong to one contact, but the case describes "
                                              f"{len(pairs)} ({', '.join(p.geometry for p in pairs)}): give one "
                                              "geometry (e.g. geometries: [sphere-plane]) or explicit bodies")
    relative = Path(data["measurements"])
    if relative.is_absolute():
        raise CaseError(path, "measurements", f"{data['measurements']!r} is an absolute path: give it relative to "
                                              "the case file's folder, so that the project can move")
    csv_path = Path(str(path)).parent / relative
    if not csv_path.is_file():
        raise CaseError(path, "measurements", f"no file {str(csv_path)!r} (the path is relative to the case "
                                              "file's folder)")
    return load_measurements(csv_path)


def load_case(path) -> Case:
    """Read and validate a case file: UTF-8 YAML, plain data, a mapping of known fields."""
    path = Path(path)
    text = read_utf8(path)
    scan_plain_yaml(text, path)
    try:
        data = yaml.load(text, Loader=yaml.SafeLoader)  # noqa: S506 - SafeLoader, after scan_plain_yaml
    except yaml.YAMLError as err:  # scan_plain_yaml has read the same events; kept as a guard
        raise CaseError(path, "(file)", f"not valid YAML: {' '.join(str(err).split())}")
    return parse_case(data, path)
