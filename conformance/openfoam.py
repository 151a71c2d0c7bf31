r"""The conformance kit's plan in OpenFOAM (ESI v1912, Debian's `openfoam`): cases and dumps.

A user-side example of docs/conformance.md on a real code. The case template, the running and the
conversion are the study's own OpenFOAM driver's (engines/openfoam.py, code ``openfoam``): this
module only turns a plan.json run into its `engines.openfoam.FoamRun` and writes the kit's dump.
OpenFOAM's lagrangian collision models are Hertz with a
Tsuji-like dashpot (src/lagrangian/intermediate/submodels/Kinematic/CollisionModel/PairCollision/
PairModel/PairSpringSliderDashpot/PairSpringSliderDashpot.C:205-212 @v1912; the wall's
WallModel/WallSpringSliderDashpot/WallSpringSliderDashpot.C:91-99, :272):

    F = k_N delta^b + eta_N d(delta)/dt,  k_N = (4/3) sqrt(R) E*,  eta_N = alpha sqrt(M k_N) delta^{1/4}

(no clip: the attractive tail is kept), which is the study's ``quarter`` form
x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 with b = sqrt(5/4) alpha. A plan of that form (``export
--keyword lammps:tsuji`` or ``liggghts:hertz-coefficientRestitution``, both unclipped ``quarter``)
gives its damping as F = k_n delta^{3/2} + g delta^{1/4} d(delta)/dt in SI: OpenFOAM's alpha is
g / sqrt(M* k_n), given directly.

    python -m conformance.openfoam cases PLAN_DIR [--only SUBSTRING]   # one OpenFOAM case per run
    python -m conformance.openfoam run PLAN_DIR [--only SUBSTRING]     # blockMesh + solver, one at a time
    python -m conformance.openfoam convert PLAN_DIR                    # cases' output -> dumps/*.csv
    python -m conformance.openfoam dumps PLAN_DIR [--only SUBSTRING]   # all three, run by run, on a tmpfs
    python -m conformance.openfoam told ALPHA                          # the export of a given alpha

The run set-up: `icoUncoupledKinematicParcelFoam` (the carrier flow frozen at zero, no drag, no
gravity: `particleForces` empty, g = 0), one `manualInjection` per body (each its own velocity),
the flow time step = the plan's dt and `collisionResolutionSteps` 1, so that OpenFOAM's own
Hertz-time rule (PairSpringSliderDashpot.C:151-157) asks for one collision sub-cycle (ceil(dt /
T_min) = 1, CollidingCloud.C:207-228): every flow step is one velocity-Verlet step of the plan's
dt (CollidingCloud.C:57-70, CollidingParcel.C:85). Every step is written (`writeInterval 1`),
the positions in cartesian form (`writeLagrangianPositions`), the velocities `U` and the contact
force `f` of each parcel.

OpenFOAM injects a parcel during the first time step and moves it twice in that step: once by the
injection itself (InjectionModel.C:533, ``pPtr->move(cloud, td, dt)`` with dt = time - timeInj = the
whole step, :493), once by the cloud's move-collide step. The case therefore injects each body one
step back, at x - v dt (free flight: the contact starts 20.5 steps later): the n-th time directory
is then step n of the plan (time n dt), which `convert` checks on the first one; row 0 is the plan's
initial state (out of contact, F = 0).
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

from engines import openfoam as engine
from engines.engine_process import run_logged
from engines.openfoam import CLOUD, SOLVER, FoamRun, case_rows as _case_rows, foam, name_problem  # noqa: F401

def alpha_of(run: dict) -> float:
    """OpenFOAM's alpha of the run's law: g / sqrt(M* k_n) (eta_N = alpha sqrt(M k_N) delta^{1/4}).

    Raises
    ------
    ValueError
        When the run's law is not of OpenFOAM's form (damping power 1/4, not clipped) or undamped.
    """
    law = run["law_equation"]
    if law["clipped"]:
        raise ValueError(f"{run['name']}: the law clips the force; OpenFOAM keeps the attractive tail")
    if law["damping_power"] not in (0.25, None):
        raise ValueError(f"{run['name']}: damping delta^{law['damping_power']} d(delta)/dt; OpenFOAM's is "
                         "delta^(1/4) d(delta)/dt (export a 'quarter' keyword: --keyword lammps:tsuji)")
    g = law["damping_coefficient_SI"] or 0.0
    return g / math.sqrt(run["effective"]["M_star_kg"] * law["k_n_N_per_m1.5"])


#: The restitution keyword whose equation is OpenFOAM's at any alpha: LIGGGHTS's b = (5/2) beta(e)
#: (contact_model/keywords.py), unclipped, told 0.05 < e <= 1.
TOLD_KEYWORD = "liggghts:hertz-coefficientRestitution"


def told_for_alpha(alpha: float) -> float:
    """The e that `TOLD_KEYWORD` must be told for OpenFOAM's `alpha`: its b = (5/2) beta(e) is
    sqrt(5/4) alpha when beta = alpha / sqrt(5), e = exp(-pi beta / sqrt(1 - beta^2)).

    Raises
    ------
    ValueError
        When no e in (0.05, 1] gives it (alpha >= sqrt(5) beta(0.05) ~ 1.54, or alpha < 0).
    """
    from contact_model.keywords import KEYWORDS

    beta = alpha / math.sqrt(5.0)
    e = math.exp(-math.pi * beta / math.sqrt(1.0 - beta * beta)) if 0.0 <= beta < 1.0 else 0.0
    low, high = KEYWORDS[TOLD_KEYWORD].accepts
    if not low < e <= high:
        raise ValueError(f"alpha = {alpha!r}: {TOLD_KEYWORD} would have to be told e = {e!r}, outside ({low}, {high}]")
    return e


def foam_run(run: dict, physics: bool = True) -> FoamRun:
    """The `engines.openfoam.FoamRun` of a plan.json run; `physics` False: its geometry, step and
    initial state alone (what the conversion reads), no material or alpha."""
    b1, b2, ini = run["body_1"], run["body_2"], run["initial"]
    plane = bool(b2["plane"])
    more = {}
    if physics:
        more = {"rho1": b1["density_kg_m3"], "E_star": run["effective"]["E_star_Pa"], "alpha": alpha_of(run)}
        if not plane:
            more["rho2"] = b2["density_kg_m3"]
    return FoamRun(name=str(run["name"]), dt=run["dt_s"], steps=int(run["steps"]), plane=plane,
                   R1=b1["radius_m"], x1=ini["x1_m"], v1=ini["v1_m_s"],
                   R2=math.nan if plane else b2["radius_m"], x2=0.0 if plane else ini["x2_m"],
                   v2=0.0 if plane else ini["v2_m_s"], **more)


def write_case(run: dict, case: Path) -> None:
    """One OpenFOAM case of one run of the plan (`engines.openfoam.write_case`), and its run.json."""
    engine.write_case(foam_run(run), case)
    (case / "run.json").write_text(json.dumps({"run": run["name"], "alpha": alpha_of(run)}, indent=1))


def case_rows(run: dict, case: Path) -> list[tuple]:
    """(time, overlap, normal_velocity, normal_force) of every step of the plan's run, from the
    case's output (`engines.openfoam.case_rows`)."""
    return _case_rows(foam_run(run, physics=False), case)


