r"""The quantities the study reads from a collision, as one table: a `Quantity` per entry of `QUANTITIES`.

The bottom layer of the quantities: an entry says what a quantity is (name, unit, symbol, whether
the gate judges it, its column of the paper's series), how it is read off an engine run
(`extract`, from `records.collision_metrics.CollisionMetrics`) and off the reference solution
(`reference`, from the reference row and the run's Hertz scales), or, for a quantity that follows
from others, how (`derive`). Every later step loops over this table: the extraction
(`records.collision_metrics.quantities_of`), the comparison rows, the extrapolation to dt -> 0,
the gate and the reports.

- ``T``: the contact time [s] under the criterion (x0 or F0);
- ``A``: the maximum contact area pi R* delta_max [m^2];
- ``eps``: the restitution coefficient V'/V under the criterion [-];
- ``Q1`` = A^{1/2} T^2 and ``Q2`` = A / (sqrt(V V') T): the paper's combinations (eqs. 6-7);
- ``delta_max``: the maximum overlap [m];
- ``F_max``: the maximum normal force [N] (the force at touching for a dashpot that acts at once).

T, A and eps are gated (config `tolerance:`; `GATED_QUANTITIES`); the others are reported. The
reference's values are the ODE's characteristics times the Hertz scales of the run: T_e, A_e,
delta_e and F_e = M* V^2 / delta_e.

Adding a quantity: an entry here with its extraction and its reference (or its derivation), the
docs naming it (docs/physics.md or docs/verdict.md) and, for a gated one, its tolerance in
config/config.yaml; tests/test_adding_a_quantity.py walks every place it must reach.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from reference import HERTZ_TAU


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
    symbol : str
        How the docs write it (e.g. 'δ_max'); its name where empty.
    extract : callable or None
        ``extract(metrics, criterion)``: its value [SI] from one run's `CollisionMetrics` under the
        criterion ('x0' or 'F0'); None for a derived quantity.
    reference : callable or None
        ``reference(row, criterion, scales)``: its value [SI] from the reference solution's row
        (dimensionless) and the run's scales (T_e, delta_e, F_e); None for a derived quantity.
    derive : callable or None
        ``derive(values)``: its value from the other quantities' values (and R, V) of the same
        collision; None for a quantity read off the collision itself.
    """

    name: str
    title: str
    unit: str
    gated: bool
    series: str | None
    display: tuple[str, float]
    symbol: str = ""
    extract: Callable[[Any, str], float] | None = None
    reference: Callable[[Mapping, str, Mapping[str, float]], float] | None = None
    derive: Callable[[Mapping[str, float]], float] | None = None


def _by_criterion(x0: str, f0: str):
    return lambda m, criterion: getattr(m, x0 if criterion == "x0" else f0)


QUANTITIES: dict[str, Quantity] = {q.name: q for q in (
    Quantity("T", "contact time", "s", True, "T/T_e", ("µs", 1e6), "T", _by_criterion("T_x0", "T_F0"),
             lambda r, c, s: (r["tau_0"] if c == "x0" else r["tau_f"]) / HERTZ_TAU * s["T_e"]),
    Quantity("A", "maximum contact area", "m^2", True, "A/A_e", ("mm²", 1e6), "A",
             derive=lambda v: math.pi * v["R"] * v["delta_max"]),
    Quantity("eps", "restitution coefficient", "-", True, "eps", ("", 1.0), "ε", _by_criterion("eps_x0", "eps_F0"),
             lambda r, c, s: r["eps_x0"] if c == "x0" else r["eps_F0"]),
    Quantity("Q1", "A^(1/2) T^2", "m s^2", False, "Q1/Q1e", ("m s²", 1.0), "Q₁",
             derive=lambda v: math.sqrt(v["A"]) * v["T"]**2),
    Quantity("Q2", "A / (sqrt(V V') T)", "m", False, "Q2/Q2e", ("m", 1.0), "Q₂",
             derive=lambda v: v["A"] / (math.sqrt(v["eps"]) * v["V"] * v["T"]) if v["eps"] > 0 and v["T"] > 0
             else math.nan),
    Quantity("delta_max", "maximum overlap", "m", False, None, ("µm", 1e6), "δ_max", lambda m, c: m.delta_max,
             lambda r, c, s: r["x_max"] * s["delta_e"]),
    Quantity("F_max", "maximum normal force", "N", False, None, ("kN", 1e-3), "F_max", lambda m, c: m.force_max,
             lambda r, c, s: r.get("force_max", math.nan) * s["F_e"]),
)}
#: The quantities the gate judges.
GATED_QUANTITIES = tuple(name for name, q in QUANTITIES.items() if q.gated)


