"""Post-processing job-seconds of one case against its engine jobs' (issue 39: post-processing
<= 0.3 x engine seconds).

    python -m benchmarks.post_processing [--case steel] [--repeats 3]

For the case's existing results (its engine jobs are run once first if it has none), it reruns the
case's post-processing REPEATS times in a row, each time as the study runs it,

    snakemake results/<case>/verdict.json --forcerun case_summary -j1

(the case's summary, then its verdict and report), and the study's advisor table once per repeat,

    snakemake results/convergence/largest_dt_over_T_R.csv --forcerun largest_steps -j1

and reads each rule's Snakemake benchmark file (logs/benchmarks/<rule>/...: ``s``, the job's wall
seconds, and ``cpu_time``, its processes' CPU seconds). It prints their medians and the ratio

    (case_summary + case_verdict job-seconds) / (the case's run_engine job-seconds),

the engine side from the case's run_engine benchmark files (the last engine jobs of the case, which
this benchmark does not rerun), and the same ratio in CPU seconds, which a machine shared with
other work disturbs less than wall seconds. The sha256 of summary.csv, checks.csv and verdict.json
after each repeat is printed: the post-processing must write the same bytes every time (and,
compared across commits, the same bytes as before a change that only makes it faster).
"""

from __future__ import annotations

import argparse
import csv
import glob
import hashlib
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The outputs whose bytes a faster post-processing must not change.
OUTPUTS = ("summary.csv", "checks.csv", "verdict.json")
#: The target of the speed issue: post-processing job-seconds / engine job-seconds.
TARGET_RATIO = 0.3


def benchmark_row(path: Path) -> dict[str, float]:
    """The last row of a Snakemake benchmark file (tab-separated, a header line): {column: value}
    of its numeric columns (s: wall seconds, cpu_time: CPU seconds, max_rss [MB], ...)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows:
        raise SystemExit(f"{path}: no benchmark row")
    out = {}
    for key, value in rows[-1].items():
        try:
            out[key] = float(value)
        except (TypeError, ValueError):
            continue
    return out


def snakemake(target: str, forcerun: str) -> None:
    """One `snakemake <target> --forcerun <rule> -j1` (an argument list: no shell), its output shown
    on failure."""
    run = subprocess.run([sys.executable, "-m", "snakemake", target, "--forcerun", forcerun, "-j1", "--cores", "1"],
                         cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stdout[-4000:], run.stderr[-4000:], file=sys.stderr)
        raise SystemExit(f"snakemake {target} --forcerun {forcerun} failed (exit {run.returncode})")


def sha256_of(path: Path) -> str:
    """The sha256 of a file's bytes (hex)."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def engine_seconds(case: str) -> tuple[float, float, int]:
    """(wall, CPU seconds, jobs) of the case's run_engine jobs, from their benchmark files."""
    rows = [benchmark_row(Path(p)) for p in sorted(glob.glob(str(ROOT / f"logs/benchmarks/run_engine/{case}/*.tsv")))]
    if not rows:
        raise SystemExit(f"logs/benchmarks/run_engine/{case}/: no engine job's benchmark file; run "
                         f"`snakemake -j2 results/{case}/verdict.json` first")
    return sum(r["s"] for r in rows), sum(r.get("cpu_time", float("nan")) for r in rows), len(rows)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="steel", help="a case of config `cases:` (default steel)")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    case, folder = args.case, ROOT / "results" / args.case
    if not (folder / "summary.csv").is_file():
        print(f"results/{case}: no results yet; running its engine jobs once", flush=True)
        run = subprocess.run([sys.executable, "-m", "snakemake", f"results/{case}/verdict.json", "-j2"], cwd=ROOT)
        if run.returncode != 0:
            raise SystemExit(f"snakemake results/{case}/verdict.json failed (exit {run.returncode})")
    seconds: dict[str, list[tuple[float, float]]] = {"case_summary": [], "case_verdict": [], "largest_steps": []}
    print(f"post-processing of case {case}, {args.repeats} repeats (job wall s / CPU s, Snakemake benchmark files)")
    for i in range(args.repeats):
        snakemake(f"results/{case}/verdict.json", "case_summary")
        snakemake("results/convergence/largest_dt_over_T_R.csv", "largest_steps")
        for rule, name in (("case_summary", case), ("case_verdict", case), ("largest_steps", "all")):
            row = benchmark_row(ROOT / f"logs/benchmarks/{rule}/{name}.tsv")
            seconds[rule].append((row["s"], row.get("cpu_time", float("nan"))))
        hashes = "  ".join(f"{o} {sha256_of(folder / o)[:16]}" for o in OUTPUTS)
        last = ", ".join(f"{rule} {v[-1][0]:.1f} / {v[-1][1]:.1f}" for rule, v in seconds.items())
        print(f"  repeat {i + 1}: {last}   {hashes}", flush=True)
    medians = {r: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for r, v in seconds.items()}
    wall, cpu, jobs = engine_seconds(case)
    post_wall = medians["case_summary"][0] + medians["case_verdict"][0]
    post_cpu = medians["case_summary"][1] + medians["case_verdict"][1]
    print("medians (wall s / CPU s): " + ", ".join(f"{r} {w:.1f} / {c:.1f}" for r, (w, c) in medians.items()))
    print(f"engine jobs of {case}: {jobs} run_engine jobs, {wall:.1f} s wall / {cpu:.1f} s CPU")
    print(f"post-processing / engine, case {case} (case_summary + case_verdict): {post_wall / wall:.2f} in wall "
          f"seconds, {post_cpu / cpu:.2f} in CPU seconds (target <= {TARGET_RATIO})")


if __name__ == "__main__":
    main()
