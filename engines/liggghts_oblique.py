"""LIGGGHTS-PUBLIC 3.8.0 oblique collisions: the deck variables and the sweep of `ObliqueRun`s
(cases/decks/liggghts/oblique_*.in).

The contact is ``model hertz/stiffness tangential history`` (the pair style, and ``fix wall/gran``
with a primitive plane of atom type 2), every coefficient given by the host, as the head-on
driver gives the normal ones (engines/liggghts.py):

- normal: F_n = kn a delta + gamman M* a d(delta)/dt with a = sqrt(R* delta), kn = 4/3 E* [Pa]
  and gamman = 2 eta / M* [1/(m s)] (`contact_model.engine_parameters.liggghts_hertz_stiffness`):
  the study's viscoelastic law (elastic: gamman = 0), ``limitForce on`` for the clipped law;
- tangential: k_t = kt a with kt = 8 G* [Pa] (Mindlin's stiffness; 1/G* = 2 (2 - nu1)(1 + nu1)/E1
  + 2 (2 - nu2)(1 + nu2)/E2), and the dashpot gamma_t = gammat M* a with gammat = x_t gamman, so
  that gamma_t = x_t 2 eta a, the reference's x_t times the normal damping prefactor
  (src/normal_model_hertz_stiffness.h:118-122 in 3.8.0: kn, kt, gamman, gammat all times
  polyhertz = sqrt(R* delta); gamman, gammat also times M*).

``model hertz`` computes the same kt = 8 G* a from Young's moduli and Poisson's ratios
(contact_model/tangential_models.yaml, `liggghts:history`, normal_model_hertz.h:232) but takes its
damping from a restitution coefficient; `hertz/stiffness` keeps the study's normal law and lets a
check scale k_t alone (`stiffness_factor`). Either feeds the same `tangential history`
(src/tangential_model_history.h): the spring xi += v_s dt, projected into the tangent plane; F_el =
-k_t xi; above mu |F_n| (F_n damping included, |.| unless limitForce) the spring is scaled back to the
cap and no dashpot acts; below it, F = F_el - gamma_t v_s. Lever arms R - delta/2 for the slip and
the torque, the plane's contact too (src/surface_model_default.h).

Runs with `ranks = 2` go to a process of their own, `mpirun -np 2` (the `mpirun` beside the
executable: Debian's Open MPI for /usr/bin/liggghts), with the box (symmetric about 0) split at
the contact as the LAMMPS decks do: along x for two spheres (each on its rank), along y for the
plane (the sphere crosses y = 0 in mid-contact with the wall's history). LIGGGHTS's dump custom has
no `proc` attribute: the decks write one file per rank (`%` in the name) at the start and the end,
and each rank's file lists the atoms it owns (`read_owners`).
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path


from contact_model.effective import effective_shear_modulus
from records.dump_file import write_dump

from .codes import code
from .engine_process import DEFAULT_TIMEOUT_FLOOR_S
from .finish_run import Sweep
from .lammps_oblique import mpirun_launcher
from .oblique_record import read_oblique_record
from .oblique_run import ObliqueJob, ObliqueRun
from .script_engine import ScriptEngine, common_variables, number

DECK_OF_GEOMETRY = {"sphere-sphere": "oblique_two_spheres.in", "sphere-plane": "oblique_sphere_plane.in"}
#: The registry's models the decks write (contact_model/tangential_models.yaml), and their words.
MODEL_WORDS = {"liggghts:history": "model hertz/stiffness tangential history"}
MODELS = tuple(MODEL_WORDS)
#: Processors grids: one rank; two ranks split at the contact (see the decks).
GRID = {(1, "sphere-sphere"): "1 1 1", (1, "sphere-plane"): "1 1 1",
        (2, "sphere-sphere"): "2 1 1", (2, "sphere-plane"): "1 2 1"}
#: A step of these decks against the head-on one of the cost table (engines.codes: 15 us), per rank count,
#: so that the process's time limit counts it: measured on this 2-core machine under load (Chung & Ooi's
#: tests 4-8, every angle), 63 us/step on one rank (8 columns, reneighbouring every step) and 1.26 ms/step
#: on two (Open MPI, --oversubscribe: each step's exchange waits on a shared core); the 60 s floor killed a
#: two-rank sweep of 51 runs (66 000 steps) that needed 83 s.
STEP_COST = {1: 5, 2: 100}


def shear_modulus(pair) -> float:
    """G* [Pa] of the pair's bodies (`contact_model.effective.effective_shear_modulus`)."""
    return effective_shear_modulus(pair.body_1, pair.body_2)


