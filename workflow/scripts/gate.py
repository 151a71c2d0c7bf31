"""Snakemake script: the study's (or one case's) last step. Writes gate.txt on PASS; on FAIL
exits non-zero naming every failing check, and writes nothing that could say PASS.

It refuses a verdict that was not computed from the summary beside it (sha256 mismatch).
"""

import json
import sys

from common import log_to
from postprocess.verdict_files import stale_sentence
from records.files import file_sha256, write_atomically

log = log_to(snakemake.log[0])
verdict = json.load(open(snakemake.input.verdict))
summary_sha = file_sha256(snakemake.input.summary)
if verdict.get("verdict") == "STALE":  # a rule changed results after the checks were made
    log.error(stale_sentence(verdict["stale"]))
    sys.exit(stale_sentence(verdict["stale"]))
if verdict.get("summary_sha256") != summary_sha:
    sys.exit(f"{snakemake.input.verdict} was computed from another {snakemake.input.summary} "
             "(sha256 differs): rerun the study, e.g. snakemake -j2 all --forcerun report")
if not verdict["pass"]:
    message = (f"FAIL: {verdict['failed']} of {verdict['checked']} gated checks fail (see "
               f"{snakemake.params.report}):\n  " + "\n  ".join(verdict["failures"]))
    log.error(message)
    sys.exit(message)
write_atomically(snakemake.output[0], f"PASS: {verdict['checked']} engine build x law x geometry x criterion "
                                      "x quantity "
                                      f"checks within tolerance (summary sha256 {summary_sha})\n")
log.info("PASS")
