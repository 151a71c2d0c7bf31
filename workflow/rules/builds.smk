# The engine builds of the study (config `builds:`): loaded, and every executable asked for its
# version (in threads, while workflow/rules/cases.smk plans the cases), before any job starts. A
# missing executable, one that is another engine, or one that cannot say its version stops the
# workflow there, naming the build and what to do.

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


# Checked at the end of workflow/rules/cases.smk, once the cases are planned.
BUILDS, _BUILD_CHECKS = start_build_checks(config["builds"], workflow.basedir)
BUILD_IDS = list(BUILDS)
LAMMPS_BUILDS = [b for b, build in BUILDS.items() if build.code == "lammps"]


def calibration_build():
    """The build of config calibration.engine (closing the calibration's loop)."""
    if config["calibration"]["engine"] not in BUILDS:
        raise BuildError(f"config 'calibration.engine': {config['calibration']['engine']!r} is not the id of a "
                         f"build; known: {', '.join(BUILD_IDS)}")
    return BUILDS[config["calibration"]["engine"]]


def build_params(build_id):
    """A build as plain data for a rule's params (the scripts rebuild the `Build`)."""
    b = BUILDS[build_id]
    return {"id": b.id, "code": b.code, "executable": b.executable}


# What the plan depends on: the builds by id and code (not where their executables live).
SETTINGS = {"builds": [{"id": b.id, "code": b.code} for b in BUILDS.values()],
            **{k: config[k] for k in ("laws", "K_grid", "ladder", "time_step_factor", "default_law_match_K",
                                      "max_overlap_ratio", "engine_timeout_floor_s")}}
