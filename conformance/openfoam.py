r"""The conformance kit's plan in OpenFOAM (ESI v1912, Debian's `openfoam`): cases and dumps.

Not an engine of the study (no build, no driver): a user-side example of docs/conformance.md
on a real code the study does not run. OpenFOAM's lagrangian collision models are Hertz with a
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
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

CLOUD = "kinematicCloud"
SOLVER = "icoUncoupledKinematicParcelFoam"
#: Where Debian's package puts OpenFOAM's etc/ (its executables find their etc/controlDict through it).
FOAM_DIR = "/usr/share/openfoam"

HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    location    "{loc}";
    object      {obj};
}}
"""


def foam(cls: str, loc: str, obj: str, body: str) -> str:
    """An OpenFOAM dictionary file: the header and `body`."""
    return HEADER.format(cls=cls, loc=loc, obj=obj) + body


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


def materials(run: dict) -> tuple[float, float, float]:
    """(E of the particles, nu, E of the wall) that give the plan's E*.

    With nu = 0: the pair's E* = E / (2 (1 - nu^2)) (PairSpringSliderDashpot.C:117) and the wall's
    1 / ((1 - nu_p^2)/E_p + (1 - nu_w^2)/E_w) (WallSpringSliderDashpot.C:196) are both E/2.
    """
    E = 2.0 * run["effective"]["E_star_Pa"]
    return E, 0.0, E


def block_mesh(plane: bool, R: float) -> str:
    """A box of hexahedra around the collision: [-L, L] in x (two spheres) or [-L, 0] with the wall
    patch `plane` at x = 0 (one face, its centre on the line of centres); the other walls 3 R away."""
    L, h = 8.0 * R, 3.0 * R
    x0, x1, nx = (-L, 0.0, 2) if plane else (-L, L, 4)
    v = [(x0, -h, -h), (x1, -h, -h), (x1, h, -h), (x0, h, -h), (x0, -h, h), (x1, -h, h), (x1, h, h), (x0, h, h)]
    verts = "\n".join(f"    ({a!r} {b!r} {c!r})" for a, b, c in v)
    walls = ["(0 4 7 3)", "(0 1 5 4)", "(3 7 6 2)", "(0 3 2 1)", "(4 5 6 7)"]
    if not plane:
        walls.append("(1 2 6 5)")

    def patch(name, faces):
        return (f"    {name}\n    {{\n        type wall;\n        faces\n        (\n"
                + "".join(f"            {f}\n" for f in faces) + "        );\n    }\n")

    patches = patch("walls", walls) + (patch("plane", ["(1 2 6 5)"]) if plane else "")
    return foam("dictionary", "system", "blockMeshDict",
                f"scale 1;\nvertices\n(\n{verts}\n);\nblocks\n(\n    hex (0 1 2 3 4 5 6 7) ({nx} 1 1) "
                f"simpleGrading (1 1 1)\n);\nedges ();\nboundary\n(\n{patches});\nmergePatchPairs ();\n")


