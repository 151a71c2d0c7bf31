# Reproducing the paper: its claims, Table 1 and Figs. 1, 3, 4 and 5 (results/paper/).

from functools import lru_cache

from engines.plan import plan_at_velocity, references_of


rule paper_reference:
    """The paper's results that need no engine, from the reference solver: its claims (each with
    its number, the computed one and a verdict), its Table 1, Fig. 1 (phi_1, phi_2 against K,
    series and solver, both criteria; inset xi) and Fig. 5 (the fracture velocity V_F/V_P against
    R/L_d, three readings of 'pressure'). One job: each Python process that solves and plots pays
    ~2.5 s of imports and numba's start-up, more than each of these outputs' own work."""
    input: cases=[f"cases/{c}.yaml" for c in ("steel", "brass", "cork", "ice", "jaques_ball")],
           fracture_case=config["paper"]["fracture"]["case"]
    output: claims="results/paper/claims.csv", table1="results/paper/table1.csv",
            figure_1="results/paper/fig1_phi.png",
            figure_5="results/paper/fig5_fracture.png", figure_5_csv="results/paper/fig5_fracture.csv"
    log: "logs/paper/reference.log"
    benchmark: "logs/benchmarks/paper_reference/all.tsv"
    params: P0=config["paper"]["fracture"]["P0"]
    resources: **cluster_resources()
    script: "../scripts/paper_reference.py"


rule paper_figure_3:
    """Fig. 3 analogue: eps of every DEM run against K."""
    input: summary="results/summary.csv"
    output: png="results/paper/fig3_eps_collapse.png"
    log: "logs/paper/figure_3.log"
    benchmark: "logs/benchmarks/paper_figure_3/all.tsv"
    params: figure=3
    priority: CRITICAL_PATH  # between the summary and the report
    script: "../scripts/paper_figure.py"


@lru_cache(maxsize=None)
def energy_plan():
    """Fig. 4's DEM runs in the first build, planned (and their reference solved) once per
    workflow, however often Snakemake evaluates the params (as convergence_plan_of)."""
    e = config["paper"]["energy"]
    return plan_at_velocity(load_case(e["case"]), BUILDS[BUILD_IDS[0]].code, e["K"],
                            [config["time_step_factor"]], e["velocity"], "energy")


rule paper_energy_runs:
    """The DEM runs of Fig. 4, in the first configured build."""
    input: case=config["paper"]["energy"]["case"], decks=DECKS[BUILDS[BUILD_IDS[0]].code]
    output:
        manifest="results/paper/energy_runs/manifest.json",
        runs=directory("results/paper/energy_runs/runs"),
    log: "logs/paper/energy_runs.log"
    benchmark: "logs/benchmarks/paper_energy_runs/all.tsv"
    params: energy=config["paper"]["energy"], build=build_params(BUILD_IDS[0]), time_step_factor=config["time_step_factor"],
            timeout_floor_s=config["engine_timeout_floor_s"], reference=lambda w: references_of(energy_plan())
    threads: CODES[BUILDS[BUILD_IDS[0]].code].processes  # as run_engine (ESyS: two MPI ranks)
    # run_engine's rule: a first build of several processes (ESyS) runs them while both cores are free
    priority: lambda w: sweep_priority(BUILDS[BUILD_IDS[0]].code, energy_plan())
    resources: **cluster_resources()
    script: "../scripts/paper_energy_runs.py"


rule paper_figure_4:
    """Fig. 4: kinetic, elastic, dissipated energy in time; the reference and one DEM run per K."""
    input: manifest="results/paper/energy_runs/manifest.json", runs="results/paper/energy_runs/runs"
    output: png="results/paper/fig4_energy.png", csv="results/paper/fig4_energy.csv"
    log: "logs/paper/figure_4.log"
    benchmark: "logs/benchmarks/paper_figure_4/all.tsv"
    params: figure=4
    script: "../scripts/paper_figure.py"
