# Comparing this study with a baseline study (an engine build's CI): `snakemake -j2 compare
# --config compare_baseline=<results folder or summary.csv>`; results/compare/.


rule compare:
    """This study against compare_baseline: exits non-zero on a regression (results/compare/)."""
    input: "results/compare/gate.txt"


rule compare_studies:
    """Check by check, baseline vs candidate (this study): compare.{md,html,csv}, compare-junit.xml."""
    input:
        candidate="results/checks.csv",
        baseline=config["compare_baseline"] or "compare_baseline (set it with --config compare_baseline=PATH)",
    output:
        csv="results/compare/compare.csv",
        md="results/compare/compare.md",
        html="results/compare/compare.html",
        junit="results/compare/compare-junit.xml",
    log: "logs/compare/studies.log"
    params: factor=config["compare_factor"], tolerance=config["tolerance"]
    script: "../scripts/compare_studies.py"


rule compare_gate:
    """gate.txt when there is no regression; otherwise exits non-zero naming them."""
    input: "results/compare/compare.csv"
    output: "results/compare/gate.txt"
    log: "logs/compare/gate.log"
    script: "../scripts/compare_gate.py"
