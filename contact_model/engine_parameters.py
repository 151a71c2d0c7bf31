"""Engine parameters of the viscoelastic Hertz contact, all derived from (E*, R*, M*, eta).

The model under test:  F = (4/3) E* sqrt(R*) delta^{3/2} + 2 eta sqrt(R*) delta^{1/2} d(delta)/dt.

Each engine writes the same force in its own parameters (SI units):

LIGGGHTS ``model hertz/stiffness`` (src/normal_model_hertz_stiffness.h)
    F = kn sqrt(R* delta) delta + gamman M* sqrt(R* delta) d(delta)/dt
    -> kn = (4/3) E*  [Pa],  gamman = 2 eta / M*  [1/(m s)]
YADE (Hertz-Mindlin elastic part plus the dissipative force added by the driver)
    F_d = c delta^{1/2} d(delta)/dt
    -> c = 2 eta sqrt(R*)  [Pa s m^{1/2}]; E* enters through young = 2 E*, poisson = 0 on
       both bodies (Mindlin's 1/E* = (1-nu1^2)/Y1 + (1-nu2^2)/Y2).
LAMMPS ``pair_style granular`` normal ``hertz`` with ``damping viscoelastic``
    F_d = eta_n0 a m_eff d(delta)/dt,  a = sqrt(R* delta)
    -> kn = (4/3) E*  [Pa],  eta_n0 = 2 eta / M*  [1/(m s)]
Kratos DEMApplication ``DEM_D_Hertz_viscous_Coulomb`` (DEM_D_Hertz_viscous_Coulomb_CL.cpp)
    F_el = (2/3) kn delta,  kn = 2 Y* sqrt(R* delta),  Y* = Y1 Y2 / (Y2 (1-nu1^2) + Y1 (1-nu2^2))
    (the same for a sphere and a wall, the wall's Y and nu its own properties)
    -> young = 2 E*  [Pa], poisson = 0 on every body (Y* = E*: F_el = (4/3) E* sqrt(R*) delta^{3/2}).
    Its damping 2 gamma sqrt(M* kn) d(delta)/dt goes as delta^{1/4}: eta has no Kratos
    parameter (the viscoelastic law is not available there, engines.codes).
ESyS-Particle ``HertzianViscoElasticPrms(A, E, nu)`` (Model/HertzianViscoElasticInteraction.cpp)
    F = 2 E sqrt(R*) / (3 (1 - nu^2)) (delta^{3/2} + A delta^{1/2} d(delta)/dt), clipped at F >= 0
    -> E = 2 E*  [Pa],  nu = 0,  A = 3 eta / (2 E*)  [s]
    ESyS has no Hertzian wall (its walls are linear springs): the plane is a fixed sphere of
    radius R_wall = R (`esys_plane_as_sphere`), its modulus scaled so that the force is the
    plane's.
"""

from __future__ import annotations

import math


def liggghts_hertz_stiffness(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'kn': (4/3) E* [Pa], 'gamman': 2 eta / M* [1/(m s)]} for ``model hertz/stiffness``.

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
    dict of str to float
        kn [Pa], gamman [1/(m s)].
    """
    return {"kn": 4.0 / 3.0 * E, "gamman": 2.0 * eta / M}


def yade_viscoelastic_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'young': 2 E*, 'poisson': 0, 'c': 2 eta sqrt(R*) [Pa s m^{1/2}]} for the YADE driver.

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
    dict of str to float
        young [Pa], poisson [-], c [Pa s m^{1/2}].
    """
    return {"young": 2.0 * E, "poisson": 0.0, "c": 2.0 * eta * math.sqrt(R)}


def lammps_granular_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'kn': (4/3) E* [Pa], 'eta_n0': 2 eta / M* [1/(m s)]} for ``hertz`` + ``damping viscoelastic``.

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
    dict of str to float
        kn [Pa], eta_n0 [1/(m s)].
    """
    return {"kn": 4.0 / 3.0 * E, "eta_n0": 2.0 * eta / M}


def kratos_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'young': 2 E* [Pa], 'poisson': 0} for every body (spheres and the wall) of a Kratos run.

    Kratos's effective modulus Y* = Y1 Y2 / (Y2 (1 - nu1^2) + Y1 (1 - nu2^2)) is then
    (2E*)^2 / (2 * 2E*) = E*, so that F_el = (2/3) (2 Y* sqrt(R* delta)) delta
    = (4/3) E* sqrt(R*) delta^{3/2} [N]. eta is not used: Kratos has no viscoelastic damping.

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
    dict of str to float
        young [Pa], poisson [-].
    """
    return {"young": 2.0 * E, "poisson": 0.0}


