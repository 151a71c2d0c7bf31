# The verdicts: of the study (report, JUnit XML, gate) and of one case (its own gate).

from verdict.verdict_files import tolerance_warnings  # noqa: E402

# A tolerance of 1 or more is refused by the config schema (config/config.schema.yaml, naming
# tolerance.T); one above 1e-2 is allowed, and said here, in the checks' logs, verdict.json,
# gate.txt and the reports.
if not IS_JOB:
    for _warning in tolerance_warnings(config["tolerance"]):
        print(f"Warning: {_warning}", file=sys.stderr)


rule summary:
    input: expand("results/{case}/summary.csv", case=CASES)
    output: "results/summary.csv"
    log: "logs/summary.log"
    benchmark: "logs/benchmarks/summary/all.tsv"
    priority: CRITICAL_PATH
    script: "../scripts/study_summary.py"


#: Whether `all` runs the oblique reduced set: extras `oblique`, config `oblique:`, and a build whose code
#: has an oblique driver (workflow/rules/oblique.smk picks them).
OBLIQUE_IN_ALL = bool("oblique" in EXTRAS and config.get("oblique")
                      and any(CODES[b.code].oblique_driver for b in BUILDS.values()))
PAPER_FIGURES = {1: "fig1_phi", 3: "fig3_eps_collapse", 4: "fig4_energy", 5: "fig5_fracture"}
EXTRA_REPORT_INPUTS = {
    **({"convergence": "results/convergence/largest_dt.csv", "convergence_orders": "results/convergence/orders.csv",
        "convergence_spread": "results/convergence/build_spread.csv",
        "largest_steps": "results/convergence/largest_dt_over_T_R.csv"} if "convergence" in EXTRAS else {}),
    **({"claims": "results/paper/claims.csv", "table1": "results/paper/table1.csv",
        "energy_check": "results/paper/fig4_energy.csv",
        **{f"figure_{n}": f"results/paper/{name}.png" for n, name in PAPER_FIGURES.items()}}
       if "paper" in EXTRAS else {}),
    **({"calibration": "results/calibration/report.md"} if "calibration" in EXTRAS else {}),
    # The oblique impacts' reduced set (workflow/rules/oblique.smk): its report, a section; its gate is
    # part of `all` (a FAIL there fails the run, with its own junit.xml and verdict.json).
    **({"oblique": "results/oblique/reduced/report.md"} if OBLIQUE_IN_ALL else {}),
    **({"regressions": "results/lammps/regressions.csv"}
       if "lammps_regressions" in EXTRAS and LAMMPS_BUILDS else {}),
}


rule checks:
    """The checks and the verdict: checks.csv, junit.xml, verdict.json (verdict.gate). It
    waits for every result the report shows (EXTRA_REPORT_INPUTS): each rule that makes one
    first withdraws the verdict files (common.start_rule), which must not happen after them."""
    input:
        summary="results/summary.csv",
        manifests=expand("results/{case}/{build}/manifest.json", case=CASES, build=BUILD_IDS),
        plans=expand("results/{case}/plan.json", case=CASES),
        series="results/reference/series.csv",
        reference="results/reference/collisions.csv",
        **EXTRA_REPORT_INPUTS,
    output:
        checks="results/checks.csv",
        junit="results/junit.xml",
        verdict="results/verdict.json",
    log: "logs/checks.log"
    benchmark: "logs/benchmarks/checks/all.tsv"
    params: tolerance=config["tolerance"]
    priority: CRITICAL_PATH
    script: "../scripts/study_checks.py"


rule report:
    """report.md and .html: the verdict of `checks`, the matrix, the plots, and links to every
    case's report, every build comparison and the calibration."""
    input:
        summary="results/summary.csv",
        checks="results/checks.csv",
        verdict="results/verdict.json",
        series="results/reference/series.csv",
        reference="results/reference/collisions.csv",
        manifests=expand("results/{case}/{build}/manifest.json", case=CASES, build=BUILD_IDS),
        plans=expand("results/{case}/plan.json", case=CASES),
        case_verdicts=expand("results/{case}/verdict.json", case=CASES),
        case_reports=expand("results/{case}/report.md", case=CASES),
        comparisons=lambda w: [str(Path(p).with_name("compare.csv")) for p in BUILD_PAIR_COMPARISONS],
        **EXTRA_REPORT_INPUTS,
    output:
        md="results/report.md",
        html="results/report.html",
    log: "logs/report.log"
    benchmark: "logs/benchmarks/report/all.tsv"
    params: builds={b: build_params(b) for b in BUILD_IDS}, ladder=config["ladder"]
    # Its plots are drawn in two processes (report.report_plots.start_drawing): it runs last,
    # when every other job is done (only the gate waits for it).
    threads: 2
    script: "../scripts/study_report.py"


rule gate:
    """The last step: gate.txt on PASS, stating its tolerances; on FAIL exits non-zero naming every
    failing check, once the report that shows them is written. Before a PASS it checks every dump
    against its manifest's sha256 (workflow/scripts/gate.py)."""
    input:
        verdict="results/verdict.json",
        summary="results/summary.csv",
        report="results/report.md",
        manifests=expand("results/{case}/{build}/manifest.json", case=CASES, build=BUILD_IDS),
    output: "results/gate.txt"
    log: "logs/gate.log"
    benchmark: "logs/benchmarks/gate/all.tsv"
    params: report="results/report.md", rerun_engines="snakemake -j2 all --forcerun run_engine"
    script: "../scripts/gate.py"


rule case_verdict:
    """One case's checks and verdict (the study's gate applied to its runs alone) and its report
    (results/<case>/report.md and .html, the study's matrix and plots for this case)."""
    input:
        summary="results/{case}/summary.csv",
        plan="results/{case}/plan.json",
        manifests=expand("results/{{case}}/{build}/manifest.json", build=BUILD_IDS),
        series="results/reference/series.csv",
        reference="results/reference/collisions.csv",
    output:
        checks="results/{case}/checks.csv",
        junit="results/{case}/junit.xml",
        verdict="results/{case}/verdict.json",
        md="results/{case}/report.md",
        html="results/{case}/report.html",
    log: "logs/{case}/verdict.log"
    benchmark: "logs/benchmarks/case_verdict/{case}.tsv"
    params: tolerance=config["tolerance"], builds={b: build_params(b) for b in BUILD_IDS}, ladder=config["ladder"]
    # On the study's critical path (the report links every case's): drawn as soon as its case
    # summary is there, beside the other cases' engine jobs, not on the study's tail (~4 s each).
    priority: CRITICAL_PATH
    script: "../scripts/case_verdict.py"


rule case_gate:
    """One case's gate.txt on PASS (as the study's gate, over the case's verdict and dumps)."""
    input:
        verdict="results/{case}/verdict.json",
        summary="results/{case}/summary.csv",
        manifests=expand("results/{{case}}/{build}/manifest.json", build=BUILD_IDS),
    output: "results/{case}/gate.txt"
    log: "logs/{case}/gate.log"
    benchmark: "logs/benchmarks/case_gate/{case}.tsv"
    params: report="results/{case}/report.md", rerun_engines=lambda w: f"snakemake -j2 {w.case} --forcerun run_engine"
    script: "../scripts/gate.py"
