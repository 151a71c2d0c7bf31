# The case files of the study: found, named and validated before any job starts.

CASE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def case_files():
    """{case name: file} for the config's `cases` (a glob or a list of globs)."""
    patterns = [config["cases"]] if isinstance(config["cases"], str) else config["cases"]
    files = sorted({f for p in patterns for f in glob.glob(p)})
    if not files:
        raise ValueError(f"config 'cases': no case file matches {config['cases']!r}")
    return {Path(f).stem: f for f in files}


def check_case_names(cases, rule_names):
    """A case's file name is its target (`snakemake steel`) and its results folder: refuse a
    name that cannot be one, rather than skip it or break the workflow."""
    for name, path in cases.items():
        if not CASE_NAME.fullmatch(name):
            raise ValueError(f"{path}: the file name {name!r} cannot name a case: it is the case's target and "
                             "results folder, so use letters, digits and underscores, starting with a letter "
                             f"(e.g. {re.sub(r'[^A-Za-z0-9_]+', '_', name).strip('_') or 'case_1'}.yaml)")
        if name in rule_names:
            raise ValueError(f"{path}: the file name {name!r} is taken by the workflow's rule '{name}'; rename the "
                             f"case file (e.g. {name}_case.yaml)")


CASES = case_files()
# Every case is validated and planned here, before any job (let alone an engine) starts: a
# malformed case, or one the engines cannot run honestly (engines.plan), stops the workflow with
# the file, the field and the reason. Two files may not claim one case name.
# The plans made here are what the plan rule writes (results/<case>/plan.json): planned once.
_names, PLANS = {}, {}
for _stem, _path in CASES.items():
    _case = load_case(_path)
    PLANS[_stem] = plan_listing(_case, plan_runs(
        _case, SETTINGS["builds"], config["laws"], config["K_grid"], config["time_step_factor"],
        config["default_law_match_K"], config["max_overlap_ratio"], ladder=config["ladder"]))
    _case_name = _case.name
    if _case_name in _names:
        raise ValueError(f"{_path}: field 'name': {_case_name!r} is already the name of {_names[_case_name]}")
    _names[_case_name] = _path


# Every build's executable answered for its version meanwhile (workflow/rules/builds.smk): a
# missing one, another engine or one that cannot say its version stops the workflow here.
finish_build_checks(BUILDS, _BUILD_CHECKS)
