"""Hung and crashed engines, for real: the runner stops the engine at its time limit and says so, the log holds
what the engine printed, the error names engine, build, case, run and the last log lines, no
process of the engine survives, and no dump is written for a run that did not complete.

The engines are the installed ones, run through a wrapper script (the runners' `executable`)
that writes its pid (the process group: the runners start a new session) and makes the real
engine hang or crash in the second of three runs."""

import dataclasses
import math
import re
import shutil
import stat
import time
from pathlib import Path

import pytest

from engine_cases import VELOCITY, VERSIONS, require_engine, steel_pair
from engines import RunSpec, engine_process, esys, kratos, yade
from engines import codes
from engines.codes import EngineCost
from engines.engine_process import time_limit
from engines.lammps import run_lammps
from engines.liggghts import run_liggghts

CASE = "stop-case"
#: The build of each script engine these tests run (its banner: engine_cases.VERSIONS).
DEFAULT_BUILD = {"liggghts": "liggghts-3.8", "lammps": "lammps-2021"}
SCRIPT_ENGINES = {"liggghts": ("liggghts", "liggghts", run_liggghts), "lammps": ("lmp", "lammps", run_lammps)}
#: What the wrapper puts before the second run's deck: a hang (a child that sleeps, so that
#: killing only the engine would leave it behind) or a real SIGSEGV of the engine.
INJECT = {"hang": "shell sleep 1000", "crash": 'shell "kill -SEGV $PPID"'}


def three_runs(engine: str) -> list[RunSpec]:
    return [RunSpec(CASE, engine, "viscoelastic", steel_pair(g, K), VELOCITY, time_step_factor=200)
            for g, K in (("sphere-plane", 0.1), ("sphere-sphere", 0.1), ("sphere-plane", 0.2))]


def executable(path: Path, text: str) -> str:
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


def script_engine_wrapper(tmp_path: Path, real: str, inject: str) -> str:
    """Runs the real engine; with `-in`, on a copy of the sweep script with `inject` before the
    second `include` (inside the second run). Version queries (no -in) go straight through."""
    (tmp_path / "inject.in").write_text(inject)
    return executable(tmp_path / "engine-wrapper.sh", f"""#!/bin/bash
echo $$ > {tmp_path / 'wrapper.pid'}
args=("$@")
for i in "${{!args[@]}}"; do
  if [ "${{args[$i]}}" = "-in" ]; then
    script="${{args[$((i + 1))]}}"
    awk -v inject="$(cat {tmp_path / 'inject.in'})" '/^include /{{n++; if (n == 2) print inject}} {{print}}' \
      "$script" > "$script.wrapped"
    args[$((i + 1))]="$script.wrapped"
  fi
done
echo "wrapper: starting the real engine"
"{real}" "${{args[@]}}"
""")


def group_members(pgid: int) -> list[str]:
    """Live (not zombie) processes in process group `pgid`, as 'pid command'."""
    found = []
    for stat_file in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat_file.read_text()
        except OSError:
            continue
        command, fields = text[text.index("(") + 1:text.rindex(")")], text[text.rindex(")") + 2:].split()
        if int(fields[2]) == pgid and fields[0] != "Z":
            found.append(f"{stat_file.parent.name} {command}")
    return found