def write_dump(plan: dict, run: dict, rows: list[tuple], out: Path, version: str) -> None:
    """The study's dump format (docs/conformance.md), every number as repr."""
    head = (f"# hertz-dem-dump: 1\n# plan_id: {json.dumps(plan['plan_id'])}\n# run: {json.dumps(run['name'])}\n"
            f"# engine_version: {json.dumps(version)}\ntime,overlap,normal_velocity,normal_force\n")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(head + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))


def openfoam_version() -> str:
    """The installed OpenFOAM's version (dpkg), for the dumps' engine_version."""
    try:
        v = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "openfoam"], capture_output=True, text=True,
                           check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        v = "unknown"
    return f"OpenFOAM {SOLVER} (Debian openfoam {v}), pairSpringSliderDashpot/wallSpringSliderDashpot"


def run_problem(run: dict) -> str | None:
    """Why a run of plan.json cannot name its case folder and dump (a name that is no plain file name,
    e.g. '../x', or a dump outside dumps/: the plan is data, never a path to delete); None when fine.

    Parameters
    ----------
    run : dict
        One entry of plan.json's ``runs``.
    """
    name = str(run.get("name", ""))
    problem = name_problem(name)  # the same check as the study's driver
    if problem:
        return f"plan.json: {problem}"
    if run.get("dump") != f"dumps/{name}.csv":
        return f"plan.json: run {name!r}: field 'dump' {run.get('dump')!r} is not dumps/{name}.csv"
    return None


