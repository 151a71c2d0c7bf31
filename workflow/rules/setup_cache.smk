# What every Snakemake process works out when it reads the workflow: the cases' plans
# (workflow/rules/cases.smk), pure Python, no engine. They are kept here by the key of what they
# depend on (the config, the case files' bytes, the plan code): the next start, and on a cluster
# every job (a Snakemake process of its own that reads the workflow again), read them instead of
# planning again; they plan only when the file is missing or was written for other inputs.

import hashlib
import json

from contact_model.strict_yaml import key_bytes


def requested():
    """(targets, target jobs) of this run, from Snakemake's own reading of the command line;
    (None, None) when it was not started from one (the API)."""
    from snakemake.cli import get_argument_parser

    try:
        args, _ = get_argument_parser().parse_known_args(sys.argv[1:])
    except (SystemExit, Exception):
        return None, None
    return list(args.targets or ()), list(args.target_jobs or ())


#: Whether this process is a job of a running workflow (a cluster job: --target-jobs), not the run.
IS_JOB = bool(requested()[1])
SETUP_CACHE = Path(".snakemake") / "hertz-setup"
#: The code whose change changes a plan: the physics and the engines' tables.
_PLAN_CODE = ("contact_model", "engines", "reference")


def setup_key(config, case_files):
    """sha256 of what the plans depend on: the config (the builds among it), every case file's bytes and
    the plan code's files (their paths, sizes and modification times)."""
    h = hashlib.sha256(json.dumps(config, sort_keys=True, default=str).encode())
    for stem, path in sorted(case_files.items()):
        # key_bytes: a regular file's bytes, or why it is refused (/dev/zero, a FIFO, > 1 MB) unread
        h.update(f"{stem}\0{path}\0".encode() + key_bytes(path))
    for package in _PLAN_CODE:
        for f in sorted(Path(workflow.basedir, package).glob("*.py")):
            st = f.stat()
            h.update(f"{f}\0{st.st_size}\0{st.st_mtime_ns}\0".encode())
    return h.hexdigest()


def read_setup(key):
    """The plans the run's process wrote for `key`, or None."""
    path = SETUP_CACHE / f"{key}.json"
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def write_setup(key, content):
    """Write the run's plans for its jobs (atomically: a job never reads half)."""
    from records.files import write_atomically

    SETUP_CACHE.mkdir(parents=True, exist_ok=True)
    write_atomically(SETUP_CACHE / f"{key}.json", json.dumps(content))


def config_case_files():
    """{case name: file} for the config's `cases` (a glob or a list of globs); {} when none matches."""
    patterns = [config["cases"]] if isinstance(config["cases"], str) else config["cases"]
    return {Path(f).stem: f for f in sorted({f for p in patterns for f in glob.glob(p)})}


SETUP_KEY = setup_key(config, config_case_files())
#: The plans made before for these inputs, or None (this process makes them).
CACHED_SETUP = read_setup(SETUP_KEY)