def gated_quantities() -> tuple[str, ...]:
    """The names of the gated quantities, read off the table at the call (a test may add one)."""
    return tuple(name for name, q in QUANTITIES.items() if q.gated)


def derived_values(measured: Mapping[str, float], R: float, V: float) -> dict[str, float]:
    """Every quantity of `QUANTITIES` (in its order) from the values of those read off the collision
    (`measured`, by name; NaN for one missing) and the effective radius R [m] and impact velocity V [m/s].

    Parameters
    ----------
    measured : mapping of str to float
        The quantities read off the collision [SI], by name.
    R : float
        Effective radius R* [m].
    V : float
        Impact velocity [m/s].
    """
    values = {"R": R, "V": V}
    values.update({name: measured.get(name, math.nan) for name, q in QUANTITIES.items() if q.derive is None})
    for name, q in QUANTITIES.items():
        if q.derive is not None:
            values[name] = q.derive(values)
    return {name: values[name] for name in QUANTITIES}


def reference_values(row: Mapping, criterion: str, scales: Mapping[str, float], R: float,
                     V: float) -> dict[str, float]:
    """Every quantity of the reference solution (`row`, dimensionless) under `criterion`, in SI
    through the run's `scales` (T_e, delta_e, F_e).

    Parameters
    ----------
    row : mapping
        The reference solution's row (dimensionless characteristics).
    criterion : {'x0', 'F0'}
        The end-of-contact criterion.
    scales : mapping of str to float
        The run's Hertz scales: T_e [s], delta_e [m], F_e [N].
    R : float
        Effective radius R* [m].
    V : float
        Impact velocity [m/s].
    """
    return derived_values({name: q.reference(row, criterion, scales) for name, q in QUANTITIES.items()
                           if q.derive is None and q.reference is not None}, R, V)


def characteristics(T: float, delta_max: float, eps: float, F_max: float, R: float, V: float) -> dict[str, float]:
    """Every quantity of `QUANTITIES` from one collision's contact time T [s], maximum overlap
    delta_max [m], restitution eps, maximum force F_max [N], effective radius R [m] and impact
    velocity V [m/s]: A = pi R delta_max, Q1 = A^{1/2} T^2, Q2 = A / (sqrt(V eps V) T).

    Parameters
    ----------
    T : float
        Contact time [s].
    delta_max : float
        Maximum overlap [m].
    eps : float
        Restitution coefficient [-].
    F_max : float
        Maximum normal force [N].
    R : float
        Effective radius R* [m].
    V : float
        Impact velocity [m/s].
    """
    return derived_values({"T": T, "delta_max": delta_max, "eps": eps, "F_max": F_max}, R, V)


#: The units a person reads each dimension in, largest first, with their factor from SI.
_PREFIXED = {"s": (("s", 1.0), ("ms", 1e3), ("µs", 1e6), ("ns", 1e9)),
             "m": (("m", 1.0), ("mm", 1e3), ("µm", 1e6), ("nm", 1e9)),
             "m^2": (("m²", 1.0), ("mm²", 1e6), ("µm²", 1e12)),
             "N": (("MN", 1e-6), ("kN", 1e-3), ("N", 1.0), ("mN", 1e3), ("µN", 1e6))}


def readable(name: str, value: float) -> str:
    """`value` [SI] of quantity `name` in the unit a person reads it in, the largest in which it is
    at least 0.1 ('52.31 µs', '2.5 kN', '0.749 mm²', '0.9045' for a ratio).

    Parameters
    ----------
    name : str
        A quantity's name in `QUANTITIES`.
    value : float
        Its value [SI].
    """
    q = QUANTITIES[name]
    units = _PREFIXED.get(q.unit)
    if units is None or not math.isfinite(value) or value == 0:
        unit, factor = q.display
        return f"{value * factor:.6g}" + (f" {unit}" if unit else "")
    unit, factor = next(((u, f) for u, f in units if abs(value) * f >= 0.1), units[-1])
    return f"{value * factor:.6g} {unit}"
