"""The oblique gate's checks before and after a change of its limit estimate: every ladder of a set's
recorded rungs (results/oblique/<set>/<build>/rungs.csv) extrapolated again by today's
`analysis.oblique.limit_rows`, set against the limits the run recorded beside them (limits.csv, the
estimate of its day). Prints the gated checks, the PASSes before and after, those that change, and the
ratio of the resolutions among the checks that pass both ways (issue 38: a change must not loosen the
gate, and must keep the resolution of a well-converging ladder of the same order). E.g.

    .venv/bin/python -m benchmarks.oblique_resolution results/oblique/reduced
    .venv/bin/python -m benchmarks.oblique_resolution results/oblique/full
"""

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.oblique import OBLIQUE_QUANTITIES, limit_rows


def compare(set_dir, tolerance: float = 1e-6) -> pd.DataFrame:
    """One row per gated check of the set's serial ladders: the recorded (err0, res0) and today's
    (err1, res1) limit and resolution, and whether each passes (|err| + res <= tolerance)."""
    rows = []
    for rungs_csv in sorted(Path(set_dir).glob("*/rungs.csv")):
        rungs = pd.read_csv(rungs_csv)
        rungs = rungs[rungs.ranks == 1]
        before = pd.read_csv(rungs_csv.with_name("limits.csv")).set_index("ladder")
        after = limit_rows(rungs).set_index("ladder")
        for ladder in after.index.intersection(before.index):
            for q in OBLIQUE_QUANTITIES:
                e0, r0 = before.at[ladder, f"err_{q}"], before.at[ladder, f"resolution_{q}"]
                e1, r1 = after.at[ladder, f"err_{q}"], after.at[ladder, f"resolution_{q}"]
                if not np.isfinite(e0):
                    continue  # e_t where the contact point does not slip: no check
                rows.append({"build": rungs_csv.parent.name, "ladder": ladder, "quantity": q, "err0": e0, "res0": r0,
                             "err1": e1, "res1": r1, "method1": after.at[ladder, f"method_{q}"],
                             "pass0": abs(e0) + r0 <= tolerance, "pass1": abs(e1) + r1 <= tolerance})
    return pd.DataFrame(rows)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("set_dir")
    args = parser.parse_args(argv)
    d = compare(args.set_dir)
    both = d[d.pass0 & d.pass1]
    ratio = both.res1 / both.res0
    print(f"{len(d)} checks; PASS before {int(d.pass0.sum())}, after {int(d.pass1.sum())}; "
          f"PASS -> FAIL {int((d.pass0 & ~d.pass1).sum())}, FAIL -> PASS {int((~d.pass0 & d.pass1).sum())}")
    print(f"resolution after / before, checks passing both: median {ratio.median():.3g}, max {ratio.max():.3g}")
    if len(both):
        print("worst:", both.loc[ratio.idxmax()].to_dict())
    with pd.option_context("display.width", 250, "display.max_colwidth", 120):
        print(d[d.pass0 != d.pass1].to_string())


if __name__ == "__main__":
    main()
