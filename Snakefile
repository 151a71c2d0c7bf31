"""The viscoelastic Hertz validation study.

    snakemake -j2 all                 every case, both engines, the report; fails if a tolerance fails
    snakemake -j2 steel               one case (any file name in cases/ without .yaml)
    snakemake -j2 results/steel/summary.csv

Settings: config/config.yaml (validated against config/config.schema.yaml). Logs: logs/,
benchmarks: benchmarks/<case>/<engine>.tsv, results: results/.
"""

import glob
import os
from pathlib import Path

from snakemake.utils import validate

configfile: "config/config.yaml"


def _as_number(value):
    """--config 'K_grid=[0.1,0.3]' arrives as strings; anything not a number stays as it is
    and is refused by the schema with its key named."""
    try:
        return float(value) if isinstance(value, str) else value
    except ValueError:
        return value


if isinstance(config.get("K_grid"), list):
    config["K_grid"] = [_as_number(v) for v in config["K_grid"]]
for _key in ("K", "time_step_factors"):
    if isinstance(config.get("convergence", {}).get(_key), list):
        config["convergence"][_key] = [_as_number(v) for v in config["convergence"][_key]]
validate(config, "config/config.schema.yaml")

# The workflow's scripts import the project's packages and workflow/scripts/common.py.
os.environ["PYTHONPATH"] = os.pathsep.join(
    [workflow.basedir, f"{workflow.basedir}/workflow/scripts", os.environ.get("PYTHONPATH", "")])

from contact_model import load_case  # noqa: E402


def case_files():
    patterns = [config["cases"]] if isinstance(config["cases"], str) else config["cases"]
    files = sorted({f for p in patterns for f in glob.glob(p)})
    if not files:
        raise ValueError(f"config 'cases': no case file matches {config['cases']!r}")
    return {Path(f).stem: f for f in files}


CASES = case_files()
# Every case is validated here, before any job (let alone an engine) starts: a malformed case
# stops the workflow with the file and the field named.
for _path in CASES.values():
    load_case(_path)

ENGINES = config["engines"]
DECKS = {"liggghts": sorted(glob.glob("cases/decks/liggghts/*.in")), "yade": ["cases/decks/yade/collisions.py"],
         "lammps": sorted(glob.glob("cases/decks/lammps/*.in"))}
SETTINGS = {k: config[k] for k in ("engines", "laws", "K_grid", "time_step_factor", "default_law_match_K",
                                   "max_overlap_ratio")}

# Light bookkeeping stays on the submitting host when a cluster profile is used.
localrules: all, plan, summary, reference_table, series, report, gate

wildcard_constraints:
    case="|".join(CASES),
    engine="|".join(ENGINES),


EXTRA_REPORT_INPUTS = {
    "convergence": "results/convergence/orders.csv",
    **({"lammps_wall": "results/lammps/wall_modulus.csv"} if "lammps" in ENGINES else {}),
}


rule all:
    input:
        "results/gate.txt",
        "results/report.md",
        "results/report.html",
        "results/summary.csv",
        "results/reference/collisions.csv",


# One target per case: `snakemake -j2 steel`.
for _case in CASES:
    rule:
        name: _case
        input: f"results/{_case}/summary.csv"


rule plan:
    """The case's runs, checked and listed (results/<case>/plan.json)."""
    input: case=lambda w: CASES[w.case]
    output: "results/{case}/plan.json"
    log: "logs/{case}/plan.log"
    params: settings=SETTINGS
    script: "workflow/scripts/plan_case.py"


rule run_engine:
    """Every run of one case in one engine process; one dump per run."""
    input:
        plan="results/{case}/plan.json",
        case=lambda w: CASES[w.case],
        decks=lambda w: DECKS[w.engine],
    output: manifest="results/{case}/{engine}/manifest.json"
    log: "logs/{case}/{engine}.log"
    benchmark: "benchmarks/{case}/{engine}.tsv"
    params: settings=SETTINGS
    threads: 1
    resources: runtime=30, mem_mb=2000
    script: "workflow/scripts/run_engine.py"


rule case_summary:
    """The case's runs beside the reference solver and the paper's series."""
    input: manifests=expand("results/{{case}}/{engine}/manifest.json", engine=ENGINES)
    output: "results/{case}/summary.csv"
    log: "logs/{case}/summary.log"
    resources: runtime=10, mem_mb=2000
    script: "workflow/scripts/case_summary.py"


rule summary:
    input: expand("results/{case}/summary.csv", case=CASES)
    output: "results/summary.csv"
    log: "logs/summary.log"
    script: "workflow/scripts/study_summary.py"


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


rule report:
    """results/report.md and .html, the plots, and the verdict."""
    input:
        summary="results/summary.csv",
        series="results/reference/series.csv",
        manifests=expand("results/{case}/{engine}/manifest.json", case=CASES, engine=ENGINES),
        plans=expand("results/{case}/plan.json", case=CASES),
        **EXTRA_REPORT_INPUTS,
    output:
        md="results/report.md",
        html="results/report.html",
        verdict="results/verdict.json",
    log: "logs/report.log"
    params: tolerance=config["tolerance"]
    script: "workflow/scripts/report.py"


rule convergence_runs:
    """Time-step convergence: one engine, every K and time-step factor, in one engine process."""
    input:
        case=config["convergence"]["case"],
        decks=lambda w: DECKS[w.engine],
    output: manifest="results/convergence/{engine}/manifest.json"
    log: "logs/convergence/{engine}.log"
    benchmark: "benchmarks/convergence/{engine}.tsv"
    params: convergence=config["convergence"]
    resources: runtime=30, mem_mb=2000
    script: "workflow/scripts/convergence_runs.py"


rule convergence_summary:
    """Errors against dt, the observed orders and the largest passing dt; the log-log plot."""
    input: manifests=expand("results/convergence/{engine}/manifest.json", engine=ENGINES)
    output:
        errors="results/convergence/errors.csv",
        orders="results/convergence/orders.csv",
        plot="results/plots/convergence.png",
    log: "logs/convergence/summary.log"
    params: tolerance=config["tolerance"]
    script: "workflow/scripts/convergence_summary.py"


rule lammps_wall_modulus:
    """Regression case: LAMMPS fix wall/gran hertz/material uses E/(2(1-nu)), not E/(2(1-nu^2))."""
    input: "cases/decks/lammps/sphere_plane.in"
    output: "results/lammps/wall_modulus.csv"
    log: "logs/lammps_wall_modulus.log"
    params: workdir="results/lammps/wall_modulus", poisson=0.3
    script: "workflow/scripts/lammps_wall_modulus.py"


rule gate:
    """The last step: exits non-zero, naming them, when an engine exceeds a tolerance."""
    input: verdict="results/verdict.json"
    output: "results/gate.txt"
    log: "logs/gate.log"
    script: "workflow/scripts/gate.py"
