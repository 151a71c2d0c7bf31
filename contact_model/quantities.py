"""Quantities written with their unit ("109 GPa", "6.7e5 P"), read strictly into SI.

A quantity is exactly one plain number, one space and a unit that pint reads as a unit alone;
comma decimals, digit groups, a second number, an expression, a dimensionless factor (pi,
percent) or any other text is refused, and so is a number beyond double precision. The field's
name picks its dimension (`DIMENSIONS`). Used by the case files and the measurement files; every
refusal is a `CaseError` naming the file and the field.
"""

from __future__ import annotations

import difflib
import functools
import math
import re

@functools.lru_cache(maxsize=None)
def units():
    """pint's unit registry, built on first use.

    Building it (and importing pint) takes about half a second, which every workflow rule that
    merely imports contact_model would pay. pint keeps its parsed definitions in the user's cache
    folder (`cache_folder=":auto:"`): the registry then builds in 0.03 s instead of 0.3 s, at every
    start of the workflow.

    Returns
    -------
    pint.UnitRegistry
    """
    import pint

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except OSError:  # no writable cache folder (e.g. a read-only home): parse the definitions
        return pint.UnitRegistry()

# field -> (pint dimensionality, SI unit)
DIMENSIONS = {
    "effective_modulus": ("[pressure]", "Pa"),
    "young": ("[pressure]", "Pa"),
    "viscosity": ("[pressure] * [time]", "Pa*s"),
    "radius": ("[length]", "m"),
    "density": ("[mass] / [length] ** 3", "kg/m^3"),
    "velocity": ("[length] / [time]", "m/s"),
    "tangential_velocity": ("[length] / [time]", "m/s"),
}

#: One poise in SI [Pa s]: the paper's unit of viscosity.
POISE = 0.1

#: The units a user most likely means, per dimension: what a "did you mean" picks from, in the
#: order it lists equally close ones.
COMMON_UNITS = {
    "[pressure]": ("Pa", "kPa", "MPa", "GPa", "bar", "psi"),
    "[pressure] * [time]": ("Pa*s", "mPa*s", "P", "cP"),
    "[length]": ("m", "cm", "mm", "um", "nm", "in"),
    "[mass] / [length] ** 3": ("kg/m^3", "g/cm^3"),
    "[length] / [time]": ("m/s", "cm/s", "mm/s", "km/h"),
}
#: At most this many units are offered, the closest first.
SUGGESTIONS = 3


def edit_distance(a: str, b: str) -> int:
    """The optimal-string-alignment distance between two strings.

    Insertions, deletions, substitutions and swaps of two neighbouring letters ('mn' -> 'nm') each
    count one.

    Parameters
    ----------
    a : str
        The first string.
    b : str
        The second string.

    Returns
    -------
    int
        The distance [edits].
    """
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def did_you_mean(unit_text: str, dimension: str) -> str:
    """' (did you mean 'MPa'?)' for a misspelt unit of `dimension`.

    For a unit that is a common unit of `dimension` (the field's: a suggestion is always of the
    right size kind) but for its letters' case ('Mpa'); else the common units one edit from it (a
    letter added, dropped, changed, or two swapped), the closest in spelling first -- same first
    letter, then same length -- up to SUGGESTIONS of them: '5 mn' as a length gives
    ' (did you mean 'mm', 'm' or 'nm'?)'; else difflib's closest; '' when none is close.

    Parameters
    ----------
    unit_text : str
        The unit as the file writes it.
    dimension : str
        The field's pint dimensionality, a key of `COMMON_UNITS` (e.g. '[pressure]').

    Returns
    -------
    str
        The suggestion, with its leading space, or ''.
    """
    options = COMMON_UNITS.get(dimension, ())
    same = [u for u in options if u.lower() == unit_text.lower()]
    if same:
        return f" (did you mean '{same[0]}'?)"
    near = sorted((u for u in options if edit_distance(unit_text, u) <= 1),
                  key=lambda u: (u[:1] != unit_text[:1], abs(len(u) - len(unit_text)), options.index(u)))
    close = near[:SUGGESTIONS] or difflib.get_close_matches(unit_text, options, n=1, cutoff=0.6)
    if not close:
        return ""
    quoted = [f"'{u}'" for u in close]
    return f" (did you mean {' or '.join([', '.join(quoted[:-1]), quoted[-1]] if len(quoted) > 1 else quoted)}?)"


