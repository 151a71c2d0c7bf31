"""What every engine driver does alike, run for real in each code of engines/codes.py: a missing
executable is refused naming how to install it; a deck that crashes names the engine's log; a
run whose bodies never touch fails on its own while the other runs of the sweep land. What only
one code does is in its own tests/test_engine_<code>.py."""

import shutil
from pathlib import Path

import pytest
import yaml

from contact_model import GATED_LAWS
from engine_cases import VELOCITY, missing, steel_pair
from engines import EngineMissing, EngineRunFailed, RunSpec
from engines.codes import CODES

ROOT = Path(__file__).resolve().parents[1]
#: Each code's first build of the default study (config/config.yaml), or its documented build entry
#: (`EngineCode.build_entry`, OpenFOAM): the executable tested.
EXECUTABLE = {}
for _build in yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"]:
    exe = _build["executable"]
    EXECUTABLE.setdefault(_build["code"], str(ROOT / exe) if "/" in exe else exe)
for _name, _code in CODES.items():  # a code the default study leaves out: the build entry docs/engines.md shows
    if _name not in EXECUTABLE and _code.build_entry:
        EXECUTABLE[_name] = yaml.safe_load(_code.build_entry)["executable"]
#: The codes driven by a Python deck of the project's (engines.driven_sweep): their deck can be
#: broken on purpose. LIGGGHTS and LAMMPS read input scripts (their crash: test_engine_stops).
DRIVEN = [name for name in CODES if hasattr(CODES[name].runner().__globals__.get("DRIVER"), "read_text")]


def needs(name):
    if shutil.which(EXECUTABLE[name]) is None:
        missing(f"{EXECUTABLE[name]} is not installed; {CODES[name].install_hint}")


def run(name, specs, workdir, **kw):
    return CODES[name].runner()(specs, workdir, executable=kw.pop("executable", EXECUTABLE[name]), **kw)


def law_of(name):
    """The first gated law the code can express (YADE: viscoelastic, ESyS: clipped, Kratos: elastic)."""
    return next(law for law in GATED_LAWS if law not in CODES[name].unavailable)


@pytest.mark.parametrize("name", CODES)
def test_missing_engine_names_how_to_install_it(name, tmp_path):
    spec = RunSpec("steel", name, law_of(name), steel_pair("sphere-plane"), VELOCITY)
    with pytest.raises(EngineMissing) as refused:
        run(name, [spec], tmp_path, executable=f"{name}-not-installed")
    assert f"{name}-not-installed" in str(refused.value)
    assert CODES[name].install_hint.split("`")[1] in str(refused.value)  # e.g. sudo apt-get install yade


@pytest.mark.parametrize("name", DRIVEN)
def test_a_deck_that_crashes_names_the_engine_log_and_leaves_no_dump(name, tmp_path, monkeypatch):
    needs(name)
    module = __import__(f"engines.{name}", fromlist=["DRIVER"])
    broken = tmp_path / "collisions.py"
    broken.write_text(module.DRIVER.read_text().replace("import json", "import json\nraise SystemExit(3)", 1))
    monkeypatch.setattr(module, "DRIVER", broken)
    spec = RunSpec("steel", name, law_of(name), steel_pair("sphere-plane"), VELOCITY)
    with pytest.raises(EngineRunFailed, match=rf"{name} exited with status 3.*{name}\.log"):
        run(name, [spec], tmp_path / "out").raise_first()
    assert not (tmp_path / "out" / f"{spec.name}.csv").exists()


@pytest.mark.parametrize("name", CODES)
def test_a_run_that_never_touches_fails_alone_and_the_others_land(name, tmp_path, monkeypatch):
    needs(name)
    good = RunSpec("steel", name, law_of(name), steel_pair("sphere-plane"), VELOCITY)
    short = RunSpec("steel", name, law_of(name), steel_pair("sphere-sphere"), VELOCITY)
    real_steps = RunSpec.steps
    monkeypatch.setattr(RunSpec, "steps", lambda self: 10 if self is short else real_steps(self))
    sweep = run(name, [good, short], tmp_path)
    assert list(sweep.dumps) == [good.name] and (tmp_path / f"{good.name}.csv").exists()
    assert "never touch" in str(sweep.failures[short.name])
    assert not (tmp_path / f"{short.name}.csv").exists()
