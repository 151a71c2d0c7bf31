"""Hertz scales and the dissipation parameter K of a viscoelastic contact (SI units).

With effective modulus E* [Pa], radius R* [m], mass M* [kg], viscosity eta [Pa s] and impact
velocity V [m/s] (the paper's eqs. 1 and 3):

    delta_e = (15 M* V^2 / (16 E* sqrt(R*)))^{2/5}     maximum Hertz overlap       [m]
    A_e     = pi R* delta_e                             maximum Hertz contact area  [m^2]
    T_e     = tau_e delta_e / V                         Hertz collision time        [s]
    F_e     = (5/4) M* V^2 / delta_e                    maximum Hertz force         [N]
    K       = 2 eta sqrt(R*) delta_e^{3/2} / (M* V) = alpha (eta^5 V R* / (M*^2 E*^3))^{1/5}
    V_D     = M*^2 E*^3 / (R* eta^5)                    viscous velocity            [m/s]

so that K = alpha (V / V_D)^{1/5} and the velocity giving a target K is V = V_D (K/alpha)^5.

DEM codes choose their time step as a fraction of the Rayleigh time of a particle (`rayleigh_time`),
a property of the material and the radius alone (not of the impact).
"""

from __future__ import annotations

import math

from reference.closed_forms import HERTZ_TAU, K_PREFACTOR


def hertz_overlap(E: float, R: float, M: float, V: float) -> float:
    """delta_e = (15 M V^2 / (16 E sqrt(R)))^{2/5}, the maximum Hertz overlap.

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    V : float
        The impact velocity [m/s].

    Returns
    -------
    float
        delta_e [m].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return (15.0 * M * V**2 / (16.0 * E * math.sqrt(R))) ** 0.4


def hertz_area(E: float, R: float, M: float, V: float) -> float:
    """A_e = pi R delta_e = pi (15 M V^2 R^2 / (16 E))^{2/5}, the maximum Hertz contact area.

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    V : float
        The impact velocity [m/s].

    Returns
    -------
    float
        A_e [m^2].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return math.pi * R * hertz_overlap(E, R, M, V)


def hertz_time(E: float, R: float, M: float, V: float) -> float:
    """T_e = tau_e delta_e / V = 2.8683 (M^2 / (R V E^2))^{1/5}, the Hertz collision time.

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    V : float
        The impact velocity [m/s].

    Returns
    -------
    float
        T_e [s].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return float(HERTZ_TAU) * hertz_overlap(E, R, M, V) / V


def hertz_force(E: float, R: float, M: float, V: float) -> float:
    """F_e = (4/3) E sqrt(R) delta_e^{3/2} = (5/4) M V^2 / delta_e, the maximum Hertz force.

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    V : float
        The impact velocity [m/s].

    Returns
    -------
    float
        F_e [N].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return 1.25 * M * V**2 / hertz_overlap(E, R, M, V)


def viscous_velocity(E: float, R: float, M: float, eta: float) -> float:
    """V_D = M^2 E^3 / (R eta^5); infinite for an elastic contact (eta = 0).

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    eta : float
        The effective viscosity [Pa s].

    Returns
    -------
    float
        V_D [m/s].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return M**2 * E**3 / (R * eta**5) if eta > 0 else math.inf


def dissipation_parameter(E: float, R: float, M: float, eta: float, V: float) -> float:
    """K = 2 eta sqrt(R) delta_e^{3/2} / (M V).

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    eta : float
        The effective viscosity [Pa s].
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
    return 2.0 * eta * math.sqrt(R) * hertz_overlap(E, R, M, V) ** 1.5 / (M * V)


def velocity_for_dissipation(E: float, R: float, M: float, eta: float, K: float) -> float:
    """The impact velocity that gives K: V = V_D (K / alpha)^5.

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    eta : float
        The effective viscosity [Pa s].
    K : float
        The dissipation parameter, K > 0 [-].

    Returns
    -------
    float
        The impact velocity V [m/s].

    Raises
    ------
    ValueError
        For K <= 0.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    if not K > 0:
        raise ValueError(f"K must be positive to define an impact velocity, got {K}")
    return viscous_velocity(E, R, M, eta) * (K / K_PREFACTOR) ** 5


def viscosity_for_dissipation(E: float, R: float, M: float, V: float, K: float) -> float:
    """The viscosity that gives K at velocity V: eta = K M V / (2 sqrt(R) delta_e^{3/2}).

    Parameters
    ----------
    E : float
        The effective modulus E* [Pa].
    R : float
        The effective radius R* [m].
    M : float
        The effective mass M* [kg].
    V : float
        The impact velocity [m/s].
    K : float
        The dissipation parameter [-].

    Returns
    -------
    float
        The effective viscosity eta [Pa s].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return K * M * V / (2.0 * math.sqrt(R) * hertz_overlap(E, R, M, V) ** 1.5)


def rayleigh_time(R: float, density: float, young: float, poisson: float) -> float:
    """T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766), G = Y / (2 (1 + nu)).

    The time a Rayleigh surface wave takes to cross half the surface of a sphere (the form LIGGGHTS
    and EDEM use). Production DEM runs take dt = 10 % to 40 % of it.

    Parameters
    ----------
    R : float
        The sphere's radius, > 0 [m].
    density : float
        The sphere's density rho, > 0 [kg/m^3].
    young : float
        Young's modulus Y, > 0 [Pa].
    poisson : float
        Poisson's ratio nu, in (-1, 0.5) [-].

    Returns
    -------
    float
        T_R [s].

    Raises
    ------
    ValueError
        For a parameter outside its range.

    References
    ----------
    Li, Xu & Thornton (2005), the Rayleigh time as DEM codes use it (as cited by the code).
    """
    if not (R > 0 and density > 0 and young > 0 and -1 < poisson < 0.5):
        raise ValueError("rayleigh_time needs R, density, Y > 0 and -1 < nu < 0.5, "
                         f"got {R}, {density}, {young}, {poisson}")
    shear = young / (2.0 * (1.0 + poisson))
    return math.pi * R * math.sqrt(density / shear) / (0.1631 * poisson + 0.8766)
