"""Snakemake script: this study's checks against a baseline study's (postprocess.compare)."""

from pathlib import Path

from common import log_to
from postprocess.compare import compare_checks, load_checks, write_comparison

log = log_to(snakemake.log[0])
tolerance = snakemake.params.tolerance
baseline, candidate = snakemake.input.baseline, Path(snakemake.input.candidate).parent
comparison = compare_checks(load_checks(baseline, tolerance), load_checks(candidate, tolerance),
                            snakemake.params.factor)
write_comparison(comparison, Path(snakemake.output.md).parent, str(baseline), str(candidate),
                 snakemake.params.factor, 1e-9)
log.info("%s", comparison.status.value_counts().to_dict())
