"""contact_model: effective quantities, Hertz scales, K and velocities, engine parameters."""

import math

import pytest

from contact_model import Body, ContactPair, effective_mass, effective_modulus, effective_radius
from contact_model import collision_scales as cs
from contact_model.engine_parameters import esys_plane_as_sphere
from engines.codes import CODES, code
from reference import HERTZ_TAU, K_PREFACTOR

STEEL = dict(E=109e9, R=0.635e-2 / 2, M=4 / 3 * math.pi * 0.635e-2**3 * 7800 / 2, eta=67e3)


def test_effective_quantities_for_unequal_spheres_of_two_materials():
    E = effective_modulus(200e9, 0.3, 70e9, 0.33)
    assert E == pytest.approx(1 / ((1 - 0.09) / 200e9 + (1 - 0.1089) / 70e9), rel=1e-15)
    assert effective_radius(0.01, 0.03) == pytest.approx(0.0075, rel=1e-15)
    assert effective_mass(2.0, 6.0) == pytest.approx(1.5, rel=1e-15)


def test_plane_and_rigid_plane_limits():
    assert effective_radius(0.01, math.inf) == 0.01
    assert effective_mass(0.3, math.inf) == 0.3
    assert effective_modulus(200e9, 0.3, math.inf, 0.0) == pytest.approx(200e9 / 0.91, rel=1e-15)


def test_two_equal_spheres_of_one_material():
    pair = ContactPair.from_bodies(Body(0.01, 7800, 210e9, 0.3), Body(0.01, 7800, 210e9, 0.3), 1e4)
    assert pair.geometry == "sphere-sphere"
    assert pair.E == pytest.approx(210e9 / (2 * 0.91), rel=1e-15)
    assert pair.R == pytest.approx(0.005, rel=1e-15)
    assert pair.M == pytest.approx(4 / 3 * math.pi * 1e-6 * 7800 / 2, rel=1e-15)


def test_hertz_scales_match_the_papers_closed_forms():
    E, R, M, V = STEEL["E"], STEEL["R"], STEEL["M"], 1.3
    T_e = cs.hertz_time(E, R, M, V)
    A_e = cs.hertz_area(E, R, M, V)
    assert T_e == pytest.approx(2.8683 * (M**2 / (R * V * E**2)) ** 0.2, rel=2e-5)     # eq. 1a
    assert A_e == pytest.approx(math.pi * (15 * M * V**2 * R**2 / (16 * E)) ** 0.4, rel=1e-14)  # eq. 1b
    assert math.sqrt(A_e) * T_e**2 == pytest.approx(14.39 * M / E, rel=5e-4)    # Q1e
    assert A_e / (V * T_e) == pytest.approx(1.0674 * R, rel=5e-5)               # Q2e
    delta_e = cs.hertz_overlap(E, R, M, V)
    # Energy: the elastic energy (8/15) E sqrt(R) delta_e^{5/2} at the maximum is (1/2) M V^2.
    assert 8 / 15 * E * math.sqrt(R) * delta_e**2.5 == pytest.approx(0.5 * M * V**2, rel=1e-14)
    assert cs.hertz_force(E, R, M, V) == pytest.approx(4 / 3 * E * math.sqrt(R) * delta_e**1.5, rel=1e-14)


def test_K_two_ways_and_the_velocity_that_gives_it():
    E, R, M, eta = STEEL["E"], STEEL["R"], STEEL["M"], STEEL["eta"]
    V = 2.5
    K = cs.dissipation_parameter(E, R, M, eta, V)
    assert K == pytest.approx(K_PREFACTOR * (eta**5 * V * R / (M**2 * E**3)) ** 0.2, rel=1e-14)
    assert K == pytest.approx(K_PREFACTOR * (V / cs.viscous_velocity(E, R, M, eta)) ** 0.2, rel=1e-14)
    assert cs.velocity_for_dissipation(E, R, M, eta, K) == pytest.approx(V, rel=1e-13)
    eta_01 = cs.viscosity_for_dissipation(E, R, M, 1.0, 0.1)
    assert cs.dissipation_parameter(E, R, M, eta_01, 1.0) == pytest.approx(0.1, rel=1e-14)
    with pytest.raises(ValueError):
        cs.velocity_for_dissipation(E, R, M, eta, 0.0)


