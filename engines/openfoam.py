r"""OpenFOAM v1912 (ESI, Debian's `openfoam`): the study's driver, its case template and the conversion.

One implementation for the study (`run_openfoam`, code ``openfoam`` of `engines.codes`) and the
conformance kit's example (conformance/openfoam.py, which only turns a plan.json run into a
`FoamRun` and writes the kit's dump). OpenFOAM's lagrangian collision models are Hertz with a
Tsuji-like dashpot (src/lagrangian/intermediate/submodels/Kinematic/CollisionModel/PairCollision/
PairModel/PairSpringSliderDashpot/PairSpringSliderDashpot.C:205-212 @v1912; the wall's
WallModel/WallSpringSliderDashpot/WallSpringSliderDashpot.C:91-99, :272):

    F = k_N delta^{3/2} + eta_N d(delta)/dt,  k_N = (4/3) sqrt(R*) E*,  eta_N = alpha sqrt(M* k_N) delta^{1/4}  [N]

(no clip: the attractive tail is kept). In x = delta/delta_e, tau = t V/delta_e that is the
study's ``quarter`` form x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 with b = sqrt(5/4) alpha
(keyword ``openfoam:alpha``, `contact_model.keywords`). The study's laws in it: ``elastic``
(alpha = 0, Hertz alone) and ``default`` (its keyword: alpha told the alpha(e) whose own
equation restitutes e); the viscoelastic delta^{1/2} d(delta)/dt force it cannot express.

The run set-up (the case template, cases/decks/openfoam/): `icoUncoupledKinematicParcelFoam`
(the carrier flow frozen at zero, no drag, no gravity: `particleForces` empty, g = 0), one
`manualInjection` per body (each its own velocity), the flow time step = the run's dt and
`collisionResolutionSteps` 1, so that OpenFOAM's own Hertz-time rule
(PairSpringSliderDashpot.C:151-157) asks for one collision sub-cycle (ceil(dt / T_min) = 1,
CollidingCloud.C:207-228): every flow step is one velocity-Verlet step of dt
(CollidingCloud.C:57-70, CollidingParcel.C:85). Every step is written (`writeInterval 1`), the
positions in cartesian form (`writeLagrangianPositions`), the velocities `U` and the contact force
`f` of each parcel: the conversion reads them back (`case_rows`).

OpenFOAM injects a parcel during the first time step and moves it twice in that step: once by the
injection itself (InjectionModel.C:533, ``pPtr->move(cloud, td, dt)`` with dt = time - timeInj = the
whole step, :493), once by the cloud's move-collide step. The case therefore injects each body one
step back, at x - v dt: the n-th time directory is then step n (time n dt), which `case_rows`
checks on the first one; row 0 is the initial state (out of contact, F = 0).

Cost: OpenFOAM writes a time folder of ~35 files every step (~35 kB; v1912 writes every field of
the parcels and of the carrier at each write time, KinematicParcelIO.C `writeFields`, and no
dictionary entry selects fewer), which on this machine's disk was most of a run. The cases
therefore run in a scratch folder of the sweep's own on a tmpfs (`scratch_folder`, /dev/shm; the
work folder where none is writable), each case removed after its run and the folder at the end of
the sweep, success or failure. Only where the files go changes: the dumps are byte-identical
(sha256; tests/test_engine_openfoam.py, benchmarks/openfoam_steps.py). Per step, medians of
`python -m benchmarks.openfoam_steps` (`make bench`; 2 runs of 574 steps, 3 repeats, 2 shared
cores at load 5.4-5.8), disk -> tmpfs: wall 90.3 -> 7.6 ms, OpenFOAM's CPU (blockMesh and the
solver, user + system) 34.5 -> 2.4 ms, the driver's own CPU (case files, the conversion
`case_rows`, removing the case) 2.3 -> 0.9 ms. Of that 0.9 ms, removing the ~35 files is ~0.6 ms
and the conversion ~0.25 ms (367 steps: 0.09 s).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import tempfile
import time
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from pathlib import Path
from string import Template

import numpy as np


from .codes import law_unavailable
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S, describe_exit, log_tail, run_logged, stop_message, time_limit
from .errors import EngineRunFailed, require_executable
from .finish_run import Sweep, write_run_dump
from .run_spec import RunSpec

CLOUD = "kinematicCloud"
SOLVER = "icoUncoupledKinematicParcelFoam"
#: The case template: its dictionaries, `string.Template`s where a run's numbers go.
DECKS = Path(__file__).resolve().parents[1] / "cases" / "decks" / "openfoam"
#: Template file -> where it goes in a case.
TEMPLATE_FILES = {"controlDict": "system/controlDict", "fvSchemes": "system/fvSchemes",
                  "fvSolution": "system/fvSolution", "g": "constant/g",
                  "transportProperties": "constant/transportProperties",
                  "turbulenceProperties": "constant/turbulenceProperties",
                  "kinematicCloudProperties": f"constant/{CLOUD}Properties", "U": "0/U"}
#: The keyword the law 'default' runs (contact_model.keywords): alpha told alpha(e).
KEYWORD = "openfoam:alpha"

HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    location    "{loc}";
    object      {obj};
}}
"""


