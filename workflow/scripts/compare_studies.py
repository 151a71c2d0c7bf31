"""Snakemake script: this study's checks against a baseline study's (postprocess.compare)."""

import shutil
from pathlib import Path

import pandas as pd

from common import log_to
from postprocess.compare import compare_checks, load_checks, pair_builds, write_comparison

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
    versions = pd.read_csv(snakemake.input.summary).groupby("build").engine_version.first()

    def described(build):
        exe = snakemake.params.executables[build]
        return f"{build} ({versions.get(build, 'no version recorded')}, {shutil.which(exe) or exe})"

    title = "Build comparison: " + " → ".join(described(b) for b in snakemake.params.builds)
comparison = compare_checks(base, cand, snakemake.params.factor)
write_comparison(comparison, Path(snakemake.output.md).parent, *names, snakemake.params.factor, 1e-9, title)
log.info("%s", comparison.status.value_counts().to_dict())
