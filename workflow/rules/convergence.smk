# Time-step convergence of every engine build, and the LAMMPS regression cases of every LAMMPS build.

from functools import lru_cache

from engines.plan import plan_at_velocity, references_of


@lru_cache(maxsize=None)
def convergence_plan_of(code):
    """`code`'s convergence runs, planned (and their reference solved) once per workflow."""
    c = config["convergence"]
    return plan_at_velocity(load_case(c["case"]), code, c["K"], c["time_step_factors"], c["velocity"], "convergence",
                            every_law=True)


def convergence_priority_of(code):
    """run_engine's priority (engine_job_priority) for `code`'s convergence sweep: these are the
    study's longest engine jobs (ESyS's ~1 min expected), and convergence_summary, which waits
    for the last of them, lands on the study's tail when they start late."""
    return sweep_priority(code, convergence_plan_of(code))


rule convergence_runs:
    """Time-step convergence: one build, every K and time-step factor, in one engine process."""
    input:
        case=config["convergence"]["case"],
        decks=lambda w: DECKS[BUILDS[w.build].code],
    output:
        manifest="results/convergence/{build}/manifest.json",
        runs=directory("results/convergence/{build}/runs"),
    log: "logs/convergence/{build}.log"
    benchmark: "logs/benchmarks/convergence_runs/{build}.tsv"
    params: convergence=config["convergence"], timeout_floor_s=config["engine_timeout_floor_s"],
            build=lambda w: build_params(w.build),
            # solved here already (the priority's plan): the job need not load the kernel again
            reference=lambda w: references_of(convergence_plan_of(BUILDS[w.build].code))
    threads: lambda w: CODES[BUILDS[w.build].code].processes  # as run_engine: ESyS runs two MPI ranks
    priority: lambda w: convergence_priority_of(BUILDS[w.build].code)
    resources: **cluster_resources(runtime=30, mem_mb=2000)
    script: "../scripts/convergence_runs.py"


rule largest_steps:
    """The largest dt / T_R holding 1e-2, 1e-3 and 1e-4 at every start phase, on the engines' map
    (analysis.timestep_maps, drawn by report.report_timestep): the viscoelastic law over the K grid, each code's keyword over e."""
    input: case=config["convergence"]["case"]
    output:
        csv="results/convergence/largest_dt_over_T_R.csv",
        plot="results/plots/largest_dt_over_T_R.png",
    log: "logs/convergence/largest_steps.log"
    benchmark: "logs/benchmarks/largest_steps/all.tsv"
    params: K=config["K_grid"], restitution=[0.3, 0.5, 0.7, 0.8, 0.9, 0.95]
    script: "../scripts/largest_steps.py"


rule convergence_summary:
    """Errors against dt from production steps on, the observed orders, the largest dt meeting
    each threshold (in T_e and in the Rayleigh time); the log-log plot."""
    input:
        manifests=expand("results/convergence/{build}/manifest.json", build=BUILD_IDS),
        runs=expand("results/convergence/{build}/runs", build=BUILD_IDS),
        case=config["convergence"]["case"],
    output:
        errors="results/convergence/errors.csv",
        orders="results/convergence/orders.csv",
        largest_dt="results/convergence/largest_dt.csv",
        spread="results/convergence/build_spread.csv",
        plot="results/plots/convergence.png",
    log: "logs/convergence/summary.log"
    benchmark: "logs/benchmarks/convergence_summary/all.tsv"
    params: thresholds=config["convergence"]["thresholds"], case=config["convergence"]["case"]
    script: "../scripts/convergence_summary.py"