@dataclass(frozen=True)
class FoamRun:
    """One collision as OpenFOAM's case takes it (SI).

    Attributes
    ----------
    name : str
        The run's name: its case folder and dump are named by it (`name_problem`).
    dt : float
        The time step [s] (OpenFOAM's deltaT).
    steps : int
        Steps to run [-].
    plane : bool
        Body 2 is the plane x = 0 (the wall patch `plane`).
    R1, rho1, x1, v1 : float
        Radius [m], density [kg/m^3], centre [m] and velocity [m/s] of body 1 (moving +x).
    R2, rho2, x2, v2 : float
        The same of body 2 (a sphere; unused for the plane).
    E_star : float
        The effective modulus E* [Pa].
    alpha : float
        OpenFOAM's damping coefficient alpha [-] (eta_N = alpha sqrt(M* k_N) delta^{1/4}).
    """

    name: str
    dt: float
    steps: int
    plane: bool
    R1: float
    x1: float
    v1: float
    rho1: float = math.nan
    R2: float = math.nan
    rho2: float = math.nan
    x2: float = 0.0
    v2: float = 0.0
    E_star: float = math.nan
    alpha: float = math.nan


def foam(cls: str, loc: str, obj: str, body: str) -> str:
    """An OpenFOAM dictionary file: the FoamFile header and `body`."""
    return HEADER.format(cls=cls, loc=loc, obj=obj) + body


def materials(E_star: float) -> tuple[float, float, float]:
    """(E of the particles [Pa], nu [-], E of the wall [Pa]) that give the effective modulus E*.

    With nu = 0 the pair's E* = E / (2 (1 - nu^2)) (PairSpringSliderDashpot.C:117) and the wall's
    1 / ((1 - nu_p^2)/E_p + (1 - nu_w^2)/E_w) (WallSpringSliderDashpot.C:196) are both E/2.
    """
    E = 2.0 * E_star
    return E, 0.0, E


def block_mesh(plane: bool, R: float) -> str:
    """system/blockMeshDict: a box of hexahedra around the collision, [-L, L] in x (two spheres) or
    [-L, 0] with the wall patch `plane` at x = 0 (one face, its centre on the line of centres); the
    other walls 3 R away (L = 8 R)."""
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


def template_values(run: FoamRun) -> dict[str, str]:
    """The numbers the case template's placeholders take (repr: no digit lost)."""
    if not (math.isfinite(run.alpha) and run.alpha >= 0):
        raise ValueError(f"{run.name}: OpenFOAM's alpha must be a finite number >= 0, got {run.alpha!r}")
    E, nu, E_wall = materials(run.E_star)
    d1 = 2.0 * run.R1
    bodies = [(1, run.v1, d1)]
    if not run.plane:
        if run.R2 != run.R1 or run.rho2 != run.rho1:
            raise ValueError(f"{run.name}: OpenFOAM's pair model takes one E and nu for every parcel; "
                             "this template also assumes equal spheres")
        bodies.append((2, run.v2, 2.0 * run.R2))
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
    return {"solver": SOLVER, "end_time": repr(run.steps * run.dt), "dt": repr(run.dt), "density": repr(run.rho1),
            "young": repr(E), "poisson": repr(nu), "young_wall": repr(E_wall), "alpha": repr(run.alpha),
            "injections": injections, "max_interaction_distance": repr(2.0 * d1)}


def injected_at(x: float, v: float, dt: float) -> float:
    """Where to inject a body that is to be at x at time 0 [m]: one free-flight step back (OpenFOAM
    moves a parcel injected at time 0 by two steps in its first step; see the module's docstring)."""
    return x - v * dt


def positions_file(i: int, x: float) -> str:
    """constant/kinematicCloudPositions<i>: the manualInjection's one position, (x 0 0)."""
    return foam("vectorField", "constant", f"{CLOUD}Positions{i}", f"(\n({x!r} 0 0)\n)\n")


