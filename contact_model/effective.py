"""Effective quantities of a two-body contact (SI units throughout).

A plane is a body of infinite radius and mass; a rigid body has 1/Y = 0. Both are written
as ``math.inf`` so that the same formulas hold for sphere-sphere and sphere-plane contacts.
"""

from __future__ import annotations

import math


def effective_modulus(young_1: float, poisson_1: float, young_2: float, poisson_2: float) -> float:
    """E* = 1 / [(1 - nu1^2)/Y1 + (1 - nu2^2)/Y2]. A rigid body has Y = inf.

    Parameters
    ----------
    young_1 : float
        Young's modulus Y1 of body 1 [Pa].
    poisson_1 : float
        Poisson's ratio nu1 of body 1 [-].
    young_2 : float
        Young's modulus Y2 of body 2 (inf: rigid) [Pa].
    poisson_2 : float
        Poisson's ratio nu2 of body 2 [-].

    Returns
    -------
    float
        The effective modulus E* [Pa].
    """
    compliance = (1.0 - poisson_1**2) / young_1 + (1.0 - poisson_2**2) / young_2
    return 1.0 / compliance


def effective_shear_modulus(body_1, body_2) -> float:
    """G* = 1 / [(2 - nu1)/G1 + (2 - nu2)/G2], G_i = Y_i / (2 (1 + nu_i)) (Mindlin's tangential
    stiffness is 8 G* a); a rigid body (Y = inf) adds nothing.

    Parameters
    ----------
    body_1, body_2 : contact_pair.Body
        The bodies, each with Young's modulus [Pa] and Poisson's ratio [-].

    Returns
    -------
    float
        The effective shear modulus G* [Pa].

    Raises
    ------
    ValueError
        Where a body lacks its Young's modulus or Poisson's ratio, or both are rigid.
    """
    compliance = 0.0
    for body in (body_1, body_2):
        if body.young is None or body.poisson is None:
            raise ValueError("the tangential stiffness needs both bodies' Young's modulus and Poisson's ratio (G*)")
        if math.isfinite(body.young):
            compliance += 2.0 * (2.0 - body.poisson) * (1.0 + body.poisson) / body.young
    if compliance == 0:
        raise ValueError("two rigid bodies have no finite G*")
    return 1.0 / compliance


def effective_radius(radius_1: float, radius_2: float = math.inf) -> float:
    """R* = R1 R2 / (R1 + R2); R2 = inf (a plane) gives R* = R1.

    Parameters
    ----------
    radius_1 : float
        The radius R1 of body 1 [m].
    radius_2 : float
        The radius R2 of body 2 (inf: a plane) [m].

    Returns
    -------
    float
        The effective radius R* [m].
    """
    return 1.0 / (1.0 / radius_1 + 1.0 / radius_2)


def effective_mass(mass_1: float, mass_2: float = math.inf) -> float:
    """M* = m1 m2 / (m1 + m2); m2 = inf (a plane) gives M* = m1.

    Parameters
    ----------
    mass_1 : float
        The mass m1 of body 1 [kg].
    mass_2 : float
        The mass m2 of body 2 (inf: a plane) [kg].

    Returns
    -------
    float
        The effective mass M* [kg].
    """
    return 1.0 / (1.0 / mass_1 + 1.0 / mass_2)


def sphere_mass(radius: float, density: float) -> float:
    """m = (4/3) pi R^3 rho.

    Parameters
    ----------
    radius : float
        The sphere's radius R [m].
    density : float
        The sphere's density rho [kg/m^3].

    Returns
    -------
    float
        The mass m [kg].
    """
    return 4.0 / 3.0 * math.pi * radius**3 * density
