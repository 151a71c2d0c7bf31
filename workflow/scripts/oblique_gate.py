"""Snakemake script: the oblique impacts' gate. gate.txt on PASS; on FAIL exits non-zero naming
every failing check, and writes nothing that could say PASS."""

import json
import sys

import pandas as pd

from common import log_to
from records.files import write_atomically

log = log_to(snakemake.log[0])
verdict = json.load(open(snakemake.input.verdict))
try:
    checks = pd.read_csv(snakemake.input.checks)
except pd.errors.EmptyDataError:  # no build ran an oblique check: nothing can pass
    checks = pd.DataFrame(columns=["build", "model", "geometry", "angle", "spin", "quantity", "status", "detail"])
if verdict["verdict"] != "PASS":
    failed = checks[checks.status == "FAIL"]
    lines = [f"{r.build} {r.model} {r.geometry} angle {r.angle:.4g} deg spin {r.spin:g} rad/s: {r.quantity}: "
             f"{r.detail}" for r in failed.itertuples()]
    message = (f"FAIL: {verdict['failed']} of {verdict['checks']} oblique checks fail (see {snakemake.params.report})"
               + (":\n  " + "\n  ".join(lines) if lines else ": no check was made"))
    log.error(message)
    sys.exit(message)
text = (f"PASS: {verdict['passed']} of {verdict['checks']} oblique checks within their tolerance with the resolution "
        f"added; {verdict['known_defects']} declared known defects within their declared size\n")
write_atomically(snakemake.output[0], text)
log.info(text.strip())
