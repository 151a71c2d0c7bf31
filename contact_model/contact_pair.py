"""A two-body contact (sphere-sphere or sphere-plane) and the numbers the study derives from it.

Everything is SI. A plane is a `Body` with infinite radius and density; a rigid body has
infinite Young's modulus.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import collision_scales as cs
from .effective import effective_mass, effective_modulus, effective_radius, sphere_mass

GEOMETRIES = ("sphere-sphere", "sphere-plane")


@dataclass(frozen=True)
class Body:
    """A sphere (finite radius) or a plane (radius = density = inf). SI units.

    young/poisson may be None where the case gives the pair's effective modulus directly.
    """

    radius: float
    density: float
    young: float | None = None
    poisson: float | None = None

    @property
    def is_plane(self) -> bool:
        """Whether the body is a plane (infinite radius).

        Returns
        -------
        bool
        """
        return math.isinf(self.radius)

    @property
    def mass(self) -> float:
        """The body's mass: (4/3) pi R^3 rho for a sphere, inf for a plane.

        Returns
        -------
        float
            The mass [kg].
        """
        return math.inf if self.is_plane else sphere_mass(self.radius, self.density)


@dataclass(frozen=True)
class ContactPair:
    """Two bodies in head-on contact with the viscoelastic Hertz law.

    Attributes: geometry ('sphere-sphere' or 'sphere-plane'), body_1 (always a sphere),
    body_2, E (effective modulus E* [Pa]) and eta (effective viscosity [Pa s]).
    """

    geometry: str
    body_1: Body
    body_2: Body
    E: float
    eta: float

    @classmethod
    def from_bodies(cls, body_1: Body, body_2: Body, eta: float) -> "ContactPair":
        """The pair of two bodies, E* from the bodies' Young's moduli and Poisson ratios.

        Parameters
        ----------
        body_1 : Body
            The sphere (SI units).
        body_2 : Body
            A sphere or a plane (SI units).
        eta : float
            The effective viscosity [Pa s].

        Returns
        -------
        ContactPair
            Its geometry 'sphere-plane' when body_2 is a plane, else 'sphere-sphere'.
        """
        E = effective_modulus(body_1.young, body_1.poisson, body_2.young, body_2.poisson)
        geometry = "sphere-plane" if body_2.is_plane else "sphere-sphere"
        return cls(geometry, body_1, body_2, E, eta)

    @property
    def R(self) -> float:
        """Effective radius R*.

        Returns
        -------
        float
            R* [m].
        """
        return effective_radius(self.body_1.radius, self.body_2.radius)

    @property
    def M(self) -> float:
        """Effective mass M*.

        Returns
        -------
        float
            M* [kg].
        """
        return effective_mass(self.body_1.mass, self.body_2.mass)

    @property
    def viscous_velocity(self) -> float:
        """V_D = M*^2 E*^3 / (R* eta^5).

        Returns
        -------
        float
            V_D [m/s] (inf for eta = 0).
        """
        return cs.viscous_velocity(self.E, self.R, self.M, self.eta)

    def dissipation_parameter(self, V: float) -> float:
        """K at impact velocity V.

        Parameters
        ----------
        V : float
            The impact velocity [m/s].

        Returns
        -------
        float
            The dissipation parameter K [-].

        References
        ----------
        He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
        the Hertz scales and K, eqs. 1 and 3.
        """
        return cs.dissipation_parameter(self.E, self.R, self.M, self.eta, V)

    def velocity_for_dissipation(self, K: float) -> float:
        """Impact velocity that gives K.

        Parameters
        ----------
        K : float
            The dissipation parameter, K > 0 [-].

        Returns
        -------
        float
            The impact velocity V [m/s].
        """
        return cs.velocity_for_dissipation(self.E, self.R, self.M, self.eta, K)

    def scales(self, V: float) -> dict[str, float]:
        """Hertz scales and K at impact velocity V, SI.

        Parameters
        ----------
        V : float
            The impact velocity [m/s].

        Returns
        -------
        dict of str to float
            V [m/s], delta_e [m], A_e [m^2], T_e [s], F_e [N], K [-], V_D [m/s].
        """
        E, R, M = self.E, self.R, self.M
        return {
            "V": V,
            "delta_e": cs.hertz_overlap(E, R, M, V),
            "A_e": cs.hertz_area(E, R, M, V),
            "T_e": cs.hertz_time(E, R, M, V),
            "F_e": cs.hertz_force(E, R, M, V),
            "K": self.dissipation_parameter(V),
            "V_D": self.viscous_velocity,
        }

    def rayleigh_time(self) -> float:
        """The Rayleigh time of the sphere (body 1), `collision_scales.rayleigh_time`.

        Of the material the engines run: the body's Young's modulus and Poisson's ratio where the case
        gives them, otherwise Y = 2 E* and nu = 0, what every engine is given (an E* alone fixes no nu;
        with nu = 0, G = E*).

        Returns
        -------
        float
            T_R [s].
        """
        b = self.body_1
        young, poisson = (b.young, b.poisson) if b.young is not None else (2.0 * self.E, 0.0)
        return cs.rayleigh_time(b.radius, b.density, young, poisson)

    def critical_velocity(self, beta: float, criterion: str = "x0") -> float:
        """V_c(beta): the impact velocity below which phi_1 and phi_2 stay under beta.

        With the critical K from the reference solver (`reference.critical.critical_dissipation`).

        Parameters
        ----------
        beta : float
            The tolerated relative deviation of Q1 or Q2 from Hertz's, in (0, 1) [-].
        criterion : str
            The end-of-collision criterion: 'x0' (the overlap returns to zero) or 'F0' (the contact
            force first returns to zero) [-].

        Returns
        -------
        float
            V_c [m/s].

        References
        ----------
        He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
        V_c(beta), its Table 1.
        """
        from reference.critical import critical_dissipation

        return self.velocity_for_dissipation(critical_dissipation(beta, criterion))