def check_run(run: ObliqueRun) -> None:
    """Refuse, before any engine starts, a run the decks cannot write: another code's model, or a
    restitution keyword as the normal law (hertz/stiffness is the study's own law alone)."""
    if run.model not in MODEL_WORDS:
        raise ValueError(f"{run.name}: LIGGGHTS's oblique decks have no tangential model {run.model!r}; "
                         f"known: {MODELS}")
    if run.normal.engine != "liggghts":
        raise ValueError(f"{run.name} is not a LIGGGHTS run (engine {run.normal.engine!r})")
    if run.normal.keyword is not None:
        raise ValueError(f"{run.name}: the oblique decks run the study's normal law (model hertz/stiffness), "
                         f"not the restitution keyword of law {run.law!r}")


def tangential_stiffness(run: ObliqueRun) -> float:
    """kt [Pa] of ``model hertz/stiffness``: 8 G*, which LIGGGHTS multiplies by a = sqrt(R* delta)
    (k_t = 8 G* a [N/m])."""
    return 8.0 * shear_modulus(run.pair)


def contact_variables(run: ObliqueRun, stiffness_factor: float = 1.0, friction_factor: float = 1.0) -> dict:
    """The deck's contact variables: kn [Pa], kt [Pa], gamman and gammat [1/(m s)], mu, model and
    tail. `stiffness_factor` scales kt and `friction_factor` mu (the sensitivity checks: 1 is the
    model's own)."""
    check_run(run)
    params = code("liggghts").contact_parameters(run.pair)
    return {"kn": number(params["kn"]), "kt": number(stiffness_factor * tangential_stiffness(run)),
            "gamman": number(params["gamman"]), "gammat": number(run.damping_ratio * params["gamman"]),
            "mu": number(friction_factor * run.friction), "model": MODEL_WORDS[run.model],
            "tail": "limitForce " + ("on" if run.law == "viscoelastic_clipped" else "off")}


def owners_pattern(out: Path, when: str = "owners") -> Path:
    """The per-rank files of who owns which atom: `<out>.<when>.<rank>` (`%` is the rank)."""
    return out.with_suffix(f".{when}.%")


def read_owners(pattern: Path) -> dict[int, int] | None:
    """{atom id: owning rank} from the per-rank `write_dump ... id x y z` files of `pattern` (None
    where none was written)."""
    owners = {}
    files = sorted(pattern.parent.glob(pattern.name.replace("%", "*")))
    for path in files:
        rank = int(re.fullmatch(re.escape(pattern.name).replace("%", r"(\d+)"), path.name).group(1))
        lines = path.read_text().splitlines()
        start = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS")) + 1
        owners.update({int(line.split()[0]): rank for line in lines[start:] if line.strip()})
    return owners if files else None


def deck_variables(job: ObliqueJob, out: Path, decks: Path) -> dict[str, str]:
    """The deck variables of one oblique run (SI): the head-on run's, the tangential velocities,
    spins and positions, the contact coefficients, the processors grid, the record and the owners
    files."""
    run = job.run
    return {**common_variables(run.normal), **{k: number(v) for k, v in run.initial_velocities().items()},
            **{k: number(v) for k, v in run.initial_positions().items()},
            **contact_variables(run, job.stiffness_factor, job.friction_factor),
            "grid": GRID[(run.ranks, run.pair.geometry)], "out": str(out),
            "owners": str(owners_pattern(out)), "owners_end": str(owners_pattern(out, "owners_end"))}


def initial_row(run: ObliqueRun) -> list[float]:
    """The record's state at t = 0 (LIGGGHTS's fix print starts at step 1): free flight, no force;
    the 8 columns of `records.dump_file.OBLIQUE_COLUMNS`."""
    v = run.initial_velocities()
    v1, v2 = run.normal.initial_velocities()
    return [0.0, -run.normal.initial_gap(), v1 - v2, 0.0, v["vy1"] - v["vy2"], v["w1"], v["w2"], 0.0]