#: One plain decimal number (ASCII digits only: Python's float() would also take other
#: scripts' digits and underscores).
NUMBER = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
#: A unit: names (letters, no digits) with optional integer exponents (^2, **-3), joined by
#: '*', '/' or a space. No parentheses, no numbers but exponents: "GPa 2" or "m2" is refused.
_FACTOR = r"[^\W\d]+(?:(?:\^|\*\*)[+-]?[0-9]+)?"
UNIT = rf"{_FACTOR}(?:(?: ?[*/] ?| ){_FACTOR})*"
QUANTITY = re.compile(rf"({NUMBER}) ({UNIT})")
PLAIN_NUMBER = re.compile(NUMBER)

def written_unit(value: str) -> str:
    """The unit of a quantity string as its file writes it ('6.7e5 P' -> 'P').

    For a value that `quantity` has read.

    Parameters
    ----------
    value : str
        The quantity string, '<number> <unit>'.

    Returns
    -------
    str
        Its unit.
    """
    return QUANTITY.fullmatch(value)[2]


def in_unit(value: float, unit: str, target: str) -> float:
    """`value` [unit] expressed in `target`.

    Parameters
    ----------
    value : float
        The magnitude, in `unit` [unit].
    unit : str
        Its unit, as pint reads it (e.g. 'Pa*s').
    target : str
        The unit to express it in, as pint reads it (e.g. a file's own 'mPa*s').

    Returns
    -------
    float
        The magnitude in `target` [target].
    """
    return float(units().Quantity(value, unit).to(target).magnitude)


#: The most characters of a file's text that a message repeats: longer text is cut, and its length
#: said, so that a message never carries a file's content (a stray /etc/passwd, a megabyte string).
SHOWN_CHARS = 40
#: The longest quantity text read (a number, a space and a unit are a few characters); a longer
#: text is refused before pint sees it.
MAX_QUANTITY_CHARS = 100


def shown(value, limit: int = SHOWN_CHARS) -> str:
    """`value` as a message repeats it.

    Its repr (control characters, NUL and invisible format characters escaped), cut to `limit`
    characters with its full length said.

    Parameters
    ----------
    value : object
        The value to repeat.
    limit : int
        The most characters repeated [characters].

    Returns
    -------
    str

    Examples
    --------
    >>> shown("0,8 P")
    "'0,8 P'"
    """
    text = repr(value)
    if len(text) <= limit:
        return text
    size = f"{len(value)} characters" if isinstance(value, str) else f"{len(text)} characters written out"
    return f"{text[:limit]}... ({size})"


def field_text(key) -> str:
    """A key of a file as a field name in a message.

    Itself when it is a short name (letters, digits, '_', '-', '.', spaces), else `shown` (escaped
    and cut).

    Parameters
    ----------
    key : object
        The key as the file gives it.

    Returns
    -------
    str
    """
    text = str(key)
    return text if re.fullmatch(r"[\w .-]{1,60}", text) else shown(key)


class CaseError(ValueError):
    """An input file (a case file, or a measurement file: `measurement_file.MeasurementError`)
    that cannot be used; the message names the file and the field."""

    def __init__(self, path, field_name: str, problem: str):
        self.path, self.field, self.problem = str(path), field_name, problem
        super().__init__(f"{path}: field '{field_name}': {problem}")


def _dimension(name: str) -> tuple[str, str]:
    """(dimensionality, SI unit) of a field path such as 'bodies[1].young' or 'impact.velocity[0]'."""
    return DIMENSIONS[name.split(".")[-1].split("[")[0]]


def not_a_quantity(value, name: str) -> str:
    """The problem with a value of field `name` that is not a quantity string at all.

    Parameters
    ----------
    value : object
        The value the file gives.
    name : str
        The field's path, e.g. 'radius' or 'bodies[0].young'.

    Returns
    -------
    str
        The problem in words, with an example in the field's SI unit.
    """
    si_unit = _dimension(name)[1]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{value!r} has no unit; write it as e.g. '{value} {si_unit}'"
    return f"expected a quantity with a unit, e.g. '1 {si_unit}', got {shown(value)}"


