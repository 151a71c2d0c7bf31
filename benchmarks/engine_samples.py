"""Cost per recorded sample of each engine build, against LAMMPS 2025's (the issue "The study at
its engines' speed": every build within 2x LAMMPS 2025's).

One fixed small sweep per build (steel, K = 0.1, V = 1 m/s; viscoelastic, viscoelastic_clipped and
the code's default law in both geometries: 6 runs), run through the project's own `engines.run_sweep`
in one process, REPEATS times in a row, build after build within each repeat (so that a change in the
machine's load hits every build alike). Prints per build the medians of: the engine process's wall
time [s], the samples it recorded (rows of its dumps), us per sample, and the ratio of that to
lammps-2025's. The process time includes the build's start-up (YADE: ~1-2 s of its Python), which a
sweep this small does not amortise as the study's larger sweeps do; the ratio to lammps-2025 is the
figure to read. Run with `make bench` or `python -m benchmarks.engine_samples [build ...]`.
"""

import math
import statistics
import sys
import tempfile
from pathlib import Path

import yaml

from contact_model import Body, ContactPair
from contact_model.collision_scales import viscosity_for_dissipation
from engines import RunSpec, run_sweep
from engines.builds import load_builds
from engines.codes import CODES
from records.dump_file import read_dump
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 3
#: Every build of the default study (config `builds:`), the baseline among them.
BUILDS = ("liggghts-3.8", "yade-2023", "yade-2025", "lammps-2021", "lammps-2025", "esys-2.3.5", "kratos-10.4")
BASELINE = "lammps-2025"
GOAL = 2.0  # x the baseline's us per sample
#: Steel (tests/engine_cases.py's case): R = 0.635 cm, 7800 kg/m^3, E* = 109 GPa, V = 1 m/s, K = 0.1.
RADIUS, DENSITY, MODULUS, VELOCITY, K = 0.635e-2, 7800.0, 109e9, 1.0, 0.1
LAWS = ("viscoelastic", "viscoelastic_clipped", "default")


def steel_pair(geometry: str) -> ContactPair:
    sphere = Body(RADIUS, DENSITY)
    other = sphere if geometry == "sphere-sphere" else Body(math.inf, math.inf)
    elastic = ContactPair(geometry, sphere, other, MODULUS, 0.0)
    eta = viscosity_for_dissipation(MODULUS, elastic.R, elastic.M, VELOCITY, K)
    return ContactPair(geometry, sphere, other, MODULUS, eta)


def sweep_specs(build) -> list[RunSpec]:
    eps = solve_collision(K)["eps_F0"]
    # the laws the code can express (ESyS: no viscoelastic x0 trajectory; engines.codes `unavailable`)
    return [RunSpec("bench", build.code, law, steel_pair(g), VELOCITY, build=build.id,
                    matched_restitution=eps if law == "default" else None)
            for g in ("sphere-sphere", "sphere-plane") for law in LAWS if law not in CODES[build.code].unavailable]


def run_once(build) -> tuple[float, int]:
    """(engine process seconds, samples recorded) of one sweep of `build`."""
    specs = sweep_specs(build)
    with tempfile.TemporaryDirectory(prefix=f"hertz-samples-{build.id}-") as workdir:
        sweep = run_sweep(build, specs, workdir).raise_first()
        samples = sum(len(read_dump(sweep.dumps[s.name])[1]["time"]) for s in specs)
    return sweep.engine_seconds, samples


def main(ids=BUILDS):
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    builds = {b.id: b for b in load_builds(config["builds"], ROOT)}
    ids = list(dict.fromkeys([*ids, BASELINE]))
    runs = {i: [] for i in ids}
    for _ in range(REPEATS):
        for i in ids:
            runs[i].append(run_once(builds[i]))
    cost = {i: statistics.median(s / n * 1e6 for s, n in runs[i]) for i in ids}
    print(f"engine cost per recorded sample, one sweep of up to {len(LAWS) * 2} runs per build "
          f"(steel, K = {K}), {REPEATS} runs each (medians)")
    for i in ids:
        seconds = statistics.median(s for s, _ in runs[i])
        samples = statistics.median(n for _, n in runs[i])
        ratio = cost[i] / cost[BASELINE]
        print(f"  {i:12s}: process {seconds:6.2f} s, {samples:7.0f} samples, {cost[i]:6.1f} us/sample, "
              f"{ratio:5.2f} x {BASELINE} (goal <= {GOAL:g}: {'met' if ratio <= GOAL else 'NOT met'})")


if __name__ == "__main__":
    main(sys.argv[1:] or BUILDS)