def write_case(run: FoamRun, case: Path) -> None:
    """One OpenFOAM case of one run: the template filled in, the mesh and the injection positions.

    `case` is replaced if it exists: its caller checks that it is the run's own folder
    (`name_problem`, `remove_case`)."""
    values = template_values(run)  # before anything is removed: a bad run leaves the folder alone
    if case.exists():
        shutil.rmtree(case)
    for sub in ("0", "constant", "system"):
        (case / sub).mkdir(parents=True)
    files = {dest: Template((DECKS / name).read_text()).substitute(values) for name, dest in TEMPLATE_FILES.items()}
    files["system/blockMeshDict"] = block_mesh(run.plane, run.R1)
    files[f"constant/{CLOUD}Positions1"] = positions_file(1, injected_at(run.x1, run.v1, run.dt))
    if not run.plane:
        files[f"constant/{CLOUD}Positions2"] = positions_file(2, injected_at(run.x2, run.v2, run.dt))
    for name, text in files.items():
        (case / name).write_text(text)


def deck_hash() -> str:
    """sha256 of the case template's files (in TEMPLATE_FILES order): the dumps' deck_sha256."""
    import hashlib

    h = hashlib.sha256()
    for name in TEMPLATE_FILES:
        h.update((DECKS / name).read_bytes())
    return h.hexdigest()


# ---------------------------------------------------------------- the names the plan gives

#: A run's name as a file name: it names a case folder this module deletes and rewrites.
RUN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")


def name_problem(name: str) -> str | None:
    """Why `name` cannot name a case folder (not a plain file name: '../x', 'a/b', ''); None when fine."""
    if not RUN_NAME.fullmatch(name) or ".." in name:
        return f"run name {name!r} is not a plain file name (letters, digits and _ . + -)"
    return None


def remove_case(case: Path, root: Path) -> None:
    """Remove the case folder `case`, refused (ValueError) unless it lies inside `root`: nothing
    outside the study's (or the plan's) own folders is removed."""
    case, root = Path(case).resolve(), Path(root).resolve()
    if case == root or not case.is_relative_to(root):
        raise ValueError(f"{case}: not inside {root}; not removed")
    shutil.rmtree(case, ignore_errors=True)


# ---------------------------------------------------------------- the scratch folder

#: Where a sweep's case folders go when one is writable: a tmpfs (RAM). OpenFOAM writes ~35 small
#: files a step; on this machine's disk that costs 10-100x the solver's own step (docstring, Cost).
SCRATCH_PARENTS = (Path("/dev/shm"),)
#: The prefix of a scratch folder: the study's, and this process's (a test finds its own by it).
SCRATCH_PREFIX = "hertz-openfoam-"
#: What a case holds of a tmpfs per step [bytes]: ~35 files of a 4 kB page each, 141 kB measured
#: (`du`, two spheres, 367 steps: 51.7 MB), with a margin. A container's /dev/shm is often 64 MB.
TMPFS_BYTES_PER_STEP = 200_000


def room(parent: Path) -> int:
    """Bytes free for an unprivileged writer in the file system of `parent` (statvfs) [bytes]."""
    st = os.statvfs(parent)
    return st.f_bavail * st.f_frsize


@contextmanager
def scratch_folder(fallback, need_bytes: int = 0):
    """A new, empty folder of the study's own for a sweep's case folders, removed on leaving (on
    success, an error or an interrupt alike): ``(path, where)``.

    The folder is made by `tempfile.mkdtemp` (a name of its own, mode 0700) in the first of
    `SCRATCH_PARENTS` that is a writable directory (a tmpfs) with `need_bytes` free, else in
    `fallback` (the run's work folder, on disk); `where` says which (``"tmpfs /dev/shm"`` or
    ``"work folder"``). Nothing from a config or a plan names it: only what this function made is
    removed.

    Parameters
    ----------
    fallback : str or os.PathLike
        The work folder, used when no tmpfs is writable or has room; it must exist.
    need_bytes : int
        What one case of the sweep holds at most [bytes] (its longest run's steps x
        `TMPFS_BYTES_PER_STEP`: the cases are removed one by one).
    """
    prefix = f"{SCRATCH_PREFIX}{os.getpid()}-"
    path, where = None, "work folder"
    for parent in SCRATCH_PARENTS:
        if parent.is_dir() and os.access(parent, os.W_OK | os.X_OK) and room(parent) >= need_bytes:
            try:
                path, where = Path(tempfile.mkdtemp(prefix=prefix, dir=parent)), f"tmpfs {parent}"
                break
            except OSError:  # full, or read-only after all: the disk still works, only slower
                continue
    if path is None:
        path = Path(tempfile.mkdtemp(prefix=prefix, dir=fallback))
    try:
        yield path, where
    finally:
        shutil.rmtree(path, ignore_errors=True)


