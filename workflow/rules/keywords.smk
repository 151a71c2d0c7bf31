# The engines' restitution keywords told every e of config `keywords:` (snakemake -j2 keywords):
# what each delivers at dt -> 0 against what it is told, beside what its own equation restitutes
# (analysis.keyword_promise; docs/keywords.md). Not part of `all`, and no verdict: the keywords'
# conformance is gated in the study itself (the law `default`).


rule keyword_runs:
    """One build's keyword told every e, a ladder each, in one engine process."""
    input:
        case=config["keywords"]["case"],
        decks=lambda w: DECKS[BUILDS[w.build].code],
    output:
        rows="results/keywords/{build}.csv",
        manifest="results/keywords/{build}/manifest.json",
        runs=directory("results/keywords/{build}/runs"),
    log: "logs/keywords/{build}.log"
    benchmark: "logs/benchmarks/keyword_runs/{build}.tsv"
    params: keywords=config["keywords"], ladder=config["ladder"], timeout_floor_s=config["engine_timeout_floor_s"],
            build=lambda w: build_params(w.build)
    threads: lambda w: CODES[BUILDS[w.build].code].processes  # as run_engine: ESyS runs two MPI ranks
    resources: **cluster_resources(runtime=30, mem_mb=2000)
    script: "../scripts/keyword_runs.py"


rule keywords_summary:
    """promise.csv (every build and e), promise.md (per build: the largest promise error and where,
    and at e = 0.5, 0.8, 0.95) and promise.png (delivered - requested against e); with config
    keywords.measured, eps_of_velocity.csv and .png: each damping form fitted to the measured eps(V);
    promise_over_velocity.csv: a keyword told e at a velocity (YADE's en + vn) at other velocities."""
    input:
        rows=expand("results/keywords/{build}.csv", build=BUILD_IDS),
        measured=config["keywords"].get("measured") or [],
    output:
        csv="results/keywords/promise.csv",
        md="results/keywords/promise.md",
        png="results/keywords/promise.png",
        forms="results/keywords/eps_of_velocity.csv",
        forms_png="results/keywords/eps_of_velocity.png",
        over_velocity="results/keywords/promise_over_velocity.csv",
    log: "logs/keywords/summary.log"
    benchmark: "logs/benchmarks/keywords_summary/all.tsv"
    script: "../scripts/keywords_summary.py"


rule keywords:
    input: rules.keywords_summary.output
