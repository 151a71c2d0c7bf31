"""A generator of case-file variants for fuzzing the loader, with an independent oracle.

Each variant starts from a valid case file (the effective-modulus form or the bodies form),
drawn at random, with at most one invalidating mutation. The generator knows, without asking the
loader, whether the variant is valid and, if it is, the SI numbers it must give (the unit
factors below are written out here, not taken from pint). For an invalid variant it knows the
field the error should name (or None where several names are fair, e.g. for random bytes).

Among the mutations are the audit's injection strings (`INJECTIONS`: backticks, ``$(touch ...)``,
``"; rm -rf x; "``, ``*``, ``../../etc/passwd``, ``/dev/zero``, very long strings, NUL, format strings,
markup, numbers as strings) in every kind of field (text, quantity, list item, key, the measurements
path), YAML bombs (billion laughs), files beyond the size limit and non-UTF-8 bytes. A string of a
case file is data: where text is allowed it is kept as it is, everywhere else it is refused. A
shell that ran one would leave a marker file in MARKER_DIR; there must be none.
`measurement_corpus` does the same to the case's other input, a measurement CSV.

    python -m tests.fuzz_case_files [N]

loads a fixed corpus of N variants (default 600, seed 0) and the measurement corpus, and prints how
many were refused clearly (CaseError naming the file and the expected field), refused unclearly
(any other exception, or a CaseError without the file or with another field), accepted although
invalid (or with numbers different from the oracle's), refused although valid, and accepted
valid; how many of them carried an injection string; and the marker files found (none).
"""

from __future__ import annotations

import json
import math
import random
import re
import sys
import tempfile
import dataclasses
from dataclasses import dataclass
from pathlib import Path

# ---------------------------------------------------------------------------- units and numbers
# SI factor of each unit string, per kind of quantity (independent of pint).
UNITS = {
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N/m^2": 1.0, "N m^-2": 1.0, "bar": 1e5},
    "viscosity": {"Pa*s": 1.0, "Pa s": 1.0, "P": 0.1, "cP": 1e-3, "mPa*s": 1e-3},
    "length": {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "µm": 1e-6, "km": 1e3, "inch": 0.0254},
    "density": {"kg/m^3": 1.0, "g/cm^3": 1e3, "kg m^-3": 1.0, "kg*m^-3": 1.0, "kg/m**3": 1.0},
    "velocity": {"m/s": 1.0, "cm/s": 1e-2, "mm/s": 1e-3, "km/s": 1e3, "km/h": 1 / 3.6},
}
KIND = {"effective_modulus": "pressure", "young": "pressure", "viscosity": "viscosity",
        "radius": "length", "density": "density", "velocity": "velocity"}
#: SI ranges of the values drawn for valid files (far from over- and underflow).
RANGE = {"pressure": (1e5, 1e12), "viscosity": (1.0, 1e6), "length": (1e-4, 1.0),
         "density": (100.0, 2e4), "velocity": (1e-3, 10.0)}


def number_text(rnd: random.Random, x: float) -> str:
    """`x` written in one of the plain forms the loader must accept."""
    style = rnd.randrange(5)
    if style == 0:
        return f"{x:.6g}"
    if style == 1:
        return f"{x:.4e}".replace("e", rnd.choice("eE"))
    if style == 2:
        return "+" + f"{x:.5g}"
    if style == 3:
        m, e = f"{x:.3e}".split("e")
        return f"{m}e{int(e)}"
    return repr(x)


def valid_quantity(rnd: random.Random, kind: str) -> tuple[str, float]:
    """(text, SI value) of a valid quantity of this kind."""
    lo, hi = RANGE[kind]
    unit, factor = rnd.choice(sorted(UNITS[kind].items()))
    si = math.exp(rnd.uniform(math.log(lo), math.log(hi)))
    text = number_text(rnd, si / factor)
    return f"{text} {unit}", float(text) * factor


#: Quantity texts that are invalid whatever the field; {u} is a unit of the field's own kind.
BAD_QUANTITIES = [
    "6,7e5 {u}", "12,5 {u}", "0,67 {u}", "7 800 {u}", "109 {u} 2", "109 {u}!", "109 {u} \U0001F600",
    "{u}", "1 {u} / 0", "(1 {u}", "1 {u})", "1 {u}; rm -rf /", "2 * 3 {u}", "1 {u} * 2", "1e400 {u}",
    "1e-400 {u}", "nan {u}", "inf {u}", "-inf {u}", "1  {u}", "1{u}", "{u} 1", "1 furlongz", "0x10 {u}",
    "1_000 {u}", "1e5.5 {u}", "--1 {u}", "1.2.3 {u}", "\u00bd {u}", "\u0661 {u}", "\uff11 {u}",
    "1 {u}\u200b", "1 {u} pi", "1 percent {u}", "1 {u}^", "1 {u}/", "1 /{u}", "1e {u}", ". {u}", "1 {u},",
    "1 {u} 'x'", "1.0e+400 {u}", "0 {u}", "-5 {u}", "1 {u}\t", "1 P a", "1 {u} 2 {u}", "1.5 {u} 0.1 {u}",
    "1 \u00b0C", "1 {u} 1 {u}", "0.5 {u}/2", "1 {u}**", "1 ({u})",
]
#: Raw YAML values that are not a quantity string at all.
BAD_TYPES = ["109", "1.5", "true", "", "~", "[1 GPa]", "{a: 1}", "[]", "{}", "!!binary AA==",
             "&x 1 GPa", "1.0e+3", ".inf", "!!str 1 GPa"]

