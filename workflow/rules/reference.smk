# The reference solver's tables: the solution over a K grid and the series coefficients.


rule reference_table:
    """The reference solver over the configured K grid (one row per K, both criteria)."""
    output: "results/reference/collisions.csv"
    log: "logs/reference_table.log"
    benchmark: "benchmarks/reference_table.tsv"
    params: grid=config["reference"]["K_grid"]
    script: "../scripts/reference_table.py"


rule series:
    """The project's Taylor coefficients beside the paper's series."""
    output: "results/reference/series.csv"
    log: "logs/series.log"
    params: order=config["reference"]["series_order"]
    script: "../scripts/series_table.py"
