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
    benchmark: "logs/benchmarks/compare_studies/all.tsv"
    params: factor=config["compare_factor"], tolerance=config["tolerance"], builds=None
    script: "../scripts/compare_studies.py"


rule compare_gate:
    """gate.txt when there is no regression; otherwise exits non-zero naming them."""
    input: "results/compare/compare.csv"
    output: "results/compare/gate.txt"
    log: "logs/compare/gate.log"
    benchmark: "logs/benchmarks/compare_gate/all.tsv"
    script: "../scripts/compare_gate.py"


def build_pair_comparisons():
    """results/compare/<baseline>_vs_<candidate>/compare.md of config compare_builds (part of `all`).
    A pair with a build the study does not run (builds given on the command line) is left out,
    saying so: it is a report, not a check."""
    out = []
    for pair in config.get("compare_builds") or []:
        missing = [pair[role] for role in ("baseline", "candidate") if pair[role] not in BUILDS]
        if missing:
            print(f"config 'compare_builds': {pair['baseline']} -> {pair['candidate']} left out: the study has no "
                  f"build {', '.join(map(repr, missing))} (its builds: {', '.join(BUILD_IDS)})", file=sys.stderr)
            continue
        out.append(f"results/compare/{pair['baseline']}_vs_{pair['candidate']}/compare.md")
    return out


rule compare_builds:
    """Two builds of this study, check by check (compare --builds): the regression cases of a
    defect fixed in the candidate show as fixes. A report, not a gate."""
    input: candidate="results/checks.csv", baseline="results/checks.csv", summary="results/summary.csv"
    output:
        csv="results/compare/{baseline}_vs_{candidate}/compare.csv",
        md="results/compare/{baseline}_vs_{candidate}/compare.md",
        html="results/compare/{baseline}_vs_{candidate}/compare.html",
        junit="results/compare/{baseline}_vs_{candidate}/compare-junit.xml",
    log: "logs/compare/{baseline}_vs_{candidate}.log"
    benchmark: "logs/benchmarks/compare_builds/{baseline}/{candidate}.tsv"
    params: factor=config["compare_factor"], tolerance=config["tolerance"],
            builds=lambda w: (w.baseline, w.candidate)
    script: "../scripts/compare_studies.py"


BUILD_PAIR_COMPARISONS = build_pair_comparisons()