def assert_group_gone(pid_file: Path):
    pgid = int(pid_file.read_text())
    deadline = time.monotonic() + 10  # SIGKILLed processes vanish at once; allow for reaping
    while group_members(pgid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert group_members(pgid) == [], "engine processes survived"


def assert_stopped_in_second_run(sweep, specs, workdir: Path, engine: str, build: str, what: str, last_words: str):
    """... and `last_words` are in the log's last lines, which the message quotes."""
    first, second, third = specs
    log = workdir / f"{engine}.log"
    assert log.exists()
    printed = log.read_text()
    assert "wrapper: starting the real engine" in printed  # streamed from the start
    assert f"RUN {first.name}" in printed and f"RUN {second.name}" in printed
    assert f"RUN {third.name}" not in printed
    assert list(sweep.dumps) == [first.name]  # the run before the stop landed
    assert (workdir / f"{first.name}.csv").exists()
    for spec in (second, third):
        assert not (workdir / f"{spec.name}.csv").exists()
    err = sweep.failures[second.name]
    message = str(err)
    assert err.engine == engine and err.case == CASE and err.run_name == second.name
    assert f"{engine} {what}" in message and build in message
    assert f"case {CASE}" in message and f"run {second.name}" in message and str(log) in message
    tail = [line.rstrip() for line in printed.splitlines() if line.strip()][-10:]
    assert list(err.log_tail) == tail and any(last_words in line for line in tail)
    for line in tail:
        assert line in message
    assert f"not run: {engine} stopped in {second.name}" in str(sweep.failures[third.name])
    return printed, message


#: The time limit of the crash tests: a crash ends the sweep at once, so the limit only bounds a
#: test whose engine failed to crash, and can be generous on a loaded machine.
CRASH_FLOOR_S = 120.0


def hang_floor(run_sweep, first: RunSpec, workdir: Path, at_least: float) -> float:
    """The time limit of a hang test: `at_least`, or five times one real sweep of `first` alone
    (start-up included) on this machine now, whichever is longer, in whole seconds. The hung sweep
    must reach its second run before the limit, and a fixed few seconds did not on a loaded CI
    machine (LIGGGHTS and YADE had not printed their first run after 3 and 10 s)."""
    started = time.monotonic()
    sweep = run_sweep([first], workdir)
    assert list(sweep.dumps) == [first.name], sweep.failures
    return float(max(at_least, math.ceil(5 * (time.monotonic() - started))))


@pytest.fixture
def no_expected_cost(monkeypatch):
    """Make the time limit the floor, so that a hung engine is killed after a few seconds."""
    for name, c in list(codes.CODES.items()):
        monkeypatch.setitem(codes.CODES, name, dataclasses.replace(c, cost=EngineCost(0.0, 0.0, 0.0)))


@pytest.mark.parametrize("engine", sorted(SCRIPT_ENGINES))
def test_hung_script_engine_is_killed_with_its_children(tmp_path, engine, no_expected_cost):
    exe, package, runner = SCRIPT_ENGINES[engine]
    require_engine(exe, package)
    wrapper = script_engine_wrapper(tmp_path, shutil.which(exe), INJECT["hang"])
    specs = three_runs(engine)
    floor = hang_floor(runner, specs[0], tmp_path / "timing", at_least=3.0)
    sweep = runner(specs, tmp_path / "out", executable=wrapper, timeout_floor_s=floor)
    build = VERSIONS[DEFAULT_BUILD[engine]]
    printed, _ = assert_stopped_in_second_run(sweep, specs, tmp_path / "out", engine, build,
                                              f"did not finish within its time limit of {floor:.3g} s",
                                              "shell sleep 1000")
    assert "shell sleep 1000" in printed  # the engine echoed the command it hung in
    assert_group_gone(tmp_path / "wrapper.pid")


@pytest.mark.parametrize("engine", sorted(SCRIPT_ENGINES))
def test_crashed_script_engine_names_the_signal_and_leaves_no_dump(tmp_path, engine):
    exe, package, runner = SCRIPT_ENGINES[engine]
    require_engine(exe, package)
    wrapper = script_engine_wrapper(tmp_path, shutil.which(exe), INJECT["crash"])
    specs = three_runs(engine)
    sweep = runner(specs, tmp_path / "out", executable=wrapper, timeout_floor_s=CRASH_FLOOR_S)
    build = VERSIONS[DEFAULT_BUILD[engine]]
    printed, _ = assert_stopped_in_second_run(sweep, specs, tmp_path / "out", engine, build,
                                              "exited with signal SIGSEGV", "Segmentation fault")
    # The wrapper's shell reports the signal last, always. MPI's own backtrace ("End of error
    # message") usually comes before it, but not always: once in CI it was missing from the log.
    assert_group_gone(tmp_path / "wrapper.pid")


def driver_stopping_in(module, tmp_path: Path, run: str, how: str) -> Path:
    """The study's driver script of a Python-driven engine `module` (yade, esys, kratos), made to
    hang or to crash (SIGSEGV of its process) when `run` starts."""
    stop = "time.sleep(1000)" if how == "hang" else "import os, signal; os.kill(os.getpid(), signal.SIGSEGV)"
    text = module.DRIVER.read_text()
    # The line that starts a run, at the sweep loop's indent (module level in the YADE and ESyS decks, in
    # a function in Kratos's, which oblique.py shares): the stop goes right after it, at that indent.
    anchors = re.findall(r'^( *)(print\("RUN %s" % run\["name"\], flush=True\)\n)', text, re.M)
    assert len(anchors) == 1, anchors
    indent, line = anchors[0]
    driver = tmp_path / "collisions.py"
    driver.write_text(text.replace(indent + line, indent + line + f'{indent}if run["name"] == {run!r}:\n'
                                                                f'{indent}    {stop}\n'))
    return driver


def driven_wrapper(tmp_path: Path, real: str) -> str:
    """Writes its pid, leaves a sleeping child behind, and runs the real engine `real`."""
    return executable(tmp_path / "wrapper.sh", f"""#!/bin/bash
echo $$ > {tmp_path / 'wrapper.pid'}
sleep 1000 &
echo "wrapper: starting the real engine"
"{real}" "$@"
""")


@pytest.mark.parametrize("how", ["hang", "crash"])
def test_hung_or_crashed_yade(tmp_path, monkeypatch, how, no_expected_cost):
    require_engine("yade", "yade")
    specs = three_runs("yade")
    monkeypatch.setattr(yade, "DRIVER", driver_stopping_in(yade, tmp_path, specs[1].name, how))
    floor = hang_floor(yade.run_yade, specs[0], tmp_path / "timing", at_least=10.0) if how == "hang" else CRASH_FLOOR_S
    sweep = yade.run_yade(specs, tmp_path / "out", executable=driven_wrapper(tmp_path, shutil.which("yade")),
                          timeout_floor_s=floor)
    what = f"did not finish within its time limit of {floor:.3g} s" if how == "hang" else "exited with signal SIGSEGV"
    yade_build = "YADE " + VERSIONS["yade-2023"].removeprefix("Yade version: ")  # as its driver prints it
    assert_stopped_in_second_run(sweep, specs, tmp_path / "out", "yade", yade_build, what, f"RUN {specs[1].name}")
    assert_group_gone(tmp_path / "wrapper.pid")


@pytest.mark.parametrize("how", ["hang", "crash"])
def test_hung_or_crashed_kratos(tmp_path, monkeypatch, how, no_expected_cost):
    if not Path(kratos.EXECUTABLE).exists():
        pytest.skip("Kratos is not installed; install it with: make kratos-10.4 (make test does this)")
    specs = [RunSpec(CASE, "kratos", "elastic", steel_pair(g), v,
                     time_step_factor=200)  # Kratos has no viscoelastic law
             for g, v in (("sphere-plane", VELOCITY), ("sphere-sphere", VELOCITY), ("sphere-plane", 2 * VELOCITY))]
    monkeypatch.setattr(kratos, "DRIVER", driver_stopping_in(kratos, tmp_path, specs[1].name, how))
    floor = (hang_floor(kratos.run_kratos, specs[0], tmp_path / "timing", at_least=10.0) if how == "hang"
             else CRASH_FLOOR_S)
    sweep = kratos.run_kratos(specs, tmp_path / "out", executable=driven_wrapper(tmp_path, kratos.EXECUTABLE),
                              timeout_floor_s=floor)
    what = f"did not finish within its time limit of {floor:.3g} s" if how == "hang" else "exited with signal SIGSEGV"
    assert_stopped_in_second_run(sweep, specs, tmp_path / "out", "kratos", VERSIONS["kratos-10.4"], what,
                                 f"RUN {specs[1].name}")
    assert_group_gone(tmp_path / "wrapper.pid")


def test_time_limit_scales_with_the_sweep_above_the_floor():
    specs = three_runs("liggghts")
    small = time_limit("liggghts", specs, floor_s=1.0)
    assert small > 1.0  # the expected length, not the floor
    assert time_limit("liggghts", specs, floor_s=1000.0) == 1000.0
    longer = [RunSpec(CASE, "liggghts", "viscoelastic", s.pair, VELOCITY, time_step_factor=100_000) for s in specs]
    extra_steps = sum(s.steps() for s in longer) - sum(s.steps() for s in specs)
    assert extra_steps > 100_000
    assert time_limit("liggghts", longer, floor_s=1.0) - small == pytest.approx(
        engine_process.SAFETY_FACTOR * codes.CODES["liggghts"].cost.per_step_s * extra_steps)
    assert time_limit("yade", [s.__class__(CASE, "yade", s.law, s.pair, VELOCITY) for s in specs], 1.0) > small
    with pytest.raises(ValueError, match="positive"):
        time_limit("lammps", specs, floor_s=0.0)


def esys_wrapper(tmp_path: Path) -> str:
    """In place of esysparticle under mpirun (both ranks run it): the master rank writes its pid
    and leaves a sleeping child behind; both run the real esysparticle."""
    return executable(tmp_path / "esys-wrapper.sh", f"""#!/bin/bash
if [ "${{OMPI_COMM_WORLD_RANK:-0}}" = 0 ]; then
  echo $$ > {tmp_path / 'wrapper.pid'}
  sleep 1000 &
  echo "wrapper: starting the real engine"
fi
"{shutil.which('esysparticle')}" "$@"
""")


@pytest.mark.parametrize("how", ["hang", "crash"])
def test_hung_or_crashed_esys(tmp_path, monkeypatch, how, no_expected_cost):
    """mpirun puts each rank in a process group of its own: killing mpirun's group must still
    leave no rank (nor a rank's child) behind."""
    require_engine("esysparticle", "esys-particle")
    specs = [RunSpec(CASE, "esys", "viscoelastic_clipped", s.pair, VELOCITY, time_step_factor=200)
             for s in three_runs("liggghts")]
    monkeypatch.setattr(esys, "DRIVER", driver_stopping_in(esys, tmp_path, specs[1].name, how))
    floor = hang_floor(esys.run_esys, specs[0], tmp_path / "timing", at_least=10.0) if how == "hang" else CRASH_FLOOR_S
    sweep = esys.run_esys(specs, tmp_path / "out", executable=esys_wrapper(tmp_path), timeout_floor_s=floor)
    # A crashed rank: mpirun returns its status, 128 + 11, and prints why it aborted the job.
    what = (f"did not finish within its time limit of {floor:.3g} s" if how == "hang"
            else "exited with signal SIGSEGV (status 139)")
    assert_stopped_in_second_run(sweep, specs, tmp_path / "out", "esys", VERSIONS["esys-2.3.5"], what,
                                 f"RUN {specs[1].name}" if how == "hang" else "Exit code:    139")
    assert_group_gone(tmp_path / "wrapper.pid")
    deadline = time.monotonic() + 10
    while processes_mentioning(str(tmp_path)) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert processes_mentioning(str(tmp_path)) == [], "ESyS processes survived"


def processes_mentioning(text: str) -> list[str]:
    """Live processes whose command line contains `text`, as 'pid command line'."""
    found = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            args = cmdline.read_bytes().replace(b"\0", b" ").decode(errors="replace")
            state = (cmdline.parent / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if text in args and state != "Z":
            found.append(f"{cmdline.parent.name} {args}")
    return found