#: Where a shell would leave its mark, were a string of a case file ever run by one.
MARKER_DIR = Path(tempfile.gettempdir()) / "hertz_fuzz_markers"
_M = MARKER_DIR.as_posix()
#: The audit's injection strings and their kin: each is text to the loader, kept as data where
#: text is allowed (name, description, notes) and refused everywhere else.
INJECTIONS = [
    f"`touch {_M}/backtick`", f"$(touch {_M}/dollar)", f'"; touch {_M}/semicolon; "', f"; touch {_M}/semi #",
    f"| touch {_M}/pipe", f"&& touch {_M}/and", f"\ntouch {_M}/newline", "$(touch /tmp/x)", '"; rm -rf x; "',
    "*", "?", "[a-z]*", "**/*.yaml", "../../etc/passwd", "../../../../../../../../etc/passwd", "/etc/passwd",
    "/dev/zero", "/dev/stdin", "/proc/self/environ", "~/.bashrc", "${HOME}", "%s%s%n", "{0.__class__}", "{{7*7}}",
    "<script>alert(1)</script>", "[x](javascript:alert(1))", "\u202egnp.yaml", "x" * 5000, "y" * 200_000,
    "a\x00b", "\x1b[31mPASS\x1b[0m", "line\n# PASS", "0.8", "1e5", "null", "true", "-rf", "C:\\Windows\\win.ini",
    "file:///etc/passwd", "\\\\server\\share", "\ud800", "caf\u00e9 \U0001F600",
]
#: What the loader refuses in a name (the case's title, one line) and in free text, said here
#: independently of the schema: control and invisible characters, and lone surrogates.
_NOT_IN_NAME = re.compile("[\x00-\x1f\x7f-\x9f\u200b-\u200f\u2028-\u202e\u2066-\u2069\ufeff\ud800-\udfff]")
_NOT_IN_TEXT = re.compile("[\x00-\x08\x0b-\x1f\x7f\ud800-\udfff]")


def yaml_string(text: str) -> str:
    """`text` as a YAML double-quoted scalar that reads back exactly: JSON's escapes are YAML's, with
    other characters written as themselves (YAML reads an escaped surrogate pair as two lone
    surrogates) but a lone surrogate escaped (no UTF-8 file holds one)."""
    return re.sub("[\ud800-\udfff]", lambda m: f"\\u{ord(m[0]):04x}", json.dumps(text, ensure_ascii=False))


def is_injection(text: bytes) -> bool:
    """Whether a variant's file carries one of INJECTIONS (as its YAML escapes write it)."""
    return any(yaml_string(s).encode() in text for s in INJECTIONS)


# ---------------------------------------------------------------------------- the case model
@dataclass
class Variant:
    kind: str
    text: bytes
    valid: bool
    field: str | None = None  # the field an error must name (None: any)
    truth: dict = dataclasses.field(default_factory=dict)  # for a valid variant: what the loader must give


def render(pairs, indent: int = 0) -> list[str]:
    """Block-style YAML of a list of (key, value) pairs; a value is raw text, a list or pairs."""
    pad = " " * indent
    lines = []
    for key, value in pairs:
        if isinstance(value, str):
            lines.append(f"{pad}{key}: {value}".rstrip())
        elif isinstance(value, list) and value and all(isinstance(v, list) for v in value):
            lines.append(f"{pad}{key}:")
            for body in value:  # a list of mappings
                sub = render(body, indent + 4)
                if sub:
                    sub[0] = pad + "  - " + sub[0].lstrip()
                    lines += sub
                else:
                    lines.append(pad + "  - {}")
        elif isinstance(value, list):
            lines.append(f"{pad}{key}:")
            lines += [f"{pad}  - {v}" for v in value]
        else:  # nested mapping
            lines.append(f"{pad}{key}:")
            lines += render(value.pairs, indent + 2)
    return lines


@dataclass
class Mapping:
    pairs: list


def get(pairs, key):
    for k, v in pairs:
        if k == key:
            return v
    raise KeyError(key)


def set_(pairs, key, value):
    for i, (k, _) in enumerate(pairs):
        if k == key:
            pairs[i] = (key, value)
            return
    pairs.append((key, value))


def drop(pairs, key):
    pairs[:] = [(k, v) for k, v in pairs if k != key]


NAMES = ["demo", "steel-2", "Stahl_\u00fc", "case one", "glass bead", "\u51b0"]


def base_case(rnd: random.Random):
    """(pairs, truth) of a random valid case file."""
    truth = {}
    pairs = []
    if rnd.random() < 0.7:
        truth["name"] = rnd.choice(NAMES)
        pairs.append(("name", truth["name"]))
    if rnd.random() < 0.3:
        pairs.append(("description", "A made-up case \u2014 for fuzzing"))
    eta_text, eta = valid_quantity(rnd, "viscosity")
    truth["eta"] = eta
    if rnd.random() < 0.5:
        truth["form"] = "material"
        for key in ("effective_modulus", "radius", "density"):
            text, si = valid_quantity(rnd, KIND[key])
            pairs.append((key, text))
            truth[key] = si
        if rnd.random() < 0.7:
            geos = rnd.choice([["sphere-sphere"], ["sphere-plane"], ["sphere-sphere", "sphere-plane"],
                               ["sphere-plane", "sphere-sphere"]])
            pairs.append(("geometries", list(geos)))
        else:
            geos = ["sphere-sphere", "sphere-plane"]
        truth["geometries"] = geos
        if rnd.random() < 0.3:
            pairs.append(("density_source", "a guess"))
    else:
        truth["form"] = "bodies"
        bodies, tb = [], []
        for i in range(2):
            kind = "sphere" if i == 0 else rnd.choice(["sphere", "plane", "rigid"])
            b, t = [], {"kind": kind}
            if kind == "rigid":
                b.append(("plane", "rigid"))
            else:
                if kind == "plane":
                    b.append(("plane", "true"))
                elif rnd.random() < 0.2:
                    b.append(("plane", "false"))
                if kind == "sphere":
                    for key in ("radius", "density"):
                        text, t[key] = valid_quantity(rnd, KIND[key])
                        b.append((key, text))
                text, t["young"] = valid_quantity(rnd, "pressure")
                b.append(("young", text))
                nu = round(rnd.uniform(-0.9, 0.49), 3)
                b.append(("poisson", f"{nu:.3f}"))
                t["poisson"] = nu
            rnd.shuffle(b)
            bodies.append(b)
            tb.append(t)
        pairs.append(("bodies", bodies))
        truth["bodies"] = tb
    pairs.insert(rnd.randrange(len(pairs) + 1), ("viscosity", eta_text))
    r = rnd.random()
    truth["K"], truth["velocities"] = [], []
    if r < 0.4:
        ks = sorted(rnd.sample([0.01, 0.03, 0.1, 0.2, 0.25, 0.3, 0.5, 1.0, 2.0, 10.0], rnd.randint(1, 4)))
        pairs.append(("impact", Mapping([("K", [f"{k:g}" if k < 1 else f"{k:.1f}" for k in ks])])))
        truth["K"] = ks
    elif r < 0.8:
        vs, texts = [], []
        while len(vs) < rnd.randint(1, 3):
            text, si = valid_quantity(rnd, "velocity")
            if all(abs(si - v) > 1e-9 * v for v in vs):
                vs.append(si)
                texts.append(text)
        pairs.append(("impact", Mapping([("velocity", texts)])))
        truth["velocities"] = vs
    return pairs, truth


