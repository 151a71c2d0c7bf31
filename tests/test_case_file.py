"""Case files: units through pint, and a clear error naming the file and field for bad input."""

import math
import textwrap

import pytest

from contact_model import CaseError, load_case

GOOD = """
name: demo
effective_modulus: 109 GPa
radius: 0.635 cm
viscosity: 6.7e5 P
density: 7.8 g/cm^3
geometries: [sphere-sphere, sphere-plane]
impact:
  velocity: [100 cm/s, 2 m/s]
"""

BODIES = """
name: unequal
viscosity: 1e4 Pa*s
bodies:
  - {radius: 5 mm, density: 7800 kg/m^3, young: 200 GPa, poisson: 0.3}
  - {radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}
impact:
  K: [0.1, 0.3]
"""


def write(tmp_path, text, name="case.yaml"):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text))
    return p


def test_paper_units_convert_to_SI(tmp_path):
    case = load_case(write(tmp_path, GOOD))
    ss, sp = case.pair("sphere-sphere"), case.pair("sphere-plane")
    assert ss.E == pytest.approx(109e9, rel=1e-15)
    assert ss.eta == pytest.approx(6.7e4, rel=1e-15)   # 1 P = 0.1 Pa s
    assert ss.body_1.radius == pytest.approx(0.00635, rel=1e-15)
    assert ss.body_1.density == pytest.approx(7800, rel=1e-15)
    assert ss.R == pytest.approx(0.003175, rel=1e-15) and sp.R == pytest.approx(0.00635, rel=1e-15)
    assert sp.M == pytest.approx(2 * ss.M, rel=1e-15)
    assert case.impact_velocities(ss) == pytest.approx([1.0, 2.0], rel=1e-15)


def test_explicit_bodies_and_target_K(tmp_path):
    case = load_case(write(tmp_path, BODIES))
    (pair,) = case.pairs
    assert pair.geometry == "sphere-sphere"
    assert pair.R == pytest.approx(0.005 * 0.01 / 0.015, rel=1e-15)
    vs = case.impact_velocities(pair)
    assert [pair.dissipation_parameter(v) for v in vs] == pytest.approx([0.1, 0.3], rel=1e-13)


def test_rigid_plane(tmp_path):
    text = BODIES.replace("{radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}", "{plane: rigid}")
    (pair,) = load_case(write(tmp_path, text)).pairs
    assert pair.geometry == "sphere-plane"
    assert pair.E == pytest.approx(200e9 / 0.91, rel=1e-15)
    assert pair.R == 0.005 and pair.M == pytest.approx(4 / 3 * math.pi * 0.005**3 * 7800, rel=1e-15)


@pytest.mark.parametrize("old, new, field, words", [
    ("viscosity: 6.7e5 P\n", "", "viscosity", "missing"),
    ("radius: 0.635 cm", "radius: 0.635 GPa", "radius", "expected a [length]"),
    ("radius: 0.635 cm", "radius: 0.635", "radius", "has no unit"),
    ("radius: 0.635 cm", "radius: 0.635 furlongz", "radius", "cannot read"),
    ("effective_modulus: 109 GPa", "effective_modulus: -109 GPa", "effective_modulus", "positive"),
    ("density: 7.8 g/cm^3", "density: 0 g/cm^3", "density", "positive"),
    ("viscosity: 6.7e5 P", "viscosity: -1 P", "viscosity", "non-negative"),
    ("[100 cm/s, 2 m/s]", "[100 cm/s, -1 m/s]", "impact.velocity[1]", "positive"),
    ("[100 cm/s, 2 m/s]", "[100 cm/s, 1 m]", "impact.velocity[1]", "expected a [length] / [time]"),
    ("geometries: [sphere-sphere, sphere-plane]", "geometries: [sphere-cube]", "geometries", "drawn from"),
])
def test_bad_material_case(tmp_path, old, new, field, words):
    path = write(tmp_path, GOOD.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert err.value.field == field
    assert str(path) in str(err.value) and words in str(err.value)


@pytest.mark.parametrize("old, new, field, words", [
    ("poisson: 0.3}", "poisson: 0.5}", "bodies[0].poisson", "(-1, 0.5)"),
    ("poisson: 0.33}", "poisson: -1.2}", "bodies[1].poisson", "(-1, 0.5)"),
    ("young: 200 GPa", "young: -200 GPa", "bodies[0].young", "positive"),
    ("young: 70 GPa, ", "", "bodies[1].young", "missing"),
    ("K: [0.1, 0.3]", "K: [0.1, 12]", "impact.K[1]", "(0, 10]"),
    ("K: [0.1, 0.3]", "K: [0.1, 0.3]\n  velocity: [1 m/s]", "impact", "exactly one"),
])
def test_bad_bodies_case(tmp_path, old, new, field, words):
    path = write(tmp_path, BODIES.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert err.value.field == field and words in str(err.value) and str(path) in str(err.value)


def test_unreadable_and_malformed_files(tmp_path):
    with pytest.raises(CaseError, match="cannot read"):
        load_case(tmp_path / "absent.yaml")
    with pytest.raises(CaseError, match="not valid YAML"):
        load_case(write(tmp_path, "a: [1, 2"))
    with pytest.raises(CaseError, match="mapping"):
        load_case(write(tmp_path, "- 1\n- 2\n"))


TABLE_1 = {  # the paper's Table 1: E* [GPa], R [cm], eta [1e5 poise]
    "steel": (109, 0.635, 6.7), "brass": (62, 0.75, 15.4), "cork": (0.025, 0.83, 0.25),
    "ice": (5.5, 2.6, 9.62), "jaques_ball": (0.13, 4.6, 1.47),
}


def test_shipped_cases_are_table_1():
    from pathlib import Path
    folder = Path(__file__).resolve().parents[1] / "cases"
    for name, (E, R, eta) in TABLE_1.items():
        case = load_case(folder / f"{name}.yaml")
        assert [p.geometry for p in case.pairs] == ["sphere-sphere", "sphere-plane"]
        for p in case.pairs:
            assert p.E == pytest.approx(E * 1e9, rel=1e-15)
            assert p.body_1.radius == pytest.approx(R * 1e-2, rel=1e-15)
            assert p.eta == pytest.approx(eta * 1e5 * 0.1, rel=1e-15)  # 1 P = 0.1 Pa s
        assert case.extra.get("density_source"), name
        assert not case.K and not case.velocities  # the study's K grid applies


def test_case_without_impact_uses_the_study_grid(tmp_path):
    case = load_case(write(tmp_path, GOOD.split("impact:")[0]))
    pair = case.pair("sphere-plane")
    vs = case.impact_velocities(pair, K_grid=(0.1, 0.2))
    assert [pair.dissipation_parameter(v) for v in vs] == pytest.approx([0.1, 0.2], rel=1e-13)
