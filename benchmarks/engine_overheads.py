"""Where each engine build's seconds go per recorded sample: its process start-up, its own step,
and the record (reading the bodies' state every step, formatting and writing the rows).

For each build (LAMMPS 2025, Kratos 10.4, ESyS-Particle 2.3.5; `BUILDS`), REPEATS times in turn
(medians printed, the builds interleaved so that they share the machine's moments):

- per recorded sample: a sweep of the steel pair in both geometries (one law of the build),
  through `engines.run_sweep` as the study runs it, at two time steps (`FACTORS`); the cost of a
  sample is the difference of the two sweeps' wall times over the difference of their steps
  (one row per step), which cancels the process's start-up and the runs' set-up, and the ratio
  to LAMMPS 2025's (the goal: at most 2);
- start-up: the engine's process doing nothing (LAMMPS on an empty input; Kratos's Python
  importing Kratos and its DEMApplication; ESyS's `mpirun -np 2` making its LsmMpi and leaving);
- the engine's own step and the record (Kratos and ESyS, whose drivers are Python): a probe in
  the engine's own Python (`PROBES`) runs the build's driver up to its sweep (`SWEEP_MARKER`),
  and times runs of `PROBE_FACTOR` steps with the driver's loop, recording and not recording
  (ESyS: also stepping and fetching the bodies from the worker, `getParticleList`, without the
  Python of the record), and the writing of the rows. LAMMPS records inside its own loop (fix
  print): not separated.

Run with `python -m benchmarks.engine_overheads` (`make bench`); it takes a few minutes.

Measured on the 2-core VM, lightly loaded (LAMMPS 2025: 15-18 us per sample, start-up 0.27 s):
Kratos 10.4 57-60 us per sample (3.1-3.9 x; before its driver's fast loop 135-177 us), its own
step 30-39 us (two spheres), recording 4-6 us, writing 5 us, start-up 0.22 s and ~0.15 s per
run; ESyS 2.3.5 49-51 us (2.8-3.1 x), its own step 21-22 us, recording 27-30 us of which the
round trip to the worker is 14-16 us, start-up 0.5 s (mpirun, two ranks; one rank is refused:
'wrong number of processes'). Kratos's own step alone is about twice LAMMPS's whole sample, and
ESyS's step and fetch together are; neither reaches the 2 x goal through its Python API.
"""

import json
import math
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import yaml

from contact_model import Body, ContactPair
from contact_model.collision_scales import viscosity_for_dissipation
from engines import RunSpec, esys, kratos, run_sweep
from engines.builds import load_builds
from engines.engine_process import engine_environment

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 3
BUILDS = ("lammps-2025", "kratos-10.4", "esys-2.3.5")
BASELINE = "lammps-2025"
GOAL = 2.0  # per recorded sample, times the baseline's
#: One law per code (any the code runs: the laws differ in the force's formula only).
LAWS = {"lammps": "viscoelastic", "kratos": "elastic", "esys": "viscoelastic_clipped"}
GEOMETRIES = ("sphere-sphere", "sphere-plane")
FACTORS = (300, 6000)  # time_step_factor of the two sweeps: dt ~ T_e / factor (their difference: ~14 000 samples)
PROBE_FACTOR = 1000
# The steel pair of the engine tests (tests/engine_cases.py): R = 0.635 cm, E* = 109 GPa, K = 0.1.
RADIUS, DENSITY, MODULUS, VELOCITY, K = 0.635e-2, 7800.0, 109e9, 1.0, 0.1


def steel_pair(geometry: str) -> ContactPair:
    sphere = Body(RADIUS, DENSITY)
    other = sphere if geometry == "sphere-sphere" else Body(math.inf, math.inf)
    elastic = ContactPair(geometry, sphere, other, MODULUS, 0.0)
    return ContactPair(geometry, sphere, other, MODULUS,
                       viscosity_for_dissipation(MODULUS, elastic.R, elastic.M, VELOCITY, K))


def sweep_specs(build, factor) -> list[RunSpec]:
    return [RunSpec("overheads", build.code, LAWS[build.code], steel_pair(g), VELOCITY, time_step_factor=factor,
                    build=build.id) for g in GEOMETRIES]