# ---------------------------------------------------------------- running OpenFOAM

def foam_environment() -> dict[str, str]:
    """The environment OpenFOAM's executables need: WM_PROJECT_DIR (its etc/), Debian's unless set
    (`engines.codes` ``environment``)."""
    from .codes import code

    return code("openfoam").process_environment()


def mesher_of(solver: str) -> str:
    """blockMesh beside the solver (the same installation), else the one on PATH."""
    beside = Path(solver).parent / "blockMesh"
    return str(beside) if beside.exists() else (shutil.which("blockMesh") or "blockMesh")


def build_line(log: Path) -> str:
    """OpenFOAM's 'Build  : ...' line of a solver log ('OPENFOAM=1912 patch=200626'), '' if absent."""
    try:
        m = re.search(r"^Build\s*:\s*(.*)$", log.read_text(errors="replace"), flags=re.M)
    except OSError:
        return ""
    return m.group(1).strip() if m else ""


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


def case_rows(run: FoamRun, case: Path) -> list[tuple]:
    """(time [s], overlap [m], normal velocity [m/s], normal force [N]) of every step, from the case's output.

    Row 0 is the initial state (out of contact, F = 0); row n (n >= 1) the n-th time directory, at
    time n dt. Body 1 is the parcel of the smaller x (it never passes body 2); the overlap is
    R1 + x1 (plane) or R1 + R2 - (x2 - x1), the velocity v1 - v2, F = -f_x of body 1 (the force on
    it, repulsive along -x).

    Raises
    ------
    ValueError
        Naming the case's file: a missing step, a time that is not n dt, a parcel count that is
        not the run's, or a first step that is not free flight (a misaligned injection).
    """
    dt, steps, plane = run.dt, run.steps, run.plane
    dirs = time_dirs(case)
    if len(dirs) != steps:
        raise ValueError(f"{case}: {len(dirs)} time directories written, the run has {steps} steps")

    def overlap(x1, x2):
        return run.R1 + x1 if plane else run.R1 + run.R2 - (x2 - x1)

    rows = [(0.0, overlap(run.x1, run.x2), run.v1 - run.v2, 0.0)]
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
            for x, x_ini, v in ((x1, run.x1, run.v1), (x2, run.x2, run.v2)):
                if abs(x - (x_ini + v * dt)) > 1e-6 * abs(v * dt):
                    raise ValueError(f"{d}: a body at x = {x!r} after the first step, the run's free flight "
                                     f"puts it at {x_ini + v * dt!r}: the injection is misaligned")
        rows.append((n * dt, overlap(x1, x2), v1 - v2, F))
    return rows


# ---------------------------------------------------------------- the study's driver

def foam_run(spec: RunSpec) -> FoamRun:
    """The `FoamRun` of a study run: its initial state (`RunSpec.initial_state`), E*, and alpha = 0
    (``elastic``) or the keyword's alpha(e) for the restitution it is told (``default``; an alpha
    given directly, `RunSpec.told_input`, as it stands).

    Raises
    ------
    ValueError
        For a law OpenFOAM cannot express (`engines.codes.law_unavailable`), with the reason.
    """
    why = law_unavailable("openfoam", spec.law)
    if why or spec.law not in ("elastic", "default"):
        raise ValueError(f"openfoam cannot run law {spec.law!r}: {why or 'not in its case template'}")
    from contact_model.keywords import KEYWORDS

    s = spec.initial_state()
    if spec.law == "elastic":
        alpha = 0.0
    elif spec.told_input is not None:  # alpha given as it stands (RunSpec.told_input), no restitution asked
        alpha = spec.told_input
    else:
        alpha = KEYWORDS[KEYWORD].told_for(spec.matched_restitution)
    return FoamRun(name=spec.name, dt=s["dt"], steps=int(s["steps"]), plane=spec.pair.body_2.is_plane,
                   R1=s["R1"], rho1=s["rho1"], x1=s["x1"], v1=s["v1"], R2=s.get("R2", math.nan),
                   rho2=s.get("rho2", math.nan), x2=s.get("x2", 0.0), v2=s.get("v2", 0.0),
                   E_star=spec.pair.E, alpha=alpha)


