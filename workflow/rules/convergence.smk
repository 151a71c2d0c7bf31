# Time-step convergence of every engine, and the LAMMPS wall-modulus regression case.


rule convergence_runs:
    """Time-step convergence: one engine, every K and time-step factor, in one engine process."""
    input:
        case=config["convergence"]["case"],
        decks=lambda w: DECKS[w.engine],
    output:
        manifest="results/convergence/{engine}/manifest.json",
        runs=directory("results/convergence/{engine}/runs"),
    log: "logs/convergence/{engine}.log"
    benchmark: "benchmarks/convergence/{engine}.tsv"
    params: convergence=config["convergence"], timeout_floor_s=config["engine_timeout_floor_s"]
    resources: runtime=30, mem_mb=2000
    script: "../scripts/convergence_runs.py"


rule convergence_summary:
    """Errors against dt, the observed orders and the largest passing dt; the log-log plot."""
    input:
        manifests=expand("results/convergence/{engine}/manifest.json", engine=ENGINES),
        runs=expand("results/convergence/{engine}/runs", engine=ENGINES),
    output:
        errors="results/convergence/errors.csv",
        orders="results/convergence/orders.csv",
        plot="results/plots/convergence.png",
    log: "logs/convergence/summary.log"
    params: tolerance=config["tolerance"]
    script: "../scripts/convergence_summary.py"


rule lammps_wall_modulus:
    """Regression case: LAMMPS fix wall/gran hertz/material uses E/(2(1-nu)), not E/(2(1-nu^2))."""
    input: "cases/decks/lammps/sphere_plane.in"
    output: csv="results/lammps/wall_modulus.csv", runs=directory("results/lammps/wall_modulus")
    log: "logs/lammps_wall_modulus.log"
    params: poisson=0.3
    script: "../scripts/lammps_wall_modulus.py"
