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

Targets (the speed issues), on the 2-core machine: full study <= 150 s with wall / engine seconds
<= 1.05, one material <= 1.5, peak memory of the full study <= 1 GB. Run with `make bench` (it
rewrites results/).

Then where the seconds of the last full study went (`breakdown`): job-seconds per rule (every
rule's Snakemake benchmark file, logs/benchmarks/<rule>/), and per engine code a least-squares fit
of its case jobs' engine seconds to start-up + steps x per-step cost (the steps from the cases'
plans), with the share of those steps spent in free flight before and after contact.
"""

import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from engines.codes import code
from reference import HERTZ_TAU

REPEATS = 3
TARGETS = (("one material (steel)", ["steel"], "results/steel/*/manifest.json", 1.5),
           ("keywords' promise table", ["keywords"], "results/keywords/*/manifest.json", 1.5),
           ("full study (all)", ["all"], "results/**/manifest.json", 1.05))


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


def rule_seconds(since: float, root="logs/benchmarks") -> dict[str, tuple[int, float]]:
    """{rule: (jobs, job-seconds)} of the Snakemake benchmark files written at or after `since`,
    largest first (a rule's files are logs/benchmarks/<rule>/...tsv)."""
    out: dict[str, list] = {}
    for path in glob.glob(f"{root}/**/*.tsv", recursive=True):
        if os.path.getmtime(path) < since:
            continue
        rule = Path(path).relative_to(root).parts[0]
        lines = Path(path).read_text().splitlines()
        seconds = float(lines[1].split("\t")[0]) if len(lines) > 1 else 0.0
        jobs, total = out.get(rule, (0, 0.0))
        out[rule] = (jobs + 1, total + seconds)
    return dict(sorted(out.items(), key=lambda kv: -kv[1][1]))


def engine_fit(since: float, results="results") -> dict[str, dict]:
    """Per engine code, from its case jobs of the run (results/<case>/<build>/manifest.json
    with results/<case>/plan.json): jobs, engine seconds, steps, the least-squares fit
    seconds = start_s + steps x per_step_s, and free_flight (the share of steps before and after
    contact: a run of dt = T_e / f has f tau_0 / HERTZ_TAU steps in contact)."""
    rows: dict[str, list] = {}
    for m in glob.glob(f"{results}/*/*/manifest.json"):
        plan_path = Path(m).parents[1] / "plan.json"
        if os.path.getmtime(m) < since or not plan_path.exists():
            continue
        manifest, plan = json.load(open(m)), json.load(open(plan_path))
        runs = [r for r in plan["runs"] if r["build"] == manifest["build"]]
        steps = sum(r["steps"] for r in runs)
        contact = sum(min(r["steps"], r["time_step_factor"] * r["reference"]["tau_0"] / HERTZ_TAU) for r in runs)
        rows.setdefault(manifest["engine"], []).append((manifest["engine_seconds"], steps, contact))
    fits = {}
    for engine, data in rows.items():
        seconds, steps, contact = (np.array(x, dtype=float) for x in zip(*data))
        if len(data) >= 2 and np.ptp(steps) > 0:
            (per_step, start), *_ = np.linalg.lstsq(np.vstack([steps, np.ones_like(steps)]).T, seconds, rcond=None)
        else:
            per_step, start = seconds.sum() / steps.sum(), 0.0
        fits[engine] = {"jobs": len(data), "seconds": seconds.sum(), "steps": int(steps.sum()), "start_s": start,
                        "per_step_s": per_step, "free_flight": 1 - contact.sum() / steps.sum()}
    return fits


def breakdown(since: float) -> None:
    """Print where the seconds of the run started at `since` went (see the module's docstring)."""
    rules = rule_seconds(since)
    total = sum(s for _, s in rules.values())
    print(f"  where the last full study's seconds went: {total:.0f} job-seconds in {sum(j for j, _ in rules.values())} "
          "jobs (two at a time); per rule, jobs and job-seconds:")
    for rule, (jobs, seconds) in rules.items():
        if seconds >= 0.5:
            print(f"    {rule:24s} {jobs:4d} jobs {seconds:7.1f} s ({seconds / total:5.1%})")
    print("  engine processes of the case jobs, fitted as start-up + steps x per-step cost:")
    for engine, f in sorted(engine_fit(since).items(), key=lambda kv: -kv[1]["seconds"]):
        print(f"    {engine:9s} {f['jobs']:2d} jobs {f['seconds']:6.1f} s, {f['steps']:8d} steps: start-up "
              f"{f['start_s']:5.2f} s per process, {f['per_step_s'] * 1e6:6.1f} us per step; "
              f"{f['free_flight']:.0%} of the steps in free flight")


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
    breakdown(run.started)  # of the last run: the full study's


if __name__ == "__main__":
    main()