def run_openfoam(specs: list[RunSpec], workdir, executable: str = SOLVER,
                 timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S) -> Sweep:
    """Run every spec in OpenFOAM, one case at a time; write `workdir/<spec.name>.csv` for each.

    Each run is a case `<scratch>/<name>.case` from the template (`write_case`), meshed by blockMesh
    and run by the solver (`executable`), both as argument lists with OpenFOAM's environment
    (`foam_environment`) and a time limit (`engines.engine_process.time_limit` of that run, at least
    `timeout_floor_s`), its output converted to the study's dump (`case_rows`, `write_run_dump`),
    and the case folder removed (~29 MB of a tmpfs per 200 steps). The cases run in one scratch
    folder the sweep makes and always removes (`scratch_folder`: a tmpfs when one is writable and
    holds the longest run's case, else inside `workdir`); each run's log
    (`workdir/<name>.openfoam.log`, the solver's own) ends with a line naming it. Only where the
    case folders are changes, never a number: the dumps are the same,
    byte for byte (tests/test_engine_openfoam.py).

    Raises
    ------
    EngineMissing
        When the solver is not installed (the hint: ``make openfoam``).
    ValueError
        Before anything runs: a law OpenFOAM cannot express, runs of another code, two runs of one
        name, or a name that is no plain file name.

    Returns
    -------
    Sweep
        A dump or an EngineRunFailed (naming the case's log) for each run; a run whose blockMesh or
        solver fails, or is stopped at its time limit, fails alone and the next runs go on.
    """
    if any(s.engine != "openfoam" for s in specs):
        raise ValueError("run_openfoam got runs for another engine")
    if len({s.name for s in specs}) != len(specs):
        raise ValueError("run_openfoam got two runs with the same name")
    problems = [p for p in (name_problem(s.name) for s in specs) if p]
    if problems:
        raise ValueError("; ".join(problems))
    runs = [foam_run(s) for s in specs]  # refuses a law it cannot run before anything starts
    exe = require_executable("openfoam", executable)
    mesher = mesher_of(exe)
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    sweep, started = Sweep(), time.monotonic()
    need = max(s.steps() for s in specs) * TMPFS_BYTES_PER_STEP if specs else 0
    with scratch_folder(workdir, need) as (scratch, where):
        for spec, run in zip(specs, runs):
            (workdir / f"{spec.name}.csv").unlink(missing_ok=True)
            case = scratch / f"{spec.name}.case"
            note = f"hertz study: case folder {case} ({where}), removed after the run\n"
            sweep.finish(spec, lambda: _run_one(spec, run, case, workdir, exe, mesher, timeout_floor_s, note))
            remove_case(case, scratch)  # at once: a long sweep holds one case in RAM, not all of them
    sweep.engine_seconds = time.monotonic() - started
    return sweep


def _run_one(spec: RunSpec, run: FoamRun, case: Path, workdir: Path, exe: str, mesher: str,
             timeout_floor_s: float, note: str = "") -> Path:
    """Write, mesh, run and convert one case; its dump's path, or EngineRunFailed. `note` (where the
    case ran) is appended to the run's log, which stays in `workdir` beside the dump."""
    write_case(run, case)
    limit = time_limit("openfoam", [spec], timeout_floor_s)
    log = workdir / f"{spec.name}.openfoam.log"
    for name, cmd in (("blockMesh", [mesher, "-case", str(case)]), (SOLVER, [exe, "-case", str(case)])):
        step_log = case / f"log.{name}"
        done = run_logged(cmd, step_log, limit, cwd=workdir, env=foam_environment())
        shutil.copyfile(step_log, log)  # the case folder goes; its last log stays beside the dump
        with log.open("a") as out:
            out.write(note)
        if done.timed_out or done.returncode != 0:
            stop = (f"{name} did not finish within its time limit of {limit:.3g} s and was killed" if done.timed_out
                    else f"{name} exited with {describe_exit(done.returncode)}")
            raise EngineRunFailed(spec.name, stop_message("openfoam", exe, spec.case, spec.name, stop, log), log,
                                  engine="openfoam", case=spec.case, log_tail=log_tail(log))
    if "move-collide subCycles" in log.read_text(errors="replace"):
        raise EngineRunFailed(spec.name, "OpenFOAM sub-cycled the collisions (its step is not the run's dt)", log)
    try:
        data = np.array(case_rows(run, case), dtype=float)
    except (OSError, ValueError) as err:
        raise EngineRunFailed(spec.name, f"openfoam: its output cannot be converted: {err}", log) from err
    meta = {"engine": "openfoam", "engine_version": f"OpenFOAM {build_line(log) or '(no Build line)'}, {SOLVER}",
            "deck": "kinematicCloudProperties", "deck_sha256": deck_hash(),
            "engine_variables": {k: v for k, v in asdict(run).items() if k != "name"}}
    return write_run_dump(spec, data, workdir / f"{spec.name}.csv", log, meta)