def quantity_paths(pairs):
    """(field path, setter) of every quantity in the case."""
    out = []
    for key, value in pairs:
        if key in ("effective_modulus", "radius", "density", "viscosity"):
            out.append((key, key, lambda v, key=key: set_(pairs, key, v)))
        elif key == "bodies":
            for i, body in enumerate(value):
                for k, _ in body:
                    if k in ("radius", "density", "young"):
                        out.append((f"bodies[{i}].{k}", k, lambda v, body=body, k=k: set_(body, k, v)))
        elif key == "impact" and isinstance(value, Mapping):
            for k, v in value.pairs:
                if k == "velocity":
                    for j in range(len(v)):
                        out.append((f"impact.velocity[{j}]", "velocity",
                                    lambda new, lst=v, j=j: lst.__setitem__(j, new)))
    return out


# ---------------------------------------------------------------------------- mutations
# Each takes (rnd, pairs, truth) and returns (valid, field) or None if it does not apply;
# it edits `pairs`/`truth` in place. Texts are produced by `finish` (some mutate the text).

def m_none(rnd, pairs, truth):
    return True, None


def m_equivalent_unit(rnd, pairs, truth):
    """A valid quantity written in another unit: still valid, numbers must follow."""
    paths = quantity_paths(pairs)
    path, key, setter = rnd.choice(paths)
    text, si = valid_quantity(rnd, KIND[key])
    if key == "velocity":
        j = int(path.split("[")[1][:-1])
        if any(abs(si - v) <= 1e-9 * v for i, v in enumerate(truth["velocities"]) if i != j):
            return None
        truth["velocities"][j] = si
    elif path.startswith("bodies"):
        truth["bodies"][int(path[7])][key] = si
    elif key == "viscosity":
        truth["eta"] = si
    else:
        truth[key] = si
    setter(rnd.choice([text, f"'{text}'", f'"{text}"']))
    return True, None


def m_bad_quantity(rnd, pairs, truth):
    path, key, setter = rnd.choice(quantity_paths(pairs))
    bad = rnd.choice(BAD_QUANTITIES).replace("{u}", rnd.choice(sorted(UNITS[KIND[key]])))
    if key == "viscosity" and bad.startswith("0 "):
        return None  # zero viscosity is valid (elastic)
    quote = bad != bad.strip() or (rnd.random() < 0.5 and "'" not in bad)  # YAML strips plain scalars
    setter(f"'{bad}'" if quote else bad)
    return False, path


def m_bad_type(rnd, pairs, truth):
    path, key, setter = rnd.choice(quantity_paths(pairs))
    setter(rnd.choice(BAD_TYPES))
    return False, None if path.startswith("impact") else path


def m_wrong_dimension(rnd, pairs, truth):
    path, key, setter = rnd.choice(quantity_paths(pairs))
    other = rnd.choice([k for k in UNITS if k != KIND[key]])
    setter(valid_quantity(rnd, other)[0])
    return False, path


def m_extreme(rnd, pairs, truth):
    """Magnitudes beyond double precision after conversion to SI."""
    path, key, setter = rnd.choice(quantity_paths(pairs))
    unit = rnd.choice(sorted(UNITS[KIND[key]]))
    setter(rnd.choice([f"1e{rnd.randint(309, 999)} {unit}", f"1e-{rnd.randint(330, 999)} {unit}",
                       f"9.9e{rnd.randint(320, 400)} {unit}"]))
    return False, path


def m_drop_required(rnd, pairs, truth):
    keys = ["viscosity"] + (["effective_modulus", "radius", "density"] if truth["form"] == "material" else ["bodies"])
    key = rnd.choice(keys)
    drop(pairs, key)
    return False, None if key == "bodies" else key  # without bodies, the other form's keys are missing


def m_drop_body_key(rnd, pairs, truth):
    if truth["form"] != "bodies":
        return None
    i = rnd.randrange(2)
    body = get(pairs, "bodies")[i]
    keys = [k for k, _ in body if k != "plane"]
    if not keys:
        return None
    key = rnd.choice(keys)
    drop(body, key)
    return False, f"bodies[{i}].{key}"


TYPO_KEYS = ["impacts", "geometry", "Radius", "viscosty", "density_sorce", "effective-modulus", "foo", "note2",
             "velocity", "K", "E", "name ", "bodys", "young"]


