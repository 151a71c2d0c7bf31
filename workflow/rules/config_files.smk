# The files the config names outside `cases:` (the convergence's, the paper's, the keywords' and the
# history's case files, the keywords' measurement file): each must be a regular file inside the
# project. One that is not stops the targets that read it, naming the config key (not only the
# file, which a user may not know where it came from); the other targets run, warned.


def _under_project(path):
    """Whether `path` (relative to the project, or absolute) resolves inside the project folder."""
    root = Path(workflow.basedir).resolve()
    return Path(root, path).resolve().is_relative_to(root)


def config_file_problem(key, path):
    """Why config `key`'s `path` cannot be read as the study's input file; None when it can."""
    if not isinstance(path, str) or not path:
        return f"config '{key}': give the path of a file in the project, e.g. cases/steel.yaml"
    if not _under_project(path):
        return f"config '{key}': {path} is outside the project folder; give a file of the project, e.g. cases/steel.yaml"
    full = Path(workflow.basedir, path)
    if not full.exists():
        return f"config '{key}': {path} does not exist; give a file of the project, e.g. cases/steel.yaml"
    if not full.is_file():
        return f"config '{key}': {path} is not a regular file"
    return None


def target_needs(prefix, in_all):
    """Whether this run's targets read the results under results/<prefix>: the target `prefix`, a
    file under results/<prefix>/, a job of its rules, or `all` (or no target) when `in_all`."""
    targets, jobs = requested()
    if targets is None:
        return True
    if any(flag in sys.argv for flag in ("--unlock", "--cleanup-metadata", "--list-rules", "-l", "--lint")):
        return False  # builds no job: reads no file
    if jobs:
        return any(str(getattr(j, "rule_name", "")).startswith(prefix) for j in jobs)
    if not targets:
        return in_all
    return any(t == prefix or t.startswith(f"results/{prefix}/") or (t == "all" and in_all) for t in targets)


#: (config key, the file it names, whether the targets of this run read it).
_CONFIG_FILES = [
    ("convergence.case", config["convergence"]["case"], target_needs("convergence", "convergence" in EXTRAS)),
    ("paper.energy.case", config["paper"]["energy"]["case"], target_needs("paper", "paper" in EXTRAS)),
    ("paper.fracture.case", config["paper"]["fracture"]["case"], target_needs("paper", "paper" in EXTRAS)),
    *([("keywords.case", config["keywords"]["case"], target_needs("keywords", False))] if "keywords" in config else []),
    *([("keywords.measured", config["keywords"]["measured"], target_needs("keywords", False))]
      if config.get("keywords", {}).get("measured") else []),
    *((f"history.cases[{i}]", path, history_requested()) for i, path in enumerate(HISTORY["cases"])),
]
for _key, _path, _needed in _CONFIG_FILES:
    if (_problem := config_file_problem(_key, _path)) is None:
        continue
    if _needed:
        SETUP_PROBLEMS.append(_problem)
    elif not IS_JOB:
        print(f"Warning: {_problem} (the targets that read it refuse it)", file=sys.stderr)