def cloud_properties(run: dict) -> str:
    """constant/kinematicCloudProperties: no forces, one manualInjection per body, Hertz + dashpot."""
    b1, b2, ini = run["body_1"], run["body_2"], run["initial"]
    E, nu, E_wall = materials(run)
    alpha = alpha_of(run)
    d1 = 2.0 * b1["radius_m"]
    bodies = [(1, ini["v1_m_s"], d1)]
    if not b2["plane"]:
        if b2["radius_m"] != b1["radius_m"] or b2["density_kg_m3"] != b1["density_kg_m3"]:
            raise ValueError(f"{run['name']}: OpenFOAM's pair model takes one E and nu for every parcel; "
                             "this template also assumes equal spheres")
        bodies.append((2, ini["v2_m_s"], 2.0 * b2["radius_m"]))
    injections = "".join(
        f"""        body{i}
        {{
            type            manualInjection;
            massTotal       0;
            parcelBasisType fixed;
            nParticle       1;
            SOI             0;
            positionsFile   "{CLOUD}Positions{i}";
            U0              ({v!r} 0 0);
            sizeDistribution
            {{
                type        fixedValue;
                fixedValueDistribution
                {{
                    value   {d!r};
                }}
            }}
        }}
""" for i, v, d in bodies)
    model = f"""            useEquivalentSize   no;
            alpha               {alpha!r};
            b                   1.5;
            mu                  0;
            cohesionEnergyDensity 0;
            collisionResolutionSteps 1;"""
    return foam("dictionary", "constant", f"{CLOUD}Properties", f"""
solution
{{
    active          true;
    coupled         false;
    transient       yes;
    cellValueSourceCorrection off;
    maxCo           1;
    interpolationSchemes
    {{
        rho             cell;
        U               cell;
        mu              cell;
    }}
    integrationSchemes
    {{
        U               Euler;
    }}
}}

constantProperties
{{
    rho0            {b1['density_kg_m3']!r};
    youngsModulus   {E!r};
    poissonsRatio   {nu!r};
}}

subModels
{{
    particleForces
    {{
    }}

    injectionModels
    {{
{injections}    }}

    dispersionModel none;
    patchInteractionModel none;
    surfaceFilmModel none;
    stochasticCollisionModel none;
    collisionModel pairCollision;

    pairCollisionCoeffs
    {{
        maxInteractionDistance  {2.0 * d1!r};
        writeReferredParticleCloud no;
        pairModel pairSpringSliderDashpot;
        pairSpringSliderDashpotCoeffs
        {{
{model}
        }}
        wallModel wallSpringSliderDashpot;
        wallSpringSliderDashpotCoeffs
        {{
{model}
            youngsModulus       {E_wall!r};
            poissonsRatio       {nu!r};
        }}
    }}
}}

cloudFunctions
{{
}}
""")


def control_dict(run: dict) -> str:
    """system/controlDict: deltaT = the plan's dt, `steps` steps, every step written at full precision."""
    dt, steps = run["dt_s"], run["steps"]
    return foam("dictionary", "system", "controlDict", f"""
application     {SOLVER};
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         {steps * dt!r};
deltaT          {dt!r};
writeControl    timeStep;
writeInterval   1;
purgeWrite      0;
writeFormat     ascii;
writePrecision  17;
writeCompression off;
timeFormat      general;
timePrecision   17;
runTimeModifiable no;

OptimisationSwitches
{{
    writeLagrangianPositions 1;
}}
""")


def injected_at(x: float, v: float, dt: float) -> float:
    """Where to inject a body that is to be at x at time 0: one free-flight step back (OpenFOAM moves
    a parcel injected at time 0 by two steps in its first step; see the module's docstring)."""
    return x - v * dt


def positions_file(i: int, x: float) -> str:
    """constant/kinematicCloudPositions<i>: the manualInjection's one position, (x 0 0)."""
    return foam("vectorField", "constant", f"{CLOUD}Positions{i}", f"(\n({x!r} 0 0)\n)\n")


