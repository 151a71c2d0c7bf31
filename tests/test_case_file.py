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
    # a misspelt unit is offered the units of the field's own dimension one edit away, closest first
    ("radius: 0.635 cm", "radius: 5 mn", "radius", "(did you mean 'mm', 'm' or 'nm'?)"),
    ("radius: 0.635 cm", "radius: 5 cn", "radius", "(did you mean 'cm' or 'in'?)"),
    ("effective_modulus: 109 GPa", "effective_modulus: 109 Gpa", "effective_modulus", "(did you mean 'GPa'?)"),
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
    ("K: [0.1, 0.3]", "K: [1 m/s]", "impact.K[0]",
     "must be a number in (0, 10], got '1 m/s'; K is the dimensionless dissipation parameter: for an impact "
     "velocity, use `velocity:`"),
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


# ---------------------------------------------------------------------------- strict reading
@pytest.mark.parametrize("old, new, field", [
    # numbers that used to run as other numbers
    ("viscosity: 6.7e5 P", "viscosity: 6,7e5 P", "viscosity"),          # ran as 6.7e6 P
    ("radius: 0.635 cm", "radius: 12,5 cm", "radius"),                   # ran as 125 cm
    ("viscosity: 6.7e5 P", "viscosity: 0,67 P", "viscosity"),            # ran as 0 (elastic)
    ("density: 7.8 g/cm^3", "density: 7 800 kg/m^3", "density"),         # ran as 5600 kg/m^3
    ("effective_modulus: 109 GPa", "effective_modulus: 109 GPa 2", "effective_modulus"),  # ran as 218 GPa
    ("effective_modulus: 109 GPa", "effective_modulus: 109 GPa!", "effective_modulus"),
    ("effective_modulus: 109 GPa", "effective_modulus: 109 GPa \U0001F600", "effective_modulus"),
    ("radius: 0.635 cm", "radius: cm", "radius"),                         # ran as 1 cm
    ("effective_modulus: 109 GPa", "effective_modulus: 109 GPa pi", "effective_modulus"),
    ("radius: 0.635 cm", "radius: 0.635 cm2", "radius"),
    ("radius: 0.635 cm", "radius: 0.635cm", "radius"),
    ("radius: 0.635 cm", "radius: '\u0661 cm'", "radius"),                # an Arabic-Indic digit
    # bare tracebacks before
    ("effective_modulus: 109 GPa", "effective_modulus: 1 GPa / 0", "effective_modulus"),
    ("effective_modulus: 109 GPa", "effective_modulus: (1 GPa", "effective_modulus"),
    ("effective_modulus: 109 GPa", "effective_modulus: 1 GPa; rm -rf /", "effective_modulus"),
    ("effective_modulus: 109 GPa", "effective_modulus: [1 GPa]", "effective_modulus"),
    ("effective_modulus: 109 GPa", "effective_modulus: 1e400 GPa", "effective_modulus"),
    ("radius: 0.635 cm", "radius: 1e-400 cm", "radius"),
    ("radius: 0.635 cm", "radius: 1e300 km", "radius"),                   # finite number, infinite in m
    # structure
    ("viscosity: 6.7e5 P", "viscosity: 6.7e5 P\nviscosity: 6.7e4 P", "viscosity"),   # the last won
    ("name: demo", "name: null", "name"),
    ("name: demo", "name: ''", "name"),
    ("impact:", "impacts:", "impacts"),
    ("geometries:", "geometry:", "geometry"),
    ("geometries: [sphere-sphere, sphere-plane]", "geometries: [sphere-plane, sphere-plane]", "geometries"),
    ("geometries: [sphere-sphere, sphere-plane]", "geometries: []", "geometries"),
    ("  velocity: [100 cm/s, 2 m/s]", "  velocity: [100 cm/s, 1 m/s]", "impact.velocity[1]"),
    ("  velocity: [100 cm/s, 2 m/s]", "  velocity: []", "impact.velocity"),
    ("  velocity: [100 cm/s, 2 m/s]", "  K: []", "impact.K"),
    ("  velocity: [100 cm/s, 2 m/s]", "  K: [0.1, 0.3, 0.1]", "impact.K"),
    ("  velocity: [100 cm/s, 2 m/s]", "  K: [1e-1]", "impact.K[0]"),      # YAML 1.1: text
    ("  velocity: [100 cm/s, 2 m/s]", "  K: [0.1_0]", "impact.K[0]"),     # YAML 1.1: 0.1
    ("  velocity: [100 cm/s, 2 m/s]", "  K: [1:30]", "impact.K[0]"),      # YAML 1.1: 90
    ("name: demo", "name: demo\nbodies: [{plane: rigid}, {plane: rigid}]", None),
    ("name: demo", "name: demo\nradius_note: &r 1 cm", "radius_note"),
    ("name: demo", "name: !!str demo", "name"),
    ("name: demo", "name: demo\n<<: {radius: 1 cm}", None),
    ("name: demo", "name: demo\nnote: " + "[" * 5000 + "]" * 5000, "note"),
])
def test_hostile_material_case(tmp_path, old, new, field):
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert str(path) in str(err.value)
    assert err.value.field and (field is None or err.value.field.startswith(field)), str(err.value)


