# The engine builds of the study (config `builds:`). When the workflow starts, each build is
# loaded and its executable looked up, nothing more: a missing one stops the workflow there,
# naming the build and what to do, and a dry run (`snakemake -n`) or `--unlock` starts no engine.
# Asking each executable for its version is the job `engine_version` (results/engine_versions/
# <build>.json), which the plans read (rule plan: a keyword runs only in the builds whose release
# has it); one that is another engine or cannot say its version fails that job, named.

from engines.builds import BuildError, executable_identity, load_builds

try:
    BUILDS = {b.id: b for b in load_builds(config["builds"], workflow.basedir)}
except BuildError as _err:  # an unknown code, a bad id: the message alone, not a traceback of the Snakefile
    sys.exit(f"config 'builds': {_err}")
BUILD_IDS = list(BUILDS)
LAMMPS_BUILDS = [b for b, build in BUILDS.items() if build.code == "lammps"]


def executable_identities(builds):
    """({build id: executable_identity}, [problems]): every build's executable looked up, none
    started; a missing one is a problem naming the build and how to install its code."""
    found, problems = {}, []
    for b in builds.values():
        try:
            found[b.id] = executable_identity(b)
        except BuildError as err:
            problems.append(str(err))
    return found, problems


EXECUTABLES, _missing_builds = executable_identities(BUILDS)
if _missing_builds:
    SETUP_PROBLEMS.append("config 'builds':\n  " + "\n  ".join(_missing_builds))


def viscoelastic_builds():
    """The ids of the builds whose code can run the viscoelastic law (engines/codes.py), in order."""
    return [b for b, build in BUILDS.items() if "viscoelastic" not in CODES[build.code].unavailable]


def calibration_build_problem():
    """Why config calibration.engine names no build that can close the calibration's loop (it
    runs the calibrated viscoelastic contact), with the fix; None when it does."""
    wanted = config["calibration"]["engine"]
    able = viscoelastic_builds()
    if wanted is None:
        return None if able else ("config 'calibration.engine': no build of this run can run the viscoelastic law "
                                  "(engines/codes.py); add one to `builds:`, or leave `calibration` out of `extras:`")
    if wanted in BUILDS and wanted in able:
        return None
    why = "is not the id of a build of this run" if wanted not in BUILDS else "cannot run the viscoelastic law"
    return (f"config 'calibration.engine': {wanted!r} {why}; set it to one of {', '.join(able) or '(none)'}, or to "
            f"null for the first of them, e.g. --config 'calibration={{engine: null}}' ... (or in config/config.yaml)")


def calibration_build():
    """The build that closes the calibration's loop: config calibration.engine, or (null) the
    first build that can run the viscoelastic law (calibration_build_problem refuses the others)."""
    wanted = config["calibration"]["engine"]
    if wanted is None:
        wanted = viscoelastic_builds()[0]
    return BUILDS[wanted]


def build_params(build_id):
    """A build as plain data for a rule's params (the scripts rebuild the `Build`)."""
    b = BUILDS[build_id]
    return {"id": b.id, "code": b.code, "executable": b.executable}


# What the plan depends on: the builds by id and code (not where their executables live).
SETTINGS = {"builds": [{"id": b.id, "code": b.code} for b in BUILDS.values()],
            **{k: config[k] for k in ("laws", "K_grid", "ladder", "time_step_factor", "default_law_match_K",
                                      "max_overlap_ratio", "engine_timeout_floor_s")}}


rule engine_version:
    """The build's version banner, asked of its executable (engines.builds.check_build): what the
    plans read to leave out the keywords its release lacks, and the report names. Asked again when
    the executable is another file (its path, size or modification time: EXECUTABLES), which reruns
    the build's engine jobs too; not at every start."""
    output: "results/engine_versions/{build}.json"
    log: "logs/engine_versions/{build}.log"
    params: build=lambda w: build_params(w.build), executable=lambda w: EXECUTABLES.get(w.build)
    # Every plan waits for these: first (a few tenths of a second each).
    priority: 2_000_000
    script: "../scripts/engine_version.py"