def write_case(run: dict, case: Path) -> None:
    """One OpenFOAM case of one run of the plan."""
    if case.exists():
        shutil.rmtree(case)
    for sub in ("0", "constant", "system"):
        (case / sub).mkdir(parents=True)
    plane, ini = run["body_2"]["plane"], run["initial"]
    files = {
        "system/controlDict": control_dict(run),
        "system/blockMeshDict": block_mesh(plane, run["body_1"]["radius_m"]),
        "system/fvSchemes": foam("dictionary", "system", "fvSchemes", "".join(
            f"{k}\n{{\n    default none;\n}}\n" for k in ("ddtSchemes", "gradSchemes", "divSchemes",
                                                         "laplacianSchemes"))
            + "interpolationSchemes\n{\n    default linear;\n}\n"),
        "system/fvSolution": foam("dictionary", "system", "fvSolution", "solvers\n{\n}\n"),
        "constant/g": foam("uniformDimensionedVectorField", "constant", "g",
                           "dimensions [0 1 -2 0 0 0 0];\nvalue (0 0 0);\n"),
        "constant/transportProperties": foam("dictionary", "constant", "transportProperties",
                                             "rhoInf 1.2;\ntransportModel Newtonian;\nnu 1e-05;\n"),
        "constant/turbulenceProperties": foam("dictionary", "constant", "turbulenceProperties",
                                              "simulationType laminar;\n"),
        f"constant/{CLOUD}Properties": cloud_properties(run),
        f"constant/{CLOUD}Positions1": positions_file(1, injected_at(ini["x1_m"], ini["v1_m_s"], run["dt_s"])),
        "0/U": foam("volVectorField", "0", "U", "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
                    "boundaryField\n{\n    \".*\"\n    {\n        type noSlip;\n    }\n}\n"),
    }
    if not plane:
        files[f"constant/{CLOUD}Positions2"] = positions_file(2, injected_at(ini["x2_m"], ini["v2_m_s"], run["dt_s"]))
    for name, text in files.items():
        (case / name).write_text(text)
    (case / "run.json").write_text(json.dumps({"run": run["name"], "alpha": alpha_of(run)}, indent=1))


# ---------------------------------------------------------------- reading OpenFOAM's output

_NUM = r"[-+0-9.eE]+"


def _list_body(text: str) -> str:
    """The text after the FoamFile header of a lagrangian field file."""
    i = text.find("}", text.find("FoamFile"))
    return text[i + 1:]


def read_vectors(path: Path) -> list[tuple[float, float, float]]:
    """A lagrangian vector field (`U`, `f`) or the v1706 `positions` file (the cell label after each
    vector is ignored): the parcels' vectors in file order."""
    body = re.sub(r"//.*", "", _list_body(path.read_text())).strip()
    vectors = [tuple(float(c) for c in m.groups())
               for m in re.finditer(rf"\(\s*({_NUM})\s+({_NUM})\s+({_NUM})\s*\)", body)]
    uniform = re.match(r"(\d+)\s*\{", body)  # N{(x y z)}: N equal vectors
    return vectors * int(uniform.group(1)) if uniform else vectors


def read_labels(path: Path) -> list[int]:
    """A lagrangian label field (`origId`), in file order (uniform `N{v}` lists too)."""
    body = re.sub(r"//.*", "", _list_body(path.read_text())).strip()
    m = re.match(r"(\d+)\s*\{\s*(-?\d+)\s*\}", body)
    if m:
        return [int(m.group(2))] * int(m.group(1))
    m = re.match(r"(\d+)\s*\((.*)\)", body, re.S)
    return [int(x) for x in m.group(2).split()]


def time_dirs(case: Path) -> list[Path]:
    """The case's time directories after 0, in time order."""
    out = []
    for p in case.iterdir():
        try:
            t = float(p.name)
        except ValueError:
            continue
        if p.is_dir() and t > 0:
            out.append((t, p))
    return [p for _, p in sorted(out)]


