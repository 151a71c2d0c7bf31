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
import shutil  # noqa: E402

from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

import fuzz_case_files as fuzz  # noqa: E402


# 100 random variants: the fixed corpus (test_the_corpus_and_the_audits_...) tries every mutation ten times
# against the same oracle (fuzz.classify); these add random combinations of the valid-preserving edits.
@settings(max_examples=100, deadline=None, derandomize=True, database=None,
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


def test_every_injection_string_is_tried_in_every_kind_of_place():
    variants = fuzz.injection_corpus()
    assert len(variants) == len(fuzz.INJECTIONS) * len(fuzz.INJECTION_MUTATIONS)
    for text in fuzz.INJECTIONS:
        assert sum(fuzz.yaml_string(text).encode() in v.text for v in variants) >= len(fuzz.INJECTION_MUTATIONS), text
    for audit in ("`touch", "$(touch /tmp/x)", '"; rm -rf x; "', "*", "../../etc/passwd", "/dev/zero", "a\x00b"):
        assert audit in fuzz.INJECTIONS or any(s.startswith(audit) for s in fuzz.INJECTIONS), audit
    assert max(map(len, fuzz.INJECTIONS)) >= 100_000  # a very long string


def test_the_corpus_and_the_audits_injection_strings_are_read_or_refused_clearly(tmp_path, capsys):
    """The fixed corpus of case files (every mutation, and every injection string in every kind of
    place) and of measurement files: each accepted with the oracle's numbers (an injection string
    kept exactly as text where text is allowed) or refused by a CaseError naming the file and the
    field, in a message of sane length; no marker file of an injection appears, and the loader
    writes no file. The counts are printed (a line per corpus, shown with -q too)."""
    shutil.rmtree(fuzz.MARKER_DIR, ignore_errors=True)
    tallies = fuzz.run_all(len(fuzz.ALL) * 10, tmp_path)
    with capsys.disabled():
        for what, tally in zip(("case files", "measurement files"), tallies):
            print(f"\nfuzz: {tally.summary(what)}")
    for tally in tallies:
        wrong = [x for o in ("unclear", "accepted-invalid", "refused-valid") for x in tally.examples.get(o, [])]
        assert tally.failures == 0, wrong[:5]
        assert tally.markers == [] and not fuzz.MARKER_DIR.exists()
        assert tally.stray_files == []  # nothing written beside the inputs
        assert tally.injected.get("clear", 0) > 0 and tally.injected.get("accepted-valid", 0) > 0
    cases, measured = tallies
    assert cases.tried == len(fuzz.ALL) * 10 + len(fuzz.INJECTIONS) * len(fuzz.INJECTION_MUTATIONS)
    assert sum(cases.injected.values()) >= len(fuzz.INJECTIONS) * len(fuzz.INJECTION_MUTATIONS)


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


# ---------------------------------------------------------------------------- files that are not small regular files
import os  # noqa: E402
import signal  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from contact_model.measurement_file import MeasurementError  # noqa: E402
from contact_model.strict_yaml import MAX_BYTES, key_bytes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def no_hang():
    """Fail, rather than hang, a test whose file would block an open or a read (a FIFO)."""
    def alarm(*_):
        raise TimeoutError("the loader blocked on a file it should have refused unread")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def _special(tmp_path, kind) -> tuple[Path, str]:
    """A path of the given kind and what the loader must say it is."""
    if kind == "character device":
        return Path("/dev/zero"), "is a character device, not a regular file"
    path = tmp_path / "case.yaml"
    if kind == "symlink to /dev/zero":
        path.symlink_to("/dev/zero")
        return path, "is a character device, not a regular file"
    if kind == "named pipe":
        os.mkfifo(path)
        return path, "is a named pipe (FIFO), not a regular file"
    if kind == "directory":
        path.mkdir()
        return path, "is a directory, not a regular file"
    with open(path, "wb") as fh:  # a sparse file: 2 MB that are never read
        fh.truncate(2 * MAX_BYTES)
    return path, (f"is {2 * MAX_BYTES} bytes; a case file is a few hundred bytes (limit {MAX_BYTES}, checked before "
                  "reading)")


@pytest.mark.parametrize("kind", ["character device", "symlink to /dev/zero", "named pipe", "directory", "too large"])
def test_a_case_path_that_is_not_a_small_regular_file_is_refused_before_it_is_read(tmp_path, no_hang, kind):
    """`cases=/dev/zero` was read whole (80 s, 20 GB) before its size was checked: now the kind and
    the size are checked first (os.stat), in well under a second, and the message names the file."""
    path, said = _special(tmp_path, kind)
    start = time.perf_counter()
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert time.perf_counter() - start < 1.0
    assert err.value.field == "(file)" and str(err.value).startswith(f"{path}: field '(file)': {said}"), str(err.value)
    # the workflow's cache key reads case files too: it takes the refusal instead, unread
    assert key_bytes(path).startswith(b"\0refused\0" + said.encode())


def test_the_cache_key_takes_a_regular_case_files_bytes(tmp_path):
    path = write(tmp_path, GOOD)
    assert key_bytes(path) == path.read_bytes()


@pytest.mark.parametrize("kind", ["named pipe", "directory", "too large"])
def test_a_measurement_path_that_is_not_a_small_regular_file_is_refused_before_it_is_read(tmp_path, no_hang, kind):
    data = tmp_path / "data"
    data.mkdir()
    path, said = _special(data, kind)
    said = said.replace("a case file is a few hundred", "a measurement file is a few thousand")
    case = write(tmp_path, MEASURED.format(path="data/case.yaml"))
    with pytest.raises(MeasurementError) as err:
        load_case(case, project=tmp_path)
    assert str(err.value).startswith(f"{path}: (file): {said}"), str(err.value)


# ---------------------------------------------------------------------------- measurement paths inside the project
MEASURED = """
effective_modulus: 70 GPa
radius: 5 mm
density: 2700 kg/m^3
viscosity: 5e4 P
geometries: [sphere-plane]
measurements: "{path}"
"""
ROWS = "velocity [m/s],restitution\n0.5,0.86\n2,0.83\n6,0.8\n"


def test_a_measurement_path_leading_outside_the_project_is_refused_unread(tmp_path):
    """'../../../../../etc/passwd' was read and its first line echoed: refused, naming the case
    file and the field, before anything is read; with the project found (the repository, for a case
    file in no project) or given."""
    path = write(tmp_path, MEASURED.format(path="../../../../../../../../etc/passwd"))
    for project, root in ((None, ROOT), (tmp_path, tmp_path.resolve())):
        with pytest.raises(CaseError) as err:
            load_case(path, project=project)
        assert str(err.value) == (f"{path}: field 'measurements': '../../../../../../../../etc/passwd' leads outside "
                                  f"the project folder {root} (symlinks followed): a measurement file must lie inside "
                                  "the project, e.g. beside the case file; nothing was read")
        assert "root:" not in str(err.value)


@pytest.mark.parametrize("target, words", [
    ("/etc/passwd", "leads outside the project folder"),
    ("/dev/zero", "leads outside the project folder"),
    ("inside.csv", None),  # a symlink that stays inside: read
])
def test_a_symlink_is_followed_before_the_path_is_judged(tmp_path, target, words):
    (tmp_path / "inside.csv").write_text(ROWS)
    (tmp_path / "link.csv").symlink_to(target if target.startswith("/") else tmp_path / target)
    path = write(tmp_path, MEASURED.format(path="link.csv"))
    if words is None:
        assert load_case(path, project=tmp_path).measurements.velocity.tolist() == [0.5, 2.0, 6.0]
        return
    with pytest.raises(CaseError) as err:
        load_case(path, project=tmp_path)
    assert err.value.field == "measurements" and words in str(err.value) and str(path) in str(err.value)


@pytest.mark.parametrize("written, words", [
    ("m\\0.csv", "'m\\x00.csv' holds a NUL character: no file is named so"),
    ("/etc/passwd", "'/etc/passwd' is an absolute path"),
    ("/dev/zero", "'/dev/zero' is an absolute path"),
    ("absent.csv", "no file"),
    (".", None),  # the project's own folder: a directory, refused by the reader
])
def test_a_measurement_path_that_names_no_file_of_the_project_is_refused(tmp_path, written, words):
    path = write(tmp_path, MEASURED.format(path=written))
    with pytest.raises(CaseError) as err:
        load_case(path, project=tmp_path)
    if words is None:
        assert str(err.value) == f"{tmp_path}: (file): is a directory, not a regular file: only a file on disk is " \
                                 f"read (at most 1000000 bytes)"
        return
    assert err.value.field == "measurements" and words in str(err.value), str(err.value)


def test_the_project_folder_is_the_nearest_one_with_the_studys_snakefile(tmp_path):
    from contact_model.case_file import project_folder

    assert project_folder(ROOT / "cases" / "calibration" / "gugan_jaques_on_wood.yaml") == ROOT
    (tmp_path / "copy" / "cases").mkdir(parents=True)
    assert project_folder(tmp_path / "copy" / "cases" / "x.yaml") == ROOT  # no Snakefile above it
    (tmp_path / "copy" / "Snakefile").write_text("")
    assert project_folder(tmp_path / "copy" / "cases" / "x.yaml") == (tmp_path / "copy").resolve()


def test_a_file_that_is_no_measurement_file_is_not_repeated(tmp_path):
    """A passwd-like file inside the project given as measurements: the message says where it is
    wrong, not what it holds."""
    (tmp_path / "stray.csv").write_text("root:x:0:0:root:/root:/bin/bash\nbin:x:1:1:bin:/bin:/sbin/nologin\n")
    path = write(tmp_path, MEASURED.format(path="stray.csv"))
    with pytest.raises(MeasurementError) as err:
        load_case(path, project=tmp_path)
    assert str(err.value) == (f"{tmp_path / 'stray.csv'}: header (line 1), column 1: not a column name (31 characters "
                              "of other text, not shown: is this a measurement file?); known: velocity, restitution, "
                              "rebound_velocity, restitution_uncertainty, rebound_velocity_uncertainty (velocities "
                              "with a unit: 'velocity [m/s]')")
    # a case file that is no case file: its text is not repeated either
    stray = tmp_path / "passwd.yaml"
    stray.write_text("root:x:0:0:root:/root:/bin/bash\nbin:x:1:1:bin:/bin:/sbin/nologin\n")
    with pytest.raises(CaseError) as err:
        load_case(stray)
    assert str(err.value) == (f"{stray}: field '(top level)': a case file must be a YAML mapping of fields, got one "
                              "text of 64 characters (not shown)")  # YAML folds the line break into a space


def test_a_long_value_is_cut_in_the_message(tmp_path):
    path = write(tmp_path, GOOD.replace("radius: 0.635 cm", "radius: " + "9" * 100_000 + " cm"))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert len(str(err.value)) < 400 and "(100003 characters) is no quantity" in str(err.value), str(err.value)


@pytest.mark.parametrize("name", ['"a\\n# PASS"', '"a\\u202eb"', '"a\\x1b[31m"', "x" * 101])
def test_a_name_is_one_line_of_printable_text(tmp_path, name):
    path = write(tmp_path, GOOD.replace("name: demo", f"name: {name}"))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert err.value.field == "name" and ("one line of printable text" in str(err.value)
                                          or "at most 100 characters" in str(err.value))


# ---------------------------------------------------------------------------- numbers written as text
@pytest.mark.parametrize("text, old, new, field, hint", [
    (RESTITUTION, "restitution: [0.8, 0.5]", "restitution: ['0.8', 0.5]", "impact.restitution[0]",
     "must be a number in (0, 1), got '0.8' ('0.8' is in quotes, so it is text, not a number: write it without "
     "quotes, 0.8)"),
    (BODIES, "K: [0.1, 0.3]", 'K: ["0.1", 0.3]', "impact.K[0]",
     "('0.1' is in quotes, so it is text, not a number: write it without quotes, 0.1)"),
    (BODIES, "poisson: 0.3}", "poisson: '0.3'}", "bodies[0].poisson",
     "got '0.3' ('0.3' is in quotes, so it is text, not a number: write it without quotes, 0.3)"),
    (BODIES, "K: [0.1, 0.3]", "K: [1e-1, 0.3]", "impact.K[0]",
     "(YAML 1.1 reads 1e-1 as text, not a number: write its mantissa with a dot and its exponent with a sign, 1.0e-1)"),
    (BODIES, "K: [0.1, 0.3]", "K: [2E1, 0.3]", "impact.K[0]",
     "(YAML 1.1 reads 2E1 as text, not a number: write its mantissa with a dot and its exponent with a sign, 2.0E+1)"),
    (BODIES, "K: [0.1, 0.3]", "K: [+.5, 0.3]", "impact.K[0]",
     "(YAML 1.1 reads +.5 as text, not a number: write it as 0.5)"),
    (GOOD, "radius: 0.635 cm", "radius: '0.635'", "radius",
     "'0.635' is a number without a unit (quoted, so text): write it with its unit, e.g. '0.635 m'"),
])
def test_a_number_written_as_text_gets_the_hint_that_fits(tmp_path, text, old, new, field, hint):
    """A quoted '0.8' was told to write its exponent with a dot and a sign, though it has none."""
    assert old in text
    path = write(tmp_path, text.replace(old, new))
    with pytest.raises(CaseError) as err:
        load_case(path)
    assert err.value.field == field and hint in str(err.value), str(err.value)
    assert ("exponent" in str(err.value)) == ("exponent" in hint)  # no exponent hint for a number without one


# ---------------------------------------------------------------------------- restitutions at several velocities
def test_every_restitution_runs_at_every_velocity_each_with_the_eta_that_restitutes_it_there(tmp_path):
    """impact: {restitution: [0.8, 0.5], velocity: [3.9 m/s, 1 m/s, 20 m/s]}: each of the six runs
    restitutes its restitution (F0) to 1e-9 by the reference solver, as an engine's restitution
    keyword does at every velocity; eta falls as V^{-1/5} (K fixed by eps)."""
    from contact_model.case_file import restitution_variants
    from reference import solve_collision

    case = load_case(write(tmp_path, RESTITUTION.replace("[3.9 m/s]", "[3.9 m/s, 1 m/s, 20 m/s]")))
    (pair,) = case.pairs
    assert solve_collision(pair.dissipation_parameter(3.9))["eps_F0"] == pytest.approx(0.8, abs=1e-9)
    variants = restitution_variants(case)
    assert [(r, v.velocities) for r, v in variants] == [(r, (V,)) for r in (0.8, 0.5) for V in (3.9, 1.0, 20.0)]
    for r, v in variants:
        (p,) = v.pairs
        assert solve_collision(p.dissipation_parameter(v.velocities[0]))["eps_F0"] == pytest.approx(r, abs=1e-9)
        assert not v.restitutions
    etas = {(r, v.velocities[0]): v.pairs[0].eta for r, v in variants}
    for r in (0.8, 0.5):
        assert etas[(r, 20.0)] / etas[(r, 1.0)] == pytest.approx(20.0 ** -0.2, rel=1e-12)


def test_a_plan_of_restitutions_at_several_velocities_restitutes_each_in_every_run(tmp_path):
    """The plan: every viscoelastic run restitutes its restitution at its own velocity, the
    out-of-the-box law is told it at each, and the notes give each velocity's eta."""
    from engines.plan import plan_runs
    from reference import solve_collision

    case = load_case(write(tmp_path, RESTITUTION.replace("[3.9 m/s]", "[3.9 m/s, 1 m/s]")))
    plan = plan_runs(case, ["lammps"], laws=["viscoelastic", "elastic", "default"])
    visco = [r for r in plan.runs if r.law == "viscoelastic"]
    assert {(round(solve_collision(r.K)["eps_F0"], 9), r.velocity) for r in visco} == {
        (0.8, 3.9), (0.8, 1.0), (0.5, 3.9), (0.5, 1.0)}
    assert {(r.matched_restitution, r.velocity) for r in plan.runs if r.law == "default"} == {
        (0.8, 3.9), (0.8, 1.0), (0.5, 3.9), (0.5, 1.0)}
    assert {r.velocity for r in plan.runs if r.law == "elastic"} == {3.9, 1.0}
    restitution_notes = [n for n in plan.notes if ": restitution " in n]
    assert [n.split(": sphere-plane")[0] for n in restitution_notes] == [
        f"alumina: restitution {r} under F0 at V = {V} m/s" for r in (0.8, 0.5) for V in (3.9, 1)]


# ---------------------------------------------------------------------------- restitutions too close to 1
@pytest.mark.parametrize("value", ["0.9999999999999999", "0.999999999", "0.99999999000001"])
def test_a_restitution_too_close_to_1_to_resolve_its_eta_is_refused(tmp_path, value):
    """0.9999999999999999 quietly became an elastic case (K = 0): refused above 1 - 1e-8, naming
    the field, the value and the limit."""
    path = write(tmp_path, RESTITUTION.replace("[0.8, 0.5]", f"[0.8, {value}]"))
    with pytest.raises(CaseError) as err:
        load_case(path)
    r = float(value)
    assert err.value.field == "impact.restitution[1]"
    assert str(err.value).startswith(f"{path}: field 'impact.restitution[1]': {r!r} lies within {1 - r:.2g} of 1, "
                                     "above the limit 0.99999999 (1 - 1e-8): the K and eta that restitute it (K "
                                     "about "), str(err.value)
    assert "Give a restitution of at most 0.99999999, or `viscosity: 0` for an elastic contact" in str(err.value)


def test_the_restitution_at_the_limit_is_resolved(tmp_path):
    """0.99999999 itself: K about 1e-8, resolved to 1e-6 relative at worst (Brent's method to 1e-14
    in K); the solver restitutes it to 1e-14."""
    from reference import solve_collision

    case = load_case(write(tmp_path, RESTITUTION.replace("[0.8, 0.5]", "[0.99999999]")))
    (K,) = case.restitution_dissipations
    assert K == pytest.approx((1 - 0.99999999) / 1.0089, rel=1e-3)
    assert solve_collision(K)["eps_F0"] == pytest.approx(0.99999999, abs=1e-14)
    assert case.pairs[0].eta > 0
