"""Snakemake script: the runs of one case (results/<case>/plan.json), validated before any engine,
with the reference solution of every run solved once, in one batch, and handed on.

The plan itself is made when the workflow starts (workflow/rules/cases.smk, which refuses a case
the engines cannot run before any job). This job cuts it to the keywords each build's release has
(`engines.plan.without_missing_keywords`, by the version banners of the engine_version jobs) and
writes it: the engine jobs run what it lists.
"""

import json
from pathlib import Path

from common import start_rule
from engines.plan import without_missing_keywords
from records.files import write_atomically

log = start_rule(snakemake)
banners = {v["id"]: v["banner"] for v in (json.loads(Path(f).read_text()) for f in snakemake.input.versions)}
listing = without_missing_keywords(dict(snakemake.params.listing), banners)
write_atomically(snakemake.output[0], json.dumps(listing, indent=1))
log.info("%s: %d runs planned, %d velocities not run, %d cells not available", listing["file"], len(listing["runs"]),
         len(listing["not_run"]), len(listing["not_available"]))
for skipped in listing["not_run"]:
    log.warning("not run: %s %s K = %.3g: %s", listing["case"], skipped["geometry"], skipped["K"], skipped["reason"])
for cell in listing["not_available"]:
    log.info("not available: %s %s %s: %s", cell.get("build"), cell["law"], cell["geometry"], cell["reason"])
for note in listing.get("notes", []):
    log.warning("%s", note)
