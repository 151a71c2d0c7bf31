"""docs/adding_an_engine.md holds for every engine code of engines/codes.py: `recipe_problems`
checks each item of its checklist for a code, so that a code that misses one fails naming it,
and a dummy code added to the registry (and nowhere else) is shown to fail at every place."""

import inspect
import math
import re
from glob import glob
from pathlib import Path

import pytest
import yaml

from conftest import tier_of
from contact_model import LAWS, engine_parameters
from contact_model.keywords import KEYWORDS
from engine_cases import OPTIONAL_VERSIONS, VERSIONS, steel_pair
from engines.codes import CODES, EngineCode

ROOT = Path(__file__).resolve().parents[1]
CHECKLIST = (ROOT / "docs" / "adding_an_engine.md").read_text()
MAKEFILE = (ROOT / "Makefile").read_text()
#: The files that list the codes for a reader, each naming every code by its title.
LISTS = ("README.md", "docs/engines.md", "pyproject.toml")


def _builds():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"]


def recipe_problems(name: str, code: EngineCode) -> list[str]:
    """Every item of docs/adding_an_engine.md that code `name` misses, one sentence each naming
    the place; empty when it follows the recipe."""
    problems = []

    def check(place, condition, what):
        if not condition:
            problems.append(f"{place}: {what}")

    # 1. The physics: a pure, documented function of the model (E*, R*, M*, eta).
    parameters = code.parameters
    ok = callable(parameters) and parameters.__module__ == engine_parameters.__name__ and bool(parameters.__doc__)
    check("contact_model/engine_parameters.py", ok, f"no documented parameters function of {name}")
    if ok:
        check("contact_model/engine_parameters.py",
              list(inspect.signature(parameters).parameters) == ["E", "R", "M", "eta"],
              f"{parameters.__name__} does not take (E, R, M, eta)")
        pair = steel_pair("sphere-sphere")
        values = code.contact_parameters(pair)
        check("contact_model/engine_parameters.py", values and all(math.isfinite(v) for v in values.values()),
              f"{parameters.__name__} gives no finite parameters")
    # 2. The deck.
    decks = [f for pattern in code.decks for f in glob(str(ROOT / pattern))]
    check(f"cases/decks/{name}/", decks and all(Path(f).is_relative_to(ROOT / "cases" / "decks" / name)
                                                for f in decks), f"no deck of {name} where its entry says")
    # 3. The driver.
    module, _, function = code.driver.partition(":")
    check(f"engines/{name}.py", (module, function) == (f"engines.{name}", f"run_{name}")
          and (ROOT / "engines" / f"{name}.py").exists(), f"no driver run_{name}")
    if not problems or (ROOT / "engines" / f"{name}.py").exists():
        try:
            runner = code.runner()
            check(f"engines/{name}.py", {"specs", "workdir", "executable", "timeout_floor_s"}
                  <= set(inspect.signature(runner).parameters), f"run_{name} does not take the sweep's arguments")
        except (ImportError, AttributeError) as err:
            check(f"engines/{name}.py", False, f"its driver cannot be imported ({err})")
    # 4. The registry entry.
    check("engines/codes.py", code.name == name and code.install_hint and code.default_law and code.processes >= 1
          and code.title and code.integrator, f"the entry of {name} is incomplete (install hint, default law, "
                                              "processes, title, integrator)")
    check("engines/codes.py", code.keyword in KEYWORDS and KEYWORDS[code.keyword].code == name
          and set(code.unavailable) <= set(LAWS)
          and all(code.unavailable.values()), f"the keyword or laws of {name} are not the registries'")
    check("engines/codes.py", code.banner.pattern.startswith("^") and code.version_args
          and min(code.cost.start_s, code.cost.per_run_s, code.cost.per_step_s) > 0,
          f"the banner, version arguments or cost model of {name}")
    # 5-7. A default build the Makefile installs, whose version the tests know; or, for a code the
    # default study leaves out (its cost), the one config entry a user adds, shown in docs/engines.md.
    builds = [b for b in _builds() if b["code"] == name]
    if code.build_entry:
        entry = yaml.safe_load(code.build_entry)
        check("engines/codes.py", entry.get("code") == name and code.left_out and not builds,
              f"the build entry of {name} is not its own, says not why it is left out, or is in builds: too")
        check("docs/engines.md", code.build_entry in (ROOT / "docs" / "engines.md").read_text(),
              f"does not show the build entry of {name} ({code.build_entry})")
        target = re.search(r"`make ([\w.-]+)`", code.install_hint)
        check("Makefile", target and re.search(rf"^{re.escape(target[1])}:", MAKEFILE, re.M)
              and re.search(rf"^test: .*\b{re.escape(target[1])}\b", MAKEFILE, re.M),
              f"no target of `test` installs {name} (its install hint names none)")
        builds = [entry]
    else:
        check("config/config.yaml", builds, f"no build of {name} in builds:")
    for build in builds:
        exe = build["executable"]
        if code.build_entry:  # its Makefile target: checked above
            pass
        elif "/" in exe:  # a venv of the project's: a Makefile target makes it, and `test` depends on it
            venv = exe.split("/")[0]
            variable = re.search(rf"^(\w+) := {re.escape(venv)}$", MAKEFILE, re.M)
            target = variable and re.search(rf"^([\w.-]+): \$\({variable[1]}\)", MAKEFILE, re.M)
            check("Makefile", target and re.search(rf"^test: .*\b{re.escape(target[1])}\b", MAKEFILE, re.M),
                  f"no target of `test` makes {venv}")
        else:  # a Debian package: the `engines` target checks for it
            check("Makefile", f"command -v {exe} " in MAKEFILE, f"the `engines` target does not check for {exe}")
        known = OPTIONAL_VERSIONS if code.build_entry else VERSIONS
        check("tests/engine_cases.py", build["id"] in known, f"{'OPTIONAL_' * bool(code.build_entry)}VERSIONS has no "
                                                              f"{build['id']}")
    # 8. Its own tests, in the engine tier.
    own = ROOT / "tests" / f"test_engine_{name}.py"
    check(f"tests/test_engine_{name}.py", own.exists(), "missing")
    check("tests/conftest.py", tier_of(own.name) == "engine", f"{own.name} is not in the engine tier")
    # 9. Named where the codes are listed for a reader.
    for listing in LISTS:
        check(listing, code.title and code.title in (ROOT / listing).read_text(), f"does not name {code.title or name}")
    return problems