def test_critical_velocity_rule():
    """V_c = V_D (K_c/alpha)^5; with the paper's K_c = 2.5 beta^{1/2} that is 3.7 beta^{5/2} V_D."""
    assert (2.5 / K_PREFACTOR) ** 5 == pytest.approx(3.7, abs=0.05)
    pair = ContactPair("sphere-sphere", Body(STEEL["R"] * 2, 7800), Body(STEEL["R"] * 2, 7800),
                       STEEL["E"], STEEL["eta"])
    from reference.critical import critical_dissipation, largest_deviation
    K_c = critical_dissipation(0.01)
    assert largest_deviation([K_c])[0] == pytest.approx(0.01, rel=1e-9)
    assert largest_deviation([0.99 * K_c])[0] < 0.01
    assert pair.critical_velocity(0.01) == pytest.approx(pair.viscous_velocity * (K_c / K_PREFACTOR) ** 5, rel=1e-12)


def test_engine_parameters_reproduce_the_model_force():
    E, R, eta = STEEL["E"], STEEL["R"], STEEL["eta"]
    pair = ContactPair("sphere-sphere", Body(2 * R, 7800), Body(2 * R, 7800), E, eta)
    delta, rate = 3e-6, 0.7
    model = 4 / 3 * E * math.sqrt(R) * delta**1.5 + 2 * eta * math.sqrt(R) * math.sqrt(delta) * rate
    lig = CODES["liggghts"].contact_parameters(pair)
    a = math.sqrt(pair.R * delta)
    assert lig["kn"] * a * delta + lig["gamman"] * pair.M * a * rate == pytest.approx(model, rel=1e-13)
    yade = CODES["yade"].contact_parameters(pair)
    E_mindlin = 1 / (2 * (1 - yade["poisson"] ** 2) / yade["young"])
    assert 4 / 3 * E_mindlin * math.sqrt(pair.R) * delta**1.5 + yade["c"] * math.sqrt(delta) * rate \
        == pytest.approx(model, rel=1e-13)
    lmp = CODES["lammps"].contact_parameters(pair)
    assert lmp["kn"] * a * delta + lmp["eta_n0"] * a * pair.M * rate == pytest.approx(model, rel=1e-13)
    with pytest.raises(ValueError, match="unknown engine code 'nosuch'; known: liggghts, yade"):
        code("nosuch")


@pytest.mark.parametrize("geometry", ["sphere-sphere", "sphere-plane"])
def test_openfoam_parameters_give_the_hertz_force(geometry):
    """OpenFOAM's pairSpringSliderDashpot / wallSpringSliderDashpot with youngsModulus = 2 E*, poissonsRatio 0
    on the parcels and the wall: the pair's E / (2 (1 - nu^2)) (PairSpringSliderDashpot.C:117) and the wall's
    1 / ((1 - nu_p^2)/E_p + (1 - nu_w^2)/E_w) (WallSpringSliderDashpot.C:196) are E*, and k_N delta^{3/2} with
    k_N = (4/3) sqrt(R*) E* is the model's Hertz force, to round-off (1e-13)."""
    E, R = STEEL["E"], STEEL["R"]
    other = Body(R, 7800) if geometry == "sphere-sphere" else Body(math.inf, math.inf)
    pair = ContactPair(geometry, Body(R, 7800), other, E, STEEL["eta"])
    k = CODES["openfoam"].contact_parameters(pair)
    assert k == {"youngsModulus": 2 * E, "poissonsRatio": 0.0}  # eta has no OpenFOAM parameter
    Y, nu = k["youngsModulus"], k["poissonsRatio"]
    E_star = Y / (2 * (1 - nu**2)) if geometry == "sphere-sphere" else 1 / ((1 - nu**2) / Y + (1 - nu**2) / Y)
    assert E_star == pytest.approx(E, rel=1e-15)
    for delta in (1e-9, 3e-6, 1e-4):
        k_N = 4 / 3 * math.sqrt(pair.R) * E_star
        assert k_N * delta**1.5 == pytest.approx(4 / 3 * E * math.sqrt(pair.R) * delta**1.5, rel=1e-13)


