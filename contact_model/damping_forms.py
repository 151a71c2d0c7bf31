r"""The damping forms of the study, one class each, registered by name: what a law's damping force
*does*, in one place.

Every law of the study adds to Hertz's force a damping force of one form. In the reference
solver's units (x = delta/delta_e, tau = t V/delta_e) its head-on collision is

    x'' + c x^p x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,

with the total force clipped at zero where the law clips it. A form owns everything that depends
on p alone:

- its equation's text for the reports (`DampingForm.equation`);
- its reference solver: the characteristics of the collision at coefficient c (`DampingForm.solve`,
  `DampingForm.restitution`);
- the powers of h = dt/T_e in the error expansion of its engine runs (`DampingForm.ladder_powers`):
  what a ladder extrapolated to dt -> 0 must eliminate. Where contact starts and ends, a force
  growing as s^p (s the time from touching) integrated by the engines' map gives terms h^{1 + p + k}
  (the generalised Euler-Maclaurin expansion, Navot 1961), beside the map's own whole powers
  (first order: the dissipative force sees a velocity half a step old). Measured on the engines'
  map for every form: tests/test_damping_forms.py;
- how its restitution moves with the impact velocity at a fixed coefficient of the physical law
  (`DampingForm.eps_of_velocity`).

The forms:

- ``half`` (p = 1/2, c = K): Kuwabara-Kono / Brilliantov, the viscoelastic model under test
  (`reference.collision_ode`); K grows as V^{1/5}, so the restitution falls with velocity;
- ``quarter`` (p = 1/4, c = b): Tsuji's form, most engines' restitution keywords
  (`reference.quarter_power_damping`, closed form); the restitution is the same at every velocity;
- ``velocity`` (p = 0, c): a linear dashpot (LAMMPS ``damping velocity`` and ``mass_velocity``;
  `reference.linear_damping`); c falls as V^{-1/5}, so the restitution rises with velocity;
- ``none``: Hertz alone (c = 0; T, A and eps = 1 in closed form).

Adding a form: a subclass of `DampingForm` with its name, p, equation and solver, decorated with
`register`; tests/test_damping_forms.py walks the recipe (a dummy form gets through it).

References
----------
Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
granular gases. Phys. Rev. E 53, 5382.
Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
Navot, I. (1961). An extension of the Euler-Maclaurin summation formula to functions with a branch
singularity. J. Math. and Phys. 40, 271-276.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

#: Hertz alone: the map is symmetric (even powers), Hertz's s^{3/2} at both ends adds 5/2 (+1 ...).
ELASTIC_POWERS = (2.0, 2.5, 3.5, 4.0)

#: {name: the form}: every damping form of the study.
DAMPING_FORMS: dict[str, DampingForm] = {}


def register(cls):
    """Class decorator: put one instance of the form `cls` into `DAMPING_FORMS` under its name."""
    if cls.name in DAMPING_FORMS:
        raise ValueError(f"damping form {cls.name!r} is registered twice")
    DAMPING_FORMS[cls.name] = cls()
    return cls


class DampingForm:
    """One damping form, c x^p x' in the reference's units.

    Attributes
    ----------
    name : str
        Its registry name ('half').
    power : float or None
        p, the power of x in the damping force; None for no damping.
    symbol : str
        The coefficient's letter in its equation ('K', 'b', 'c').
    label : str
        The force in physical words, for legends ("δ^½ δ'").
    eps_of_velocity : str
        How its restitution moves with the impact velocity V at a fixed coefficient of the physical
        law: 'falls', 'constant', 'rises' or 'none' (eps = 1).
    """

    name: ClassVar[str]
    power: ClassVar[float | None]
    symbol: ClassVar[str] = "c"
    label: ClassVar[str] = ""
    eps_of_velocity: ClassVar[str] = "none"
    #: The power of V its coefficient goes with at a fixed coefficient of the physical law (K ~ V^{1/5},
    #: b ~ V^0, c ~ V^{-1/5}): from the force's units, c x^p x' in delta_e = O(V^{4/5}) gives (1/5)(4p - 1).
    velocity_exponent: ClassVar[float] = 0.0

    @property
    def is_viscoelastic(self) -> bool:
        """Whether its coefficient is the viscoelastic model's K (form ``half``): the paper's series, the
        ladder refined by sqrt(K) above K = 1 and the reference's K range apply to it."""
        return self.power == 0.5

    def restitution_at(self, coefficient: float, criterion: str, V) -> np.ndarray:
        """eps at impact velocities `V` [m/s] of the collision whose coefficient is `coefficient` at
        1 m/s (the physical law fixed): the coefficient times V^`velocity_exponent` at each."""
        V = np.asarray(V, dtype=float)
        return np.array([self.restitution(coefficient * v**self.velocity_exponent, criterion) for v in V])

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        r"""The powers of h = dt/T_e in the error expansion of an engine run of this form.

        Parameters
        ----------
        coefficient : float
            The damping coefficient c [-]; 0 (no damping) gives `ELASTIC_POWERS`.

        Returns
        -------
        tuple of float
            1 (the lagged velocity), then 1 + p + k from the force's s^p where contact starts and
            ends, and 2, in increasing order: five powers (a ladder of n rungs eliminates n - 1).
        """
        if self.power is None or coefficient == 0:
            return ELASTIC_POWERS
        p = self.power
        return tuple(sorted({1.0, 1.0 + p, 2.0, 2.0 + p, 2.5} if p else {1.0, 2.0, 2.5, 3.0}))

    def equation(self, value: str | None = None) -> str:
        """Its head-on collision's equation, in the reference's units: "x'' + K x^(1/2) x' + (5/4)
        x^(3/2) = 0"; `value` in place of the coefficient's letter when given."""
        c = value if value is not None else self.symbol
        if self.power is None:
            return "x'' + (5/4) x^(3/2) = 0"
        if self.power == 0:
            return f"x'' + {c} x' + (5/4) x^(3/2) = 0"
        return f"x'' + {c} x^({_fraction(self.power)}) x' + (5/4) x^(3/2) = 0"

    def solve(self, coefficient: float) -> dict:
        """The reference characteristics of its collision at `coefficient` [-]: a row with x_max,
        tau_0, tau_f, eps_x0 and eps_F0 (the reference's units), from the form's solver."""
        raise NotImplementedError

    def restitution(self, coefficient: float, criterion: str) -> float:
        """The restitution of its collision at `coefficient` [-] under `criterion` ('x0' or 'F0')."""
        return float(self.solve(coefficient)[f"eps_{criterion}"])


