"""Wall time of the study (`snakemake -j2 all`, set-up excluded) and of one material, against
the engines' own process time.

Runs each target with --forceall REPEATS times and prints medians, plus the ratio of the
workflow's wall time to the sum of the engine processes' wall times (from the manifests).
Goals on the 2-core machine: full study <= 120 s, one material <= 20 s.
Run with `make bench` (it rewrites results/).
"""

import glob
import json
import statistics
import subprocess
import sys
import time

REPEATS = 3
TARGETS = (("one material (steel)", ["steel"], 20.0), ("full study (all)", ["all"], 120.0))


def engine_seconds(pattern):
    return sum(json.load(open(m))["engine_seconds"] for m in glob.glob(pattern))


def main():
    print(f"study wall time, snakemake -j2 --forceall, {REPEATS} runs each")
    for label, target, goal in TARGETS:
        walls, ratios = [], []
        for _ in range(REPEATS):
            t0 = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "snakemake", "-j2", "--forceall", *target],
                                  capture_output=True, text=True)
            wall = time.perf_counter() - t0
            if done.returncode != 0:
                print(done.stdout[-2000:], done.stderr[-2000:])
                raise SystemExit(f"snakemake {' '.join(target)} failed; see above")
            pattern = "results/steel/*/manifest.json" if target == ["steel"] else "results/*/*/manifest.json"
            walls.append(wall)
            ratios.append(wall / engine_seconds(pattern))
        med = statistics.median(walls)
        print(f"  {label:22s}: median {med:6.1f} s (min {min(walls):.1f}, max {max(walls):.1f}); "
              f"wall / engine-process time = {statistics.median(ratios):.2f}; goal <= {goal:.0f} s: "
              f"{'met' if med <= goal else 'NOT met'}")


if __name__ == "__main__":
    main()
