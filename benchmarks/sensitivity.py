"""How small an implementation error the gate catches: the smallest relative change in LAMMPS's
`kn` and in its `eta_n0` that makes the gate fail, per K, measured on real LAMMPS.

    python -m benchmarks.sensitivity [--executable lmp]

Steel on a plane at V = 1 m/s, eta set for each K (K = 0: kn alone; the damping has nothing to
act on). Each trial runs the gated ladder of the viscoelastic law (tail kept: criteria x0 and F0)
with the parameter scaled by (1 + s) in the input LAMMPS is given (`engines.lammps` deck
overrides), extrapolates it like the study (`analysis.extrapolation`) and asks the gate
(`verdict.gate.judge`, the default tolerance 1e-6) whether T, A and eps all pass. s is
bisected in log between 1e-8 and 1e-3; all the trials of one bisection step run in one LAMMPS
process. Printed per K and parameter:

- gate: the smallest s the gate fails (bisection, to 2 %);
- resolution: the smallest s whose effect stands out of the ladder's resolution, from the linear
  response at s = 1e-4 (what a tolerance at the resolution could see);
- which quantity fails first.
"""

from __future__ import annotations

import argparse
import math
import tempfile
from dataclasses import replace
from pathlib import Path

import pandas as pd

from contact_model import load_case
from engines.codes import CODES
from engines.lammps import TANGENTIAL, run_lammps
from engines.plan import plan_at_velocity, rungs_of
from engines.script_engine import number
from records.collision_metrics import collision_metrics
from analysis.comparison import comparison_rows
from records.dump_file import read_dump
from analysis.extrapolation import extrapolated_rows
from verdict.gate import GATED_QUANTITIES, judge

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = 1e-6
KS = (0.0, 0.1, 0.5, 1.0, 2.0, 5.0)
LOW, HIGH = 1e-8, 1e-3


def ladders():
    """{(K, parameter): the ladder's base run}: steel on a plane at 1 m/s, the law viscoelastic
    (elastic at K = 0), each (K, parameter) its own label so that their runs have their own names."""
    case = load_case(ROOT / "cases" / "steel.yaml")
    plane = [p for p in case.pairs if p.geometry == "sphere-plane"]
    case = replace(case, pairs=tuple(plane))
    base = plan_at_velocity(case, "lammps", KS, [1000], 1.0, "sensitivity")
    out = {}
    for spec in base:
        for parameter in ("kn", "eta_n0") if spec.K > 0 else ("kn",):
            out[(spec.K, parameter)] = replace(spec, label=parameter)
    return out


def model(spec, parameter: str, s: float) -> str:
    """The granular model words of `spec` with `parameter` scaled by (1 + s)."""
    p = CODES["lammps"].contact_parameters(spec.pair)
    kn = p["kn"] * (1 + s if parameter == "kn" else 1)
    eta = p["eta_n0"] * (1 + s if parameter == "eta_n0" else 1)
    return f"hertz {number(kn)} {number(eta)} damping viscoelastic {TANGENTIAL}"


def trial(specs: dict, scales: dict, executable: str, workdir: Path) -> dict:
    """Run every (K, parameter) ladder at its scale s in one LAMMPS process; {(K, parameter):
    {quantity: (worst |error|, resolution, passes)}} over both criteria."""
    runs, overrides = [], {}
    for key, spec in specs.items():
        runs += rungs_of(spec)
        overrides[spec.ladder] = {"model": model(spec, key[1], scales[key])}
    sweep = run_lammps(runs, workdir, executable, overrides=overrides).raise_first()
    rows = []
    for spec in runs:
        meta, c = read_dump(sweep.dumps[spec.name])
        m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"], meta["impact_velocity"])
        rows += [{**r, "run": spec.name} for r in comparison_rows(meta, m)]
    limits = extrapolated_rows(pd.DataFrame(rows))
    out = {}
    for key, spec in specs.items():
        mine = limits[limits.ladder == spec.ladder]
        out[key] = {}
        for q in GATED_QUANTITIES:
            e, r = mine[f"err_{q}"].abs().to_numpy(), mine[f"resolution_{q}"].to_numpy()
            i = int(e.argmax())
            out[key][q] = (float(e[i]), float(r[i]), all(judge(x, y, TOLERANCE) == "pass" for x, y in zip(e, r)))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.sensitivity", description=__doc__.split("\n\n")[0])
    parser.add_argument("--executable", default="lmp", help="the LAMMPS executable (default: Debian's lmp)")
    args = parser.parse_args(argv)
    specs = ladders()
    with tempfile.TemporaryDirectory() as tmp:
        clean = trial(specs, {k: 0.0 for k in specs}, args.executable, Path(tmp) / "clean")
        probe = trial(specs, {k: 1e-4 for k in specs}, args.executable, Path(tmp) / "probe")
        lo, hi = {k: LOW for k in specs}, {k: HIGH for k in specs}
        for step in range(int(math.ceil(math.log2(math.log(HIGH / LOW) / math.log(1.02))))):
            mid = {k: math.sqrt(lo[k] * hi[k]) for k in specs}
            result = trial(specs, mid, args.executable, Path(tmp) / f"step{step}")
            for k in specs:
                (hi if not all(p for *_, p in result[k].values()) else lo)[k] = mid[k]
        first = trial(specs, hi, args.executable, Path(tmp) / "at-threshold")
    print(f"Smallest relative change in LAMMPS's parameters that the gate fails (tolerance {TOLERANCE:g}), steel on a "
          f"plane at 1 m/s, {args.executable}:")
    print(f"  {'K':>4}  {'parameter':9}  {'gate fails from':>15}  {'resolved from':>13}  fails first  "
          "(clean: worst |error|, resolution)")
    for (K, parameter) in sorted(specs):
        key = (K, parameter)
        # linear response: d|error|/ds from s = 1e-4, against the clean ladder's resolution
        slopes = {q: abs(probe[key][q][0] - clean[key][q][0]) / 1e-4 for q in GATED_QUANTITIES}
        resolved = min(clean[key][q][1] / slopes[q] for q in GATED_QUANTITIES if slopes[q] > 0)
        failing = [q for q in GATED_QUANTITIES if not first[key][q][2]]
        worst = max(GATED_QUANTITIES, key=lambda q: clean[key][q][0])
        print(f"  {K:4g}  {parameter:9}  {hi[key]:15.2e}  {resolved:13.1e}  {', '.join(failing):11}  "
              f"({worst} {clean[key][worst][0]:.1e}, {clean[key][worst][1]:.1e})")


if __name__ == "__main__":
    main()
