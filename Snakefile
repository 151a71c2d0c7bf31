"""The viscoelastic Hertz validation study.

    snakemake -j2 all                 every case, every engine build, the report, the verdict and the gate
    snakemake -j2 steel               one case (its file name in cases/ without .yaml) and its own gate
    snakemake -j2 results/steel/summary.csv
    snakemake -j2 calibration         eta fitted to every case with measurements (results/calibration/)
    snakemake -j2 keywords            each build's restitution keyword over e: its promise (results/keywords/)
    snakemake -j2 history             every release of each code against the checks and known defects (results/history/)
    snakemake -j2 oblique             oblique impacts: every build's tangential models gated (results/oblique/full/)

Settings: config/config.yaml (validated against config/config.schema.yaml). Logs: logs/,
benchmarks: logs/benchmarks/<case>/<build>.tsv, results: results/. The rules live in
workflow/rules/*.smk, one file per concern; this file keeps the config, the includes and the
targets.
"""

import glob
import os
import re
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

configfile: "config/config.yaml"

_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


_YAML_WORDS = {"null": None, "~": None, "true": True, "false": False}


def numbers_from_strings(value):
    """--config values nested in a list or mapping arrive as strings ('1e-6', even '0.1', 'null'):
    turn those that are exactly a number into one, and YAML's null, true and false into None,
    True and False, recursively; anything else stays as it is and the schema refuses it with its
    key named."""
    if isinstance(value, dict):
        return {k: numbers_from_strings(v) for k, v in value.items()}
    if isinstance(value, list):
        return [numbers_from_strings(v) for v in value]
    if isinstance(value, str) and value.strip().lower() in _YAML_WORDS:
        return _YAML_WORDS[value.strip().lower()]
    if isinstance(value, str) and _NUMBER.fullmatch(value.strip()):
        text = value.strip()
        return int(text) if re.fullmatch(r"[+-]?\d+", text) else float(text)
    return value


# A release name is text ("9.10" is not 9.1): history.releases keeps what the command line gave.
_RELEASES = config["history"].get("releases") if isinstance(config.get("history"), dict) else None
for _key in list(config):
    config[_key] = numbers_from_strings(config[_key])
if _RELEASES is not None:
    config["history"]["releases"] = _RELEASES


def release_problems(releases):
    """Why entries of config history.releases cannot be PyPI releases (engines.releases), each naming
    its key; checked before the schema, whose message would not say to quote a number."""
    from engines.releases import release_problem

    if not isinstance(releases, dict):
        return []
    return [p for code, values in releases.items() if isinstance(values, list)
            for i, value in enumerate(values)
            if (p := release_problem(code, value, f"config 'history.releases.{code}[{i}]'"))]


def schema_problems(config, schema_file):
    """Each way `config` breaks the schema, one line naming its key ("config 'history.K[0]': -1 is
    less than or equal to the minimum of 0"): snakemake's own message prints the whole schema."""
    import jsonschema
    import yaml

    schema = yaml.safe_load(open(schema_file))
    lines = []
    for err in sorted(jsonschema.Draft7Validator(schema).iter_errors(config), key=lambda e: list(e.path)):
        key = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in err.path).lstrip(".") or "(top level)"
        shown = repr(err.instance)
        shown = shown if len(shown) <= 80 else shown[:77] + "..."
        why = err.message if len(err.message) <= 160 else (
            f"{shown} is not of type {err.validator_value!r}" if err.validator == "type"
            else f"{shown} does not meet the schema's {err.validator!r}")
        hint = (" (a --config value that is not valid YAML arrives as text: check its brackets and quotes)"
                if isinstance(err.instance, str) and err.validator == "type" else "")
        lines.append(f"config '{key}': {why}{hint}")
    return lines


if _problems := release_problems(_RELEASES) or schema_problems(config, "config/config.schema.yaml"):
    sys.exit(f"{len(_problems)} problem(s) in the config (config/config.yaml, --config, --configfile; "
             "config/config.schema.yaml):\n  " + "\n  ".join(_problems))
validate(config, "config/config.schema.yaml")

# The workflow's scripts import the project's packages and workflow/scripts/common.py.
os.environ["PYTHONPATH"] = os.pathsep.join(
    [workflow.basedir, f"{workflow.basedir}/workflow/scripts", os.environ.get("PYTHONPATH", "")])

# Where the cluster path's jobs go (profiles/slurm): the environment's SBATCH_PARTITION /
# SBATCH_ACCOUNT, else config `slurm:`, else nothing (the cluster's default partition, the user's
# default account). Local runs ignore these resources.
_SLURM = {"slurm_partition": os.environ.get("SBATCH_PARTITION") or (config.get("slurm") or {}).get("partition"),
          "slurm_account": os.environ.get("SBATCH_ACCOUNT") or (config.get("slurm") or {}).get("account")}
SLURM_RESOURCES = {k: v for k, v in _SLURM.items() if v}


