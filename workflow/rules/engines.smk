# From a case to its engine runs and its summary.


rule plan:
    """The case's runs, checked and listed (results/<case>/plan.json)."""
    input: case=lambda w: CASES[w.case], codes=CODES_FILE  # which laws each code can run
    output: "results/{case}/plan.json"
    log: "logs/{case}/plan.log"
    params: listing=lambda w: PLANS[w.case]  # planned when the workflow started (workflow/rules/cases.smk)
    script: "../scripts/plan_case.py"


def engine_priority(wildcards):
    """Longest expected sweep first (engines.codes cost model, from the plan's steps): two
    lanes finish together when the long jobs start early, not last."""
    runs = [r for r in PLANS[wildcards.case]["runs"] if r["build"] == wildcards.build]
    return 1 + int(10 * CODES[BUILDS[wildcards.build].code].expected_seconds(len(runs), sum(r["steps"] for r in runs)))


rule run_engine:
    """Every run of one case in one process of one engine build: one dump per run in runs/, and the manifest
    (dumps with sha256, failed runs)."""
    input:
        plan="results/{case}/plan.json",
        case=lambda w: CASES[w.case],
        decks=lambda w: DECKS[BUILDS[w.build].code],
    output:
        manifest="results/{case}/{build}/manifest.json",
        runs=directory("results/{case}/{build}/runs"),
    log: "logs/{case}/{build}.log"
    benchmark: "benchmarks/{case}/{build}.tsv"
    params: settings=SETTINGS, build=lambda w: build_params(w.build)
    threads: lambda w: CODES[BUILDS[w.build].code].processes  # ESyS: two MPI ranks
    priority: engine_priority
    resources: runtime=30, mem_mb=2000
    script: "../scripts/run_engine.py"


rule case_summary:
    """The case's runs beside the reference solver and the paper's series (dumps verified)."""
    input:
        plan="results/{case}/plan.json",
        manifests=expand("results/{{case}}/{build}/manifest.json", build=BUILD_IDS),
        runs=expand("results/{{case}}/{build}/runs", build=BUILD_IDS),
    output: "results/{case}/summary.csv"
    log: "logs/{case}/summary.log"
    resources: runtime=10, mem_mb=2000
    script: "../scripts/case_summary.py"
