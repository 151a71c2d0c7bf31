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
    """Class decorator: put one instance of the form `cls` into `DAMPING_FORMS` under its name.

    Parameters
    ----------
    cls : type
        A subclass of `DampingForm` with its `name`.

    Returns
    -------
    type
        `cls` itself.

    Raises
    ------
    ValueError
        When a form of that name is registered already.
    """
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
        """Whether its coefficient is the viscoelastic model's K (form ``half``).

        The paper's series, the ladder refined by sqrt(K) above K = 1 and the reference's K range apply
        to it.

        Returns
        -------
        bool
        """
        return self.power == 0.5

    def restitution_at(self, coefficient: float, criterion: str, V) -> np.ndarray:
        """eps at impact velocities `V` of the collision whose coefficient is `coefficient` at 1 m/s.

        The physical law fixed: the coefficient times V^`velocity_exponent` at each.

        Parameters
        ----------
        coefficient : float
            The damping coefficient at V = 1 m/s, in the reference's units (K, b or c) [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].
        V : float or array_like
            The impact velocities [m/s].

        Returns
        -------
        numpy.ndarray
            The restitution coefficient at each V [-].
        """
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
        """Its head-on collision's equation, in the reference's units.

        E.g. "x'' + K x^(1/2) x' + (5/4) x^(3/2) = 0".

        Parameters
        ----------
        value : str or None
            Written in place of the coefficient's letter when given [-].

        Returns
        -------
        str
            The equation.
        """
        c = value if value is not None else self.symbol
        if self.power is None:
            return "x'' + (5/4) x^(3/2) = 0"
        if self.power == 0:
            return f"x'' + {c} x' + (5/4) x^(3/2) = 0"
        return f"x'' + {c} x^({_fraction(self.power)}) x' + (5/4) x^(3/2) = 0"

    def solve(self, coefficient: float) -> dict:
        """The reference characteristics of its collision at `coefficient`.

        Parameters
        ----------
        coefficient : float
            The damping coefficient c of c x^p x' in the reference's units (K, b or c) [-].

        Returns
        -------
        dict
            A row with x_max [delta_e], tau_0 and tau_f [delta_e/V], eps_x0 and eps_F0 [-] (the
            reference's units), from the form's solver.
        """
        raise NotImplementedError

    def restitution(self, coefficient: float, criterion: str) -> float:
        """The restitution of its collision at `coefficient` under `criterion`.

        Parameters
        ----------
        coefficient : float
            The damping coefficient c of c x^p x' in the reference's units (K, b or c) [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].

        Returns
        -------
        float
            The restitution coefficient [-].
        """
        return float(self.solve(coefficient)[f"eps_{criterion}"])


def _fraction(p: float) -> str:
    return {0.5: "1/2", 0.25: "1/4", 0.75: "3/4"}.get(p, f"{p:g}")


@register
class HalfPower(DampingForm):
    """Kuwabara-Kono / Brilliantov: K x^{1/2} x', the viscoelastic model (`reference.collision_ode`)."""

    name, power, symbol, label, eps_of_velocity = "half", 0.5, "K", "δ^½ δ'", "falls"
    velocity_exponent = 0.2

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        """1, 3/2, 2, 5/2, 3 (tests/test_ladder.py measures the first three on the map).

        Parameters
        ----------
        coefficient : float
            The damping coefficient [-]; 0 (no damping) gives `ELASTIC_POWERS`.

        Returns
        -------
        tuple of float
            The powers of h = dt/T_e [-], in increasing order.
        """
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 1.5, 2.0, 2.5, 3.0)

    def solve(self, coefficient: float) -> dict:
        """The viscoelastic collision at K, by `reference.solve_collision`.

        Parameters
        ----------
        coefficient : float
            The dissipation parameter K, in [0, 10] [-].

        Returns
        -------
        dict
            A row with x_max [delta_e], tau_0 and tau_f [delta_e/V], eps_x0 and eps_F0 [-] (the
            reference's units), from the form's solver.

        References
        ----------
        Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
        granular gases. Phys. Rev. E 53, 5382.
        Kuwabara, G. & Kono, K. (1987), the dissipative force (cited as [Kuwabara87] by He & Wettlaufer).
        """
        from reference import solve_collision

        return solve_collision(coefficient)

    def restitution_at(self, coefficient, criterion, V):
        """As `DampingForm.restitution_at`, the whole batch of K in one solve.

        Parameters
        ----------
        coefficient : float
            The dissipation parameter K at V = 1 m/s [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].
        V : float or array_like
            The impact velocities [m/s].

        Returns
        -------
        numpy.ndarray
            The restitution coefficient at each V [-].

        References
        ----------
        He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
        the Hertz scales and K, eqs. 1 and 3.
        """
        from reference import solve_collisions

        return np.asarray(getattr(solve_collisions(coefficient * np.asarray(V, dtype=float) ** 0.2),
                                  f"eps_{criterion}"))


