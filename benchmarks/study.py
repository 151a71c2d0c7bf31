"""Wall time and peak memory of the study (`snakemake -j2 all`, set-up excluded) and of one
material (`snakemake -j2 steel`), against the engines' own process time.

Runs each target with --forceall REPEATS times in a row and prints medians, and the ratio of the
workflow's wall time to the sum of the engine processes' wall times (from the manifests of the run:
every engine job writes one, the cases', the convergence runs', Fig. 4's, the calibration's and the
LAMMPS regression cases'), which cancels the machine's speed. It is printed twice: with every engine
run counted once (its launcher's wall time), and with every engine process counted, which differs
for ESyS only: its `mpirun -np 2` runs two ranks while its job holds both cores (Snakemake
`threads: 2`). Measured on the steel sweep, alone on the two cores: each rank keeps 75-85 % of a core busy
(0.5-0.8 s of each rank's CPU is the yield-spin of a rank waiting for the other), and both ranks
pinned to one core take 1.4-1.6 times as long. So the first figure counts ESyS's engine work as one
core, the second as two, and the truth (about 1.5) lies between them: both are printed. Peak memory:
the largest sum over snakemake and all its descendants, sampled every 50 ms from /proc, of the
proportional set size (PSS: a shared page counts once, split between its sharers) and, for
comparison, of the resident set size (RSS, which counts the Python and MPI libraries that every job
maps once per job).

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
import tempfile
import time

from engines.codes import code

REPEATS = 3
TARGETS = (("one material (steel)", ["steel"], "results/steel/*/manifest.json", 1.5),
           ("full study (all)", ["all"], "results/**/manifest.json", 1.0))


def engine_seconds(pattern, since: float) -> tuple[float, float]:
    """(engine runs' seconds, engine process seconds) of the manifests written at or after
    `since` (a time.time()): folders of earlier layouts or configurations left in results/ are
    not counted. The second counts each of a run's processes (`EngineCode.processes`: ESyS's two
    MPI ranks)."""
    runs = processes = 0.0
    for m in glob.glob(pattern, recursive=True):
        if os.path.getmtime(m) >= since:
            manifest = json.load(open(m))
            runs += manifest["engine_seconds"]
            processes += manifest["engine_seconds"] * code(manifest["engine"]).processes
    return runs, processes


def _children(pid: int) -> list[int]:
    kids = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                kids += [int(k) for k in f.read().split()]
    except OSError:
        pass
    return kids


def tree_memory_bytes(root: int) -> tuple[int, int]:
    """(PSS, RSS) summed over `root` and all its descendants, from /proc (0 for those gone)."""
    pss = rss = 0
    todo = [root]
    while todo:
        pid = todo.pop()
        try:
            with open(f"/proc/{pid}/smaps_rollup") as f:
                for line in f:
                    if line.startswith("Rss:"):
                        rss += int(line.split()[1]) * 1024
                    elif line.startswith("Pss:"):
                        pss += int(line.split()[1]) * 1024
        except OSError:
            continue
        todo += _children(pid)
    return pss, rss


def run(target) -> tuple[float, int, int]:
    """(wall seconds, peak tree PSS, peak tree RSS [bytes]) of one `snakemake -j2 --forceall target`."""
    t0 = time.perf_counter()
    run.started = time.time()
    # Its output goes to a file, not a pipe: nobody reads a pipe while the memory is sampled,
    # and a full pipe (64 KiB) would block a job writing to it, and so the study, for ever.
    with tempfile.TemporaryFile(mode="w+") as out:
        proc = subprocess.Popen([sys.executable, "-m", "snakemake", "-j2", "--forceall", "--rerun-incomplete",
                                 *target], stdout=out, stderr=subprocess.STDOUT, text=True)
        peak_pss = peak_rss = 0
        while proc.poll() is None:
            pss, rss = tree_memory_bytes(proc.pid)
            peak_pss, peak_rss = max(peak_pss, pss), max(peak_rss, rss)
            time.sleep(0.05)
        wall = time.perf_counter() - t0
        out.seek(0)
        output = out.read()
    if proc.returncode != 0:
        print(output[-3000:])
        raise SystemExit(f"snakemake {' '.join(target)} failed; see above")
    return wall, peak_pss, peak_rss


def main():
    print(f"study wall time, snakemake -j2 --forceall, {REPEATS} runs each (medians)")
    for label, target, pattern, goal in TARGETS:
        walls, runs, processes, pss, rss = [], [], [], [], []
        for _ in range(REPEATS):
            wall, peak_pss, peak_rss = run(target)
            walls.append(wall)
            r, p = engine_seconds(pattern, run.started)
            runs.append(r)
            processes.append(p)
            pss.append(peak_pss)
            rss.append(peak_rss)
        ratio_runs = statistics.median(w / e for w, e in zip(walls, runs))
        ratio = statistics.median(w / e for w, e in zip(walls, processes))
        print(f"  {label:22s}: wall {statistics.median(walls):6.1f} s (min {min(walls):.1f}, max {max(walls):.1f}); "
              f"engine processes {statistics.median(processes):5.1f} s, wall / engine process seconds = {ratio:.2f} "
              f"(goal <= {goal}: {'met' if ratio <= goal else 'NOT met'}); each engine run counted once "
              f"(ESyS's two ranks as one) {statistics.median(runs):5.1f} s, ratio {ratio_runs:.2f} "
              f"({'met' if ratio_runs <= goal else 'NOT met'}); peak memory (PSS) "
              f"{statistics.median(pss) / 2**20:.0f} MiB (max {max(pss) / 2**20:.0f}; goal <= 1024 for the full "
              f"study), peak RSS sum {statistics.median(rss) / 2**20:.0f} MiB")


if __name__ == "__main__":
    main()