@pytest.mark.parametrize("geometry", ["sphere-sphere", "sphere-plane"])
def test_kratos_parameters_give_the_hertz_force(geometry):
    """Kratos's DEM_D_Hertz_viscous_Coulomb with young = 2 E*, poisson = 0 on both bodies (the wall
    too): Y* = Y1 Y2 / (Y2 (1 - nu1^2) + Y1 (1 - nu2^2)) = E*, kn = 2 Y* sqrt(R* delta) and
    F_el = (2/3) kn delta = (4/3) E* sqrt(R*) delta^{3/2}, to round-off (1e-13)."""
    E, R = STEEL["E"], STEEL["R"]
    other = Body(R, 7800) if geometry == "sphere-sphere" else Body(math.inf, math.inf)
    pair = ContactPair(geometry, Body(R, 7800), other, E, STEEL["eta"])
    k = CODES["kratos"].contact_parameters(pair)
    assert k == {"young": 2 * E, "poisson": 0.0}  # eta has no Kratos parameter
    Y1 = Y2 = k["young"]
    nu1 = nu2 = k["poisson"]
    Y_star = Y1 * Y2 / (Y2 * (1 - nu1**2) + Y1 * (1 - nu2**2))
    assert Y_star == pytest.approx(E, rel=1e-15)
    for delta in (1e-9, 3e-6, 1e-4):
        kn = 2 * Y_star * math.sqrt(pair.R * delta)
        assert 2 / 3 * kn * delta == pytest.approx(4 / 3 * E * math.sqrt(pair.R) * delta**1.5, rel=1e-13)


def test_esys_parameters_reproduce_the_model_force_on_a_sphere_and_on_the_plane():
    """ESyS (Model/HertzianViscoElasticInteraction.cpp): F = 2 E sqrt(R*) / (3 (1 - nu^2))
    (delta^{3/2} + A delta^{1/2} d(delta)/dt), R* = 1 / (1/r1 + 1/r2), written out here."""
    E, R, eta = STEEL["E"], STEEL["R"], STEEL["eta"]
    delta, rate = 3e-6, 0.7

    def esys_force(p, r1, r2):
        R_star = 1.0 / (1.0 / r1 + 1.0 / r2)
        return 2 * p["E"] * math.sqrt(R_star) / (3 * (1 - p["nu"] ** 2)) * (
            delta**1.5 + p["A"] * math.sqrt(delta) * rate)

    def model(R_star):
        return 4 / 3 * E * math.sqrt(R_star) * delta**1.5 + 2 * eta * math.sqrt(R_star) * math.sqrt(delta) * rate

    two = ContactPair("sphere-sphere", Body(2 * R, 7800), Body(2 * R, 7800), E, eta)
    p = CODES["esys"].contact_parameters(two)
    assert esys_force(p, 2 * R, 2 * R) == pytest.approx(model(two.R), rel=1e-14)
    # Its Hertz-Mindlin law (HertzMindlinViscoInteraction.cpp) takes E* itself: F_el = 4/3 E sqrt(R*) delta^{3/2}.
    assert 4 / 3 * p["E_hertz_mindlin"] * math.sqrt(two.R) * delta**1.5 == pytest.approx(
        4 / 3 * E * math.sqrt(two.R) * delta**1.5, rel=1e-15)
    plane = ContactPair("sphere-plane", Body(R, 7800), Body(math.inf, math.inf), E, eta)
    assert plane.R == R
    wall = esys_plane_as_sphere(R)
    assert wall["R_wall"] == R and wall["modulus_factor"] == pytest.approx(math.sqrt(2.0), rel=1e-15)
    q = CODES["esys"].contact_parameters(plane)
    scaled = {**q, "E": q["E"] * wall["modulus_factor"]}
    assert esys_force(scaled, R, wall["R_wall"]) == pytest.approx(model(R), rel=1e-14)
    assert (esys_force(q, R, wall["R_wall"]) / model(R) - 1
            == pytest.approx(math.sqrt(0.5) - 1, rel=1e-12))  # unscaled: R* = R/2
    # Any radius gives the plane's force once scaled (the study takes R: the smallest rounding).
    far = esys_plane_as_sphere(R, 1e3)
    assert (esys_force({**q, "E": q["E"] * far["modulus_factor"]}, R, far["R_wall"])
            == pytest.approx(model(R), rel=1e-14))
    with pytest.raises(ValueError, match="at least 1"):
        esys_plane_as_sphere(R, ratio=0.5)


def test_hertz_time_tau_is_the_reference_constant():
    E, R, M = STEEL["E"], STEEL["R"], STEEL["M"]
    assert cs.hertz_time(E, R, M, 1.0) == pytest.approx(HERTZ_TAU * cs.hertz_overlap(E, R, M, 1.0), rel=1e-15)