def case_rows(run: dict, case: Path) -> list[tuple]:
    """(time, overlap, normal_velocity, normal_force) of every step of the run, from the case's output.

    Row 0 is the plan's initial state (out of contact, F = 0); row n (n >= 1) the n-th time
    directory, at time n dt. Body 1 is the parcel injected by `body1` (the smaller x, it never
    passes body 2); F = -f_x of body 1 (the force on it, repulsive along -x).
    """
    dt, steps, ini = run["dt_s"], run["steps"], run["initial"]
    b1, b2 = run["body_1"], run["body_2"]
    plane = b2["plane"]
    dirs = time_dirs(case)
    if len(dirs) != steps:
        raise ValueError(f"{case}: {len(dirs)} time directories written, the plan has {steps} steps")

    def overlap(x1, x2):
        return b1["radius_m"] + x1 if plane else b1["radius_m"] + b2["radius_m"] - (x2 - x1)

    rows = [(0.0, overlap(ini["x1_m"], ini["x2_m"]), ini["v1_m_s"] - ini["v2_m_s"], 0.0)]
    for n, d in enumerate(dirs, start=1):
        t = float(d.name)
        if abs(t - n * dt) > 1e-6 * dt:
            raise ValueError(f"{d}: time {t!r} is not step {n} x dt = {n * dt!r}")
        lag = d / "lagrangian" / CLOUD
        pos, U, f = (read_vectors(lag / name) for name in ("positions", "U", "f"))
        want = 1 if plane else 2
        if not (len(pos) == len(U) == len(f) == want):
            raise ValueError(f"{lag}: {len(pos)} parcels, the run has {want} bodies")
        order = sorted(range(want), key=lambda i: pos[i][0])
        i1 = order[0]
        x1, v1, F = pos[i1][0], U[i1][0], 0.0 - f[i1][0]  # 0.0 - : no -0.0 out of contact
        x2, v2 = (0.0, 0.0) if plane else (pos[order[1]][0], U[order[1]][0])
        if n == 1:  # the first step is free flight: x + v dt, or the injection is misaligned
            for x, x_ini, v in ((x1, ini["x1_m"], ini["v1_m_s"]), (x2, ini["x2_m"], ini["v2_m_s"])):
                if abs(x - (x_ini + v * dt)) > 1e-6 * abs(v * dt):
                    raise ValueError(f"{d}: a body at x = {x!r} after the first step, the plan's free flight "
                                     f"puts it at {x_ini + v * dt!r}: the injection is misaligned")
        rows.append((n * dt, overlap(x1, x2), v1 - v2, F))
    return rows


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


#: A run's name as the kit's export writes it: it names a case folder this module deletes and rewrites.
RUN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")


def run_problem(run: dict) -> str | None:
    """Why a run of plan.json cannot name its case folder and dump (a name that is no plain file name,
    e.g. '../x', or a dump outside dumps/: the plan is data, never a path to delete); None when fine.

    Parameters
    ----------
    run : dict
        One entry of plan.json's ``runs``.
    """
    name = str(run.get("name", ""))
    if not RUN_NAME.fullmatch(name) or ".." in name:
        return f"plan.json: run name {name!r} is not a plain file name (letters, digits and _ . + -)"
    if run.get("dump") != f"dumps/{name}.csv":
        return f"plan.json: run {name!r}: field 'dump' {run.get('dump')!r} is not dumps/{name}.csv"
    return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m conformance.openfoam", description=__doc__.split("\n\n")[0])
    ap.add_argument("action", choices=("cases", "run", "convert", "told"))
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
    cases = args.plan_dir / "openfoam"
    for run in runs:
        case = cases / run["name"]
        if args.action == "cases":
            write_case(run, case)
            print(f"{case}: alpha = {alpha_of(run)!r}")
        elif args.action == "run":
            env = {**os.environ, "WM_PROJECT_DIR": os.environ.get("WM_PROJECT_DIR", FOAM_DIR)}
            for cmd in (["blockMesh"], [SOLVER]):
                with open(case / f"log.{cmd[0]}", "w") as log:
                    rc = subprocess.run(cmd + ["-case", str(case)], stdout=log, stderr=subprocess.STDOUT,
                                        env=env).returncode
                if rc:
                    print(f"{case}: {cmd[0]} failed (exit {rc}), see log.{cmd[0]}", file=sys.stderr)
                    return 1
            log = (case / f"log.{SOLVER}").read_text()
            if "move-collide subCycles" in log:
                print(f"{case}: OpenFOAM sub-cycled the collisions (the step is not the plan's dt)", file=sys.stderr)
                return 1
            print(f"{case}: ran")
        else:
            rows = case_rows(run, case)
            write_dump(plan, run, rows, args.plan_dir / run["dump"], openfoam_version())
            print(f"{args.plan_dir / run['dump']}: {len(rows)} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
