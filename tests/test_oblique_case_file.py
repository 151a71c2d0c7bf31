"""Oblique impacts in a case file (issue 'Oblique impacts'): friction, angle, tangential_velocity,
spin, read into SI and every bad input refused naming the file and the field."""

import math
import textwrap

import pytest

from contact_model import CaseError, load_case

pytestmark = pytest.mark.unit

OBLIQUE = """
name: chung_ooi_like
viscosity: 0 P
bodies:
  - {radius: 2.5 mm, density: 4000 kg/m^3, young: 380 GPa, poisson: 0.23}
  - {plane: true, young: 380 GPa, poisson: 0.23}
friction: 0.092
impact:
  velocity: [3.9 m/s]
  angle: [5 deg, 45 deg, 0.5 rad]
"""


def write(tmp_path, text):
    p = tmp_path / "case.yaml"
    p.write_text(textwrap.dedent(text))
    return p


def test_angles_split_the_resultant_into_normal_and_tangential(tmp_path):
    case = load_case(write(tmp_path, OBLIQUE))
    assert case.friction == 0.092 and case.is_oblique
    assert case.angles == pytest.approx((5.0, 45.0, math.degrees(0.5)), rel=1e-15)
    impacts = case.oblique_impacts()
    assert len(impacts) == 3
    for imp, angle in zip(impacts, case.angles):
        # The resultant is the case's velocity; the angle is measured from the normal.
        assert math.hypot(imp["normal_velocity"], imp["tangential_velocity"]) == pytest.approx(3.9, rel=1e-15)
        assert imp["angle"] == pytest.approx(angle, rel=1e-14)
        assert imp["spin"] == 0.0


def test_tangential_velocity_keeps_the_normal_component_and_spins_multiply(tmp_path):
    text = OBLIQUE.replace("angle: [5 deg, 45 deg, 0.5 rad]",
                           "tangential_velocity: [0.5 m/s, 100 cm/s]\n  spin: [0 rad/s, 60 rpm]")
    case = load_case(write(tmp_path, text))
    impacts = case.oblique_impacts()
    assert [(i["normal_velocity"], i["tangential_velocity"]) for i in impacts] == [
        (3.9, 0.5), (3.9, 0.5), (3.9, 1.0), (3.9, 1.0)]
    assert [i["spin"] for i in impacts] == pytest.approx([0.0, 2 * math.pi, 0.0, 2 * math.pi], rel=1e-15)


def test_a_head_on_case_is_not_oblique(tmp_path):
    case = load_case(write(tmp_path, OBLIQUE.replace("friction: 0.092\n", "").replace(
        "  angle: [5 deg, 45 deg, 0.5 rad]\n", "")))
    assert case.friction is None and not case.is_oblique


@pytest.mark.parametrize("edit, field, words", [
    (("friction: 0.092", "friction: -0.1"), "friction", ">= 0"),
    (("friction: 0.092", "friction: 0.1 deg"), "friction", "plain number"),
    (("5 deg, 45 deg", "5 deg, 90 deg"), "impact.angle[1]", "[0, 90)"),
    (("5 deg, 45 deg", "-5 deg, 45 deg"), "impact.angle[0]", "[0, 90)"),
    (("5 deg, 45 deg", "5 deg, 45 grad"), "impact.angle[1]", "deg"),
    (("5 deg, 45 deg", "5, 45 deg"), "impact.angle[0]", "unit"),
    (("5 deg, 45 deg", "5 deg, 5 deg"), "impact.angle[1]", "second time"),
    (("friction: 0.092", "friction: 0\n# no friction"), "impact.spin", "no friction"),
    (("friction: 0.092\n", ""), "impact.angle", "needs `friction:`"),
    (("  angle: [5 deg, 45 deg, 0.5 rad]", "  angle: [5 deg]\n  tangential_velocity: [1 m/s]"),
     "impact.tangential_velocity", "not both"),
    (("  angle: [5 deg, 45 deg, 0.5 rad]", "  tangential_velocity: [1 kg]"), "impact.tangential_velocity[0]",
     "velocity"),
    (("  velocity: [3.9 m/s]", "  K: [0.1]"), "impact", "needs 'velocity'"),
    (("  angle: [5 deg, 45 deg, 0.5 rad]", ""), "friction", "is for oblique impacts"),
])
def test_bad_oblique_input_is_refused_naming_the_field(tmp_path, edit, field, words):
    text = OBLIQUE + "  spin: [10 rad/s]\n" if "no friction" in words else OBLIQUE
    text = text.replace(*edit)
    with pytest.raises(CaseError) as err:
        load_case(write(tmp_path, text))
    message = str(err.value)
    assert str(tmp_path / "case.yaml") in message and field in message and words in message, message


def test_friction_needs_the_bodies_shear_moduli(tmp_path):
    text = """
    name: no_bodies
    effective_modulus: 109 GPa
    radius: 0.635 cm
    density: 7800 kg/m^3
    viscosity: 0 P
    friction: 0.3
    impact: {velocity: [1 m/s], angle: [30 deg]}
    """
    with pytest.raises(CaseError, match=r"friction.*bodies.*shear modulus"):
        load_case(write(tmp_path, text))