def m_unknown_key(rnd, pairs, truth):
    where = rnd.randrange(3)
    if where == 0:
        key = rnd.choice(TYPO_KEYS)
        if any(k == key.strip() for k, _ in pairs):
            return None
        pairs.insert(rnd.randrange(len(pairs) + 1), (key, rnd.choice(["1", "x", "1 m", "[1, 2]"])))
        return False, key.strip()
    if where == 1 and truth["form"] == "bodies":
        body = get(pairs, "bodies")[rnd.randrange(2)]
        key = rnd.choice(["Young", "poison", "mass", "radius_mm", "shape", "name"])
        body.append((key, "1"))
        return False, key
    if where == 2 and truth["K"] + truth["velocities"]:
        imp = get(pairs, "impact")
        imp.pairs.append((rnd.choice(["Ks", "angle", "velocities", "k"]), "[1]"))
        return False, None
    return None


def m_doc_key(rnd, pairs, truth):
    """Named documentation keys are allowed (strings only)."""
    key = rnd.choice(["description", "density_source", "radius_source", "viscosity_note", "note",
                      "effective_modulus_source"])
    if any(k == key for k, _ in pairs):
        return None
    text = rnd.choice(["from a handbook", "'quoted: with colon'", "\u00e9t\u00e9 \U0001F600", ">-\n  folded\n  text"])
    pairs.append((key, text))
    return True, None


def m_bad_doc_key(rnd, pairs, truth):
    key = rnd.choice(["description", "density_source", "note"])
    drop(pairs, key)
    pairs.append((key, rnd.choice(["", "12", "[a, b]", "{a: 1}", "true"])))
    return False, key


def m_duplicate_key(rnd, pairs, truth):
    if truth["form"] == "bodies" and rnd.random() < 0.5:
        i = rnd.randrange(2)
        body = get(pairs, "bodies")[i]
        k, v = rnd.choice(body)
        body.insert(rnd.randrange(len(body) + 1), (k, v))
        return False, f"bodies[{i}].{k}"
    k, v = rnd.choice(pairs)
    pairs.append((k, v))
    return False, k


def m_contradiction(rnd, pairs, truth):
    if truth["form"] == "bodies":
        choice = rnd.randrange(3)
        if choice == 0:
            key = rnd.choice(["effective_modulus", "radius", "density", "geometries"])
            pairs.append((key, {"effective_modulus": "100 GPa", "radius": "1 cm", "density": "1000 kg/m^3",
                                "geometries": ["sphere-plane"]}[key]))
            return False, key
        body = get(pairs, "bodies")[1]
        kind = truth["bodies"][1]["kind"]
        if kind == "rigid":
            key = rnd.choice(["young", "poisson", "radius", "density"])
            body.append((key, {"young": "-5 GPa", "poisson": "0.3", "radius": "1 cm", "density": "1 kg/m^3"}[key]))
            return False, f"bodies[1].{key}"
        if kind == "plane":
            key = rnd.choice(["radius", "density"])
            body.append((key, "1 cm" if key == "radius" else "7800 kg/m^3"))
            return False, f"bodies[1].{key}"
        first = get(pairs, "bodies")[0]
        drop(first, "plane")
        first.append(("plane", rnd.choice(["true", "rigid"])))
        return False, "bodies[0].plane"
    pairs.append(("bodies", [[("plane", "rigid")], [("plane", "rigid")]]))
    return False, None


def m_impact(rnd, pairs, truth):
    drop(pairs, "impact")
    options = [
        (Mapping([("K", ["0.1"]), ("velocity", ["1 m/s"])]), "impact"),
        (Mapping([]), "impact"), ("", "impact"), ("[]", "impact"), ("0.1", "impact"),
        (Mapping([("K", "[]")]), "impact.K"), (Mapping([("velocity", "[]")]), "impact.velocity"),
        (Mapping([("K", ["0.1", "0.3", "0.1"])]), "impact.K"),
        (Mapping([("K", ["0.1", "0.10"])]), "impact.K"),
        (Mapping([("velocity", ["1 m/s", "100 cm/s"])]), "impact.velocity"),
        (Mapping([("velocity", ["2 m/s", "0.5 m/s", "200 cm/s"])]), "impact.velocity"),
        (Mapping([("K", ["0"])]), "impact.K"), (Mapping([("K", ["-0.1"])]), "impact.K"),
        (Mapping([("K", ["0.2", "10.5"])]), "impact.K"), (Mapping([("K", ["1.0e+400"])]), "impact.K"),
        (Mapping([("K", ["'0.1'"])]), "impact.K"), (Mapping([("K", ["1e-1"])]), "impact.K"),
        (Mapping([("K", ["true"])]), "impact.K"), (Mapping([("K", ["[0.1]"])]), "impact.K"),
        (Mapping([("K", ["0.1_0"])]), "impact.K"), (Mapping([("K", ["1:30"])]), "impact.K"),
        (Mapping([("K", ["010"])]), "impact.K"), (Mapping([("K", [".nan"])]), "impact.K"),
        (Mapping([("K", "0.1")]), "impact.K"), (Mapping([("velocity", "1 m/s")]), "impact.velocity"),
        (Mapping([("velocity", ["1 m/s", ""])]), "impact.velocity"),
    ]
    value, where = rnd.choice(options)
    pairs.append(("impact", value))
    return False, where


def m_K_elastic(rnd, pairs, truth):
    set_(pairs, "viscosity", rnd.choice(["0 P", "0 Pa*s", "0.0 Pa s"]))
    drop(pairs, "impact")
    pairs.append(("impact", Mapping([("K", ["0.1"])])))
    return False, "impact.K"


def m_elastic_velocity(rnd, pairs, truth):
    """Zero viscosity with impact velocities: a valid elastic case."""
    if not truth["velocities"]:
        return None
    set_(pairs, "viscosity", rnd.choice(["0 P", "0 Pa*s", "0.0 Pa s", "-0 P"]))
    truth["eta"] = 0.0
    return True, None