def quantity(value, name: str, path) -> float:
    """Convert a '<number> <unit>' string to SI for field `name`.

    Strict: exactly one plain number, one space, one unit that pint reads as a unit alone; the
    result must be finite.

    Parameters
    ----------
    value : str
        The quantity string, e.g. '70 GPa' [the unit it writes].
    name : str
        The field's path, such as 'radius' or 'bodies[0].young'; its last name picks the dimension.
    path : str or pathlib.Path
        The file, named in messages.

    Returns
    -------
    float
        The value in the field's SI unit: [Pa] for a modulus, [Pa s] for a viscosity, [m] for a
        radius, [kg/m^3] for a density, [m/s] for a velocity.

    Raises
    ------
    CaseError
        Naming the file and the field.
    """
    dimension, si_unit = _dimension(name)
    if not isinstance(value, str):
        raise CaseError(path, name, not_a_quantity(value, name))
    if len(value) > MAX_QUANTITY_CHARS:
        raise CaseError(path, name, f"{shown(value)} is no quantity: one plain number, one space and a unit are a "
                                    f"few characters (at most {MAX_QUANTITY_CHARS} are read), e.g. '1.5 {si_unit}'")
    if PLAIN_NUMBER.fullmatch(value.strip()):
        raise CaseError(path, name, f"{shown(value)} is a number without a unit (quoted, so text): write it with "
                                    f"its unit, e.g. '{value.strip()} {si_unit}'")
    match = QUANTITY.fullmatch(value)
    if not match:
        written = re.fullmatch(rf"\s*{NUMBER}\s*(.+?)\s*", value)  # e.g. '7800 kg/m3': its unit's spelling
        raise CaseError(path, name, f"cannot read {shown(value)} as a quantity: write one plain number, one space "
                                    f"and a unit, e.g. '1.5 {si_unit}' (no comma decimals, digit groups, "
                                    f"second numbers, expressions or other text)"
                                    f"{did_you_mean(written[1], dimension) if written else ''}")
    number, unit_text = match.groups()
    x = float(number)
    if not math.isfinite(x):
        raise CaseError(path, name, f"the number {number} in {shown(value)} is beyond double precision")
    if x == 0 and any(c in "123456789" for c in re.split("[eE]", number)[0]):
        raise CaseError(path, name, f"the number {number} in {shown(value)} underflows to 0 in double precision")
    try:  # pint parses user text: any of its exceptions means the unit cannot be read
        unit = units().parse_units(unit_text)
        factors = [units().Unit(u) for u in unit._units]
    except Exception as err:  # noqa: BLE001
        raise CaseError(path, name, f"cannot read the unit {unit_text!r} of {shown(value)} ({type(err).__name__}: "
                                    f"{err}){did_you_mean(unit_text, dimension)}")
    plain = [str(f) for f in factors if f.dimensionless]
    if plain:  # 'pi', 'percent', 'radian' would silently scale the number
        raise CaseError(path, name, f"cannot read {shown(value)}: {plain[0]!r} is a dimensionless factor, not a unit")
    if unit.dimensionless:
        raise CaseError(path, name, f"{shown(value)} has no unit; expected a {dimension} such as '{si_unit}'")
    try:
        q = units().Quantity(x, unit)
        if not q.check(dimension):
            raise CaseError(path, name, f"{shown(value)} is a {q.dimensionality}, expected a {dimension} "
                                        f"(e.g. {si_unit}){did_you_mean(unit_text, dimension)}")
        si = float(q.to(si_unit).magnitude)
    except CaseError:
        raise
    except Exception as err:  # noqa: BLE001 - e.g. an offset unit (degC) or an overflow in the conversion
        raise CaseError(path, name, f"cannot convert {shown(value)} to {si_unit} ({type(err).__name__}: {err})")
    if not math.isfinite(si):
        raise CaseError(path, name, f"{shown(value)} is beyond double precision in SI ({si_unit})")
    if si == 0 and x != 0:
        raise CaseError(path, name, f"{shown(value)} underflows to 0 {si_unit} in double precision")
    return si + 0.0  # -0.0 -> 0.0
