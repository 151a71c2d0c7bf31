# The reference solver's tables: the solution over a K grid and the series coefficients.


rule reference_tables:
    """The reference solver over the configured K grid (one row per K, both criteria), and the
    project's Taylor coefficients beside the paper's series. One job for both: each Python process
    that solves pays ~2 s of imports and numba's start-up, more than either table's own work."""
    output: collisions="results/reference/collisions.csv", series="results/reference/series.csv"
    log: "logs/reference_tables.log"
    benchmark: "logs/benchmarks/reference_tables/all.tsv"
    params: grid=config["reference"]["K_grid"], order=config["reference"]["series_order"]
    script: "../scripts/reference_tables.py"
