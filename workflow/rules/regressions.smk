# Known defects of engine builds, as regression cases run in every build of the code (config
# extras: lammps_regressions). Their checks appear in checks.csv and in `compare`, marked as not
# gating: a defect of Debian's LAMMPS is a finding about that build, not a failure of the study.


rule lammps_regression_runs:
    """The LAMMPS regression cases (engines.lammps.regression_cases) in one LAMMPS build: the
    wall's hertz/material modulus and the mixed pair of per-type coefficients."""
    input: DECKS["lammps"]
    output: csv="results/lammps/{lammps_build}/regressions.csv",
            runs=directory("results/lammps/{lammps_build}/regressions"),
            # As every engine job's: the dumps with their sha256, the failed runs and the engine
            # process seconds (which benchmarks/study.py sums)
            manifest="results/lammps/{lammps_build}/manifest.json"
    log: "logs/lammps_regressions/{lammps_build}.log"
    benchmark: "logs/benchmarks/lammps_regression_runs/{lammps_build}.tsv"
    params: build=lambda w: build_params(w.lammps_build), timeout_floor_s=config["engine_timeout_floor_s"]
    resources: **cluster_resources()
    script: "../scripts/lammps_regression_runs.py"


rule lammps_regressions:
    """The regression cases of every LAMMPS build in one table: build x case -> error."""
    input: expand("results/lammps/{lammps_build}/regressions.csv", lammps_build=LAMMPS_BUILDS)
    output: "results/lammps/regressions.csv"
    log: "logs/lammps_regressions.log"
    benchmark: "logs/benchmarks/lammps_regressions/all.tsv"
    script: "../scripts/lammps_regressions.py"