@register
class QuarterPower(DampingForm):
    """Tsuji's b x^{1/4} x', the engines' restitution keywords (`reference.quarter_power_damping`)."""

    name, power, symbol, label, eps_of_velocity = "quarter", 0.25, "b", "δ^¼ δ'", "constant"

    def ladder_powers(self, coefficient: float = 1.0) -> tuple[float, ...]:
        """1, 5/4, 2, 9/4, 5/2 (measured on every code's keyword, tests/test_engine_keywords.py).

        Parameters
        ----------
        coefficient : float
            The damping coefficient [-]; 0 (no damping) gives `ELASTIC_POWERS`.

        Returns
        -------
        tuple of float
            The powers of h = dt/T_e [-], in increasing order.
        """
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 1.25, 2.0, 2.25, 2.5)

    def solve(self, coefficient: float) -> dict:
        """The Tsuji-type collision at b, by `reference.quarter_power_damping.solve_quarter_power`.

        Parameters
        ----------
        coefficient : float
            The damping coefficient b of b x^{1/4} x', >= 0 [-].

        Returns
        -------
        dict
            A row with x_max [delta_e], tau_0 and tau_f [delta_e/V], eps_x0 and eps_F0 [-] (the
            reference's units), from the form's solver.

        References
        ----------
        Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
        cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
        """
        from reference.quarter_power_damping import solve_quarter_power

        return solve_quarter_power(coefficient)

    def restitution(self, coefficient: float, criterion: str) -> float:
        """The restitution at b in closed form (`reference.quarter_power_damping`).

        Parameters
        ----------
        coefficient : float
            The damping coefficient b of b x^{1/4} x', >= 0 [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].

        Returns
        -------
        float
            The restitution coefficient [-].

        References
        ----------
        Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
        cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
        """
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
        """1, 2, 5/2, 3: whole powers of h plus Hertz's h^{5/2}.

        Parameters
        ----------
        coefficient : float
            The damping coefficient [-]; 0 (no damping) gives `ELASTIC_POWERS`.

        Returns
        -------
        tuple of float
            The powers of h = dt/T_e [-], in increasing order.
        """
        return ELASTIC_POWERS if coefficient == 0 else (1.0, 2.0, 2.5, 3.0)

    def solve(self, coefficient: float) -> dict:
        """The linear-dashpot collision at c, by `reference.linear_damping.solve_linear_damping`.

        Parameters
        ----------
        coefficient : float
            The dashpot coefficient c, >= 0 [-].

        Returns
        -------
        dict
            A row with x_max [delta_e], tau_0 and tau_f [delta_e/V], eps_x0 and eps_F0 [-] (the
            reference's units), from the form's solver.
        """
        from reference.linear_damping import solve_linear_damping

        return solve_linear_damping(coefficient)

    def restitution(self, coefficient: float, criterion: str) -> float:
        """The restitution at c (`reference.linear_damping`).

        Parameters
        ----------
        coefficient : float
            The dashpot coefficient c, >= 0 [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].

        Returns
        -------
        float
            The restitution coefficient [-].
        """
        from reference.linear_damping import restitution_linear_damping

        return restitution_linear_damping(coefficient, criterion)


@register
class NoDamping(DampingForm):
    """Hertz alone: T, A and eps = 1 in closed form."""

    name, power, symbol, label, eps_of_velocity = "none", None, "", "none", "none"

    def solve(self, coefficient: float = 0.0) -> dict:
        """Hertz's collision (K = 0), whatever the coefficient.

        Parameters
        ----------
        coefficient : float
            Ignored: there is no damping [-].

        Returns
        -------
        dict
            A row with x_max [delta_e], tau_0 and tau_f [delta_e/V], eps_x0 and eps_F0 [-] (the
            reference's units), from the form's solver.
        """
        from reference import solve_collision

        return solve_collision(0.0)


def damping_form(name: str) -> DampingForm:
    """The registered form `name`.

    Parameters
    ----------
    name : str
        The form's registry name ('half', 'quarter', 'velocity', 'none').

    Returns
    -------
    DampingForm
        The registered instance.

    Raises
    ------
    ValueError
        Naming the known forms, for an unknown name.
    """
    try:
        return DAMPING_FORMS[name]
    except KeyError:
        raise ValueError(f"unknown damping form {name!r}; known: {', '.join(DAMPING_FORMS)}") from None


__all__ = ["DAMPING_FORMS", "DampingForm", "ELASTIC_POWERS", "damping_form", "register"]
