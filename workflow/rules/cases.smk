# The case files of the study: found, named and validated before any job starts.

CASE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def case_files():
    """{case name: file} for the config's `cases` (`config_case_files`), at least one."""
    files = config_case_files()
    if not files:
        raise WorkflowError(f"config 'cases': no case file matches {config['cases']!r}")
    return files


#: The folders of results/ that are the study's, not a case's (besides its rules' names).
STUDY_FOLDERS = {"engine_versions", "reference", "paper", "convergence", "lammps"}


def case_name_problems(cases, rule_names):
    """A case's file name is its target (`snakemake steel`) and its results folder: the problem
    of each name that cannot be one (refused, rather than skipped or left to break the workflow)."""
    problems = []
    for name, path in cases.items():
        if not CASE_NAME.fullmatch(name):
            problems.append(f"{path}: the file name {name!r} cannot name a case: it is the case's target and "
                            "results folder, so use letters, digits and underscores, starting with a letter "
                            f"(e.g. {re.sub(r'[^A-Za-z0-9_]+', '_', name).strip('_') or 'case_1'}.yaml)")
        elif name in rule_names:
            problems.append(f"{path}: the file name {name!r} is taken by the workflow's rule '{name}'; rename the "
                            f"case file (e.g. {name}_case.yaml)")
        elif name in STUDY_FOLDERS:
            problems.append(f"{path}: the file name {name!r} is taken by the study's folder results/{name}/; rename "
                            f"the case file (e.g. {name}_case.yaml)")
    return problems


def _case_of(target, case_names):
    """The case a target belongs to: its own target (`rubber`) or a file under results/<case>/;
    None for a target of the whole study."""
    parts = Path(target).parts
    if target in case_names:
        return target
    return parts[1] if len(parts) > 2 and parts[0] == "results" and parts[1] in case_names else None


def cases_requested(case_names):
    """The cases this run's targets need: a case's target (`snakemake -j2 rubber`), a file under
    results/<case>/, or a cluster job's `--target-jobs` with a case wildcard; every case for
    `all`, no target, or anything else (a rule of the whole study, a file of no one case)."""
    targets, jobs = requested()
    if targets is None or not (targets or jobs):
        return set(case_names)
    needed = set()
    for job in jobs:
        if "case" not in job.wildcards_dict:
            return set(case_names)
        needed.add(job.wildcards_dict["case"])
    for target in targets:
        case = _case_of(target, case_names)
        if case is None:  # `all`, another rule, another file: the whole study
            return set(case_names)
        needed.add(case)
    return needed


def calibration_requested(case_names):
    """Whether this run's targets need the calibration's cases: `calibration`, a file under
    results/calibration/, a calibration job, or `all` when the report includes the calibration;
    not a case's own target or files."""
    targets, jobs = requested()
    if targets is None:
        return True
    if jobs:
        return any("case" not in j.wildcards_dict for j in jobs)
    if not targets:
        return "calibration" in EXTRAS
    return any(_case_of(t, case_names) is None and not (t == "all" and "calibration" not in EXTRAS)
               for t in targets)


def load_cases(files):
    """({stem: Case} of the usable case files, {stem: error} of the others): every file is read
    and validated (contact_model.load_case), so that one run reports every bad file at once; a
    file read before (LOADED, by path) is not read again."""
    cases, errors = {}, {}
    for stem, path in files.items():
        if path not in LOADED:
            try:
                LOADED[path] = (load_case(path), None)
            except ValueError as err:  # CaseError (and MeasurementError) name the file and the field
                LOADED[path] = (None, str(err))
        case, error = LOADED[path]
        if error is None:
            cases[stem] = case
        else:
            errors[stem] = error
    return cases, errors


def plan_cases(cases):
    """({stem: plan listing}, {stem: error}): each case planned (engines.plan), a case the engines
    cannot run honestly refused with its reason, two files claiming one case name refused."""
    plans, errors, names = {}, {}, {}
    for stem, case in cases.items():
        if case.name in names:
            errors[stem] = f"{case.path}: field 'name': {case.name!r} is already the name of {names[case.name]}"
            continue
        try:
            plans[stem] = plan_listing(case, plan_runs(
                case, SETTINGS["builds"], config["laws"], config["K_grid"], config["time_step_factor"],
                config["default_law_match_K"], config["max_overlap_ratio"], ladder=config["ladder"]))
        except ValueError as err:
            errors[stem] = str(err)
            continue
        names[case.name] = case.path
    return plans, errors


def unusable(errors, needed, total, what="case files"):
    """The problem the targets' `needed` files among `errors` make, every bad file named (the
    needed first), or None when none is needed; the others are reported as left out."""
    blocking = [err for stem, err in errors.items() if stem in needed]
    others = [err for stem, err in errors.items() if stem not in needed]
    if not blocking:
        for err in others:
            print(f"Left out (not needed by this target): {err}", file=sys.stderr)
        return None
    text = f"{len(blocking)} of the {what} this target needs cannot be used (of {total} in all):\n  " + \
        "\n  ".join(blocking)
    if others:
        text += "\nAlso not usable (not needed by this target):\n  " + "\n  ".join(others)
    return text


ALL_CASES = case_files()
# Every case is validated and planned here, before any job (let alone an engine) starts. A
# case file that cannot be used stops the targets that need it, each bad file named with its
# field and the reason, all of them at once; the other cases' targets still run (and say which
# files they left out). Planning is pure Python (no engine: the releases' keywords are cut from
# each plan by the plan rule, which reads the engine_version jobs), ~3 s for the study, and is
# done once per set of inputs: the plans are kept by their inputs' key (setup_cache.smk). The
# plan rule writes them, cut to each release's keywords, to results/<case>/plan.json, which is
# what the engine jobs run.
#: {path: (Case or None, error or None)} of every case file read (also by the calibration's).
LOADED = {}
_cases, CASE_ERRORS = load_cases(ALL_CASES)
if CACHED_SETUP is not None:  # planned before for these inputs (workflow/rules/setup_cache.smk)
    PLANS, _plan_errors = CACHED_SETUP["plans"], CACHED_SETUP["plan_errors"]
else:
    PLANS, _plan_errors = plan_cases(_cases)
CASE_ERRORS.update(_plan_errors)
if not IS_JOB:
    for _note in (note for listing in PLANS.values() for note in listing.get("notes", [])):
        print(f"Note: {_note}", file=sys.stderr)
_problem = unusable(CASE_ERRORS, cases_requested(list(ALL_CASES)), len(ALL_CASES))
if _problem:
    _fine = sorted(set(ALL_CASES) - set(CASE_ERRORS))
    SETUP_PROBLEMS.append(_problem + (f"\nFix them, or run the cases that are fine alone, e.g. snakemake -j2 "
                                      f"{' '.join(_fine[:3])}" if _fine else ""))
CASES = {stem: path for stem, path in ALL_CASES.items() if stem not in CASE_ERRORS}
if CACHED_SETUP is None:  # the next start, and this run's jobs (a cluster's), read them
    write_setup(SETUP_KEY, {"plans": PLANS, "plan_errors": _plan_errors})
