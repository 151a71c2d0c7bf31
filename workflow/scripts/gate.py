"""Snakemake script: the study's (or one case's) last step. Writes gate.txt on PASS, stating the
tolerances the PASS was judged against (verdict.verdict_files.gate_text); on FAIL exits
non-zero naming every failing check, and writes nothing that could say PASS.

It refuses a verdict that was not computed from the summary beside it (sha256 mismatch), and a
PASS over dumps that are no longer the ones their engine jobs wrote: every dump of the manifests
is checked against its sha256 first (records.run_manifest.changed_dumps); a changed one marks the
folder's verdict stale and fails, naming the file.
"""

import json
import sys
import time
from pathlib import Path

from common import log_to
from verdict.verdict_files import gate_text, mark_stale, stale_sentence, withdraw_gate
from records.files import file_sha256, write_atomically
from records.run_manifest import changed_dumps

log = log_to(snakemake.log[0])
folder = Path(snakemake.output[0]).parent
withdraw_gate(folder)  # Snakemake removed it already; a stamp written by hand goes too
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
started = time.perf_counter()
changed = changed_dumps(snakemake.input.manifests)
log.info("%d manifests' dumps checked against their sha256 in %.2f s", len(snakemake.input.manifests),
         time.perf_counter() - started)
if changed:
    mark_stale(folder, f"{len(changed)} dump(s) changed after their engine job wrote them (first: "
                       f"{changed[0].split(': ', 1)[0]})", snakemake.params.rerun_engines)
    message = (f"FAIL: {len(changed)} dump(s) are not the ones their engine jobs wrote; the verdict of "
               f"{folder} is withdrawn (STALE):\n  " + "\n  ".join(changed))
    log.error(message)
    sys.exit(message)
write_atomically(snakemake.output[0], gate_text(verdict, summary_sha))
for warning in verdict.get("warnings", []):
    log.warning("%s", warning)
log.info("PASS (tolerance, relative: %s)", verdict["tolerance"])