def m_geometries(rnd, pairs, truth):
    if truth["form"] != "material":
        return None
    drop(pairs, "geometries")
    value = rnd.choice(["[]", ["sphere-sphere", "sphere-sphere"], ["sphere-cube"], "sphere-sphere", "",
                        ["sphere-plane", "Sphere-Plane"], ["[sphere-plane]"], "{a: b}"])
    pairs.append(("geometries", value))
    return False, "geometries"


def m_name(rnd, pairs, truth):
    drop(pairs, "name")
    pairs.insert(0, ("name", rnd.choice(["", "~", "null", "''", "123", "1.5", "[a]", "{a: b}", "yes", "true"])))
    return False, "name"


def m_poisson(rnd, pairs, truth):
    if truth["form"] != "bodies":
        return None
    i = rnd.randrange(2)
    body = get(pairs, "bodies")[i]
    if truth["bodies"][i]["kind"] == "rigid":
        return None
    set_(body, "poisson", rnd.choice(["0.5", "0.7", "-1", "-1.5", "1", "'0.3'", "0.3 GPa", "", "[0.3]", ".nan",
                                      ".inf", "true", "0.3_0", "1.0e+400", "0,3", "3e-1", "0.5000"]))
    return False, f"bodies[{i}].poisson"


def m_bodies_shape(rnd, pairs, truth):
    if truth["form"] != "bodies":
        return None
    bodies = get(pairs, "bodies")
    choice = rnd.randrange(5)
    if choice == 0:
        del bodies[1]
    elif choice == 1:
        bodies.append([("plane", "rigid")])
    elif choice == 2:
        set_(pairs, "bodies", rnd.choice(["[]", "", "rigid", "{a: 1}", "[1, 2]"]))
    elif choice == 3:
        set_(pairs, "bodies", [[("plane", "rigid")], [("plane", "rigid")]])
    else:
        get(pairs, "bodies")[1] = [("plane", rnd.choice(["yes", "'true'", "1", "elastic", ""]))]
    return False, None


def m_plane_false_sphere(rnd, pairs, truth):
    """A sphere may say plane: false."""
    if truth["form"] != "bodies" or truth["bodies"][1]["kind"] != "sphere":
        return None
    body = get(pairs, "bodies")[1]
    set_(body, "plane", "false")
    return True, None


def m_injection_text(rnd, pairs, truth, text=None):
    """An injection string as free text (name, description, a note): data, kept exactly, where it
    is printable (a name: one line of at most 100 characters); else refused naming the field."""
    key = rnd.choice(["name", "name", "description", "note", "viscosity_note"])
    text = rnd.choice(INJECTIONS) if text is None else text
    drop(pairs, key)
    pairs.insert(rnd.randrange(len(pairs) + 1), (key, yaml_string(text)))
    if key == "name":
        valid = 0 < len(text) <= 100 and not _NOT_IN_NAME.search(text)
        if valid:
            truth["name"] = text
        return valid, None if valid else "name"
    return (True, None) if not _NOT_IN_TEXT.search(text) else (False, key)


def m_injection_quantity(rnd, pairs, truth, text=None):
    """An injection string where a quantity goes: refused, naming the field."""
    path, key, setter = rnd.choice(quantity_paths(pairs))
    setter(yaml_string(rnd.choice(INJECTIONS) if text is None else text))
    return False, path


def m_injection_measurements(rnd, pairs, truth, text=None):
    """An injection string as the measurements path: nothing is read, refused naming the field."""
    drop(pairs, "measurements")
    pairs.append(("measurements", yaml_string(rnd.choice(INJECTIONS) if text is None else text)))
    return False, "measurements"


def m_injection_key(rnd, pairs, truth, text=None):
    """An injection string as a key: an unknown field, refused."""
    pairs.insert(rnd.randrange(len(pairs) + 1), (yaml_string(rnd.choice(INJECTIONS) if text is None else text), "1"))
    return False, None


def m_injection_item(rnd, pairs, truth, text=None):
    """An injection string in a list: geometries, impact.K, impact.velocity."""
    text = yaml_string(rnd.choice(INJECTIONS) if text is None else text)
    where = rnd.choice(["geometries", "K", "velocity"])
    if where == "geometries":
        if truth["form"] != "material":
            return None
        drop(pairs, "geometries")
        pairs.append(("geometries", ["sphere-plane", text]))
        return False, "geometries"
    drop(pairs, "impact")
    pairs.append(("impact", Mapping([(where, ["1 m/s" if where == "velocity" else "0.1", text])])))
    return False, f"impact.{where}"


MUTATIONS = [m_none, m_equivalent_unit, m_bad_quantity, m_bad_type, m_wrong_dimension, m_extreme,
             m_drop_required, m_drop_body_key, m_unknown_key, m_doc_key, m_bad_doc_key, m_duplicate_key,
             m_contradiction, m_impact, m_K_elastic, m_elastic_velocity, m_geometries, m_name, m_poisson,
             m_bodies_shape, m_plane_false_sphere, m_injection_text, m_injection_quantity, m_injection_measurements,
             m_injection_key, m_injection_item]

# Whole-text mutations: (name, function(rnd, text) -> (bytes, field)) on a valid text; all invalid.


def t_truncate(rnd, pairs, truth):
    """Cut the file inside its last line, a required quantity (viscosity), so every cut is invalid."""
    drop(pairs, "viscosity")
    text = "\n".join(render(pairs)) + "\nviscosity: 6.7e5 P"
    cut = rnd.randrange(len(text) - len("viscosity: 6.7e5 P"), len(text))
    return text[:cut].encode(), None


def t_random_bytes(rnd, pairs, truth):
    return bytes(rnd.randrange(256) for _ in range(rnd.randint(0, 200))), None