class ObliqueEngine(ScriptEngine):
    """LIGGGHTS's ScriptEngine for `ObliqueJob`s: an 8-column record (the step-0 row prepended), written
    with the oblique metadata."""

    def _dump(self, job: ObliqueJob, raw: Path, workdir: Path, log: Path, version: str, override: dict) -> Path:
        run = job.run
        data = read_oblique_record(raw, run, log, initial_row(run))
        variables = {**self.variables(job, raw, self.decks), **override}
        start, end = owners_pattern(raw), owners_pattern(raw, "owners_end")
        owners, owners_end = read_owners(start), read_owners(end)
        meta = {"engine": self.name, "engine_version": version, "deck": self.deck_files(job)[0],
                "deck_sha256": self.deck_hash(job),
                "engine_variables": {k: v for k, v in variables.items() if k not in ("out", "owners", "owners_end")},
                "tangential_stiffness": job.stiffness_factor * tangential_stiffness(run),
                "tangential_stiffness_unit": "Pa (times a: N/m)",
                "owners": {str(k): v for k, v in owners.items()} if owners is not None else None,
                "owners_end": {str(k): v for k, v in owners_end.items()} if owners_end is not None else None,
                **run.metadata()}
        dump = workdir / f"{run.name}.csv"
        write_dump(dump, meta, data)
        raw.unlink()
        for pattern in (start, end):
            for path in pattern.parent.glob(pattern.name.replace("%", "*")):
                path.unlink()
        return dump


OBLIQUE = ObliqueEngine(
    name="liggghts", executable="liggghts", version_prefix="LIGGGHTS",
    decks=Path(__file__).resolve().parents[1] / "cases" / "decks" / "liggghts",
    variables=deck_variables, deck_files=lambda job: [DECK_OF_GEOMETRY[job.run.pair.geometry]],
    step0_in_record=False,
)


def run_liggghts_oblique(runs: list[ObliqueRun], workdir, executable: str = "liggghts",
                         timeout_floor_s: float = DEFAULT_TIMEOUT_FLOOR_S, mpirun: str | None = None,
                         stiffness_factor: float = 1.0, friction_factor: float = 1.0,
                         overrides: dict | None = None) -> Sweep:
    """Run oblique LIGGGHTS collisions: the one-rank runs in one process, the two-rank runs in one
    `mpirun -np 2` process (`workdir/np2/`); each run's dump is `<name>.csv` (8 columns,
    records.dump_file.OBLIQUE_COLUMNS, header `ObliqueRun.metadata()` and the engine's).

    Parameters
    ----------
    runs : list of ObliqueRun
        The collisions (names unique), each of a model of `MODELS`.
    workdir : str or os.PathLike
        Where the sweep scripts, logs and dumps go.
    executable : str
        The LIGGGHTS executable.
    timeout_floor_s : float
        The least time limit of each engine process [s].
    mpirun : str, optional
        The MPI launcher of the two-rank runs (default: `engines.lammps_oblique.mpirun_launcher`'s
        choice, the `mpirun` beside the executable).
    stiffness_factor : float
        kt is multiplied by it in the generated deck (1: the model's own; a sensitivity check).
    friction_factor : float
        mu is multiplied by it in the generated deck (1: the case's own; a sensitivity check).
    overrides : dict, optional
        Deck variables replaced per run or ladder name (`ScriptEngine.run`).

    Raises
    ------
    ValueError
        Before any engine starts, for a run of another code or model, or with a restitution keyword.
    """
    for run in runs:
        check_run(run)
    sweep = Sweep()
    for ranks, sub in ((1, Path(workdir)), (2, Path(workdir) / "np2")):
        jobs = [ObliqueJob(r, STEP_COST[r.ranks], stiffness_factor, friction_factor) for r in runs if r.ranks == ranks]
        if not jobs:
            continue
        engine = OBLIQUE if ranks == 1 else replace(OBLIQUE, launcher=mpirun_launcher(executable, mpirun))
        done = engine.run(jobs, sub, executable, overrides=overrides, timeout_floor_s=timeout_floor_s)
        sweep.dumps.update(done.dumps)
        sweep.failures.update(done.failures)
        sweep.engine_seconds += done.engine_seconds
    return sweep

