"""Wall time and peak memory of the study (`snakemake -j2 all`, set-up excluded) and of one
material (`snakemake -j2 steel`), against the engines' own process time.

Runs each target with --forceall REPEATS times in a row and prints medians, and the ratio of the
workflow's wall time to the sum of the engine processes' wall times (from the manifests of the
run), which cancels the machine's speed. Peak memory: the largest sum of the resident set sizes
of snakemake and all its descendants, sampled every 50 ms from /proc.

Targets (the speed issue), on the 2-core machine: full study wall / engine seconds <= 1.0, one
material <= 1.5, peak memory of the full study <= 1 GB. Run with `make bench` (it rewrites
results/).
"""

import glob
import json
import os
import statistics
import subprocess
import sys
import time

REPEATS = 3
TARGETS = (("one material (steel)", ["steel"], "results/steel/*/manifest.json", 1.5),
           ("full study (all)", ["all"], "results/**/manifest.json", 1.0))


def engine_seconds(pattern) -> float:
    return sum(json.load(open(m))["engine_seconds"] for m in glob.glob(pattern, recursive=True))


def _children(pid: int) -> list[int]:
    kids = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                kids += [int(k) for k in f.read().split()]
    except OSError:
        pass
    return kids


def tree_rss_bytes(root: int) -> int:
    """Resident memory of `root` and all its descendants, from /proc (0 for those gone)."""
    total, todo = 0, [root]
    while todo:
        pid = todo.pop()
        try:
            with open(f"/proc/{pid}/statm") as f:
                total += int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            continue
        todo += _children(pid)
    return total


def run(target) -> tuple[float, int]:
    """(wall seconds, peak tree RSS bytes) of one `snakemake -j2 --forceall target`."""
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "snakemake", "-j2", "--forceall", *target],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    peak = 0
    while proc.poll() is None:
        peak = max(peak, tree_rss_bytes(proc.pid))
        time.sleep(0.05)
    wall = time.perf_counter() - t0
    output = proc.stdout.read()
    if proc.returncode != 0:
        print(output[-3000:])
        raise SystemExit(f"snakemake {' '.join(target)} failed; see above")
    return wall, peak


def main():
    print(f"study wall time, snakemake -j2 --forceall, {REPEATS} runs each (medians)")
    for label, target, pattern, goal in TARGETS:
        walls, engines, peaks = [], [], []
        for _ in range(REPEATS):
            wall, peak = run(target)
            walls.append(wall)
            engines.append(engine_seconds(pattern))
            peaks.append(peak)
        ratios = [w / e for w, e in zip(walls, engines)]
        ratio = statistics.median(ratios)
        print(f"  {label:22s}: wall {statistics.median(walls):6.1f} s (min {min(walls):.1f}, max {max(walls):.1f}); "
              f"engine processes {statistics.median(engines):5.1f} s; wall / engine seconds = {ratio:.2f} "
              f"(goal <= {goal}: {'met' if ratio <= goal else 'NOT met'}); peak memory "
              f"{statistics.median(peaks) / 2**20:.0f} MiB (max {max(peaks) / 2**20:.0f} MiB)")


if __name__ == "__main__":
    main()
