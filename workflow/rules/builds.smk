# The engine builds of the study (config `builds:`): loaded, and every executable asked for its
# version (in threads, while workflow/rules/cases.smk plans the cases), before any job starts. A
# missing executable, one that is another engine, or one that cannot say its version stops the
# workflow there, naming the build and what to do. A cluster job reads the plans the run's own
# process made from them (workflow/rules/setup_cache.smk) and asks no executable.

from concurrent.futures import ThreadPoolExecutor

from engines.builds import BuildError, check_build, load_builds


def start_build_checks(entries, project_dir):
    """({id: Build} of config `builds:`, the running checks of their executables): every check
    in a thread of its own (each waits ~0.4-1.5 s on its engine), while the cases are planned."""
    builds = load_builds(entries, project_dir)
    pool = ThreadPoolExecutor(max_workers=len(builds))
    futures = {b.id: pool.submit(check_build, b) for b in builds}
    pool.shutdown(wait=False)
    return {b.id: b for b in builds}, futures


def finish_build_checks(builds, futures):
    """Wait for the checks of `start_build_checks`; BuildError naming every build that failed."""
    errors = []
    for b in builds:
        try:
            futures[b].result()
        except BuildError as err:
            errors.append(str(err))
    if errors:
        raise BuildError("config 'builds':\n  " + "\n  ".join(errors))


# Checked at the end of workflow/rules/cases.smk, once the cases are planned. A build entry that
# cannot be a build (an unknown code, a bad id) stops the workflow here with its message alone: a
# traceback of the Snakefile would say nothing about the user's config.
try:
    if CACHED_SETUP is not None:  # a job: the run's process asked them (workflow/rules/setup_cache.smk)
        BUILDS, _BUILD_CHECKS = {b.id: b for b in load_builds(config["builds"], workflow.basedir)}, None
    else:
        BUILDS, _BUILD_CHECKS = start_build_checks(config["builds"], workflow.basedir)
except BuildError as _err:
    sys.exit(f"config 'builds': {_err}")
BUILD_IDS = list(BUILDS)
LAMMPS_BUILDS = [b for b, build in BUILDS.items() if build.code == "lammps"]


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
