"""Snakemake script: the runs of one case (results/<case>/plan.json), validated before any engine,
with the reference solution of every run solved once, in one batch, and handed on.

The plan itself is made when the workflow starts (workflow/rules/cases.smk, which refuses a case
the engines cannot run before any job): this job only writes it, so it imports nothing heavy.
"""

import json

from common import start_rule
from records.files import write_atomically

log = start_rule(snakemake)
listing = snakemake.params.listing
write_atomically(snakemake.output[0], json.dumps(listing, indent=1))
log.info("%s: %d runs planned, %d velocities not run, %d cells not available", listing["file"], len(listing["runs"]),
         len(listing["not_run"]), len(listing["not_available"]))
for skipped in listing["not_run"]:
    log.warning("not run: %s %s K = %.3g: %s", listing["case"], skipped["geometry"], skipped["K"], skipped["reason"])
for note in listing.get("notes", []):
    log.warning("%s", note)