def t_non_utf8(rnd, pairs, truth):
    text = "\n".join(render(pairs)) + "\n"
    where = rnd.choice(["description: caf\u00e9\n", "name: caf\u00e9\n"])
    return text.encode() + where.encode("latin-1"), None


def t_not_mapping(rnd, pairs, truth):
    return rnd.choice([b"", b"# only a comment\n", b"- 1\n- 2\n", b"just text\n", b"42\n", b"~\n", b"---\n...\n",
                       b"[a, b]\n", b"a: 1\n---\nb: 2\n", b"\xef\xbb\xbf"]), None


def t_deep(rnd, pairs, truth):
    n = rnd.choice([50, 500, 2000])
    text = "\n".join(render(pairs)) + "\nnote: " + "[" * n + "]" * n + "\n"
    return text.encode(), None


def t_anchor_alias(rnd, pairs, truth):
    text = "\n".join(render(pairs)) + "\n"
    extra = rnd.choice([
        "note: &a text\ndescription: *a\n",
        "a: &a [1, 2]\nb: [*a, *a, *a]\n",
        "note: !!python/object/apply:os.system ['echo hi']\n",
        "note: !custom text\n",
        "<<: {name: merged}\n",
        "? [a, b]\n: c\n",
        "1: one\n",
        "null: x\n",
    ])
    return (text + extra).encode(), None


def t_nul(rnd, pairs, truth):
    text = "\n".join(render(pairs))
    cut = rnd.randrange(len(text))
    return (text[:cut] + rnd.choice(["\x00", "\x07", "\ufffe", "\x1b[31m"]) + text[cut:]).encode(), None


def t_yaml_bomb(rnd, pairs, truth):
    """A 'billion laughs': nine levels of aliases to nine-item lists (9^9 items if expanded), or
    aliases that grow a key; refused at its first anchor, nothing expanded."""
    levels = ["a: &a [\"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\"]"]
    for i in range(1, rnd.choice([3, 9])):
        prev, name = chr(ord("a") + i - 1), chr(ord("a") + i)
        levels.append(f"{name}: &{name} [{', '.join(['*' + prev] * 9)}]")
    text = "\n".join(render(pairs)) + "\n" + "\n".join(levels) + "\n"
    return text.encode(), None


def t_huge(rnd, pairs, truth):
    """A case file beyond the size limit (1 MB): refused unread, naming the file."""
    text = "\n".join(render(pairs)) + "\ndescription: " + yaml_string("z" * 1_000_001) + "\n"
    return text.encode(), "(file)"


def t_bad_encoding(rnd, pairs, truth):
    """Bytes that are not UTF-8: UTF-16 with its BOM, an overlong '/', a lone continuation byte, an
    encoded surrogate, Latin-1."""
    text = "\n".join(render(pairs)) + "\n"
    return rnd.choice([b"\xff\xfe" + text.encode("utf-16-le"), text.encode() + b"note: \xc0\xaf\n",
                       text.encode() + b"note: \x80\n", text.encode() + b"note: \xed\xa0\x80\n",
                       b"name: \xe9t\xe9\n" + text.encode()]), "(file)"


def t_injection_document(rnd, pairs, truth):
    """A whole file that is an injection string: not a mapping."""
    return rnd.choice(INJECTIONS[:12]).encode("utf-8", "surrogatepass"), None


TEXT_MUTATIONS = [t_truncate, t_random_bytes, t_non_utf8, t_not_mapping, t_deep, t_anchor_alias, t_nul, t_yaml_bomb,
                  t_huge, t_bad_encoding, t_injection_document]
ALL = MUTATIONS + TEXT_MUTATIONS
VALID_PRESERVING = [m_equivalent_unit, m_doc_key, m_elastic_velocity, m_plane_false_sphere]


def make_variant(rnd: random.Random, mutation=None) -> Variant:
    """A random variant: a valid base, a few valid-preserving edits, then `mutation` (or a random one)."""
    mutation = mutation or rnd.choice(ALL)
    while True:
        pairs, truth = base_case(rnd)
        for _ in range(rnd.randint(0, 2)):
            rnd.choice(VALID_PRESERVING)(rnd, pairs, truth)
        if mutation in TEXT_MUTATIONS:
            data, fld = mutation(rnd, pairs, truth)
            return Variant(mutation.__name__, data, False, fld)
        outcome = mutation(rnd, pairs, truth)
        if outcome is not None:
            valid, fld = outcome
            return Variant(mutation.__name__, ("\n".join(render(pairs)) + "\n").encode(), valid, fld,
                           truth if valid else {})


def corpus(n: int = 600, seed: int = 0) -> list[Variant]:
    """A fixed corpus: every mutation in turn, each drawn from its own seeded generator."""
    return [make_variant(random.Random(f"{seed}-{i}"), ALL[i % len(ALL)]) for i in range(n)]


INJECTION_MUTATIONS = [m_injection_text, m_injection_quantity, m_injection_measurements, m_injection_key,
                       m_injection_item]


def injection_corpus(seed: int = 0) -> list[Variant]:
    """Every injection string in every kind of place (`INJECTION_MUTATIONS`), once each, on a
    seeded valid base: what the random corpus may miss."""
    out = []
    for i, text in enumerate(INJECTIONS):
        for mutation in INJECTION_MUTATIONS:
            rnd = random.Random(f"injection-{seed}-{i}-{mutation.__name__}")
            while True:
                pairs, truth = base_case(rnd)
                outcome = mutation(rnd, pairs, truth, text)
                if outcome is not None:
                    valid, fld = outcome
                    out.append(Variant(mutation.__name__, ("\n".join(render(pairs)) + "\n").encode(), valid, fld,
                                       truth if valid else {}))
                    break
    return out


