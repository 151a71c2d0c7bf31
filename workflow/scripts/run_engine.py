"""Snakemake script: every run of one case in one engine, in one engine process.

Dumps, the engine's log and its input go into the rule's declared folder `runs/`; the manifest
lists the dumps with their sha256 (paths relative to it). A run the engine did not complete is
recorded in the manifest, not raised: every law is gated (against its own equation), so a run
that failed fails its checks at the gate, which names it, and the study still writes its report
and JUnit XML. A missing engine stops the rule at once (that is set-up, not a verdict).
"""

import shutil

from common import start_rule
from engines import run_sweep
from engines.builds import Build
from engines.plan import runs_from_listing
from records.run_manifest import write_manifest

log = start_rule(snakemake)
s = snakemake.params.settings
build = Build(**snakemake.params.build)
listing = snakemake.params.listing  # the build's part of plan.json (the plan rule's, cut to its release)
runs = runs_from_listing(None, listing, build.id)  # the plan's runs and pairs, solved there: no case file read
case_name = listing["case"]
log.info("%s: %d runs of build %s (%s) into %s", case_name, len(runs), build.id, build.executable,
         snakemake.output.runs)
sweep = run_sweep(build, runs, snakemake.output.runs, timeout_floor_s=s["engine_timeout_floor_s"])
for name, err in sweep.failures.items():
    log.error("run failed (the gate will fail its checks): %s", err)
write_manifest(snakemake.output.manifest, [sweep.dumps[r.name] for r in runs if r.name in sweep.dumps],
               sweep.failed_runs(runs),
               case=case_name, build=build.id, engine=build.code, engine_seconds=sweep.engine_seconds,
               executable=shutil.which(build.executable) or build.executable)
log.info("%d runs landed, %d failed; engine process %.2f s", len(sweep.dumps), len(sweep.failures),
         sweep.engine_seconds)