def sweep_seconds(build, factor) -> tuple[float, int]:
    """(wall seconds, recorded samples) of one sweep of `build` through engines.run_sweep."""
    specs = sweep_specs(build, factor)
    with tempfile.TemporaryDirectory() as work:
        t0 = time.perf_counter()
        run_sweep(build, specs, work).raise_first()
        return time.perf_counter() - t0, sum(s.steps() for s in specs)


#: The line of the drivers (cases/decks/{kratos,esys}/collisions.py) where their sweep starts: a
#: probe runs a driver up to it, for its functions.
SWEEP_MARKER = "# The sweep (benchmarks/engine_overheads.py runs this file up to this line"
# The probes run in the engine's own Python; argv: driver, job file. They print one JSON line.
STARTUP = {
    "kratos": "import KratosMultiphysics, KratosMultiphysics.DEMApplication\n",
    "esys": "from esys.lsm import LsmMpi\nLsmMpi(numWorkerProcesses=1, mpiDimList=[1, 1, 1]).exit()\n",
}
PROBES = {
    "kratos": r'''
import json, shutil, sys, time
import KratosMultiphysics as KM
KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
sys.argv = sys.argv[1:]  # the driver reads its job from argv[1]
driver = {"__name__": "engine_overheads", "__file__": sys.argv[0]}
text = open(sys.argv[0]).read()
exec(compile(text[:text.index(%(marker)r)], sys.argv[0], "exec"), driver)
run = driver["JOB"]["runs"][0]
out = {"step": [], "record": [], "write": []}
for _ in range(%(repeats)d):
    for recording in (False, True):
        stage, folder = driver["make_stage"](run)
        stage.recording = recording
        stage.Initialize()
        if not stage.fast:
            raise SystemExit("the driver's fast loop is off on this Kratos")
        t0 = time.perf_counter()
        stage.RunSolutionLoop()
        out["record" if recording else "step"].append((time.perf_counter() - t0) / run["steps"])
        stage.Finalize()
        if recording:
            t0 = time.perf_counter()
            driver["write_record"](run, stage.states)
            out["write"].append((time.perf_counter() - t0) / run["steps"])
        shutil.rmtree(folder)
print("PROBE " + json.dumps(out), flush=True)
''',
    "esys": r'''
import json, sys, time
sys.argv = sys.argv[1:]  # the driver reads its job from argv[1]
driver = {"__name__": "engine_overheads", "__file__": sys.argv[0]}
text = open(sys.argv[0]).read()
exec(compile(text[:text.index(%(marker)r)], sys.argv[0], "exec"), driver)
run_one = driver["run_one"]
record = run_one.__globals__["record"]
sim = driver["make_simulation"]()


def step_only(sim, run, a, b, R2):
    for n in range(int(run["steps"])):
        sim.runTimeStep()
    return []


def step_and_fetch(sim, run, a, b, R2):
    fetch, ids = sim.getParticleList, [a, b]
    for n in range(int(run["steps"])):
        sim.runTimeStep()
        fetch(ids)
    return []


out = {"step": [], "fetch": [], "record": [], "write": []}
for k, run in enumerate(driver["RUNS"]):
    mode = ("step", "fetch", "record")[k %% 3]
    run_one.__globals__["record"] = {"step": step_only, "fetch": step_and_fetch, "record": record}[mode]
    t0 = time.perf_counter()
    rows = run_one(sim, k, run)
    out[mode].append((time.perf_counter() - t0) / run["steps"])
    if mode == "record":
        t0 = time.perf_counter()
        driver["write_rows"](run["out"], rows)
        out["write"].append((time.perf_counter() - t0) / run["steps"])
sim.exit()
print("PROBE " + json.dumps(out), flush=True)
''',
}


def engine_command(build, script: Path, *args: str) -> tuple[list[str], dict]:
    """How the runner starts `build` on a Python `script` (Kratos, ESyS): (command, environment)."""
    if build.code == "kratos":
        return [build.executable, str(script), *args], engine_environment(kratos.ENVIRONMENT)
    return (esys.mpirun_command("mpirun", build.executable, script, *args),
            engine_environment({"PYTHONUNBUFFERED": "1", "OMPI_MCA_mpi_yield_when_idle": "1"}))


