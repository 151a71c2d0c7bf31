"""Material case files (YAML) -> validated `Case` objects in SI units.

Two ways to describe the bodies (README.md, "Case files", gives the full format):

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

import functools
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from .contact_pair import GEOMETRIES, Body, ContactPair



@functools.lru_cache(maxsize=None)
def units():
    """pint's unit registry, built on first use: building it (and importing pint) takes about
    half a second, which every workflow rule that merely imports contact_model would pay.
    pint keeps its parsed definitions in the user's cache folder (`cache_folder=":auto:"`):
    the registry then builds in 0.03 s instead of 0.3 s, at every start of the workflow."""
    import pint

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except OSError:  # no writable cache folder (e.g. a read-only home): parse the definitions
        return pint.UnitRegistry()
SCHEMA_PATH = Path(__file__).with_name("case_file.schema.yaml")

# field -> (pint dimensionality, SI unit)
DIMENSIONS = {
    "effective_modulus": ("[pressure]", "Pa"),
    "young": ("[pressure]", "Pa"),
    "viscosity": ("[pressure] * [time]", "Pa*s"),
    "radius": ("[length]", "m"),
    "density": ("[mass] / [length] ** 3", "kg/m^3"),
    "velocity": ("[length] / [time]", "m/s"),
}

#: One plain decimal number (ASCII digits only: Python's float() would also take other
#: scripts' digits and underscores).
NUMBER = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
#: A unit: names (letters, no digits) with optional integer exponents (^2, **-3), joined by
#: '*', '/' or a space. No parentheses, no numbers but exponents: "GPa 2" or "m2" is refused.
_FACTOR = r"[^\W\d]+(?:(?:\^|\*\*)[+-]?[0-9]+)?"
UNIT = rf"{_FACTOR}(?:(?: ?[*/] ?| ){_FACTOR})*"
QUANTITY = re.compile(rf"({NUMBER}) ({UNIT})")
_PLAIN_INT = re.compile(r"[+-]?(?:0|[1-9][0-9]*)")
_PLAIN_FLOAT = re.compile(NUMBER)

#: Deeper nesting than a case file needs (mapping > bodies > body > value) is refused before
#: PyYAML's recursive composer sees it.
MAX_DEPTH = 6
MAX_BYTES = 1_000_000


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
    measurements: object = None  # a measurement_file.Measurements, or None

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


def _dimension(name: str) -> tuple[str, str]:
    """(dimensionality, SI unit) of a field path such as 'bodies[1].young' or 'impact.velocity[0]'."""
    return DIMENSIONS[name.split(".")[-1].split("[")[0]]


def _not_a_quantity(value, name: str) -> str:
    """The problem with a value that is not a quantity string at all."""
    si_unit = _dimension(name)[1]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{value!r} has no unit; write it as e.g. '{value} {si_unit}'"
    return f"expected a quantity with a unit, e.g. '1 {si_unit}', got {value!r}"


def quantity(value, name: str, path) -> float:
    """Convert a '<number> <unit>' string to SI for field `name` (a path such as 'radius' or
    'bodies[0].young'; its last name picks the dimension). Strict: exactly one plain number,
    one space, one unit that pint reads as a unit alone; the result must be finite."""
    dimension, si_unit = _dimension(name)
    if not isinstance(value, str):
        raise CaseError(path, name, _not_a_quantity(value, name))
    match = QUANTITY.fullmatch(value)
    if not match:
        raise CaseError(path, name, f"cannot read {value!r} as a quantity: write one plain number, one space "
                                    f"and a unit, e.g. '1.5 {si_unit}' (no comma decimals, digit groups, "
                                    f"second numbers, expressions or other text)")
    number, unit_text = match.groups()
    x = float(number)
    if not math.isfinite(x):
        raise CaseError(path, name, f"the number {number} in {value!r} is beyond double precision")
    if x == 0 and any(c in "123456789" for c in re.split("[eE]", number)[0]):
        raise CaseError(path, name, f"the number {number} in {value!r} underflows to 0 in double precision")
    try:  # pint parses user text: any of its exceptions means the unit cannot be read
        unit = units().parse_units(unit_text)
        factors = [units().Unit(u) for u in unit._units]
    except Exception as err:  # noqa: BLE001
        raise CaseError(path, name, f"cannot read the unit {unit_text!r} of {value!r} ({type(err).__name__}: {err})")
    plain = [str(f) for f in factors if f.dimensionless]
    if plain:  # 'pi', 'percent', 'radian' would silently scale the number
        raise CaseError(path, name, f"cannot read {value!r}: {plain[0]!r} is a dimensionless factor, not a unit")
    if unit.dimensionless:
        raise CaseError(path, name, f"{value!r} has no unit; expected a {dimension} such as '{si_unit}'")
    try:
        q = units().Quantity(x, unit)
        if not q.check(dimension):
            raise CaseError(path, name, f"{value!r} is a {q.dimensionality}, expected a {dimension} (e.g. {si_unit})")
        si = float(q.to(si_unit).magnitude)
    except CaseError:
        raise
    except Exception as err:  # noqa: BLE001 - e.g. an offset unit (degC) or an overflow in the conversion
        raise CaseError(path, name, f"cannot convert {value!r} to {si_unit} ({type(err).__name__}: {err})")
    if not math.isfinite(si):
        raise CaseError(path, name, f"{value!r} is beyond double precision in SI ({si_unit})")
    if si == 0 and x != 0:
        raise CaseError(path, name, f"{value!r} underflows to 0 {si_unit} in double precision")
    return si + 0.0  # -0.0 -> 0.0


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


# ------------------------------------------------------------------------------ YAML as plain data
def _char(c) -> str:
    return f"U+{c if isinstance(c, int) else ord(c):04X}"


def _join(parent: str, key) -> str:
    return f"{parent}.{key}" if parent else str(key)


class _Frame:
    """A mapping or sequence being read: its field path and where in it the reader is."""

    def __init__(self, kind: str, path: str):
        self.kind, self.path = kind, path
        self.key = None  # mapping: the key whose value comes next (None: a key comes next)
        self.keys: dict[str, int] = {}  # mapping: key -> line
        self.index = 0  # sequence: index of the next item

    def child(self) -> str:
        if self.kind == "seq":
            return f"{self.path}[{self.index}]"
        return _join(self.path, self.key) if self.key is not None else (self.path or "(top level)")

    def done(self, key: str | None = None):
        """A child node ended (`key`: it was a key)."""
        if self.kind == "seq":
            self.index += 1
        else:
            self.key = key


def _scan(text: str, path) -> None:
    """Walk the YAML events once and refuse what is not plain data, naming the field:
    duplicated keys, keys that are not names, anchors and aliases, explicit tags, YAML 1.1
    spellings of numbers and booleans, nesting deeper than MAX_DEPTH, several documents."""
    try:  # the reader refuses control characters (NUL, ESC, ...) as it is made
        loader = yaml.SafeLoader(text)
    except yaml.reader.ReaderError as err:
        line = text[:err.position].count("\n") + 1
        raise CaseError(path, "(file)", f"not valid YAML: character {_char(err.character)} at line {line} is not "
                                        "allowed in a YAML file")
    stack: list[_Frame] = []
    documents = 0

    def here() -> str:
        return stack[-1].child() if stack else "(top level)"

    def refuse(problem: str, event) -> None:
        raise CaseError(path, here(), f"{problem} (line {event.start_mark.line + 1})")

    try:
        while loader.check_event():
            event = loader.get_event()
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise CaseError(path, "(file)", f"holds more than one YAML document (line {event.start_mark.line + 1})")
                continue
            if isinstance(event, (yaml.StreamStartEvent, yaml.StreamEndEvent, yaml.DocumentEndEvent)):
                continue
            if isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                stack.pop()
                if stack:
                    stack[-1].done()
                continue
            if isinstance(event, yaml.AliasEvent) or event.anchor is not None:
                refuse("anchors (&name) and aliases (*name) are not allowed: write each value out", event)
            if event.tag is not None:
                refuse(f"explicit YAML tags ({event.tag}) are not allowed: a case file is plain data", event)
            is_key = bool(stack) and stack[-1].kind == "map" and stack[-1].key is None
            if is_key and not isinstance(event, yaml.ScalarEvent):
                refuse("a key must be a plain name, not a list or mapping", event)
            if isinstance(event, yaml.ScalarEvent):
                tag = loader.resolve(yaml.ScalarNode, event.value, event.implicit)
                raw = event.value
                if is_key:
                    if tag != "tag:yaml.org,2002:str":
                        refuse(f"a key must be a name, got {raw!r}"
                               + (" (a YAML merge key)" if tag.endswith(":merge") else ""), event)
                    frame = stack[-1]
                    if raw in frame.keys:
                        raise CaseError(path, _join(frame.path, raw),
                                        f"given twice (lines {frame.keys[raw]} and {event.start_mark.line + 1}); "
                                        "YAML would silently keep the last: give it once")
                    frame.keys[raw] = event.start_mark.line + 1
                    frame.done(raw)
                    continue
                if tag == "tag:yaml.org,2002:int" and not _PLAIN_INT.fullmatch(raw) or \
                        tag == "tag:yaml.org,2002:float" and not _PLAIN_FLOAT.fullmatch(raw):
                    refuse(f"{raw!r} is not a plain decimal number (YAML 1.1 reads underscores, leading zeros, "
                           "'a:b', .inf and .nan as numbers you may not mean): write e.g. 0.25", event)
                if tag == "tag:yaml.org,2002:bool" and raw not in ("true", "false"):
                    refuse(f"YAML 1.1 reads {raw!r} as a boolean: write true or false, or quote text", event)
                if stack:
                    stack[-1].done()
                continue
            # the start of a mapping or a sequence
            if len(stack) >= MAX_DEPTH:
                refuse(f"nested more than {MAX_DEPTH} levels deep; a case file needs 3", event)
            stack.append(_Frame("map" if isinstance(event, yaml.MappingStartEvent) else "seq",
                                here() if stack else ""))
    except yaml.reader.ReaderError as err:
        line = text[:err.position].count("\n") + 1
        raise CaseError(path, here(), f"not valid YAML: character {_char(err.character)} at line {line} is not "
                                      "allowed in a YAML file")
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        at = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(err, "problem", None) or " ".join(str(err).split())
        raise CaseError(path, here() if stack else "(file)", f"not valid YAML{at}: {problem}")
    finally:
        loader.dispose()


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
        out = f"{out}[{part}]" if isinstance(part, int) else _join(out, part)
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
        return (_field(where + [extra[0]]),
                f"unknown field (a typo?); known here: {', '.join(known)}; documentation: {docs}")
    if schema.get("x-parent"):  # an item error better said about its list
        where, instance = where[:-1], data
        for part in where:
            instance = instance[part]
    if err.validator in messages:
        problem = messages[err.validator].replace("{instance!r}", repr(instance))
    elif schema.get("x-kind") == "quantity" and err.validator == "type":
        return _field(where), _not_a_quantity(instance, _field(where))
    else:
        problem = err.message
    if err.validator == "type" and isinstance(instance, str) and _PLAIN_FLOAT.fullmatch(instance.strip()):
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
    _check_schema(data, path)
    name = data.get("name", Path(str(path)).stem)
    eta = quantity(data["viscosity"], "viscosity", path)
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
    measurements = _measurements(data, pairs, path)
    known = {"name", "description", "viscosity", "bodies", "effective_modulus", "radius",
             "density", "geometries", "impact", "measurements"}
    extra = {k: v for k, v in data.items() if k not in known}  # the documentation keys
    return Case(str(name), str(path), pairs, K, velocities, str(data.get("description", "")), extra,
                measurements)


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


def read_utf8(path: Path, error=CaseError, max_bytes: int = MAX_BYTES, what: str = "a case file is a few "
              "hundred") -> str:
    """The text of a small UTF-8 file, or `error(path, '(file)', problem)`: unreadable, larger
    than `max_bytes`, or not UTF-8 (the byte and its line named)."""
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise error(path, "(file)", f"cannot read: {err.strerror or err}")
    if len(raw) > max_bytes:
        raise error(path, "(file)", f"is {len(raw)} bytes; {what} (limit {max_bytes})")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = raw[:err.start].count(b"\n") + 1
        raise error(path, "(file)", f"is not UTF-8 text (byte 0x{raw[err.start]:02x} at line {line}); "
                                    "save it as UTF-8")


def load_case(path) -> Case:
    """Read and validate a case file: UTF-8 YAML, plain data, a mapping of known fields."""
    path = Path(path)
    text = read_utf8(path)
    _scan(text, path)
    try:
        data = yaml.load(text, Loader=yaml.SafeLoader)  # noqa: S506 - SafeLoader, after _scan
    except yaml.YAMLError as err:  # _scan has read the same events; kept as a guard
        raise CaseError(path, "(file)", f"not valid YAML: {' '.join(str(err).split())}")
    return parse_case(data, path)
