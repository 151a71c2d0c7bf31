"""Snakemake script: this study's checks against a baseline study's (verdict.compare)."""

from pathlib import Path

from common import log_to
from verdict.compare import build_title, compare_checks, load_checks, pair_builds, write_comparison

log = log_to(snakemake.log[0])
tolerance = snakemake.params.tolerance
baseline, candidate = Path(snakemake.input.baseline).parent, Path(snakemake.input.candidate).parent
if not Path(snakemake.input.baseline).name == "checks.csv":
    baseline = snakemake.input.baseline  # a results folder or summary.csv given as compare_baseline
base, cand = load_checks(baseline, tolerance), load_checks(candidate, tolerance)
names = str(baseline), str(candidate)
title = "Comparison of two studies"
if snakemake.params.builds:  # two builds of one study: named by their version and executable
    base, cand = pair_builds(base, cand, *snakemake.params.builds)
    names = tuple(f"{folder} build {b}" for folder, b in zip(names, snakemake.params.builds))
    title = build_title(Path(snakemake.input.summary).parent, Path(snakemake.input.summary).parent,
                        *snakemake.params.builds)
comparison = compare_checks(base, cand, snakemake.params.factor)
write_comparison(comparison, Path(snakemake.output.md).parent, *names, snakemake.params.factor, 1e-9, title)
log.info("%s", comparison.status.value_counts().to_dict())
