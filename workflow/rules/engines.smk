# From a case to its engine runs and its summary.


rule plan:
    """The case's runs, checked and listed (results/<case>/plan.json)."""
    input: case=lambda w: CASES[w.case]
    output: "results/{case}/plan.json"
    log: "logs/{case}/plan.log"
    params: settings=SETTINGS
    script: "../scripts/plan_case.py"


rule run_engine:
    """Every run of one case in one engine process: one dump per run in runs/, and the manifest
    (dumps with sha256, failed runs)."""
    input:
        plan="results/{case}/plan.json",
        case=lambda w: CASES[w.case],
        decks=lambda w: DECKS[w.engine],
    output:
        manifest="results/{case}/{engine}/manifest.json",
        runs=directory("results/{case}/{engine}/runs"),
    log: "logs/{case}/{engine}.log"
    benchmark: "benchmarks/{case}/{engine}.tsv"
    params: settings=SETTINGS
    threads: 1
    resources: runtime=30, mem_mb=2000
    script: "../scripts/run_engine.py"


rule case_summary:
    """The case's runs beside the reference solver and the paper's series (dumps verified)."""
    input:
        plan="results/{case}/plan.json",
        manifests=expand("results/{{case}}/{engine}/manifest.json", engine=ENGINES),
        runs=expand("results/{{case}}/{engine}/runs", engine=ENGINES),
    output: "results/{case}/summary.csv"
    log: "logs/{case}/summary.log"
    resources: runtime=10, mem_mb=2000
    script: "../scripts/case_summary.py"