# ---------------------------------------------------------------------------- the oracle
def effective(truth) -> dict:
    """E*, R*, M*, geometry list from the truth, by the textbook formulas (independent code)."""
    if truth["form"] == "material":
        r, rho, E = truth["radius"], truth["density"], truth["effective_modulus"]
        m = 4.0 / 3.0 * math.pi * r**3 * rho
        out = {"sphere-sphere": (E, r / 2, m / 2), "sphere-plane": (E, r, m)}
        return {g: out[g] for g in truth["geometries"]}
    b1, b2 = truth["bodies"]
    m1 = 4.0 / 3.0 * math.pi * b1["radius"] ** 3 * b1["density"]
    c = (1 - b1["poisson"] ** 2) / b1["young"]
    if b2["kind"] != "rigid":
        c += (1 - b2["poisson"] ** 2) / b2["young"]
    if b2["kind"] == "sphere":
        m2 = 4.0 / 3.0 * math.pi * b2["radius"] ** 3 * b2["density"]
        return {"sphere-sphere": (1 / c, b1["radius"] * b2["radius"] / (b1["radius"] + b2["radius"]),
                                  m1 * m2 / (m1 + m2))}
    return {"sphere-plane": (1 / c, b1["radius"], m1)}


def mismatch(case, truth, path) -> str | None:
    """Why the loaded `case` differs from the oracle's numbers (None if it agrees)."""
    def close(a, b):
        return math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0)

    expect = effective(truth)
    if [p.geometry for p in case.pairs] != list(expect):
        return f"geometries {[p.geometry for p in case.pairs]} != {list(expect)}"
    for p in case.pairs:
        E, R, M = expect[p.geometry]
        if not (close(p.E, E) and close(p.R, R) and close(p.M, M)):
            return f"{p.geometry}: E*, R*, M* = {p.E, p.R, p.M}, expected {E, R, M}"
        if not (p.eta == truth["eta"] or close(p.eta, truth["eta"])):
            return f"eta = {p.eta}, expected {truth['eta']}"
    if len(case.K) != len(truth["K"]) or not all(close(a, b) for a, b in zip(case.K, truth["K"])):
        return f"K = {case.K}, expected {truth['K']}"
    if len(case.velocities) != len(truth["velocities"]) or not all(
            close(a, b) for a, b in zip(case.velocities, truth["velocities"])):
        return f"velocities = {case.velocities}, expected {truth['velocities']}"
    if case.name != truth.get("name", Path(path).stem):
        return f"name {case.name!r}, expected {truth.get('name')!r}"
    return None


def classify(variant: Variant, folder: Path, load=None) -> tuple[str, str]:
    """('clear' | 'unclear' | 'accepted-invalid' | 'refused-valid' | 'accepted-valid', detail).

    A refusal is clear when it is a CaseError naming the file and the expected field, in a message
    of a sane length (a value of the file is repeated only cut short)."""
    from contact_model import CaseError
    load = load or __import__("contact_model").load_case
    path = folder / "case.yaml"
    path.write_bytes(variant.text)
    try:
        case = load(path)
    except CaseError as err:
        message = str(err)
        if not variant.valid:
            if len(message) > len(str(path)) + 2000:
                return "unclear", f"a message of {len(message)} characters: {message[:300]}"
            if str(path) in message and err.field and (variant.field is None or variant.field in err.field):
                return "clear", message
            return "unclear", f"expected field {variant.field!r}: {message}"
        return "refused-valid", message
    except BaseException as err:  # noqa: BLE001 - the point is to catch anything else
        if isinstance(err, KeyboardInterrupt):
            raise
        return "unclear", f"{type(err).__name__}: {err}"
    if not variant.valid:
        return "accepted-invalid", "accepted"
    why = mismatch(case, variant.truth, path)
    return ("accepted-invalid", why) if why else ("accepted-valid", "")


# ---------------------------------------------------------------------------- the measurement file
#: A valid measurement file: header, three rows at three velocities.
MEASURED_HEADER = "velocity [m/s],restitution,restitution_uncertainty"
MEASURED_ROWS = [("0.5", "0.86", "0.005"), ("2", "0.83", "0.005"), ("6", "0.8", "0.005")]
MEASURED_PLACES = ("velocity", "restitution", "uncertainty", "header", "column", "comment")
#: The injection strings that are not plain numbers: a quoted CSV cell "0.8" is the number 0.8.
_PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
CSV_INJECTIONS = [s for s in INJECTIONS if not _PLAIN_NUMBER.fullmatch(s)]


def measurement_variant(rnd: random.Random, where: str | None = None) -> Variant:
    """A measurement CSV with one injection string in a cell, the header, an extra column or a
    comment line (the provenance: text, kept; every other place refuses it, naming the file)."""
    text = rnd.choice(CSV_INJECTIONS)
    where = where or rnd.choice(MEASURED_PLACES)
    cell = '"' + text.replace('"', '""') + '"'  # one CSV cell, whatever it holds
    header, rows, comments = MEASURED_HEADER, [list(r) for r in MEASURED_ROWS], ["made up for the fuzz test"]
    if where == "comment":
        while any(c in text for c in "\n\r\x00\ud800"):  # a comment is one line of text
            text = rnd.choice(CSV_INJECTIONS)
        comments.append(text.strip())
    elif where == "header":
        header = header.replace("restitution_uncertainty", cell)
    elif where == "column":
        header += "," + cell
        rows = [r + ["1"] for r in rows]
    else:
        rows[rnd.randrange(3)][["velocity", "restitution", "uncertainty"].index(where)] = cell
    body = "".join(f"# {c}\n" for c in comments) + header + "\n" + "".join(",".join(r) + "\n" for r in rows)
    return Variant(f"measurement_{where}", body.encode("utf-8", "surrogatepass"), where == "comment", None,
                   {"provenance": "\n".join(comments)})


def measurement_corpus(n: int = 120, seed: int = 0) -> list[Variant]:
    """A fixed corpus: every place in turn, each variant from its own seeded generator."""
    return [measurement_variant(random.Random(f"measured-{seed}-{i}"), MEASURED_PLACES[i % len(MEASURED_PLACES)])
            for i in range(n)]