def test_the_checklist_names_every_place_this_test_checks():
    for place in ("contact_model/engine_parameters.py", "cases/decks/<code>/", "engines/<code>.py", "engines/codes.py",
                  "config/config.yaml", "Makefile", "tests/engine_cases.py", "tests/test_engine_drivers.py",
                  "tests/test_engine_<code>.py", *LISTS):
        assert place in CHECKLIST, place


@pytest.mark.parametrize("name", CODES)
def test_every_code_follows_the_recipe(name):
    assert recipe_problems(name, CODES[name]) == []


def test_a_code_added_to_the_registry_alone_fails_at_every_other_place(monkeypatch):
    """The recipe test is shown to catch what it claims: a dummy code, in the registry and
    nowhere else, is named at each place a new code must reach."""
    lammps = CODES["lammps"]
    dummy = EngineCode(name="dummy", banner=re.compile(r"^Dummy .*$", re.M), version_args=("--version",),
                       install_hint="none", parameters=lambda E, R, M, eta: {},
                       driver="engines.dummy:run_dummy", decks=("cases/decks/dummy/*.in",), cost=lammps.cost,
                       default_law="none", title="DummyDEM", integrator="velocity Verlet")
    monkeypatch.setitem(CODES, "dummy", dummy)
    problems = recipe_problems("dummy", dummy)
    places = [p.split(":")[0] for p in problems]
    for place in ("contact_model/engine_parameters.py", "cases/decks/dummy/", "engines/dummy.py",
                  "config/config.yaml", "tests/test_engine_dummy.py", *LISTS):
        assert place in places, (place, problems)
    # Its test file would be an engine test without an entry of its own.
    assert tier_of("test_engine_dummy.py") == "engine"
