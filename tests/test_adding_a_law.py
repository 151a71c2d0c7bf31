"""The recipe of contact_model/laws.py holds for every law of `LAW_REGISTRY`: `recipe_problems`
checks each place a law must reach (its entry, the config schema, its keyword and its code's
driver, the solution of its equation, the ladder's powers, the docs), so that a law that misses
one fails naming it, and a dummy law added to the registry alone fails at every place."""

import math
from pathlib import Path

import pytest
import yaml

from contact_model import laws as laws_module
from contact_model.keywords import KEYWORDS, keyword_reference
from contact_model.laws import CRITERIA, DAMPING_POWER, LAW_REGISTRY, Law
from engines.codes import CODES
from engines.ladder import form_of, powers_of
from test_damping_forms import FIRST, SECOND, measured_powers
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = yaml.safe_load((ROOT / "config" / "config.schema.yaml").read_text())
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
DOCS = "\n".join(p.read_text() for p in (ROOT / "docs").glob("*.md"))


def recipe_problems(law: Law) -> list[str]:
    """Every place law `law` misses, one sentence each naming the place; empty when it follows
    the recipe of contact_model/laws.py."""
    problems = []

    def check(place, condition, what):
        if not condition:
            problems.append(f"{place}: {what}")

    # 1. Its entry: a known damping form, criteria the reference knows, an end among them.
    check("contact_model/laws.py", law.damping in DAMPING_POWER, f"damping form {law.damping!r} is not known")
    check("contact_model/laws.py", set(law.criteria) <= set(CRITERIA), f"criteria {law.criteria} not in {CRITERIA}")
    check("contact_model/laws.py", law.aligned_end is None or law.aligned_end in law.criteria,
          f"aligned end {law.aligned_end!r} is not one of its criteria")
    check("contact_model/laws.py", law.told in ("eta", "none", "e"), f"told {law.told!r}")
    # 2. The config schema lets a user name it.
    check("config/config.schema.yaml", law.name in SCHEMA["properties"]["laws"]["items"]["enum"],
          f"the enum of `laws` lacks {law.name!r}")
    # 3. A keyword law: its keyword's entry (map, clip, source), its code, and that code's driver.
    if law.keyword is not None:
        keyword = KEYWORDS.get(law.keyword)
        check("contact_model/keywords.py", keyword is not None, f"no keyword {law.keyword!r}")
        if keyword is not None:
            check("contact_model/keywords.py",
                  keyword.form in ("quarter", "half", "velocity") and keyword.coefficient is not None,
                  f"{law.keyword} has no map to the coefficient of an equation reference solves (x^(1/4) form: "
                  "reference.quarter_power_damping; x^(1/2): reference.collision_ode; linear dashpot: "
                  "reference.linear_damping)")
            check("contact_model/laws.py", keyword.form == law.damping or law.damping == "keyword",
                  f"{law.keyword} is of form {keyword.form!r}, the law says {law.damping!r}")
            check("contact_model/keywords.py", (keyword.criterion,) == law.criteria and keyword.clipped == law.clipped,
                  f"{law.keyword} clips ({keyword.clipped}) where the law says {law.clipped}")
            check("engines/codes.py", keyword.code in CODES, f"no engine code {keyword.code!r}")
            driver = ROOT / "engines" / f"{keyword.code}.py"
            check(f"engines/{keyword.code}.py", driver.exists() and law.keyword in driver.read_text(),
                  f"the driver does not translate {law.keyword}")
            check("docs/keywords.md", keyword.written.split(" ")[-1].split("(")[0] in DOCS,
                  f"the docs do not describe {keyword.written}")
    # 4. The solution of its equation, and the ladder's powers of its error.
    try:
        if law.keyword is not None:
            row = keyword_reference(law.keyword, 0.8)
        elif law.is_keyword:  # each code's own keyword (law `default`): solved per keyword
            row = keyword_reference(CODES["lammps"].keyword, 0.8)
        else:
            row = solve_collision(0.0 if law.damping == "none" else 0.1)
        ok = all(math.isfinite(row[k]) for k in ("x_max", "tau_0", "tau_f", "eps_x0", "eps_F0"))
    except (KeyError, ValueError, TypeError):
        ok = False
    check("reference/", ok, f"no solution of {law.name}'s equation")
    # The ladder's powers are those its damping form's expansion gives on the engines' map, measured
    # (tests/test_damping_forms.py), for each code's keyword where the law is each code's own.
    codes = [c for c in CODES if law.damping == "keyword"] or [None]
    for code in codes:
        where = f" in {code}" if code else ""
        try:
            powers = powers_of(0.0 if law.damping == "none" else 1.0, law.name, code)
            form = form_of(law.name, code)
        except (KeyError, ValueError) as err:
            problems.append(f"engines/ladder.py: no powers for {law.name}{where} ({err})")
            continue
        measured = measured_powers(form.power)
        check("engines/ladder.py", len(powers) >= 3 and abs(powers[0] - measured[0]) <= FIRST
              and abs(powers[1] - measured[1]) <= SECOND,
              f"{law.name}{where}'s ladders eliminate {powers[:2]}, but its force on the engines' map measures "
              f"({measured[0]:.3f}, {measured[1]:.3f})")
    # 5. The default study runs it, or its entry says why not.
    check("config/config.yaml", law.name in CONFIG["laws"] or law.left_out,
          f"`laws:` does not list {law.name!r} and its entry gives no reason (Law.left_out)")
    # 6. A reader finds it.
    check("docs/", f"`{law.name}`" in DOCS, f"no doc names the law `{law.name}`")
    return problems