def _fraction(p: float) -> str:
    return {0.5: "1/2", 0.25: "1/4", 0.75: "3/4"}.get(p, f"{p:g}")


@register
class HalfPower(DampingForm):
    """Kuwabara-Kono / Brilliantov: K x^{1/2} x', the viscoelastic model (`reference.collision_ode`)."""

    name, power, symbol, label, eps_of_velocity = "half", 0.5, "K", "δ^½ δ'", "falls"
    velocity_exponent = 0.2

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        """1, 3/2, 2, 5/2, 3 (tests/test_ladder.py measures the first three on the map)."""
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 1.5, 2.0, 2.5, 3.0)

    def solve(self, coefficient: float) -> dict:
        from reference import solve_collision

        return solve_collision(coefficient)

    def restitution_at(self, coefficient, criterion, V):
        """As `DampingForm.restitution_at`, the whole batch of K in one solve."""
        from reference import solve_collisions

        return np.asarray(getattr(solve_collisions(coefficient * np.asarray(V, dtype=float) ** 0.2),
                                  f"eps_{criterion}"))


@register
class QuarterPower(DampingForm):
    """Tsuji's b x^{1/4} x', the engines' restitution keywords (`reference.quarter_power_damping`)."""

    name, power, symbol, label, eps_of_velocity = "quarter", 0.25, "b", "δ^¼ δ'", "constant"

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        """1, 5/4, 2, 9/4, 5/2 (measured on every code's keyword, tests/test_engine_keywords.py)."""
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 1.25, 2.0, 2.25, 2.5)

    def solve(self, coefficient: float) -> dict:
        from reference.quarter_power_damping import solve_quarter_power

        return solve_quarter_power(coefficient)

    def restitution(self, coefficient: float, criterion: str) -> float:
        from reference.quarter_power_damping import restitution_quarter_power

        return restitution_quarter_power(coefficient, criterion)


@register
class LinearDashpot(DampingForm):
    """A linear dashpot c x' (LAMMPS ``damping velocity``, ``mass_velocity``; `reference.linear_damping`).
    Its force jumps to c V at touching and from c x' to 0 at the x0 end: steps of a smooth force, so
    whole powers of h plus Hertz's h^{5/2}."""

    name, power, symbol, label, eps_of_velocity = "velocity", 0.0, "c", "δ'", "rises"
    velocity_exponent = -0.2

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 2.0, 2.5, 3.0)

    def solve(self, coefficient: float) -> dict:
        from reference.linear_damping import solve_linear_damping

        return solve_linear_damping(coefficient)

    def restitution(self, coefficient: float, criterion: str) -> float:
        from reference.linear_damping import restitution_linear_damping

        return restitution_linear_damping(coefficient, criterion)


@register
class NoDamping(DampingForm):
    """Hertz alone: T, A and eps = 1 in closed form."""

    name, power, symbol, label, eps_of_velocity = "none", None, "", "none", "none"

    def solve(self, coefficient: float = 0.0) -> dict:
        from reference import solve_collision

        return solve_collision(0.0)


def damping_form(name: str) -> DampingForm:
    """The registered form `name`; ValueError naming the known forms otherwise."""
    try:
        return DAMPING_FORMS[name]
    except KeyError:
        raise ValueError(f"unknown damping form {name!r}; known: {', '.join(DAMPING_FORMS)}") from None


__all__ = ["DAMPING_FORMS", "DampingForm", "ELASTIC_POWERS", "damping_form", "register"]
