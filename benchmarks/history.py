"""Wall time of the history of releases (`snakemake history`, the default config's releases: the full
history, a benchmark, not a test), run locally (`-j2`) and through the local SLURM cluster
(`--profile profiles/slurm`, `make slurm-up`) in one run, side by side, and whether both give the
same rows (results/history/history.csv, the project's path aside).

Each way runs with --forceall in a copy of the workflow (tests/workflow_copy.py: the releases
`make build` installed are linked, so no way pays for an installation), REPEATS times, and prints
the median, min and max wall time, the SLURM jobs it submitted (one per release: its install and
its runs are one group job) and the ratio SLURM / local. Without SLURM (not installed, or the
cluster does not start) it says so and prints the local figures alone. A cluster it started, it stops."""

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 3


def _copy(dest: Path) -> Path:
    sys.path.insert(0, str(ROOT / "tests"))
    from workflow_copy import copy_workflow

    return copy_workflow(dest)


def _run(cmd, project, env=None) -> tuple[float, str]:
    start = time.monotonic()
    out = subprocess.run(cmd, cwd=project, capture_output=True, text=True, timeout=3600, env=env)
    wall = time.monotonic() - start
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed in {project}:\n{out.stderr[-3000:]}")
    return wall, out.stdout + out.stderr


def _rows(project: Path) -> str:
    return (project / "results" / "history" / "history.csv").read_text().replace(str(project), "<project>")


def main():
    scratch = Path(tempfile.mkdtemp(prefix="hertz-history-bench-"))
    stop = []  # the local cluster, when this benchmark started it (a later CI run refuses a running one)
    try:
        local = _copy(scratch / "local")
        walls = [_run([sys.executable, "-m", "snakemake", "-j2", "history", "--forceall"], local)[0]
                 for _ in range(REPEATS)]
        releases = len(list((local / "results" / "history" / "installs").glob("*.json")))
        print(f"history of releases ({releases} releases, default config), {REPEATS} runs each, --forceall (medians)")
        print(f"  local (-j2)        : wall {statistics.median(walls):6.1f} s (min {min(walls):.1f}, "
              f"max {max(walls):.1f})")
        script = str(ROOT / "profiles" / "slurm" / "local_cluster.sh")
        up = subprocess.run([script, "up"], capture_output=True, text=True, timeout=300)
        if up.returncode == 0 and "already running" not in up.stdout:  # started here: stopped here
            stop.append(script)
        snakemake = ROOT / ".venv-slurm" / "bin" / "snakemake"
        if up.returncode != 0 or not snakemake.exists():
            print(f"  through SLURM      : not measured (make slurm-venv slurm-up: {(up.stdout + up.stderr)[-200:]})")
            return
        env = {**os.environ, "SLURM_CONF": str(ROOT / ".slurm" / "etc" / "slurm.conf")}
        cluster = _copy(scratch / "slurm")
        slurm_walls, jobs = [], 0
        for _ in range(REPEATS):
            wall, log = _run([str(snakemake), "--profile", "profiles/slurm", "history", "--forceall"], cluster, env)
            slurm_walls.append(wall)
            jobs = log.count("has been submitted with SLURM jobid")
        same = _rows(cluster) == _rows(local)
        print(f"  through SLURM      : wall {statistics.median(slurm_walls):6.1f} s (min {min(slurm_walls):.1f}, "
              f"max {max(slurm_walls):.1f}); {jobs} SLURM jobs per run (one per release); "
              f"SLURM / local = {statistics.median(slurm_walls) / statistics.median(walls):.2f}; "
              f"history.csv {'identical' if same else 'DIFFERENT'} to the local run's")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        for script in stop:
            subprocess.run([script, "down"], capture_output=True, text=True, timeout=300)


if __name__ == "__main__":
    main()
