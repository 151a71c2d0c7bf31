"""One oblique impact's ladder, run for real to finer rungs than the study's default: what an
oblique limit's resolution is checked against (docs/tangential.md, "The full set", finding 1).

Runs, in one build, the impacts of one oblique case whose contact-point incidence is `--angle`
[deg], with the models named (`--model`, repeatable; default: every model the build has), at every
time-step factor of `--ladder` (dt ~ T_e / factor, aligned as the study's rungs are), through the
project's own plan, sweep and rung rows (`engines.oblique_plan`, `engines.oblique_sweep`,
`analysis.oblique.rung_rows`), and writes the rungs as CSV (`--out`) with the engine seconds. E.g.

    .venv/bin/python -m benchmarks.oblique_ladder lammps-2025 cases/oblique/chung_ooi_test5.yaml \
        --angle 20 --model lammps:mindlin/force --ladder 1000 2000 4000 8000 16000 32000 64000 128000 \
        --out /tmp/t5_lammps.csv
"""

import argparse
import tempfile
import time
from pathlib import Path

import yaml

from analysis.oblique import rung_rows
from contact_model import load_case
from engines.builds import check_build, load_builds
from engines.oblique_plan import oblique_plan
from engines.oblique_sweep import run_oblique_sweep

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build")
    parser.add_argument("case")
    parser.add_argument("--angle", type=float, required=True, help="contact-point incidence [deg]")
    parser.add_argument("--geometry", default=None, help="sphere-plane or sphere-sphere (default: both)")
    parser.add_argument("--model", action="append", default=None)
    parser.add_argument("--ladder", type=float, nargs="+", required=True)
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    build = next(b for b in load_builds(config["builds"], ROOT) if b.id == args.build)
    banner = check_build(build)
    plan = oblique_plan([load_case(args.case)], build.code, build.id, banner, args.ladder, (1,))
    runs = [r for r in plan.runs if round(r.contact_angle, 6) == round(args.angle, 6)
            and (args.model is None or r.model in args.model)
            and (args.geometry is None or r.pair.geometry == args.geometry)]
    if not runs:
        raise SystemExit(f"{args.case}: no impact at {args.angle} deg with models {args.model} in {build.id}")
    with tempfile.TemporaryDirectory() as work:
        start = time.perf_counter()
        sweep = run_oblique_sweep(build, runs, work, timeout_floor_s=3600.0)
        wall = time.perf_counter() - start
        rungs = rung_rows(runs, sweep, known_defects=config["oblique"].get("known_defects", []))
    rungs["engine_seconds_total"] = sweep.engine_seconds
    rungs.to_csv(args.out, index=False, float_format="%.17g")
    print(f"{build.id} ({banner}): {len(runs)} runs, {len(sweep.failures)} failed, "
          f"engine {sweep.engine_seconds:.1f} s, "
          f"wall {wall:.1f} s -> {args.out}")
    for name, why in sweep.failures.items():
        print("FAILED", name, why)


if __name__ == "__main__":
    main()
