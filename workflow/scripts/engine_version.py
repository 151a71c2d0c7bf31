"""Snakemake script: ask one engine build for its version (results/engine_versions/<build>.json).

Writes {id, code, executable, banner}: the banner is the line the code's version pattern finds
(`engines.codes`), e.g. 'LAMMPS (22 Jul 2025 - Update 4)'. An executable that is another engine,
or that cannot say its version, fails the job with the build named and what to do
(`engines.builds.check_build`), and no file is written.
"""

import json

from common import start_rule
from engines.builds import Build, check_build
from records.files import write_atomically

log = start_rule(snakemake)
b = snakemake.params.build
build = Build(b["id"], b["code"], b["executable"])
banner = check_build(build)
write_atomically(snakemake.output[0], json.dumps({**b, "banner": banner, "file": snakemake.params.executable},
                                                 indent=1))
log.info("%s (%s): %s", build.id, build.executable, banner)
