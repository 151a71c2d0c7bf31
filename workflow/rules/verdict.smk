# The verdicts: of the study (report, JUnit XML, gate) and of one case (its own gate).


rule summary:
    input: expand("results/{case}/summary.csv", case=CASES)
    output: "results/summary.csv"
    log: "logs/summary.log"
    priority: CRITICAL_PATH
    script: "../scripts/study_summary.py"


PAPER_FIGURES = {1: "fig1_phi", 3: "fig3_eps_collapse", 4: "fig4_energy", 5: "fig5_fracture"}
EXTRA_REPORT_INPUTS = {
    **({"convergence": "results/convergence/largest_dt.csv", "convergence_orders": "results/convergence/orders.csv",
        "convergence_spread": "results/convergence/build_spread.csv"} if "convergence" in EXTRAS else {}),
    **({"claims": "results/paper/claims.csv", "table1": "results/paper/table1.csv",
        "energy_check": "results/paper/fig4_energy.csv",
        **{f"figure_{n}": f"results/paper/{name}.png" for n, name in PAPER_FIGURES.items()}}
       if "paper" in EXTRAS else {}),
    **({"calibration": "results/calibration/report.md"} if "calibration" in EXTRAS else {}),
    **({"regressions": "results/lammps/regressions.csv"}
       if "lammps_regressions" in EXTRAS and LAMMPS_BUILDS else {}),
}


rule report:
    """The checks and the verdict (verdict.json, junit.xml, checks.csv), report.md and .html."""
    input:
        summary="results/summary.csv",
        series="results/reference/series.csv",
        reference="results/reference/collisions.csv",
        manifests=expand("results/{case}/{build}/manifest.json", case=CASES, build=BUILD_IDS),
        plans=expand("results/{case}/plan.json", case=CASES),
        **EXTRA_REPORT_INPUTS,
    output:
        md="results/report.md",
        html="results/report.html",
        checks="results/checks.csv",
        junit="results/junit.xml",
        verdict="results/verdict.json",
    log: "logs/report.log"
    params: tolerance=config["tolerance"], builds={b: build_params(b) for b in BUILD_IDS}, ladder=config["ladder"]
    # Its plots are drawn in two processes (postprocess.report.start_drawing): it runs last, when
    # every other job is done (only the gate and the build comparison wait for it).
    threads: 2
    script: "../scripts/report.py"


rule gate:
    """The last step: gate.txt on PASS; on FAIL exits non-zero naming every failing check."""
    input: verdict="results/verdict.json", summary="results/summary.csv"
    output: "results/gate.txt"
    log: "logs/gate.log"
    params: report="results/report.md"
    script: "../scripts/gate.py"


rule case_verdict:
    """One case's checks and verdict (the study's gate applied to its runs alone)."""
    input:
        summary="results/{case}/summary.csv",
        plan="results/{case}/plan.json",
        manifests=expand("results/{{case}}/{build}/manifest.json", build=BUILD_IDS),
    output:
        checks="results/{case}/checks.csv",
        junit="results/{case}/junit.xml",
        verdict="results/{case}/verdict.json",
    log: "logs/{case}/verdict.log"
    params: tolerance=config["tolerance"]
    script: "../scripts/case_verdict.py"


rule case_gate:
    input: verdict="results/{case}/verdict.json", summary="results/{case}/summary.csv"
    output: "results/{case}/gate.txt"
    log: "logs/{case}/gate.log"
    params: report="results/{case}/checks.csv"
    script: "../scripts/gate.py"
