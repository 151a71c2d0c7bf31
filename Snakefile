"""The Hertz DEM validation study. `snakemake -j2 all` runs it; results go to results/."""

from snakemake.utils import validate

configfile: "config/config.yaml"
validate(config, "config/config.schema.yaml")


rule all:
    input:
        "results/reference/collisions.csv",
        "results/reference/series.csv",


rule reference_table:
    """The reference solver over the configured K grid (one row per K, both criteria)."""
    output: "results/reference/collisions.csv"
    log: "logs/reference_table.log"
    benchmark: "benchmarks/reference_table.tsv"
    params: grid=config["reference"]["K_grid"]
    script: "workflow/scripts/reference_table.py"


rule series:
    """The project's Taylor coefficients beside the paper's series."""
    output: "results/reference/series.csv"
    log: "logs/series.log"
    params: order=config["reference"]["series_order"]
    script: "workflow/scripts/series_table.py"
