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
"""

from __future__ import annotations

import math


def liggghts_hertz_stiffness(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'kn': (4/3) E* [Pa], 'gamman': 2 eta / M* [1/(m s)]} for ``model hertz/stiffness``."""
    return {"kn": 4.0 / 3.0 * E, "gamman": 2.0 * eta / M}


def yade_viscoelastic_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'young': 2 E*, 'poisson': 0, 'c': 2 eta sqrt(R*) [Pa s m^{1/2}]} for the YADE driver."""
    return {"young": 2.0 * E, "poisson": 0.0, "c": 2.0 * eta * math.sqrt(R)}


def lammps_granular_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'kn': (4/3) E* [Pa], 'eta_n0': 2 eta / M* [1/(m s)]} for ``hertz`` + ``damping viscoelastic``."""
    return {"kn": 4.0 / 3.0 * E, "eta_n0": 2.0 * eta / M}


def kratos_hertz(E: float, R: float, M: float, eta: float) -> dict[str, float]:
    """{'young': 2 E* [Pa], 'poisson': 0} for every body (spheres and the wall) of a Kratos run.

    Kratos's effective modulus Y* = Y1 Y2 / (Y2 (1 - nu1^2) + Y1 (1 - nu2^2)) is then
    (2E*)^2 / (2 * 2E*) = E*, so that F_el = (2/3) (2 Y* sqrt(R* delta)) delta
    = (4/3) E* sqrt(R*) delta^{3/2} [N]. eta is not used: Kratos has no viscoelastic damping.
    """
    return {"young": 2.0 * E, "poisson": 0.0}


ENGINE_PARAMETERS = {
    "liggghts": liggghts_hertz_stiffness,
    "yade": yade_viscoelastic_hertz,
    "lammps": lammps_granular_hertz,
    "kratos": kratos_hertz,
}