def openfoam_spring_slider_dashpot(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'youngsModulus': 2 E* [Pa], 'poissonsRatio': 0} of every parcel and of the wall in OpenFOAM's
    pairSpringSliderDashpot / wallSpringSliderDashpot.

    OpenFOAM's pair modulus is E / (2 (1 - nu^2)) (PairSpringSliderDashpot.C:117 @v1912) and the
    wall's 1 / ((1 - nu_p^2)/E_p + (1 - nu_w^2)/E_w) (WallSpringSliderDashpot.C:196): with nu = 0 and
    E = 2 E* both are E*, so that F_el = (4/3) E* sqrt(R*) delta^{3/2} [N] (k_N = (4/3) E* sqrt(R*),
    PairSpringSliderDashpot.C:205). eta is not used: OpenFOAM's dashpot is alpha sqrt(M* k_N)
    delta^{1/4} d(delta)/dt, not the viscoelastic delta^{1/2} d(delta)/dt.

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
    dict of str to float
        youngsModulus [Pa], poissonsRatio [-].
    """
    return {"youngsModulus": 2.0 * E, "poissonsRatio": 0.0}


def esys_hertzian_viscoelastic(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'E': 2 E* [Pa], 'nu': 0, 'A': 3 eta / (2 E*) [s]} for ESyS's ``HertzianViscoElasticPrms``,
    and 'E_hertz_mindlin': E* [Pa], the modulus of its ``HertzMindlinViscoPrms`` (the out-of-the-box law).

    ESyS (Model/HertzianViscoElasticInteraction.cpp) computes, with R* = 1 / (1/r1 + 1/r2),

        F = 2 E sqrt(R*) / (3 (1 - nu^2)) (delta^{3/2} + A delta^{1/2} d(delta)/dt)   [N]

    With nu = 0 and E = 2 E* the prefactor is (4/3) E* sqrt(R*), and A (4/3) E* sqrt(R*) = 2 eta
    sqrt(R*) gives A = 3 eta / (2 E*): the model's force exactly (ESyS then clips it at 0).

    ESyS's Hertz-Mindlin law with restitution damping (Model/HertzMindlinViscoInteraction.cpp)
    uses its modulus as the effective one, F_el = (4/3) E sqrt(R*) delta^{3/2}: E = E*.

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
    dict of str to float
        E [Pa], nu [-], A [s], E_hertz_mindlin [Pa].
    """
    return {"E": 2.0 * E, "nu": 0.0, "A": 3.0 * eta / (2.0 * E), "E_hertz_mindlin": E}


#: The radius of the sphere that stands for the plane in ESyS, in radii of the sphere hitting it:
#: the smallest, so that the overlap is a difference of positions no larger than two spheres'
#: (a wall of 1000 R put a rounding noise of u 1000 R / delta_max on every sample of the overlap:
#: 3e-7 for cork at K = 0.1, which made its extrapolated A miss the 1e-6 gate; the force is the
#: plane's at any ratio, see `esys_plane_as_sphere`).
ESYS_WALL_RADIUS_RATIO = 1.0


def esys_plane_as_sphere(R: float, ratio: float = ESYS_WALL_RADIUS_RATIO) -> dict[str, float]:
    """How ESyS represents the plane hit by a sphere of radius R [m]: a non-dynamic sphere of
    radius R_wall = ratio R [m] with the modulus of its contact multiplied by `modulus_factor`.

    ESyS forms R*_esys = R R_wall / (R + R_wall) = R / (1 + 1/ratio); its force is
    proportional to E sqrt(R*_esys), so the factor sqrt(R / R*_esys) = sqrt(1 + 1/ratio) makes
    E sqrt(R*_esys) = E sqrt(R): the force of the sphere on the plane (R* = R), exactly, at
    every overlap and rate of a head-on impact. (The damping of ESyS's own Hertz-Mindlin law
    scales with sqrt(E) R*^{1/4}: the same factor makes it exact too.) Any ratio >= 1 gives the
    plane's force; the study takes 1 (ESYS_WALL_RADIUS_RATIO) because positions are doubles: the
    wall's centre sits at x = R_wall, and the overlap R + R_wall - distance is rounded by about
    u R_wall (u = 2^-53) at every sample.

    Parameters
    ----------
    R : float
        The radius of the sphere hitting the plane [m].
    ratio : float
        R_wall / R, finite and >= 1 [-].

    Returns
    -------
    dict of str to float
        R_wall [m], R_star_esys [m], modulus_factor [-].

    Raises
    ------
    ValueError
        For a ratio below 1 or not finite.
    """
    if not (ratio >= 1 and math.isfinite(ratio)):
        raise ValueError(f"the wall's radius ratio must be a finite number of at least 1, got {ratio}")
    R_wall = ratio * R
    R_star = 1.0 / (1.0 / R + 1.0 / R_wall)
    return {"R_wall": R_wall, "R_star_esys": R_star, "modulus_factor": math.sqrt(R / R_star)}

