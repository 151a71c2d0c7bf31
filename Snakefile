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


PAPER_FIGURES = {1: "fig1_phi", 3: "fig3_eps_collapse", 4: "fig4_energy", 5: "fig5_fracture"}
EXTRA_REPORT_INPUTS = {
    "convergence": "results/convergence/orders.csv",
    "claims": "results/paper/claims.csv",
    "table1": "results/paper/table1.csv",
    "energy_check": "results/paper/fig4_energy.csv",
    **{f"figure_{n}": f"results/paper/{name}.png" for n, name in PAPER_FIGURES.items()},
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


rule paper_claims:
    """The paper's claims, each with its number, the computed one and a verdict; its Table 1."""
    input: cases=[f"cases/{c}.yaml" for c in ("steel", "brass", "cork", "ice", "jaques_ball")]
    output: claims="results/paper/claims.csv", table1="results/paper/table1.csv"
    log: "logs/paper/claims.log"
    script: "workflow/scripts/paper_claims.py"


rule paper_figure_1:
    """Fig. 1: phi_1, phi_2 against K (series and solver, both criteria); inset xi."""
    output: png="results/paper/fig1_phi.png"
    log: "logs/paper/figure_1.log"
    params: figure=1
    script: "workflow/scripts/paper_figure.py"


rule paper_figure_3:
    """Fig. 3 analogue: eps of every DEM run against K."""
    input: summary="results/summary.csv"
    output: png="results/paper/fig3_eps_collapse.png"
    log: "logs/paper/figure_3.log"
    params: figure=3
    script: "workflow/scripts/paper_figure.py"


rule paper_energy_runs:
    """The DEM runs of Fig. 4, in the first configured engine."""
    input: case=config["paper"]["energy"]["case"], decks=DECKS[ENGINES[0]]
    output: manifest="results/paper/energy_runs/manifest.json"
    log: "logs/paper/energy_runs.log"
    params: energy=config["paper"]["energy"], engine=ENGINES[0], time_step_factor=config["time_step_factor"]
    script: "workflow/scripts/paper_energy_runs.py"


rule paper_figure_4:
    """Fig. 4: kinetic, elastic, dissipated energy in time; the reference and one DEM run per K."""
    input: manifest="results/paper/energy_runs/manifest.json"
    output: png="results/paper/fig4_energy.png", csv="results/paper/fig4_energy.csv"
    log: "logs/paper/figure_4.log"
    params: figure=4
    script: "workflow/scripts/paper_figure.py"


rule paper_figure_5:
    """Fig. 5: the fracture velocity V_F/V_P against R/L_d, three readings of 'pressure'."""
    input: case=config["paper"]["fracture"]["case"]
    output: png="results/paper/fig5_fracture.png", csv="results/paper/fig5_fracture.csv"
    log: "logs/paper/figure_5.log"
    params: figure=5, P0=config["paper"]["fracture"]["P0"]
    script: "workflow/scripts/paper_figure.py"


rule gate:
    """The last step: exits non-zero, naming them, when an engine exceeds a tolerance."""
    input: verdict="results/verdict.json"
    output: "results/gate.txt"
    log: "logs/gate.log"
    script: "workflow/scripts/gate.py"
