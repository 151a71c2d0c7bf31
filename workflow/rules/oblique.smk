# Oblique impacts (snakemake -j2 oblique; docs/tangential.md): every case of config `oblique:`
# (cases/oblique/: Chung & Ooi's tests 4-8) in every build of `oblique.builds`, with each
# tangential model its release has (contact_model/tangential_models.yaml), a ladder of time steps
# each, extrapolated to dt -> 0 and gated against the model's own equation (analysis.oblique).
# `all` runs the reduced set `oblique.reduced` of the same cases (the `oblique_reduced` target).


from contact_model.tangential_models import REGISTRY_PATH as TANGENTIAL_MODELS_FILE  # noqa: E402

OBLIQUE = config.get("oblique") or {"cases": "", "builds": [], "reduced": {"cases": []}, "tolerance": 1e-6}


def oblique_cases(reduced=False):
    """The case files of config oblique (`reduced`: oblique.reduced.cases)."""
    o = OBLIQUE
    return sorted(o["reduced"]["cases"] if reduced else glob.glob(o["cases"]))


rule oblique_runs:
    """One build's oblique ladders of one set (full or reduced), in its engine: rungs.csv (every
    rung against its reference), limits.csv (each ladder at dt -> 0) and checks.csv."""
    input:
        cases=lambda w: oblique_cases(w.set == "reduced"),
        decks=lambda w: DECKS[BUILDS[w.build].code],
        models=str(TANGENTIAL_MODELS_FILE),  # the registry (where the package is: a copy of the workflow too)
    output:
        rungs="results/oblique/{set}/{build}/rungs.csv",
        limits="results/oblique/{set}/{build}/limits.csv",
        checks="results/oblique/{set}/{build}/checks.csv",
        manifest="results/oblique/{set}/{build}/manifest.json",
        runs=directory("results/oblique/{set}/{build}/runs"),
    log: "logs/oblique/{set}/{build}.log"
    benchmark: "logs/benchmarks/oblique_runs/{set}/{build}.tsv"
    wildcard_constraints: set="full|reduced"
    params: oblique=OBLIQUE, build=lambda w: build_params(w.build),
            timeout_floor_s=config["engine_timeout_floor_s"]
    threads: lambda w: CODES[BUILDS[w.build].code].processes
    resources: **cluster_resources(runtime=60, mem_mb=2000)
    script: "../scripts/oblique_runs.py"


rule oblique_summary:
    """summary.csv (every build's rungs and limits), checks.csv, report.md with the conformance
    matrix and the figures e_t, omega' and rebound angle against incidence, verdict.json."""
    input:
        rungs=lambda w: expand("results/oblique/{set}/{build}/rungs.csv", set=w.set, build=OBLIQUE_BUILDS),
        limits=lambda w: expand("results/oblique/{set}/{build}/limits.csv", set=w.set, build=OBLIQUE_BUILDS),
        checks=lambda w: expand("results/oblique/{set}/{build}/checks.csv", set=w.set, build=OBLIQUE_BUILDS),
    output:
        summary="results/oblique/{set}/summary.csv",
        checks="results/oblique/{set}/checks.csv",
        report="results/oblique/{set}/report.md",
        verdict="results/oblique/{set}/verdict.json",
        junit="results/oblique/{set}/junit.xml",
        figures=directory("results/oblique/{set}/figures"),
    wildcard_constraints: set="full|reduced"
    log: "logs/oblique/{set}/summary.log"
    params: tolerance=OBLIQUE["tolerance"]
    script: "../scripts/oblique_summary.py"


def oblique_builds():
    """The builds the oblique sets run: those of config oblique.builds the study has, or, where it has
    none of them (a study of builds of your own), every study build whose code has an oblique driver."""
    named = [b for b in OBLIQUE["builds"] if b in BUILDS]
    return named or [b for b, build in BUILDS.items() if CODES[build.code].oblique_driver]


OBLIQUE_BUILDS = oblique_builds()


rule oblique_gate:
    """gate.txt on PASS; on FAIL exits non-zero naming every failing check (the report stays)."""
    input: verdict="results/oblique/{set}/verdict.json", checks="results/oblique/{set}/checks.csv"
    output: "results/oblique/{set}/gate.txt"
    wildcard_constraints: set="full|reduced"
    log: "logs/oblique/{set}/gate.log"
    params: report="results/oblique/{set}/report.md"
    script: "../scripts/oblique_gate.py"


rule oblique:
    input: "results/oblique/full/gate.txt", "results/oblique/full/report.md", "results/oblique/full/junit.xml"


rule oblique_reduced:
    input: "results/oblique/reduced/gate.txt", "results/oblique/reduced/report.md", "results/oblique/reduced/junit.xml"
