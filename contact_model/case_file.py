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
case and its data move together and the path does not depend on the working directory). The path
is data, not a licence to read: it must lead, symlinks followed, to a regular file inside the
project folder (`project_folder`), else it is refused unread. The file is read and checked when
the case is loaded. A case with measurements describes exactly one contact (one geometry, or
explicit bodies): the data belong to one pair. For such a case ``viscosity`` is the starting value
only; the calibration fits it.

``impact: {restitution: [...], velocity: [...]}`` replaces ``viscosity``: every restitution runs
at every impact velocity, each run with the eta that restitutes it exactly there
(`restitution_variants`), as an engine's restitution keyword restitutes it at every velocity.

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

Every error is a `CaseError` naming the file and the field. A message repeats a value of the
file only escaped and cut short (`quantities.shown`), and never the text of a file that is not a
case file.
"""

from __future__ import annotations

import difflib
import math
import os
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import yaml

from .contact_pair import GEOMETRIES, Body, ContactPair
from .quantities import CaseError, field_text, not_a_quantity, quantity, shown, written_unit
from .strict_yaml import PLAIN_FLOAT, join_field, read_utf8, scan_plain_yaml

#: What `impact.velocity` means, said wherever a velocity is refused: Chung & Ooi's test 1, written
#: as 10 m/s per sphere instead of 20 m/s between them, gives T off by 15 %.
VELOCITY_MEANING = ("`velocity` is the relative normal velocity of the two bodies at impact: two spheres each "
                    "moving at 10 m/s towards the other collide at 20 m/s; a sphere on a plane at rest, at its own "
                    "speed")



SCHEMA_PATH = Path(__file__).with_name("case_file.schema.yaml")
#: The repository this package belongs to: the project folder of a case file that lies in no
#: folder of the study (`project_folder`).
REPOSITORY_ROOT = Path(__file__).resolve().parents[1]
#: The largest restitution a case may ask for. Above it (1 - eps < 1e-8) the K, hence the eta, that
#: restitutes eps is below 1e-8: the inversion (`reference.dissipation_for_restitution`, Brent's
#: method to 1e-14 in K) resolves it to no better than 1e-6 relative, the study's tolerance, at the
#: limit, and to nothing at all near 1 - 1.1e-16 (the last double below 1, where it gives K = 0, an
#: elastic contact); and the ladders, which resolve eps to 1e-8 at best, could not tell such a
#: run from an elastic one.
RESTITUTION_MAX = 0.99999999

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
    #: `impact: restitution`: the restitution coefficients to run at every impact velocity, and
    #: the end of contact they refer to ('F0' or 'x0'). The pairs' eta restitutes the first at the
    #: first velocity; `restitution_variants` gives one case per restitution and velocity.
    restitutions: tuple[float, ...] = ()
    restitution_criterion: str = "F0"
    #: The K that restitutes each of `restitutions` under the criterion (independent of the bodies
    #: and the velocity: eta follows from it per contact and velocity).
    restitution_dissipations: tuple[float, ...] = ()
    #: Oblique impacts (docs/tangential.md): Coulomb's mu (None: a head-on case), the incidences
    #: from the normal [deg] (with `velocities` the resultants) or the tangential velocities [m/s]
    #: (with `velocities` the normal components), and body 1's initial spins about +z [rad/s].
    friction: float | None = None
    angles: tuple[float, ...] = ()
    tangential_velocities: tuple[float, ...] = ()
    spins: tuple[float, ...] = ()

    @property
    def is_oblique(self) -> bool:
        """Whether the case gives oblique impacts (`friction` with an angle, tangential velocity or spin)."""
        return self.friction is not None

    def oblique_impacts(self) -> list[dict]:
        """The case's oblique impacts: every velocity with every angle or tangential velocity, and
        every spin.

        Returns
        -------
        list of dict
            Each with ``normal_velocity`` v_n [m/s] (> 0), ``tangential_velocity`` v_t [m/s] (the
            centres' relative velocity along +y), ``spin`` w1 [rad/s], ``angle`` [deg] (the
            incidence atan(v_t / v_n)) and ``given`` ('angle' or 'tangential_velocity').
        """
        out = []
        for V in self.velocities:
            if self.angles:
                pairs = [(V * math.cos(math.radians(a)), V * math.sin(math.radians(a)), "angle")
                         for a in self.angles]
            else:
                pairs = [(V, vt, "tangential_velocity") for vt in (self.tangential_velocities or (0.0,))]
            for v_n, v_t, given in pairs:
                for w in self.spins or (0.0,):
                    out.append({"normal_velocity": v_n, "tangential_velocity": v_t, "spin": w,
                                "angle": math.degrees(math.atan2(v_t, v_n)), "given": given})
        return out

    def pair(self, geometry: str) -> ContactPair:
        """The case's contact pair of `geometry`.

        Parameters
        ----------
        geometry : str
            'sphere-sphere' or 'sphere-plane'.

        Returns
        -------
        ContactPair

        Raises
        ------
        KeyError
            When the case has no contact of that geometry.
        """
        for p in self.pairs:
            if p.geometry == geometry:
                return p
        raise KeyError(f"case {self.name!r} has no {geometry} contact")

    def impact_velocities(self, pair: ContactPair, K_grid=()) -> list[float]:
        """The impact velocities of this case for one of its pairs.

        Its own velocities, or those giving its own K list, or those giving `K_grid` (the study's).

        Parameters
        ----------
        pair : ContactPair
            One of the case's pairs (SI).
        K_grid : sequence of float
            The dissipation parameters used when the case gives neither velocities nor K [-].

        Returns
        -------
        list of float
            The impact velocities [m/s].
        """
        if self.velocities:
            return list(self.velocities)
        return [pair.velocity_for_dissipation(k) for k in (self.K or tuple(K_grid))]


def _positive(value, name, path) -> float:
    x = quantity(value, name, path)
    if not (x > 0 and math.isfinite(x)):
        raise CaseError(path, name, f"must be positive and finite, got {shown(value)}")
    return x


def _poisson(value, name, path) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CaseError(path, name, f"must be a number (dimensionless), got {shown(value)}")
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
        close = difflib.get_close_matches(extra[0][:100], list(known), n=1, cutoff=0.7)
        guess = f"did you mean '{close[0]}'? " if close else "a typo? "
        return (_field(where + [field_text(extra[0])]),
                f"unknown field ({guess}known here: {', '.join(known)}; documentation: {docs})")
    if schema.get("x-parent"):  # an item error better said about its list
        where, instance = where[:-1], data
        for part in where:
            instance = instance[part]
    if err.validator in messages:
        problem = messages[err.validator].replace("{instance!r}", shown(instance))
    elif schema.get("x-kind") == "quantity" and err.validator == "type":
        return _field(where), not_a_quantity(instance, _field(where))
    else:
        problem = err.message if len(err.message) <= 300 else err.message[:300] + "... (cut)"  # it may hold a value
    if err.validator == "type" and isinstance(instance, str) and PLAIN_FLOAT.fullmatch(instance.strip()):
        problem += number_as_text_hint(instance)
    return _field(where), problem


def number_as_text_hint(text: str) -> str:
    """Why a number in a case file arrived as text, and how to write it.

    For a `text` that is one plain number: quoted ('0.8', "1"), or an exponent that YAML 1.1 reads
    as text (1e-1, 1.5E3).

    Parameters
    ----------
    text : str
        The value as YAML gave it.

    Returns
    -------
    str
        The hint, with its leading space.
    """
    number = text.strip()
    if isinstance(yaml.safe_load(number), (int, float)):  # YAML reads it unquoted as a number: it was quoted
        return f" ({shown(text)} is in quotes, so it is text, not a number: write it without quotes, {number})"
    if not re.search("[eE]", number):  # '+.5': YAML 1.1 wants a digit before the dot after a sign
        return f" (YAML 1.1 reads {number} as text, not a number: write it as {float(number)!r})"
    mantissa, exponent = re.split("[eE]", number)
    mantissa += "" if "." in mantissa else ".0"
    exponent = exponent if exponent[:1] in "+-" else "+" + exponent
    e = "E" if "E" in number else "e"
    return (f" (YAML 1.1 reads {number} as text, not a number: write its mantissa with a dot and its exponent "
            f"with a sign, {mantissa}{e}{exponent})")


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
                raise CaseError(path, f"impact.K[{i}]", f"must be a number in (0, 10], got {shown(k)}")
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
                                f"{shown(v)} is the velocity of impact.velocity[{j}] again ({y:g} m/s)")
        vs.append(x)
    return (), tuple(vs)


#: The units an angle may be written in, in degrees per unit.
ANGLE_UNITS = {"deg": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / math.pi}
#: The units a spin may be written in, in rad/s per unit.
SPIN_UNITS = {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0}
_NUMBER_AND_UNIT = re.compile(r"([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?) ([a-z/]+)")


def _number_in(value, units: dict, name: str, path, example: str) -> float:
    """'<number> <unit>' with a unit of `units` (per unit: the factor to the field's unit), strictly."""
    match = _NUMBER_AND_UNIT.fullmatch(value) if isinstance(value, str) else None
    if not match or match[2] not in units:
        raise CaseError(path, name, f"must be one plain number, one space and a unit of {', '.join(units)}, e.g. "
                                    f"'{example}', got {shown(value)}")
    x = float(match[1]) * units[match[2]]
    if not math.isfinite(x):
        raise CaseError(path, name, f"{shown(value)} is beyond double precision")
    return x + 0.0


def _oblique(data: dict, path) -> tuple[float | None, tuple, tuple, tuple]:
    """(friction, angles [deg], tangential velocities [m/s], spins [rad/s]) of a case, checked."""
    impact = data.get("impact") or {}
    given = [k for k in ("angle", "tangential_velocity", "spin") if k in impact]
    if "friction" not in data:
        if given:
            raise CaseError(path, f"impact.{given[0]}", "an oblique impact needs `friction:` (Coulomb's mu) at the "
                                                        "top level of the case file")
        return None, (), (), ()
    mu = float(data["friction"])
    if not math.isfinite(mu):
        raise CaseError(path, "friction", f"must be a finite number >= 0, got {shown(data['friction'])}")
    if not given:
        raise CaseError(path, "friction", "is for oblique impacts: give `impact: angle: [...]`, "
                                          "`impact: tangential_velocity: [...]` or `impact: spin: [...]` with it")
    if "bodies" not in data:
        raise CaseError(path, "friction", "needs the contact given as `bodies:` (each with young and poisson): the "
                                          "tangential stiffness 8 G* needs each body's shear modulus, which E* alone "
                                          "does not give")
    if "angle" in impact and "tangential_velocity" in impact:
        raise CaseError(path, "impact.tangential_velocity", "give either `angle` (with `velocity` the resultant) or "
                                                            "`tangential_velocity` (with `velocity` the normal "
                                                            "component), not both")
    if "restitution" in impact:
        raise CaseError(path, "impact.restitution", "oblique impacts run the normal law of `viscosity:` (0 P for an "
                                                    "elastic contact); a restitution is not supported with them")
    angles = []
    for i, a in enumerate(impact.get("angle", ())):
        x = _number_in(a, ANGLE_UNITS, f"impact.angle[{i}]", path, "30 deg")
        if not 0.0 <= x < 90.0:
            raise CaseError(path, f"impact.angle[{i}]", f"must lie in [0, 90) deg from the normal (90 deg grazes: "
                                                        f"no normal velocity, no collision), got {shown(a)}")
        if x in angles:
            raise CaseError(path, f"impact.angle[{i}]", f"gives {shown(a)} a second time")
        angles.append(x)
    tangential = []
    for i, v in enumerate(impact.get("tangential_velocity", ())):
        x = quantity(v, f"impact.tangential_velocity[{i}]", path)
        if x in tangential:
            raise CaseError(path, f"impact.tangential_velocity[{i}]", f"gives {shown(v)} a second time")
        tangential.append(x)
    spins = []
    for i, w in enumerate(impact.get("spin", ())):
        x = _number_in(w, SPIN_UNITS, f"impact.spin[{i}]", path, "50 rad/s")
        if x in spins:
            raise CaseError(path, f"impact.spin[{i}]", f"gives {shown(w)} a second time")
        spins.append(x)
    if spins and any(spins) and mu == 0:
        raise CaseError(path, "impact.spin", "a spin with no friction (friction: 0) never acts on the collision: "
                                             "give friction > 0, or leave the spin out")
    return mu, tuple(angles), tuple(tangential), tuple(spins)


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


def _what_it_holds(data) -> str:
    """What a YAML document that is not a mapping holds, without repeating its text (it may be any
    file given as a case file: /etc/passwd reads as one long string)."""
    if data is None:
        return "nothing (an empty file)"
    if isinstance(data, str):
        return f"one text of {len(data)} characters (not shown)"
    if isinstance(data, list):
        return f"a list of {len(data)} items"
    return f"a single {type(data).__name__} ({shown(data)})"


def parse_case(data, path, project=None) -> Case:
    """Validate the parsed YAML `data` of case file `path` (used in messages).

    Parameters
    ----------
    data : dict
        The YAML document, as `yaml.safe_load` gives it (quantities as '<number> <unit>' strings).
    path : str or pathlib.Path
        The case file: named in every message; its folder is where a `measurements:` path starts.
    project : str or pathlib.Path, optional
        The folder a measurement file must lie in (symlinks followed); default
        `project_folder(path)`.

    Returns
    -------
    Case
        The case in SI units.

    Raises
    ------
    CaseError
        Naming the file and the field.
    """
    if not isinstance(data, dict):
        raise CaseError(path, "(top level)", f"a case file must be a YAML mapping of fields, got "
                                             f"{_what_it_holds(data)}")
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
        raise CaseError(path, "viscosity", f"must be non-negative, got {shown(data['viscosity'])}")

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
    dissipations = ()
    if restitutions:  # the K of each (reachable?), and the eta of each at each velocity (finite?)
        dissipations = tuple(_dissipation_for_restitution(r, criterion, i, path) for i, r in enumerate(restitutions))
        for i, K_r in enumerate(dissipations):
            for V in velocities:
                for p in pairs:
                    _viscosity(p, V, K_r, i, path)
        pairs = tuple(replace(p, eta=_viscosity(p, velocities[0], dissipations[0], 0, path)) for p in pairs)
    measurements = _measurements(data, pairs, path, project)
    friction, angles, tangential, spins = _oblique(data, path)
    known = {"name", "description", "viscosity", "bodies", "effective_modulus", "radius",
             "density", "geometries", "impact", "measurements", "friction"}
    extra = {k: v for k, v in data.items() if k not in known}  # the documentation keys
    return Case(str(name), str(path), pairs, K, velocities, str(data.get("description", "")), extra,
                measurements, viscosity_unit=written_unit(data["viscosity"]) if "viscosity" in data else "Pa*s",
                restitutions=restitutions, restitution_criterion=criterion, restitution_dissipations=dissipations,
                friction=friction, angles=angles, tangential_velocities=tangential, spins=spins)


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
    restitutions = tuple(float(r) for r in impact["restitution"])  # the schema has checked: numbers in (0, 1)
    for i, r in enumerate(restitutions):
        if r > RESTITUTION_MAX:
            raise CaseError(path, f"impact.restitution[{i}]",
                            f"{r!r} lies within {1 - r:.2g} of 1, above the limit {RESTITUTION_MAX!r} (1 - 1e-8): "
                            f"the K and eta that restitute it (K about {(1 - r) / 1.0089:.2g}) cannot be resolved in "
                            "double precision (the inversion resolves K to 1e-14; near 1 - 1.1e-16 it gives K = 0, an "
                            "elastic contact), and no ladder could tell the run from an elastic one. Give a "
                            f"restitution of at most {RESTITUTION_MAX!r}, or `viscosity: 0` for an elastic contact")
    return restitutions, str(impact.get("criterion", "F0"))


def _dissipation_for_restitution(eps: float, criterion: str, i: int, path) -> float:
    """The K whose viscoelastic collision restitutes eps under `criterion`; a CaseError naming
    impact.restitution[i] when no K in the solver's range does."""
    from reference.dissipation_for_restitution import dissipation_for_restitution

    try:
        K = dissipation_for_restitution(eps, criterion)
    except ValueError as err:
        raise CaseError(path, f"impact.restitution[{i}]", f"no viscoelastic law can reach it: {err}") from None
    if not K > 0:  # RESTITUTION_MAX keeps eps far enough from 1: a guard
        raise CaseError(path, f"impact.restitution[{i}]", f"{eps!r} gives K = {K!r}: it cannot be told from an elastic "
                                                          "contact; give `viscosity: 0` for one")
    return K


def _viscosity(pair, V: float, K: float, i: int, path) -> float:
    """The eta [Pa s] that gives `pair` the dissipation parameter K at impact velocity V [m/s]; a
    CaseError naming impact.restitution[i] when it is not a positive double."""
    from .collision_scales import viscosity_for_dissipation

    try:
        eta = viscosity_for_dissipation(pair.E, pair.R, pair.M, V, K)
    except (OverflowError, ZeroDivisionError):
        eta = math.nan
    if not (eta > 0 and math.isfinite(eta)):
        raise CaseError(path, f"impact.restitution[{i}]", f"the eta that restitutes it at {V:g} m/s ({pair.geometry}) "
                                                          "is beyond double precision")
    return eta


def restitution_variants(case: Case) -> list[tuple[float, Case]]:
    """Every restitution of `case` at every impact velocity, each with its own viscosity.

    Parameters
    ----------
    case : Case
        A case with `impact: restitution` (SI).

    Returns
    -------
    list of (restitution, Case)
        Restitution by restitution (the case's order), velocity by velocity within each: the
        case at that one impact velocity [m/s], each contact's eta [Pa s] set so that its
        viscoelastic collision restitutes the restitution [-] exactly there, under the case's
        criterion, as an engine's restitution keyword restitutes it at every velocity (eta
        depends on V: K = f(eps) is fixed, eta ~ K V^{-1/5}). The variants have no restitutions
        of their own. A case without restitutions: [].
    """
    out = []
    for i, (r, K) in enumerate(zip(case.restitutions, case.restitution_dissipations)):
        for V in case.velocities:
            pairs = tuple(replace(p, eta=_viscosity(p, V, K, i, case.path)) for p in case.pairs)
            out.append((r, replace(case, pairs=pairs, velocities=(V,), restitutions=(),
                                   restitution_dissipations=())))
    return out


def project_folder(case_path) -> Path:
    """The project folder of a case file, symlinks resolved.

    The nearest folder above it that holds the study's Snakefile (the repository root, or a copy
    of the project), else `REPOSITORY_ROOT` (the repository of this package). A case's measurement
    file must lie inside it.

    Parameters
    ----------
    case_path : str or pathlib.Path
        The case file.

    Returns
    -------
    pathlib.Path
    """
    here = Path(os.path.abspath(str(case_path))).parent
    for folder in (here, *here.parents):
        if (folder / "Snakefile").is_file():
            return folder.resolve()
    return REPOSITORY_ROOT


def _measurements(data: dict, pairs, path, project=None):
    """The case's measurement file, read (its path relative to the case file's folder, inside the
    project folder), or None."""
    if "measurements" not in data:
        return None
    from .measurement_file import load_measurements  # it imports this module

    if len(pairs) != 1:
        raise CaseError(path, "measurements", f"measurements belong to one contact, but the case describes "
                                              f"{len(pairs)} ({', '.join(p.geometry for p in pairs)}): give one "
                                              "geometry (e.g. geometries: [sphere-plane]) or explicit bodies")
    written = data["measurements"]  # a non-empty string (the schema)
    if "\x00" in written:
        raise CaseError(path, "measurements", f"{shown(written, 200)} holds a NUL character: no file is named so")
    bad = re.search("[\x01-\x1f\x7f\ud800-\udfff]", written)
    if bad:
        what = "a lone surrogate" if bad[0] >= chr(0xD800) else "a control character"
        raise CaseError(path, "measurements", f"{shown(written, 200)} holds {what} ({bad[0]!r}): a file name of the "
                                              "project is printable text")
    relative = Path(written)
    if relative.is_absolute():
        raise CaseError(path, "measurements", f"{shown(written, 200)} is an absolute path: give it relative to "
                                              "the case file's folder, so that the project can move")
    csv_path = Path(str(path)).parent / relative
    root = Path(project).resolve() if project is not None else project_folder(path)
    try:
        target = Path(os.path.abspath(csv_path)).resolve()
    except (OSError, RuntimeError) as err:  # a symlink loop
        raise CaseError(path, "measurements", f"{shown(written, 200)} cannot be followed ({type(err).__name__}): "
                                              "nothing was read") from None
    if not target.is_relative_to(root):
        raise CaseError(path, "measurements", f"{shown(written, 200)} leads outside the project folder {root} "
                                              "(symlinks followed): a measurement file must lie inside the project, "
                                              "e.g. beside the case file; nothing was read")
    try:
        found = target.exists()
    except OSError as err:  # e.g. a name too long for the file system
        raise CaseError(path, "measurements", f"{shown(written, 200)} cannot be read ({err.strerror or err})") from None
    if not found:
        raise CaseError(path, "measurements", f"no file {shown(str(csv_path), 200)} (the path is relative to the "
                                              "case file's folder)")
    return load_measurements(csv_path)  # a regular file of at most MAX_BYTES, checked before reading


def load_case(path, project=None) -> Case:
    """Read and validate a case file: UTF-8 YAML, plain data, a mapping of known fields.

    Parameters
    ----------
    path : str or pathlib.Path
        The case file: a regular file of at most `strict_yaml.MAX_BYTES` bytes (a device such as
        /dev/zero, a FIFO or a larger file is refused before it is read).
    project : str or pathlib.Path, optional
        The folder a `measurements:` file must lie in; default `project_folder(path)`.

    Returns
    -------
    Case
        The case in SI units.

    Raises
    ------
    CaseError
        Naming the file and the field; `measurement_file.MeasurementError` for its measurements.
    """
    path = Path(path)
    text = read_utf8(path)
    scan_plain_yaml(text, path)
    try:
        data = yaml.load(text, Loader=yaml.SafeLoader)  # noqa: S506 - SafeLoader, after scan_plain_yaml
    except yaml.YAMLError as err:  # scan_plain_yaml has read the same events; kept as a guard
        raise CaseError(path, "(file)", f"not valid YAML: {shown(' '.join(str(err).split()), 300)}")
    return parse_case(data, path, project)
