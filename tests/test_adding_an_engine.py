"""docs/adding_an_engine.md holds for every engine code of engines/codes.py: each item of its
checklist is checked here, code by code, so that a code that misses one fails naming it."""

import inspect
import math
import re
from glob import glob
from pathlib import Path

import pytest
import yaml

from contact_model import CRITERIA, LAWS, engine_parameters
from engine_cases import VERSIONS, steel_pair
from engines.codes import CODES

ROOT = Path(__file__).resolve().parents[1]
CHECKLIST = (ROOT / "docs" / "adding_an_engine.md").read_text()
BUILDS = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"]
MAKEFILE = (ROOT / "Makefile").read_text()


def test_the_checklist_names_every_place_this_test_checks():
    for place in ("contact_model/engine_parameters.py", "cases/decks/<code>/", "engines/<code>.py", "engines/codes.py",
                  "config/config.yaml", "Makefile", "tests/engine_cases.py", "tests/test_engine_drivers.py"):
        assert place in CHECKLIST, place


@pytest.mark.parametrize("name", CODES)
def test_1_the_physics_is_a_pure_function_of_the_model(name):
    parameters = CODES[name].parameters
    assert parameters.__module__ == engine_parameters.__name__ and parameters.__doc__
    assert list(inspect.signature(parameters).parameters) == ["E", "R", "M", "eta"]
    pair = steel_pair("sphere-sphere")
    values = CODES[name].contact_parameters(pair)
    assert values and all(math.isfinite(v) for v in values.values())
    assert values == parameters(pair.E, pair.R, pair.M, pair.eta)  # the registry's call is the function's


@pytest.mark.parametrize("name", CODES)
def test_2_3_the_deck_and_the_driver_are_where_the_entry_says(name):
    code = CODES[name]
    decks = [f for pattern in code.decks for f in glob(str(ROOT / pattern))]
    assert decks and all(Path(f).is_relative_to(ROOT / "cases" / "decks" / name) for f in decks), code.decks
    module, function = code.driver.split(":")
    assert (module, function) == (f"engines.{name}", f"run_{name}")
    runner = code.runner()
    assert {"specs", "workdir", "executable", "timeout_floor_s"} <= set(inspect.signature(runner).parameters)


@pytest.mark.parametrize("name", CODES)
def test_4_the_entry_is_complete(name):
    code = CODES[name]
    assert code.name == name and code.install_hint and code.default_law and code.processes >= 1
    assert code.default_criterion in CRITERIA
    assert code.banner.pattern.startswith("^") and code.version_args
    assert set(code.unavailable) <= set(LAWS) and all(code.unavailable.values())
    assert min(code.cost.start_s, code.cost.per_run_s, code.cost.per_step_s) > 0


@pytest.mark.parametrize("name", CODES)
def test_5_6_7_a_default_build_that_the_makefile_installs_and_whose_version_is_known(name):
    builds = [b for b in BUILDS if b["code"] == name]
    assert builds, f"config/config.yaml has no build of {name}"
    for build in builds:
        exe = build["executable"]
        if "/" in exe:  # a venv of the project's: a Makefile target makes it, and `test` depends on it
            venv = exe.split("/")[0]
            variable = re.search(rf"^(\w+) := {re.escape(venv)}$", MAKEFILE, re.M)
            assert variable, f"the Makefile makes no {venv}"
            target = re.search(rf"^([\w.-]+): \$\({variable[1]}\)", MAKEFILE, re.M)
            assert target and re.search(rf"^test: .*\b{re.escape(target[1])}\b", MAKEFILE, re.M), exe
        else:  # a Debian package: the `engines` target checks for it
            assert f"command -v {exe} " in MAKEFILE, exe
        assert build["id"] in VERSIONS, f"tests/engine_cases.py VERSIONS has no {build['id']}"


@pytest.mark.parametrize("name", CODES)
def test_8_its_own_tests(name):
    assert (ROOT / "tests" / f"test_engine_{name}.py").exists()
