"""Snakemake script: fail on a regression against the baseline, naming every one."""

import sys

import pandas as pd

from common import log_to
from records.files import write_atomically

log = log_to(snakemake.log[0])
comparison = pd.read_csv(snakemake.input[0])
regressions = comparison[comparison.status == "regression"]
if len(regressions):
    names = [" ".join(str(r[k]) for k in ("build", "law", "geometry", "criterion", "quantity")) +
             f": {r['baseline_error']:.3e} -> {r['candidate_error']:.3e}" for r in regressions.to_dict("records")]
    message = (f"{len(regressions)} regressions against the baseline (results/compare/compare.md):\n  " +
               "\n  ".join(names))
    log.error(message)
    sys.exit(message)
write_atomically(snakemake.output[0], f"NO REGRESSION: {len(comparison)} checks, "
                                      f"{int((comparison.status == 'fix').sum())} fixes\n")
log.info("no regression")
