"""OpenFOAM's cost per step through the study's driver, its case folders on the disk against a tmpfs.

OpenFOAM v1912 writes a time folder of ~35 small files every step (`writeInterval 1`: the driver
reads every step back, engines/openfoam.py). On this machine's disk that writing, not the solver,
was most of a run. The driver now runs its cases in a scratch folder on a tmpfs
(`engines.openfoam.scratch_folder`, /dev/shm) when one is writable; "disk" here is the same driver
with no tmpfs (`SCRATCH_PARENTS` empty: the cases in the work folder, as before).

One fixed small sweep (steel, K = 0.1: the shortest rung of ``default`` between two spheres and of
``elastic`` on the plane, as tests/test_engine_openfoam.py plans them; 2 runs, 574 steps), REPEATS
times, disk and tmpfs in turn within each repeat (so that a change of the machine's load hits both
alike). Per variant, the medians of, per step [ms]:

- wall: the sweep's wall time (`Sweep.engine_seconds`: writing the cases, blockMesh, the solver,
  the conversion, removing the cases);
- OpenFOAM CPU: user + system of blockMesh and the solver (this process's children);
- driver CPU: this process's own user + system over the sweep (the case files, the conversion
  `case_rows`, the dump, removing the case folder);

and the ratio disk / tmpfs of each, with the load average. Both variants' dumps are checked to be
byte-identical (sha256) every repeat. Run with `python -m benchmarks.openfoam_steps` (`make bench`;
OpenFOAM from `make openfoam`); it takes about a minute on an idle machine, several under load.
"""

from __future__ import annotations

import hashlib
import os
import resource
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

from contact_model import load_case
from engines import openfoam
from engines.builds import Build
from engines.plan import plan_runs

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 3
BUILD = Build("openfoam-v1912", "openfoam", openfoam.SOLVER)
VARIANTS = ("disk", "tmpfs")


def sweep_specs() -> list:
    """The shortest rung of each of the engine test's two ladders (steel, K = 0.1)."""
    plan = plan_runs(load_case(ROOT / "cases" / "steel.yaml"), [BUILD], laws=["elastic", "default"], K_grid=[0.1])
    shortest = {}
    for s in plan.runs:
        key = (s.law, s.pair.geometry)
        if key in {("default", "sphere-sphere"), ("elastic", "sphere-plane")}:
            if key not in shortest or s.steps() < shortest[key].steps():
                shortest[key] = s
    return list(shortest.values())


def cpu(who) -> float:
    """User + system seconds of `who` (resource.RUSAGE_SELF or RUSAGE_CHILDREN) so far."""
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


def run_once(specs, variant: str) -> tuple[dict, dict]:
    """({figure: seconds}, {run: dump sha256}) of one sweep with its cases on `variant`."""
    saved = openfoam.SCRATCH_PARENTS
    if variant == "disk":
        openfoam.SCRATCH_PARENTS = ()  # no tmpfs: scratch_folder falls back to the work folder
    try:
        with tempfile.TemporaryDirectory(prefix="hertz-openfoam-bench-") as work:
            own, children = cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN)
            sweep = openfoam.run_openfoam(specs, work).raise_first()
            figures = {"wall": sweep.engine_seconds, "OpenFOAM CPU": cpu(resource.RUSAGE_CHILDREN) - children,
                       "driver CPU": cpu(resource.RUSAGE_SELF) - own}
            sums = {s.name: hashlib.sha256(sweep.dumps[s.name].read_bytes()).hexdigest() for s in specs}
    finally:
        openfoam.SCRATCH_PARENTS = saved
    return figures, sums


def main() -> int:
    if shutil.which(openfoam.SOLVER) is None:
        print(f"openfoam_steps: {openfoam.SOLVER} is not installed (make openfoam); skipped")
        return 0
    specs = sweep_specs()
    steps = sum(s.steps() for s in specs)
    got = {v: [] for v in VARIANTS}
    loads = []
    for _ in range(REPEATS):
        sums = {}
        for v in VARIANTS:
            figures, sums[v] = run_once(specs, v)
            got[v].append(figures)
        loads.append(os.getloadavg()[0])
        if sums["disk"] != sums["tmpfs"]:
            print(f"openfoam_steps: the dumps differ between disk and tmpfs: {sums}", file=sys.stderr)
            return 1
    print(f"OpenFOAM v1912 per step through engines.openfoam, {len(specs)} runs of {steps} steps "
          f"(steel, K = 0.1), {REPEATS} runs each (medians; load {min(loads):.1f}-{max(loads):.1f}); "
          "dumps byte-identical")
    med = {v: {k: statistics.median(f[k] for f in got[v]) * 1e3 / steps for k in got[v][0]} for v in VARIANTS}
    for k in med["disk"]:
        print(f"  {k:13s}: disk {med['disk'][k]:7.2f} ms/step, tmpfs {med['tmpfs'][k]:7.2f} ms/step, "
              f"disk / tmpfs {med['disk'][k] / med['tmpfs'][k]:5.1f} x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