def start_up_seconds(build, work: Path) -> float:
    """Wall seconds of the build's process doing nothing."""
    if build.code == "lammps":
        empty = work / "empty.in"
        empty.write_text("")
        cmd, env = [build.executable, "-log", "none", "-in", str(empty)], engine_environment()
    else:
        script = work / f"{build.code}-startup.py"
        script.write_text(STARTUP[build.code])
        cmd, env = engine_command(build, script)
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True,
                   timeout=120)
    return time.perf_counter() - t0


def probe(build, work: Path) -> dict:
    """{part: seconds per step} medians of the probe's REPEATS runs of PROBE_FACTOR steps (sphere-sphere)."""
    module = {"kratos": kratos, "esys": esys}[build.code]
    spec = sweep_specs(build, PROBE_FACTOR)[0]
    runs = []
    for i in range(REPEATS * (3 if build.code == "esys" else 1)):  # ESyS: one run per mode and repeat
        entry = module.job_entry(spec, work / f"probe-{i}.csv")
        runs.append({**entry, "name": f"{entry['name']}-{i}"})
    job = work / f"{build.code}-probe-job.json"
    job.write_text(json.dumps({"runs": runs, "status": str(work / "status.json"),
                               "progress": str(work / "progress.txt")}))
    script = work / f"{build.code}-probe.py"
    script.write_text(PROBES[build.code] % {"repeats": REPEATS, "marker": SWEEP_MARKER})
    cmd, env = engine_command(build, script, str(module.DRIVER), str(job))
    done = subprocess.run(cmd, env=env, cwd=work, capture_output=True, text=True, timeout=600)
    lines = [line for line in done.stdout.splitlines() if line.startswith("PROBE ")]
    if not lines:
        raise SystemExit(f"the {build.id} probe failed:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    return {part: statistics.median(values) for part, values in json.loads(lines[-1][6:]).items()}


def main():
    builds = {b.id: b for b in load_builds(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"],
                                           ROOT)}
    chosen = [builds[b] for b in BUILDS]
    per_sample, fixed, start_up = ({b.id: [] for b in chosen} for _ in range(3))
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for _ in range(REPEATS):
            for build in chosen:
                (t1, n1), (t2, n2) = (sweep_seconds(build, f) for f in FACTORS)
                per_sample[build.id].append((t2 - t1) / (n2 - n1))
                fixed[build.id].append(t1 - n1 * per_sample[build.id][-1])
                start_up[build.id].append(start_up_seconds(build, work))
        probes = {b.id: probe(b, work) for b in chosen if b.code in PROBES}
    base = statistics.median(per_sample[BASELINE])
    print(f"engine overheads: steel, {'/'.join(GEOMETRIES)}, sweeps at dt = T_e/{FACTORS[0]} and T_e/{FACTORS[1]} "
          f"(medians of {REPEATS}; {os.cpu_count()} cores)")
    for build in chosen:
        sample = statistics.median(per_sample[build.id])
        ratio = sample / base
        print(f"  {build.id:12s} per recorded sample {sample * 1e6:7.1f} us = {ratio:4.2f} x {BASELINE} "
              f"(goal <= {GOAL:g}: {'met' if ratio <= GOAL else 'NOT met'}); start-up "
              f"{statistics.median(start_up[build.id]):5.2f} s (the process alone), "
              f"{statistics.median(fixed[build.id]):5.2f} s per sweep of {len(GEOMETRIES)} runs (fitted)")
        p = probes.get(build.id)
        if p:
            recording = f"recording {(p['record'] - p['step']) * 1e6:6.1f} us"
            if "fetch" in p:
                recording += f" (of which fetching the bodies from the worker {(p['fetch'] - p['step']) * 1e6:.1f} us)"
            parts = [f"own step {p['step'] * 1e6:6.1f} us", recording,
                     f"writing {p['write'] * 1e6:5.1f} us per step (driver probe, {PROBE_FACTOR} steps a run)"]
            print("  " + " " * 12 + " " + ", ".join(parts))


if __name__ == "__main__":
    main()
