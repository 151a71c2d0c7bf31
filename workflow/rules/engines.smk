# From a case to its engine runs and its summary.


# Job priorities: Snakemake starts the highest-priority ready job that fits the free cores.
#: A job of several processes (ESyS's two MPI ranks, `threads` = processes) needs every core free
#: at once, and the job selection finds them free only at the study's start: later, each job that
#: ends frees one core, which a ready single-process job takes. So such jobs waited for all the
#: others and ran alone on the study's tail, while the case summaries, the summary and the report
#: behind them ran on one core. They are ready as soon as their case's plan is written (the
#: version queries and the plans go first: a few seconds) and go first.
ALL_CORES_FIRST = 1_000_000
#: The jobs between a case's last engine run and the report (the case's summary, the study's
#: summary, Fig. 3): ahead of any single-process engine job, so that they run as soon as they can
#: while the post-processing that waits for no engine (priority 0: calibration, paper figures,
#: closed forms) fills the other core on the study's tail.
CRITICAL_PATH = 100_000


def engine_job_priority(code, n_runs, steps):
    """Priority of an engine job of `n_runs` runs of `steps` time steps in all of engine `code`:
    1 + 10 x its expected seconds (engines.codes cost model), longest first, so that two lanes
    finish together; plus ALL_CORES_FIRST for a code of several processes."""
    first = ALL_CORES_FIRST if CODES[code].processes > 1 else 0
    return first + 1 + int(10 * CODES[code].expected_seconds(n_runs, steps))


def sweep_priority(code, runs):
    """engine_job_priority of a sweep of planned runs (RunSpec) of engine `code`."""
    return engine_job_priority(code, len(runs), sum(r.steps() for r in runs))


def engine_priority(wildcards):
    """run_engine's priority: engine_job_priority of the case's runs in the build."""
    runs = [r for r in PLANS[wildcards.case]["runs"] if r["build"] == wildcards.build]
    return engine_job_priority(BUILDS[wildcards.build].code, len(runs), sum(r["steps"] for r in runs))


from engines.plan import build_part  # noqa: E402
from engines.plan_digest import PlanListing  # noqa: E402


rule plan:
    """The case's runs, checked and listed (results/<case>/plan.json): the plan made when the workflow
    started (workflow/rules/cases.smk), cut to the keywords each build's release has (its
    engine_version). What the engine jobs run."""
    input:
        case=lambda w: CASES[w.case],
        codes=CODES_FILE,  # which laws each code can run
        versions=expand("results/engine_versions/{build}.json", build=BUILD_IDS),
    output: "results/{case}/plan.json"
    log: "logs/{case}/plan.log"
    benchmark: "logs/benchmarks/plan/{case}.tsv"
    # named in the log by its digest
    params: listing=lambda w: PlanListing(PLANS[w.case])
    # The engine jobs wait for it: first, after the version queries.
    priority: ALL_CORES_FIRST + CRITICAL_PATH
    script: "../scripts/plan_case.py"


def build_listing(wildcards, input):
    """run_engine's plan: the build's part of the case's plan.json (`engines.plan.build_part`),
    read when the job runs. A change of it reruns the job; another build's runs do not."""
    return PlanListing(build_part(json.loads(Path(input.plan).read_text()), wildcards.build))


rule run_engine:
    """Every run of one case in one process of one engine build: one dump per run in runs/, and the manifest
    (dumps with sha256, failed runs)."""
    input:
        case=lambda w: CASES[w.case],
        plan="results/{case}/plan.json",
        decks=lambda w: DECKS[BUILDS[w.build].code],
    output:
        manifest="results/{case}/{build}/manifest.json",
        runs=directory("results/{case}/{build}/runs"),
    log: "logs/{case}/{build}.log"
    benchmark: "logs/benchmarks/run_engine/{case}/{build}.tsv"
    # Its runs from plan.json (cut to the build's release), read when the job starts: Snakemake
    # evaluates a param that reads an input file then. A changed plan reruns the job.
    params: settings=SETTINGS, build=lambda w: build_params(w.build), listing=build_listing
    threads: lambda w: CODES[BUILDS[w.build].code].processes  # ESyS: two MPI ranks
    priority: engine_priority
    resources: **cluster_resources(runtime=30, mem_mb=2000)
    script: "../scripts/run_engine.py"


from records.run_manifest import changed_dumps  # noqa: E402


def dumps_changed_since_summary(wildcards):
    """The dumps of the case's engine jobs that are no longer the ones their jobs wrote (each
    `records.run_manifest.dump_problem`, naming the file), while the case has a summary; [] when
    every dump is intact or there is no summary yet (the rule runs then anyway, and verifies every
    dump). A param of case_summary: a dump truncated or edited by hand changes it, and Snakemake
    reruns the summary on the next run (its params trigger), which refuses the dump by name and
    withdraws the PASS, with no --forcerun. A dump edited in place leaves the folder's mtime, the
    rule's input, as it was. Cost per workflow start: a stat of every dump, and a sha256 of those
    not verified before with the same inode, size, mtime and ctime (records.run_manifest.changed_dumps,
    its cache in .snakemake/hertz-verified-dumps/<case>.json): the study's 5600 dumps in 0.1 s, or
    0.8 s when every one is hashed (a fresh copy; 3.5 s from disk)."""
    if not Path(f"results/{wildcards.case}/summary.csv").exists():
        return []
    manifests = [f"results/{wildcards.case}/{b}/manifest.json" for b in BUILD_IDS]
    return changed_dumps([m for m in manifests if Path(m).exists()],
                         verified=f".snakemake/hertz-verified-dumps/{wildcards.case}.json")


rule case_summary:
    """The case's runs beside the reference solver and the paper's series (dumps verified; a dump
    changed since reruns it: dumps_changed_since_summary)."""
    input:
        plan="results/{case}/plan.json",
        manifests=expand("results/{{case}}/{build}/manifest.json", build=BUILD_IDS),
        runs=expand("results/{{case}}/{build}/runs", build=BUILD_IDS),
    output: "results/{case}/summary.csv"
    log: "logs/{case}/summary.log"
    benchmark: "logs/benchmarks/case_summary/{case}.tsv"
    params: dumps_changed=dumps_changed_since_summary
    priority: CRITICAL_PATH
    resources: **cluster_resources(runtime=10, mem_mb=2000)
    script: "../scripts/case_summary.py"