@pytest.mark.parametrize("old, new, field", [
    ("{radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}", "{plane: rigid, young: -5 GPa}",
     "bodies[1].young"),
    ("{radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}",
     "{plane: true, radius: 1 cm, young: 70 GPa, poisson: 0.33}", "bodies[1].radius"),
    ("{radius: 5 mm,", "{plane: true, radius: 5 mm,", "bodies[0].plane"),
    ("{radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}",
     "{plane: yes, young: 70 GPa, poisson: 0.33}", "bodies[1].plane"),
    ("young: 70 GPa", "young: 70 GPa, Young: 71 GPa", "bodies[1].Young"),
    ("young: 70 GPa", "young: 70 GPa, young: 71 GPa", "bodies[1].young"),
    ("poisson: 0.3}", "poisson: '0.3'}", "bodies[0].poisson"),
    ("poisson: 0.3}", "poisson: .nan}", "bodies[0].poisson"),
    ("name: unequal", "name: unequal\neffective_modulus: 100 GPa", "effective_modulus"),
    ("name: unequal", "name: unequal\ngeometries: [sphere-plane]", "geometries"),
    ("bodies:", "bodies:\n  - {radius: 5 mm, density: 7800 kg/m^3, young: 200 GPa, poisson: 0.3}", "bodies"),
    ("young: 200 GPa", "young: 1e-320 Pa", "bodies"),                     # E* = 1/inf = 0
])
def test_hostile_bodies_case(tmp_path, old, new, field):
    assert old in BODIES
    path = write(tmp_path, BODIES.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert str(path) in str(err.value) and err.value.field.startswith(field), str(err.value)


@pytest.mark.parametrize("content, words", [
    (b"", "empty file"), (b"# only a comment\n", "empty file"), (b"- 1\n- 2\n", "mapping"),
    (b"name: caf\xe9\n", "not UTF-8"), (bytes(range(256)), "not UTF-8"), (b"name: a\x00b\n", "not allowed"),
    (b"a: 1\n---\nb: 2\n", "more than one YAML document"), (b"a: [1, 2", "not valid YAML"),
])
def test_files_that_are_not_case_files(tmp_path, content, words):
    path = tmp_path / "case.yaml"
    path.write_bytes(content)
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert str(path) in str(err.value) and err.value.field and words in str(err.value)


@pytest.mark.parametrize("text, si", [
    ("7800 kg/m^3", 7800), ("7.8 g/cm^3", 7800), ("7800 kg m^-3", 7800), ("7800 kg*m^-3", 7800),
    ("7.8e3 kg/m**3", 7800), ("+7.8E+3 kg/m^3", 7800), (".78e4 kg/m^3", 7800), ("7800. kg/m^3", 7800),
])
def test_plain_quantities_are_read(tmp_path, text, si):
    case = load_case(write(tmp_path, GOOD.replace("density: 7.8 g/cm^3", f"density: {text}")))
    assert case.pairs[0].body_1.density == pytest.approx(si, rel=1e-15)


def test_named_documentation_keys_are_kept(tmp_path):
    text = GOOD + "density_source: a handbook\nnote: made up\nradius_note: measured\n"
    case = load_case(write(tmp_path, text))
    assert case.extra == {"density_source": "a handbook", "note": "made up", "radius_note": "measured"}
    with pytest.raises(CaseError) as err:
        load_case(write(tmp_path, GOOD + "denisty_source: a handbook\n"))
    assert err.value.field == "denisty_source" and "unknown" in str(err.value)


# ---------------------------------------------------------------------------- fuzzing
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

import fuzz_case_files as fuzz  # noqa: E402


@settings(max_examples=250, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(rnd=st.randoms(use_true_random=False))
def test_fuzzed_case_files_are_read_or_refused_clearly(tmp_path, rnd):
    """Any variant of a valid file: accepted with the oracle's numbers, or a CaseError naming
    the file and the field the mutation touched; never another exception."""
    variant = fuzz.make_variant(rnd)
    outcome, detail = fuzz.classify(variant, tmp_path)
    expected = "accepted-valid" if variant.valid else "clear"
    assert outcome == expected, f"{variant.kind}: {variant.text[:300]!r}\n{detail}"


def test_every_mutation_is_exercised_by_the_corpus():
    kinds = {v.kind for v in fuzz.corpus(len(fuzz.ALL) * 2)}
    assert kinds == {m.__name__ for m in fuzz.ALL}


RESTITUTION = """
name: alumina
effective_modulus: 190 GPa
radius: 5 mm
density: 3900 kg/m^3
geometries: [sphere-plane]
impact:
  restitution: [0.8, 0.5]
  velocity: [3.9 m/s]
"""


@pytest.mark.parametrize("criterion", ["F0", "x0"])
def test_a_restitution_sets_the_viscosity_that_restitutes_it(tmp_path, criterion):
    """impact: restitution [0.8, 0.5] at 3.9 m/s: each contact's eta restitutes 0.8 under the case's
    criterion (F0 unless it says x0) to 1e-9 by the reference solver, the second variant 0.5."""
    from contact_model.case_file import restitution_variants
    from reference import solve_collision

    text = RESTITUTION + (f"  criterion: {criterion}\n" if criterion == "x0" else "")
    case = load_case(write(tmp_path, text))
    assert case.restitutions == (0.8, 0.5) and case.restitution_criterion == criterion
    (pair,) = case.pairs
    assert solve_collision(pair.dissipation_parameter(3.9))[f"eps_{criterion}"] == pytest.approx(0.8, abs=1e-9)
    variants = restitution_variants(case)
    assert [r for r, _ in variants] == [0.8, 0.5] and all(not v.restitutions for _, v in variants)
    K = variants[1][1].pairs[0].dissipation_parameter(3.9)
    assert solve_collision(K)[f"eps_{criterion}"] == pytest.approx(0.5, abs=1e-9)


@pytest.mark.parametrize("old, new, field, words", [
    ("restitution: [0.8, 0.5]", "restitution: [0.8, 1.2]", "impact.restitution[1]", "must be a number in (0, 1)"),
    ("restitution: [0.8, 0.5]", "restitution: [0, 0.5]", "impact.restitution[0]", "must be a number in (0, 1)"),
    ("  velocity: [3.9 m/s]\n", "", "impact.restitution", "needs the impact velocity it holds at"),
    ("restitution: [0.8, 0.5]", "restitution: [0.8, 0.01]", "impact.restitution[1]",
     "no viscoelastic law can reach it: no K in [0, 10] restitutes 0.01 under F0"),
    ("geometries: [sphere-plane]", "geometries: [sphere-plane]\nviscosity: 1 P", "viscosity",
     "the impact's restitution sets the viscosity"),
    ("  velocity: [3.9 m/s]", "  velocity: [3.9 m/s]\n  criterion: F1", "impact.criterion", "must be F0"),
])
def test_a_bad_restitution_is_refused_naming_its_field(tmp_path, old, new, field, words):
    path = write(tmp_path, RESTITUTION.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert err.value.field == field and words in str(err.value) and str(path) in str(err.value)


def test_a_case_without_viscosity_or_restitution_is_refused(tmp_path):
    with pytest.raises(CaseError) as err:
        load_case(write(tmp_path, GOOD.replace("viscosity: 6.7e5 P\n", "")))
    assert err.value.field == "viscosity" and "missing" in str(err.value)