#: The time limit of one blockMesh or solver process of the kit's `run` [s] (a run of 2 700 steps: ~40 s).
RUN_TIMEOUT_S = 1800.0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m conformance.openfoam", description=__doc__.split("\n\n")[0])
    ap.add_argument("action", choices=("cases", "run", "convert", "dumps", "told"))
    ap.add_argument("plan_dir", help="the plan's folder (`export --out`); for `told`, OpenFOAM's alpha")
    ap.add_argument("--only", default="", help="only the runs whose name contains this")
    args = ap.parse_args(argv)
    if args.action == "told":
        e = told_for_alpha(float(args.plan_dir))
        print(f"python -m conformance export CASE --keyword {TOLD_KEYWORD} --told {e!r} --K K --out DIR")
        return 0
    args.plan_dir = Path(args.plan_dir)
    plan = json.loads((args.plan_dir / "plan.json").read_text())
    runs = [r for r in plan["runs"] if args.only in str(r.get("name", ""))]
    problems = [p for p in map(run_problem, runs) if p]
    if problems:
        print("\n".join(problems), file=sys.stderr)
        return 2
    if args.action == "dumps":
        return make_dumps(plan, runs, args.plan_dir)
    cases = args.plan_dir / "openfoam"
    for run in runs:
        case = cases / run["name"]
        if args.action == "cases":
            write_case(run, case)
            print(f"{case}: alpha = {alpha_of(run)!r}")
        elif args.action == "run":
            if run_case(case):
                return 1
            print(f"{case}: ran")
        else:
            convert(plan, run, case, args.plan_dir)
    return 0


def run_case(case: Path) -> int:
    """blockMesh and the solver on `case` (argument lists, OpenFOAM's environment, `RUN_TIMEOUT_S`
    each); 0, or 1 after saying on stderr what failed and where its log is."""
    solver = engine.require_executable("openfoam", SOLVER)
    for cmd in ([engine.mesher_of(solver)], [solver]):
        name = Path(cmd[0]).name
        done = run_logged(cmd + ["-case", str(case)], case / f"log.{name}", RUN_TIMEOUT_S,
                          env=engine.foam_environment())
        rc = -9 if done.timed_out else done.returncode
        if rc:
            print(f"{case}: {name} failed (exit {rc}), see log.{name}", file=sys.stderr)
            return 1
    if "move-collide subCycles" in (case / f"log.{SOLVER}").read_text():
        print(f"{case}: OpenFOAM sub-cycled the collisions (the step is not the plan's dt)", file=sys.stderr)
        return 1
    return 0


def convert(plan: dict, run: dict, case: Path, plan_dir: Path) -> None:
    """The run's dump (plan_dir / its ``dump``) from the case's output."""
    rows = case_rows(run, case)
    write_dump(plan, run, rows, plan_dir / run["dump"], openfoam_version())
    print(f"{plan_dir / run['dump']}: {len(rows)} rows")


def make_dumps(plan: dict, runs: list[dict], plan_dir: Path) -> int:
    """`cases`, `run` and `convert` of each run in turn, its case in a scratch folder of its own
    (`engines.openfoam.scratch_folder`: a tmpfs when one is writable and holds the longest run's
    case, else in the plan's folder),
    removed after its dump is written: one run's time folders at a time, never on the disk when a
    tmpfs is there. A failing run stops the rest and keeps its log (copied beside the plan as
    ``openfoam-<run>.log``); the scratch folder goes in every case. 0, or 1 on a failure."""
    need = max((int(r["steps"]) for r in runs), default=0) * engine.TMPFS_BYTES_PER_STEP
    with engine.scratch_folder(plan_dir, need) as (scratch, where):
        print(f"cases in {scratch} ({where}), each removed after its dump")
        for run in runs:
            case = scratch / run["name"]
            write_case(run, case)
            failed = run_case(case)
            if failed:
                for log in sorted(case.glob("log.*")):
                    shutil.copyfile(log, plan_dir / f"openfoam-{run['name']}.{log.name}")
                return failed
            convert(plan, run, case, plan_dir)
            engine.remove_case(case, scratch)
    return 0

if __name__ == "__main__":
    sys.exit(main())
