r"""The quantities the study reads from a collision, as data: one `Quantity` per entry of `QUANTITIES`.

Each is computed the same way from an engine run and from the reference solution
(`characteristics`), so that their ratio is the run's error:

- ``T``: the contact time [s] under the criterion (x0 or F0);
- ``A``: the maximum contact area pi R* delta_max [m^2];
- ``eps``: the restitution coefficient V'/V under the criterion [-];
- ``Q1`` = A^{1/2} T^2 and ``Q2`` = A / (sqrt(V V') T): the paper's combinations (eqs. 6-7);
- ``delta_max``: the maximum overlap [m];
- ``F_max``: the maximum normal force [N] (the force at touching for a dashpot that acts at once).

T, A and eps are gated (config `tolerance:`; `GATED_QUANTITIES`); the others are reported. The
reference's values are the ODE's characteristics times the Hertz scales of the run: T_e, A_e,
delta_e and F_e = M* V^2 / delta_e.

Adding a quantity: an entry here and its value in `characteristics` (and, for a gated one, its
tolerance in config/config.yaml); tests/test_quantities.py checks that every entry has them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Quantity:
    """One quantity of a collision.

    Attributes
    ----------
    name : str
        Its name in summary.csv (``<name>``, ``<name>_ref``, ``err_<name>``, ...) and config.
    title : str
        What it is, for a reader.
    unit : str
        Its SI unit ('-' for a ratio).
    gated : bool
        Whether the gate judges it (a tolerance in config `tolerance:`).
    series : str or None
        The name of its column of the paper's series (`reference.series`), None where the paper
        gives none.
    display : tuple of (str, float)
        The unit a person reads it in and the factor from SI (e.g. ('µs', 1e6)).
    """

    name: str
    title: str
    unit: str
    gated: bool
    series: str | None
    display: tuple[str, float]


QUANTITIES: dict[str, Quantity] = {q.name: q for q in (
    Quantity("T", "contact time", "s", True, "T/T_e", ("µs", 1e6)),
    Quantity("A", "maximum contact area", "m^2", True, "A/A_e", ("mm²", 1e6)),
    Quantity("eps", "restitution coefficient", "-", True, "eps", ("", 1.0)),
    Quantity("Q1", "A^(1/2) T^2", "m s^2", False, "Q1/Q1e", ("m s²", 1.0)),
    Quantity("Q2", "A / (sqrt(V V') T)", "m", False, "Q2/Q2e", ("m", 1.0)),
    Quantity("delta_max", "maximum overlap", "m", False, None, ("µm", 1e6)),
    Quantity("F_max", "maximum normal force", "N", False, None, ("kN", 1e-3)),
)}
#: The quantities the gate judges.
GATED_QUANTITIES = tuple(name for name, q in QUANTITIES.items() if q.gated)


def characteristics(T: float, delta_max: float, eps: float, F_max: float, R: float, V: float) -> dict[str, float]:
    """Every quantity of `QUANTITIES` from one collision's contact time T [s], maximum overlap
    delta_max [m], restitution eps, maximum force F_max [N], effective radius R [m] and impact
    velocity V [m/s]: A = pi R delta_max, Q1 = A^{1/2} T^2, Q2 = A / (sqrt(V eps V) T)."""
    A = math.pi * R * delta_max
    return {"T": T, "A": A, "eps": eps, "Q1": math.sqrt(A) * T**2,
            "Q2": A / (math.sqrt(eps) * V * T) if eps > 0 and T > 0 else math.nan,
            "delta_max": delta_max, "F_max": F_max}


#: The units a person reads each dimension in, largest first, with their factor from SI.
_PREFIXED = {"s": (("s", 1.0), ("ms", 1e3), ("µs", 1e6), ("ns", 1e9)),
             "m": (("m", 1.0), ("mm", 1e3), ("µm", 1e6), ("nm", 1e9)),
             "m^2": (("m²", 1.0), ("mm²", 1e6), ("µm²", 1e12)),
             "N": (("MN", 1e-6), ("kN", 1e-3), ("N", 1.0), ("mN", 1e3), ("µN", 1e6))}


def readable(name: str, value: float) -> str:
    """`value` [SI] of quantity `name` in the unit a person reads it in, the largest in which it is
    at least 0.1 ('52.31 µs', '2.5 kN', '0.749 mm²', '0.9045' for a ratio)."""
    q = QUANTITIES[name]
    units = _PREFIXED.get(q.unit)
    if units is None or not math.isfinite(value) or value == 0:
        unit, factor = q.display
        return f"{value * factor:.6g}" + (f" {unit}" if unit else "")
    unit, factor = next(((u, f) for u, f in units if abs(value) * f >= 0.1), units[-1])
    return f"{value * factor:.6g} {unit}"
