# Calibrating eta from measured restitution: `snakemake -j2 calibration` (results/calibration/).
# Not part of `all`: it fits measured cases, it does not validate the engines.


def calibration_cases():
    """({name: file} of the case files in config calibration.cases that have `measurements:`,
    {name: error} of those that cannot be read): read once with the study's (cases.smk)."""
    files = sorted({f for p in config["calibration"]["cases"] for f in glob.glob(p)})
    cases, errors = load_cases({f: f for f in files})
    errors = {f: err for f, err in errors.items() if f not in ALL_CASES.values()}  # the study's: said there
    found = {}
    for f, case in cases.items():
        if case.measurements is not None:
            stem = Path(f).stem
            if not CASE_NAME.fullmatch(stem) or stem in found:
                errors[f] = f"{f}: a calibrated case needs a unique file name of letters, digits and underscores"
                continue
            found[stem] = f
    return found, errors


CALIBRATION_CASES, _calibration_errors = calibration_cases()
_problem = unusable(_calibration_errors, set(_calibration_errors) if calibration_requested(list(ALL_CASES)) else set(),
                    len(_calibration_errors) + len(CALIBRATION_CASES), "calibration's case files")
if _problem:
    SETUP_PROBLEMS.append(_problem)
if calibration_requested(list(ALL_CASES)) and calibration_build_problem():
    SETUP_PROBLEMS.append(calibration_build_problem())
CALIBRATION = config["calibration"]


rule calibration:
    """Every measured case fitted, checked in an engine, and the report (results/calibration/report.md)."""
    input: "results/calibration/report.md"


rule calibration_fit:
    """Exact (x0, F0) and series fits of eta, intervals, residuals, engine parameters, plot."""
    input:
        case=lambda w: CALIBRATION_CASES[w.cal_case],
        data=lambda w: load_case(CALIBRATION_CASES[w.cal_case]).measurements.path,
    output:
        fit="results/calibration/{cal_case}/fit.json",
        residuals="results/calibration/{cal_case}/residuals.csv",
        engine_parameters="results/calibration/{cal_case}/engine_parameters.csv",
        png="results/calibration/{cal_case}/fit.png",
    log: "logs/calibration/{cal_case}/fit.log"
    benchmark: "logs/benchmarks/calibration_fit/{cal_case}.tsv"
    params: modulus_factors=CALIBRATION["modulus_factors"]
    resources: **cluster_resources()
    script: "../scripts/calibration_fit.py"


rule calibration_dem:
    """Closing the loop: the calibrated parameters in one build (calibration.engine) at the measured velocities."""
    input:
        case=lambda w: CALIBRATION_CASES[w.cal_case],
        fit="results/calibration/{cal_case}/fit.json",
        decks=lambda w: DECKS[calibration_build().code],
    output:
        manifest="results/calibration/{cal_case}/dem/manifest.json",
        runs=directory("results/calibration/{cal_case}/dem/runs"),
    log: "logs/calibration/{cal_case}/dem.log"
    benchmark: "logs/benchmarks/calibration_dem/{cal_case}.tsv"
    params: build=lambda w: build_params(calibration_build().id), time_step_factor=CALIBRATION["time_step_factor"],
            timeout_floor_s=config["engine_timeout_floor_s"]
    threads: lambda w: CODES[calibration_build().code].processes  # as run_engine (ESyS: two MPI ranks)
    # run_engine's rule, with the engine's start alone: its runs follow from the fit, not known yet
    priority: lambda w: engine_job_priority(calibration_build().code, 0, 0)
    resources: **cluster_resources(runtime=30, mem_mb=2000)
    script: "../scripts/calibration_dem.py"


rule calibration_loop:
    """DEM eps beside the fitted model and the data; the fit plot with the DEM points."""
    input:
        case=lambda w: CALIBRATION_CASES[w.cal_case],
        fit="results/calibration/{cal_case}/fit.json",
        residuals="results/calibration/{cal_case}/residuals.csv",
        manifest="results/calibration/{cal_case}/dem/manifest.json",
        runs="results/calibration/{cal_case}/dem/runs",
    output:
        csv="results/calibration/{cal_case}/loop.csv",
        png="results/calibration/{cal_case}/fit_with_dem.png",
    log: "logs/calibration/{cal_case}/loop.log"
    benchmark: "logs/benchmarks/calibration_loop/{cal_case}.tsv"
    resources: **cluster_resources()
    script: "../scripts/calibration_loop.py"


rule closed_forms:
    """The literature's eps(K) against the solver, and the bias each causes in a fitted eta."""
    output:
        errors="results/calibration/closed_forms.csv",
        bias="results/calibration/closed_form_bias.csv",
    log: "logs/calibration/closed_forms.log"
    benchmark: "logs/benchmarks/closed_forms/all.tsv"
    params: settings=CALIBRATION["closed_forms"]
    resources: **cluster_resources()
    script: "../scripts/closed_forms.py"


rule calibration_report:
    """results/calibration/report.md: one section per measured case, then the closed forms."""
    input:
        fits=expand("results/calibration/{cal_case}/fit.json", cal_case=CALIBRATION_CASES),
        residuals=expand("results/calibration/{cal_case}/residuals.csv", cal_case=CALIBRATION_CASES),
        loops=expand("results/calibration/{cal_case}/loop.csv", cal_case=CALIBRATION_CASES),
        errors="results/calibration/closed_forms.csv",
        bias="results/calibration/closed_form_bias.csv",
    output: "results/calibration/report.md"
    log: "logs/calibration/report.log"
    benchmark: "logs/benchmarks/calibration_report/all.tsv"
    script: "../scripts/calibration_report.py"
