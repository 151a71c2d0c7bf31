"""The tangential model registry (contact_model/tangential_models.yaml) walked entry by entry, and a
model a build's release lacks refused by the plan, naming the release (issue 'Oblique impacts')."""

import math
from dataclasses import replace

import pytest

from contact_model import Body, ContactPair
from contact_model.tangential_models import TANGENTIAL_MODELS, NoReference, form_of, models_for
from engines.codes import CODES
from engines import oblique_plan as plan_module
from reference import TangentialForm

pytestmark = pytest.mark.unit


@pytest.mark.parametrize("name", sorted(TANGENTIAL_MODELS))
def test_every_entry_is_a_model_with_its_sources(name):
    """The recipe of adding a model: an entry with its code, words, a block per geometry, its
    releases and source lines; a model the study runs (its code has an oblique driver, in scope) is
    a form of the reference in every geometry it has."""
    m = TANGENTIAL_MODELS[name]
    assert m.code in CODES and name.startswith(m.code + ":")
    assert m.words and m.geometries and m.sources and m.releases
    for citations in m.sources.values():
        assert all(":" in c for c in citations), citations  # file:line
    for geometry in m.geometries:
        if CODES[m.code].oblique_driver and not m.out_of_scope:
            assert isinstance(form_of(name, geometry), TangentialForm)
        else:
            try:
                form_of(name, geometry)
            except NoReference as err:
                assert name in str(err) and geometry in str(err)


def test_the_codes_with_a_driver_run_their_models():
    lammps, missing = models_for("lammps", "LAMMPS (22 Jul 2025 - Update 4)")
    assert {m.name for m in lammps} == {"lammps:mindlin", "lammps:mindlin_rescale", "lammps:mindlin/force",
                                        "lammps:mindlin_rescale/force", "lammps:linear_history",
                                        "lammps:hertz/history"} and not missing
    assert "lammps:hooke/history" not in {m.name for m in lammps}  # a linear normal spring: out of scope
    yade, _ = models_for("yade", "YADE 2023.02a")
    assert [m.name for m in yade] == ["yade:mindlin"]
    # no_history has no spring (viscous friction alone): not a form of the reference, out of scope
    liggghts, _ = models_for("liggghts", "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2022-01-26)")
    assert [m.name for m in liggghts] == ["liggghts:history"]
    assert "no tangential spring" in TANGENTIAL_MODELS["liggghts:no_history"].out_of_scope
    with pytest.raises(KeyError, match="unknown tangential model 'lammps:nope'"):
        form_of("lammps:nope", "sphere-plane")
    with pytest.raises(KeyError, match="has no sphere-sphere contact"):
        form_of("lammps:hooke/history", "sphere-sphere")


def test_a_model_the_release_lacks_is_refused_naming_the_release(monkeypatch, tmp_path):
    """A registry whose `mindlin/force` is absent in 29 Sep 2021: its runs are not planned there, and
    the plan says why, naming the release; 22 Jul 2025 still runs it."""
    from contact_model import tangential_models
    from contact_model.case_file import load_case

    lacking = dict(TANGENTIAL_MODELS)
    entry = lacking["lammps:mindlin/force"]
    lacking["lammps:mindlin/force"] = replace(entry, releases={**entry.releases,
                                                               "lammps-2021": "absent (added in 2022)"})
    monkeypatch.setattr(tangential_models, "TANGENTIAL_MODELS", lacking)
    case = load_case("cases/oblique/chung_ooi_test4.yaml")
    old = plan_module.oblique_plan([case], "lammps", "lammps-2021", "LAMMPS (29 Sep 2021 - Update 2)", [1000])
    assert ("chung_ooi_test4", "lammps:mindlin/force") in old.refused
    why = old.refused[("chung_ooi_test4", "lammps:mindlin/force")]
    assert "lammps-2021" in why and "absent (added in 2022)" in why
    assert not any(r.model == "lammps:mindlin/force" for r in old.runs)
    new = plan_module.oblique_plan([case], "lammps", "lammps-2025", "LAMMPS (22 Jul 2025 - Update 4)", [1000])
    assert any(r.model == "lammps:mindlin/force" for r in new.runs) and not new.refused


def test_a_normal_law_the_driver_cannot_run_is_refused_with_its_reason():
    from contact_model.case_file import load_case

    case = load_case("cases/oblique/damped/alumina_viscoelastic.yaml")
    plan = plan_module.oblique_plan([case], "yade", "yade-2023", "YADE 2023.02a", [1000])
    assert plan.runs == [] and "viscoelastic" in plan.refused[("alumina_viscoelastic", "yade:mindlin")]


def test_g_star_is_mindlins():
    """1/G* = (2 - nu1)/G1 + (2 - nu2)/G2, G = E/(2(1 + nu)): two bodies of one material give
    E/(4 (2 - nu)(1 + nu)); a rigid plane adds nothing."""
    from contact_model.effective import effective_shear_modulus

    a = Body(2.5e-3, 4000.0, 380e9, 0.23)
    assert effective_shear_modulus(a, a) == pytest.approx(380e9 / (4 * 1.77 * 1.23), rel=1e-15)
    rigid = Body(math.inf, math.inf, math.inf, 0.0)
    assert effective_shear_modulus(a, rigid) == pytest.approx(380e9 / (2 * 1.77 * 1.23), rel=1e-15)
    with pytest.raises(ValueError, match="Young's modulus and Poisson's ratio"):
        effective_shear_modulus(Body(1e-3, 1000.0), a)
    assert ContactPair.from_bodies(a, rigid, 0.0).geometry == "sphere-plane"