@pytest.mark.parametrize("name", list(LAW_REGISTRY))
def test_every_law_follows_the_recipe(name):
    assert recipe_problems(LAW_REGISTRY[name]) == []


def test_a_law_added_to_the_registry_alone_fails_at_every_place(monkeypatch):
    dummy = Law("dummy", "a law nobody wrote", "cubic", True, ("F1",), "F1", False, keyword="nowhere:dummy",
                told="e")
    monkeypatch.setitem(laws_module.LAW_REGISTRY, "dummy", dummy)
    places = {p.split(":")[0] for p in recipe_problems(dummy)}
    assert places == {"contact_model/laws.py", "config/config.schema.yaml", "contact_model/keywords.py",
                      "reference/", "engines/ladder.py", "config/config.yaml", "docs/"}, recipe_problems(dummy)


def test_the_ladder_that_gave_every_keyword_the_quarter_powers_fails_naming_en_vn(monkeypatch):
    """Before the damping forms, engines.ladder.powers_of gave every keyword law x^{1/4}'s powers, YADE's
    en + vn (a x^{1/2} force) too: measured on the map, the recipe now names that place."""
    import test_adding_a_law as this
    from engines.ladder import DISSIPATIVE_POWERS, ELASTIC_POWERS, QUARTER_POWERS

    def old_powers_of(eta, law="viscoelastic", engine=None):
        if LAW_REGISTRY[law].is_keyword:
            return QUARTER_POWERS
        return ELASTIC_POWERS if eta == 0 else DISSIPATIVE_POWERS

    monkeypatch.setattr(this, "powers_of", old_powers_of)
    problems = recipe_problems(LAW_REGISTRY["en_vn"])
    assert len(problems) == 1 and problems[0].startswith(
        "engines/ladder.py: en_vn's ladders eliminate (1.0, 1.25), but its force on the engines' map measures (1.0"
    ), problems
    assert recipe_problems(LAW_REGISTRY["betan"]) == []  # an x^{1/4} keyword was right all along


def test_the_derived_tuples_are_the_registry():
    assert laws_module.LAWS == tuple(LAW_REGISTRY)
    assert set(laws_module.MODEL_LAWS) == {"viscoelastic", "viscoelastic_clipped", "elastic"}
    assert set(laws_module.KEYWORD_LAWS) == {"default", "betan", "en_vn", "coeff_restitution", "velocity",
                                             "mass_velocity"}
    assert laws_module.LAW_CRITERIA["viscoelastic"] == ("x0", "F0")
    with pytest.raises(ValueError, match="unknown contact law 'viscoelastik'; known: viscoelastic"):
        laws_module.law("viscoelastik")
