# Every release of each code against the study's reduced checks and the defects it found
# (snakemake -j2 history; results/history/, analysis/history.py). Not part of `all`, and no
# verdict: a defect of a release is a finding about that release. PyPI releases are installed on
# demand (engines.releases, as `make build <code>==<release>` does: a venv each); a release that cannot be installed is a row
# naming the command, and the other releases still run. On the cluster (profiles/slurm) the install
# and the runs of one release are one job (group `history`): SLURM's per-job cost once per release.

HISTORY = config["history"]
#: Where the history writes: config history.folder, results/history unless given (report.history_query
#: gives each answer a folder of its own); its logs go to logs/ and the same path after results/.
HISTORY_DIR = HISTORY.get("folder", "results/history")
_HISTORY_SUB = HISTORY_DIR.removeprefix("results/")
_HISTORY_BENCH = "logs/benchmarks" if _HISTORY_SUB == "history" else f"logs/benchmarks/{_HISTORY_SUB}"


def history_releases():
    """({release id: {code, release, build (as data) and/or install}}, [problem]) of config
    history: history.builds (study builds by id, and entries of their own, whose `install` is a
    make target of engines.releases.INSTALL_TARGETS, as an argument list) and history.releases'
    PyPI releases (engines.releases: digits and dots), in config order. An entry that cannot be
    one is a problem naming its key, not a release."""
    from engines.releases import ReleaseError, checked, install_command

    out, problems = {}, []
    for i, entry in enumerate(HISTORY["builds"]):
        where = f"config 'history.builds[{i}]'"
        if isinstance(entry, dict):  # a build of its own, installed on demand by its `install` command
            try:
                build = load_builds([{k: entry[k] for k in ("id", "code", "executable")}], workflow.basedir)[0]
                install = install_command(entry["install"], f"{where}.install") if "install" in entry else []
            except (BuildError, ReleaseError) as err:
                problems.append(str(err) if str(err).startswith(where) else f"{where}: {err}")
                continue
            out[build.id] = {"code": build.code, "release": build.id, "install": install,
                             "build": {"id": build.id, "code": build.code, "executable": build.executable}}
            continue
        build_id = entry
        if build_id not in BUILDS:  # builds given on the command line: the history runs without it
            if "history" in (requested()[0] or ()):
                print(f"{where}: {build_id} left out: the study has no build {build_id!r} (its "
                      f"builds: {', '.join(BUILDS)})", file=sys.stderr)
            continue
        out[build_id] = {"code": BUILDS[build_id].code, "release": build_id, "build": build_params(build_id)}
    for code, releases in HISTORY["releases"].items():
        for i, release in enumerate(releases):
            try:
                release = checked(code, release, f"config 'history.releases.{code}[{i}]'")
            except ReleaseError as err:
                problems.append(str(err))
                continue
            out[f"{code}-{release}"] = {"code": code, "release": release, "pypi": True,
                                        "install": ["make", "build", f"{code}=={release}"]}
    return out, problems


def history_requested():
    """Whether this run's targets need the history: `history`, a file under results/history/, or
    a history job; a bad history entry stops these alone, and only warns the others."""
    targets, jobs = requested()
    if targets is None:
        return True
    return (any(t == "history" or t.startswith("results/history") or t.startswith(HISTORY_DIR) for t in targets)
            or any(str(getattr(j, "rule_name", "")).startswith("history") for j in jobs))


HISTORY_RELEASES, _history_problems = history_releases()
if _history_problems and history_requested():
    SETUP_PROBLEMS.append("\n".join(_history_problems))
elif _history_problems and not IS_JOB:
    print("\n".join(f"Warning: {p} (snakemake history refuses it)" for p in _history_problems), file=sys.stderr)


rule history_install:
    """One release as a build: a study build's version banner, or a PyPI release installed with
    `make build <code>==<release>` (idempotent) and its banner; a release that cannot be installed
    writes why (the command and its output), not an error, so that the other releases still run."""
    output: f"{HISTORY_DIR}/installs/{{release}}.json"
    log: f"logs/{_HISTORY_SUB}/install/{{release}}.log"
    benchmark: f"{_HISTORY_BENCH}/history_install/{{release}}.tsv"
    params: spec=lambda w: HISTORY_RELEASES[w.release], project=workflow.basedir
    group: "history"
    resources: **cluster_resources(runtime=30, mem_mb=2000)
    script: "../scripts/history_install.py"


rule history_runs:
    """One release's checks (analysis.history): the reduced cases' viscoelastic ladders, its
    restitution keywords' promise, its code's regression cases, and each of its tangential models on
    the oblique reduced set (analysis.oblique); results/history/<release>.csv."""
    input:
        install=f"{HISTORY_DIR}/installs/{{release}}.json",
        cases=HISTORY["cases"],
        decks=lambda w: DECKS[HISTORY_RELEASES[w.release]["code"]],
        # the oblique reduced set's cases, for codes with an oblique driver (analysis.oblique)
        oblique_cases=lambda w: (OBLIQUE["reduced"]["cases"] if config.get("oblique")
                                 and CODES[HISTORY_RELEASES[w.release]["code"]].oblique_driver else []),
    output:
        rows=f"{HISTORY_DIR}/{{release}}.csv",
        runs=directory(f"{HISTORY_DIR}/{{release}}/runs"),
        manifest=f"{HISTORY_DIR}/{{release}}/manifest.json",
    log: f"logs/{_HISTORY_SUB}/{{release}}.log"
    benchmark: f"{_HISTORY_BENCH}/history_runs/{{release}}.tsv"
    params: spec=lambda w: HISTORY_RELEASES[w.release], history=HISTORY, ladder=config["ladder"],
            oblique=config.get("oblique"),
            tolerance=config["tolerance"], timeout_floor_s=config["engine_timeout_floor_s"]
    group: "history"
    threads: lambda w: CODES[HISTORY_RELEASES[w.release]["code"]].processes
    resources: **cluster_resources(runtime=60, mem_mb=2000)
    script: "../scripts/history_runs.py"


rule history_summary:
    """history.csv (code, release, check, status, error, resolution, ...), history.md and .html (a
    release x check matrix per code, each defect as a sentence) and history.png (each check's error
    against release)."""
    input: expand(f"{HISTORY_DIR}/{{release}}.csv", release=HISTORY_RELEASES)
    output:
        csv=f"{HISTORY_DIR}/history.csv",
        md=f"{HISTORY_DIR}/history.md",
        html=f"{HISTORY_DIR}/history.html",
        png=f"{HISTORY_DIR}/history.png",
    log: f"logs/{_HISTORY_SUB}/summary.log"
    benchmark: f"{_HISTORY_BENCH}/history_summary/all.tsv"
    script: "../scripts/history_summary.py"


rule history:
    input: rules.history_summary.output