def cluster_resources(runtime=None, mem_mb=None):
    """The `resources` of a rule whose jobs are cluster jobs (not `localrules`): SLURM_RESOURCES,
    and its time limit `runtime` [min] and memory `mem_mb` [MB] times the attempt, so that a
    retry (the profile's `retries`) of a job SLURM killed at a limit gets twice that limit.
    Unset, the profile's default-resources apply."""
    limits = {name: (lambda w, attempt, value=value: value * attempt)
              for name, value in (("runtime", runtime), ("mem_mb", mem_mb)) if value is not None}
    return {**SLURM_RESOURCES, **limits}


from contact_model import load_case  # noqa: E402
from engines.plan import plan_listing, plan_runs, without_missing_keywords  # noqa: E402

EXTRAS = config["extras"]
import engines.codes  # noqa: E402
from engines.codes import CODES  # noqa: E402

CODES_FILE = engines.codes.__file__  # the engine codes' table: a plan input (the laws a code can run)

# The deck files of each engine code (engines.codes): a change reruns that code's jobs.
DECKS = {name: sorted(f for pattern in c.decks for f in glob.glob(pattern)) for name, c in CODES.items()}


rule all:
    input:
        "results/gate.txt",
        "results/report.md",
        "results/report.html",
        "results/junit.xml",
        "results/summary.csv",
        "results/reference/collisions.csv",
        lambda w: BUILD_PAIR_COMPARISONS,  # config compare_builds (workflow/rules/compare.smk, below)
        # extras `oblique`: the reduced oblique set's gate (workflow/rules/oblique.smk)
        lambda w: ["results/oblique/reduced/gate.txt"] if OBLIQUE_IN_ALL else [],


#: What stops the workflow before any job, each with what to do: bad case files (workflow/rules/
#: cases.smk), missing engine executables (builds.smk), bad config files; raised together below.
SETUP_PROBLEMS = []

include: "workflow/rules/setup_cache.smk"
include: "workflow/rules/builds.smk"
include: "workflow/rules/cases.smk"
include: "workflow/rules/engines.smk"
include: "workflow/rules/verdict.smk"
include: "workflow/rules/reference.smk"
include: "workflow/rules/convergence.smk"
include: "workflow/rules/regressions.smk"
include: "workflow/rules/paper.smk"
include: "workflow/rules/calibration.smk"
include: "workflow/rules/compare.smk"
include: "workflow/rules/keywords.smk"
include: "workflow/rules/history.smk"
include: "workflow/rules/config_files.smk"
include: "workflow/rules/oblique.smk"

# Light bookkeeping stays on the submitting host when a cluster profile is used. Every other
# rule's job is a SLURM job of its own there (profiles/slurm), with its cluster_resources.
localrules: all, engine_version, plan, summary, lammps_regressions, reference_tables, checks, report, gate, case_verdict, case_gate, calibration,
            calibration_report,
            compare, compare_studies, compare_gate, compare_builds, convergence_summary, paper_figure_3, paper_figure_4,
            keywords, keywords_summary, history, history_summary

# The rules whose failure is a verdict: a gate exits non-zero on FAIL, after writing it.
VERDICT_RULES = ("gate", "case_gate", "compare_gate")


onerror:
    # A job that failed (SLURM killed it at its time or memory limit, it was cancelled, its
    # script crashed) leaves no verdict of its own: write the FAIL naming it (verdict.failed_jobs).
    # An interruption (Ctrl-C) is no FAIL: it names the jobs and the command that continues.
    from verdict.failed_jobs import continue_command, record_failed_jobs

    _continue = continue_command(sys.argv)
    _lost = record_failed_jobs(log, "results", {r.name: [str(o) for o in r.output] for r in workflow.rules},
                               verdict_rules=VERDICT_RULES, command=_continue)
    if _lost and all(f["reason"].startswith("interrupted") for f in _lost):
        print(f"INTERRUPTED: {', '.join(f['job'] for f in _lost)} did not finish; their unfinished outputs were "
              f"removed, and the verdicts they touch are marked stale. Continue with:\n  {_continue}", file=sys.stderr)
    elif _lost:
        print(f"FAIL: {len(_lost)} job(s) did not finish (results/report.md, results/junit.xml):\n  "
              + "\n  ".join(f"{f['job']}: {f['reason']}" for f in _lost), file=sys.stderr)


wildcard_constraints:
    case="|".join(map(re.escape, CASES)),
    build="|".join(map(re.escape, BUILD_IDS)),
    lammps_build="|".join(map(re.escape, LAMMPS_BUILDS)) or "(?!)",
    cal_case="|".join(map(re.escape, CALIBRATION_CASES)) or "(?!)",
    release="|".join(map(re.escape, HISTORY_RELEASES)) or "(?!)",

# Bad case files and builds, every one named with what to do, stop the workflow before any job
# starts, with their messages alone: a WorkflowError would add the lines of the Snakefile and
# includes it was raised in, which say nothing about the user's files.
SETUP_PROBLEMS += case_name_problems(CASES, {r.name for r in workflow.rules})
if SETUP_PROBLEMS:
    sys.exit("\n\n".join(SETUP_PROBLEMS))

# One target per case, named as its file: `snakemake -j2 steel` runs the case and its gate.
for _case in CASES:
    rule:
        name: _case
        input: f"results/{_case}/gate.txt"