def classify_measurements(variant: Variant, folder: Path) -> tuple[str, str]:
    """As `classify`, for a measurement variant read through a case file in `folder` (its project):
    a refusal is clear when it is a CaseError that starts with the CSV file's path."""
    from contact_model import CaseError, load_case

    csv_path = folder / "m.csv"
    csv_path.write_bytes(variant.text)
    (folder / "measured.yaml").write_text("effective_modulus: 70 GPa\nradius: 5 mm\ndensity: 2700 kg/m^3\n"
                                          "viscosity: 5e4 P\ngeometries: [sphere-plane]\nmeasurements: m.csv\n")
    try:
        case = load_case(folder / "measured.yaml", project=folder)
    except CaseError as err:
        message = str(err)
        if variant.valid:
            return "refused-valid", message
        if message.startswith(f"{csv_path}: ") and len(message) < len(str(csv_path)) + 2000:
            return "clear", message
        return "unclear", message[:300]
    except BaseException as err:  # noqa: BLE001 - the point is to catch anything else
        if isinstance(err, KeyboardInterrupt):
            raise
        return "unclear", f"{type(err).__name__}: {err}"
    if not variant.valid:
        return "accepted-invalid", "accepted"
    m = case.measurements
    ok = m.provenance == variant.truth["provenance"] and m.velocity.tolist() == [0.5, 2.0, 6.0]
    return ("accepted-valid", "") if ok else ("accepted-invalid", f"provenance {m.provenance!r}")


# ---------------------------------------------------------------------------- running a corpus
OUTCOMES = ("clear", "unclear", "accepted-invalid", "refused-valid", "accepted-valid")


@dataclass
class Tally:
    """What a corpus run found: outcomes, those of the variants carrying an injection, examples,
    marker files, and files that appeared beside the inputs."""

    tried: int = 0
    counts: dict = dataclasses.field(default_factory=dict)
    injected: dict = dataclasses.field(default_factory=dict)
    examples: dict = dataclasses.field(default_factory=dict)
    markers: list = dataclasses.field(default_factory=list)
    stray_files: list = dataclasses.field(default_factory=list)

    def add(self, variant: Variant, outcome: str, detail: str) -> None:
        self.tried += 1
        self.counts[outcome] = self.counts.get(outcome, 0) + 1
        if is_injection(variant.text) or variant.kind.startswith("measurement_"):
            self.injected[outcome] = self.injected.get(outcome, 0) + 1
        self.examples.setdefault(outcome, []).append((variant.kind, variant.text[:120], detail[:300]))

    @property
    def failures(self) -> int:
        return sum(self.counts.get(o, 0) for o in ("unclear", "accepted-invalid", "refused-valid"))

    def summary(self, what: str) -> str:
        """One line: how many were tried, refused clearly, accepted; of them with an injection."""
        wrong = ", ".join(f"{o} {self.counts.get(o, 0)}" for o in OUTCOMES[1:4])
        return (f"{what}: {self.tried} tried, {self.counts.get('clear', 0)} refused clearly, "
                f"{self.counts.get('accepted-valid', 0)} accepted as valid, {self.failures} wrong ({wrong}); "
                f"with an injection string: {sum(self.injected.values())} tried, {self.injected.get('clear', 0)} "
                f"refused, {self.injected.get('accepted-valid', 0)} kept as text; marker files: {len(self.markers)}; "
                f"other files written: {len(self.stray_files)}")


def run(variants, classify_one, folder: Path, expected_files: set[str]) -> Tally:
    """Classify every variant in `folder`; then look for marker files (MARKER_DIR, a new /tmp/x) and
    for any file in `folder` beyond `expected_files` (the loader writes nothing)."""
    tally = Tally()
    x_before = Path("/tmp/x").exists()
    for v in variants:
        outcome, detail = classify_one(v, folder)
        tally.add(v, outcome, detail)
    tally.markers = sorted(str(p) for p in MARKER_DIR.glob("*")) if MARKER_DIR.exists() else []
    if Path("/tmp/x").exists() and not x_before:
        tally.markers.append("/tmp/x")
    tally.stray_files = sorted(p.name for p in folder.iterdir() if p.name not in expected_files)
    return tally


def run_all(n: int, folder: Path) -> tuple[Tally, Tally]:
    """The case-file corpus of `n` variants with every injection string in every place
    (`injection_corpus`), and the measurement corpus (n / 5, at least three per injection string),
    each in a folder of its own under `folder`."""
    cases, measured = folder / "cases", folder / "measured"
    cases.mkdir(parents=True, exist_ok=True)
    measured.mkdir(parents=True, exist_ok=True)
    return (run(corpus(n) + injection_corpus(), classify, cases, {"case.yaml"}),
            run(measurement_corpus(max(3 * len(INJECTIONS), n // 5)), classify_measurements, measured,
                {"m.csv", "measured.yaml"}))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    numbers = [a for a in argv if a.isdigit()]
    n = int(numbers[0]) if numbers else 600
    with tempfile.TemporaryDirectory() as tmp:
        tallies = run_all(n, Path(tmp))
    for what, tally in zip(("case files", "measurement files"), tallies):
        print(tally.summary(what))
        for outcome in OUTCOMES:
            print(f"  {outcome:17s} {tally.counts.get(outcome, 0)}")
        if "-v" in argv or "--verbose" in argv:
            for outcome in ("unclear", "accepted-invalid", "refused-valid"):
                for kind, text, detail in tally.examples.get(outcome, []):
                    print(f"\n[{outcome}] {kind}: {text!r}\n    {detail}")
    return 0 if all(t.failures == 0 and not t.markers and not t.stray_files for t in tallies) else 1


if __name__ == "__main__":
    sys.exit(main())
