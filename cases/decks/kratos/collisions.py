# Kratos Multiphysics 10.4 DEMApplication driver: a sequence of head-on collisions in one
# Python process (the interpreter of the Kratos venv, OMP_NUM_THREADS=1).
#
#   .venv-kratos/bin/python collisions.py <job.json>
#
# Runs under the Kratos venv's Python: KratosMultiphysics, its DEMApplication and the standard
# library only. The job file (written by engines/kratos.py on the host) lists runs; every number
# in it comes from the host's contact model. For each run this script writes, without GiD, the
# inputs a Kratos DEM case reads (ProjectParametersDEM.json, MaterialsDEM.json, <problem>DEM.mdpa
# and, for the plane, <problem>DEM_FEM_boundary.mdpa) into <out>.d/, runs a DEMAnalysisStage on a
# fresh Model, and writes <out> (one row per step: time, overlap, d(overlap)/dt at full steps,
# normal force); at the end it writes <status> (JSON). It prints its build first and
# "RUN <name>" when a run starts, "RUN FAILED <name>: <error>" when one fails.
#
# Contact law: DEM_D_Hertz_viscous_Coulomb (Kratos source
# applications/DEMApplication/custom_constitutive/DEM_D_Hertz_viscous_Coulomb_CL.cpp and .h):
#   kn = 2 Y* sqrt(R* delta),  F_el = (2/3) kn delta = (4/3) Y* sqrt(R*) delta^{3/2},
#   F_d = 2 gamma sqrt(M* kn) d(delta)/dt   (proportional to delta^{1/4}),
#   F = max(F_el + F_d, 0)                  (the normal force is clipped at zero),
# with Y* = Y1 Y2 / (Y2 (1 - nu1^2) + Y1 (1 - nu2^2)) for two spheres and for a sphere and a
# wall alike (the wall's Y, nu are its own properties), R* = R1 R2 / (R1 + R2) for two spheres
# and R* = R - ini_delta (= R here: the sphere starts clear of the wall) against a wall.
# gamma (DAMPING_GAMMA) is set by applications/DEMApplication/python_scripts/sphere_strategy.py
# (ModifySubProperties -> GammaForHertzThornton) from the material relation's
# COEFFICIENT_OF_RESTITUTION e with Thornton et al.'s fit; e > 0.999 gives gamma = 0 exactly.
# The host sends Y = 2 E*, nu = 0 on every body, so that Y* = E*, and e = 1 for law 'elastic'
# (Hertz alone) or the matched restitution for law 'default'. Friction is zero, rotation off.
#
# Geometry (as in the other decks): body A, a sphere at x1 < 0, moves +x; body B is a sphere at
# x2 > 0 moving -x, or the plane x = 0: one RigidFace3D3N triangle (a rigid wall of the FEM
# model part, fixed) with vertices (0, -L, -L), (0, 2L, -L), (0, -L, 2L), L = 10 R: the contact
# point (0, 0, 0) is L / sqrt(2) ~ 7 R from its nearest edge, so the sphere only meets its face.
#
# Time: Kratos's default translational scheme, Symplectic_Euler
# (applications/DEMApplication/custom_strategies/schemes/symplectic_euler_scheme.cpp,
# UpdateTranslationalVariables), in one solution step n -> n+1 computes the contact force F_n
# from the positions x_n, then v_{n+1} = v_n + F_n dt / m and x_{n+1} = x_n + v_{n+1} dt. So after step n+1 a node holds x_{n+1}, v_{n+1} = v(t_n + dt/2)
# and TOTAL_FORCES = F_n: the force lags the position by one step. Row n of the record pairs
# x_n with F_n, and gives the full-step rate d(delta)/dt(t_n) = r(t_n + dt/2) + F_n dt / (2 M*)
# (the force slows the approach: d^2 delta/dt^2 = -F / M*).
import hashlib
import importlib.metadata
import inspect
import json
import math
import os
import shutil
import sys
import time

import KratosMultiphysics as KM
import KratosMultiphysics.DEMApplication as DEM
from KratosMultiphysics.analysis_stage import AnalysisStage
from KratosMultiphysics.DEMApplication.DEM_analysis_stage import DEMAnalysisStage

with open(sys.argv[1]) as f:
    JOB = json.load(f)

PROBLEM = "collision"
LAW = "DEM_D_Hertz_viscous_Coulomb"


def project_parameters(run):
    """ProjectParametersDEM.json: no gravity, no rotation, no output, search every step."""
    return {
        "problem_name": PROBLEM, "Dimension": 3,
        "BoundingBoxOption": False, "AutomaticBoundingBoxOption": False, "dem_inlet_option": False,
        "GravityX": 0.0, "GravityY": 0.0, "GravityZ": 0.0,
        "RotationOption": False, "RollingFrictionOption": False, "CleanIndentationsOption": False,
        "solver_settings": {"strategy": "sphere_strategy", "RemoveBallsInitiallyTouchingWalls": False,
                            "material_import_settings": {"materials_filename": "MaterialsDEM.json"}},
        "DeltaOption": "Absolute", "SearchTolerance": 0.0, "CoordinationNumber": 10,
        "VirtualMassCoefficient": 1.0, "GlobalDamping": 0.0,
        "TranslationalIntegrationScheme": "Symplectic_Euler", "RotationalIntegrationScheme": "Direct_Integration",
        "AutomaticTimestep": False, "DeltaTimeSafetyFactor": 1.0, "MaxTimeStep": run["dt"],
        # The loop is stopped by step count (Recorder.KeepAdvancingSolutionLoop); the final time
        # only has to lie beyond it.
        "FinalTime": (run["steps"] + 10) * run["dt"],
        "NeighbourSearchFrequency": 1, "ElementType": "SphericPartDEMElement3D",
        "do_print_results_option": False, "GraphExportFreq": 1e30, "VelTrapGraphExportFreq": 1e30,
        "OutputTimeStep": 1e30, "PostDisplacement": False, "PostVelocity": False, "PostTotalForces": False,
        "post_vtk_option": False,
    }


def materials(run):
    """MaterialsDEM.json: Y = 2 E*, nu = 0 on every body; the restitution of the run on every pair."""
    bodies = [("sphere_a", 1, {"PARTICLE_DENSITY": run["rho1"]})]
    if run["geometry"] == "sphere-sphere":
        bodies.append(("sphere_b", 2, {"PARTICLE_DENSITY": run["rho2"]}))
    else:
        bodies.append(("wall", 2, {}))
    relation = {"COEFFICIENT_OF_RESTITUTION": run["restitution"], "STATIC_FRICTION": 0.0,
                "DYNAMIC_FRICTION": 0.0, "FRICTION_DECAY": 500.0, "ROLLING_FRICTION": 0.0,
                "ROLLING_FRICTION_WITH_WALLS": 0.0, "DEM_DISCONTINUUM_CONSTITUTIVE_LAW_NAME": LAW}
    pairs = [(1, 1), (1, 2), (2, 2)]
    names = {i: n for n, i, _ in bodies}
    return {
        "materials": [{"material_name": n, "material_id": i,
                       "Variables": {"YOUNG_MODULUS": run["young"], "POISSON_RATIO": run["poisson"], **v}}
                      for n, i, v in bodies],
        "material_relations": [{"material_names_list": [names[a], names[b]], "material_ids_list": [a, b],
                                "Variables": relation} for a, b in pairs],
        "material_assignation_table": [["SpheresPart.spheres", "sphere_a"]]
        + ([["SpheresPart.spheres_b", "sphere_b"]] if run["geometry"] == "sphere-sphere"
           else [["RigidFacePart.plane", "wall"]]),
    }


def sub_model_part(name, nodes, elements=(), conditions=()):
    text = "Begin SubModelPart %s\n Begin SubModelPartNodes\n%s End SubModelPartNodes\n" % (
        name, "".join(" %d\n" % i for i in nodes))
    if elements:
        text += " Begin SubModelPartElements\n%s End SubModelPartElements\n" % "".join(" %d\n" % i for i in elements)
    if conditions:
        text += " Begin SubModelPartConditions\n%s End SubModelPartConditions\n" % "".join(
            " %d\n" % i for i in conditions)
    return text + "End SubModelPart\n"


def write_model(run, folder):
    """The model parts: sphere A (node 1), and sphere B (node 2) or the wall triangle."""
    two = run["geometry"] == "sphere-sphere"
    spheres = [(1, run["x1"], run["R1"], run["v1"])] + ([(2, run["x2"], run["R2"], run["v2"])] if two else [])
    with open(os.path.join(folder, PROBLEM + "DEM.mdpa"), "w") as f:
        f.write("Begin ModelPartData\nEnd ModelPartData\n\nBegin Properties 0\nEnd Properties\n\n")
        f.write("Begin Nodes\n%sEnd Nodes\n\n" % "".join(" %d %r 0.0 0.0\n" % (i, x) for i, x, _, _ in spheres))
        f.write("Begin Elements SphericParticle3D\n%sEnd Elements\n\n" % "".join(
            " %d 0 %d\n" % (i, i) for i, _, _, _ in spheres))
        f.write("Begin NodalData RADIUS\n%sEnd NodalData\n\n" % "".join(" %d 0 %r\n" % (i, r) for i, _, r, _ in spheres))
        f.write("Begin NodalData VELOCITY_X\n%sEnd NodalData\n\n" % "".join(
            " %d 0 %r\n" % (i, v) for i, _, _, v in spheres))
        f.write(sub_model_part("spheres", [1], [1]))
        if two:
            f.write(sub_model_part("spheres_b", [2], [2]))
    if not two:
        L = 10.0 * run["R1"]  # the contact point (0, 0, 0) lies ~7 R inside the triangle
        with open(os.path.join(folder, PROBLEM + "DEM_FEM_boundary.mdpa"), "w") as f:
            f.write("Begin ModelPartData\nEnd ModelPartData\n\nBegin Properties 0\nEnd Properties\n\n")
            f.write("Begin Nodes\n 1 0.0 %r %r\n 2 0.0 %r %r\n 3 0.0 %r %r\nEnd Nodes\n\n" % (-L, -L, 2 * L, -L, -L, 2 * L))
            f.write("Begin Conditions RigidFace3D3N\n 1 0 1 2 3\nEnd Conditions\n\n")
            f.write(sub_model_part("plane", [1, 2, 3], conditions=[1]))


# The Python methods of one solution step that Recorder.RunSolutionLoop inlines (by owner): the
# fast loop runs only where their source is the one it was written from (Kratos 10.4's, sha256
# below); elsewhere (other releases) the stock loop runs, with the same record.
STEP_METHODS = (
    (AnalysisStage, ("RunSolutionLoop", "_AdvanceTime", "InitializeSolutionStep", "ApplyBoundaryConditions",
                     "ChangeMaterialProperties", "SolveSolutionStep", "FinalizeSolutionStep")),
    (DEMAnalysisStage, ("FinalizeSolutionStep", "RunAnalytics", "MakeAnalyticsMeasurements",
                        "IsTimeToPrintPostProcess")),
    ("solver", ("AdvanceInTime", "_UpdateTimeInModelParts", "_UpdateTimeInOneModelPart", "Predict",
                "_MoveAllMeshes", "InitializeSolutionStep", "FixDOFsManually", "FixExternalForcesManually",
                "SolveSolutionStep", "FinalizeSolutionStep")),
)
STEP_METHODS_SHA256 = "1959a174ae8213478771da7082598efec883bc60803c7e4240ca14a10c6c7e53"


def step_methods_sha256(solver):
    """sha256 of the source of STEP_METHODS, as this Kratos defines them."""
    digest = hashlib.sha256()
    for owner, names in STEP_METHODS:
        cls = type(solver) if owner == "solver" else owner
        for name in names:
            digest.update(inspect.getsource(getattr(cls, name)).encode())
    return digest.hexdigest()


def empty(part):
    """Whether a model part holds nothing: no node, element, condition or sub model part."""
    return not (part.NumberOfNodes() or part.NumberOfElements() or part.NumberOfConditions()
                or part.NumberOfSubModelParts())


class Recorder(DEMAnalysisStage):
    """The DEM analysis of one run, recording sphere A (and B) after every solution step."""

    #: False: the fast loop records nothing (benchmarks/engine_overheads.py times Kratos's own step).
    recording = True

    def __init__(self, model, parameters, run, folder):
        self.run, self.folder = run, folder
        self.states = []  # (overlap, d(overlap)/dt at the half step before, force on A along -x)
        super().__init__(model, parameters)

    def GetMainPath(self):
        return self.folder

    def KeepAdvancingSolutionLoop(self):
        return len(self.states) <= self.run["steps"]

    def OutputSolutionStep(self):
        pass  # no graphs, no GiD/VTK files

    def InitializeSolutionStep(self):
        # DEMAnalysisStage.InitializeSolutionStep is AnalysisStage's plus options this driver
        # turns off (inlet analytics, contact mesh, servo or moving bounding box, 2D strain);
        # deciding that, it reads Parameters.keys() twice a step, which takes ~1 ms here (three
        # times the step itself). Initialize checks that the options are off.
        AnalysisStage.InitializeSolutionStep(self)

    def Initialize(self):
        super().Initialize()
        p = self.DEM_parameters
        on = [name for name, value in (
            # getattr: releases before an option (9.5 has no servo loading) cannot turn it on
            ("post_normal_impact_velocity_option", getattr(self, "post_normal_impact_velocity_option", False)),
            ("ContactMeshOption", p["ContactMeshOption"].GetBool()),
            ("bounding_box_servo_loading_option", getattr(self, "bounding_box_servo_loading_option", False)),
            ("Dimension 2", p["Dimension"].GetInt() == 2),
            ("BoundingBoxMoveOption", p.Has("BoundingBoxMoveOption") and p["BoundingBoxMoveOption"].GetBool())) if value]
        if on:
            raise RuntimeError("options the recorder's InitializeSolutionStep skips are on: %s" % ", ".join(on))
        nodes = sorted(self.spheres_model_part.Nodes, key=lambda n: n.X)  # ids are renumbered with a wall
        expected = 2 if self.run["geometry"] == "sphere-sphere" else 1
        if len(nodes) != expected:
            raise RuntimeError("the sphere model part has %d nodes, expected %d" % (len(nodes), expected))
        self.a = nodes[0]
        self.b = nodes[1] if expected == 2 else None
        # The fast loop leaves out what these would do (the stock loop does it).
        self.fast = (hasattr(KM, "TensorAdaptors") and step_methods_sha256(self._GetSolver()) == STEP_METHODS_SHA256
                     and not (p["dem_inlet_option"].GetBool() or self.do_print_results_option
                              or self._GetListOfProcesses() or self.SurfacesAnalyzerClass.surface_analyzers_list
                              or getattr(self, "rve_utils", None) is not None))

    def FinalizeSolutionStep(self):  # the stock loop's
        super().FinalizeSolutionStep()
        self.record()

    def record(self):  # the stock loop's
        a, b, run = self.a, self.b, self.run
        if b is not None:
            overlap = run["R1"] + run["R2"] - (b.X - a.X)
            rate = a.GetSolutionStepValue(KM.VELOCITY_X) - b.GetSolutionStepValue(KM.VELOCITY_X)
        else:
            overlap = run["R1"] + a.X
            rate = a.GetSolutionStepValue(KM.VELOCITY_X)
        force = -a.GetSolutionStepValue(KM.TOTAL_FORCES)[0]  # the repulsive normal force on A points to -x
        self.states.append((overlap, rate, force))

    def RunSolutionLoop(self):
        """The stock loop (AnalysisStage.RunSolutionLoop), or where Kratos is the release it was
        written from (self.fast), the same loop with DEMAnalysisStage's and the sphere strategy's
        step inlined: the same calls into Kratos in the same order, without the Python work
        around them that this driver's options make void (progress reports, processes,
        analytics, inlet, output; Initialize checks that they are off). Through the stock
        methods a step took ~4 times Kratos's own SolveSolutionStep (model parts looked up by
        name, a new AuxiliaryUtilities per model part and step, Parameters and hasattr lookups,
        and Node.GetSolutionStepValue, which resolves among twenty overloads per call)."""
        if not self.fast:
            self.record()
            return super().RunSolutionLoop()
        solver = self._GetSolver()
        strategy = solver.cplusplus_strategy
        reset_flags, initialize = strategy.ResetPrescribedMotionFlagsRespectingImposedDofs, strategy.InitializeSolutionStep
        solve, finalize = strategy.SolveSolutionStep, strategy.FinalizeSolutionStep
        parts = solver.all_model_parts
        spheres, clusters = parts.Get("SpheresPart"), parts.Get("ClusterPart")
        inlet, faces = parts.Get("DEMInletPart"), parts.Get("RigidFacePart")
        update_time = DEM.AuxiliaryUtilities().UpdateTimeInOneModelPart
        move_meshes = solver.dem_fem_utils.MoveAllMeshes
        dt = solver.dt
        # The record reads the spheres' velocities and forces in one call each, into a tensor
        # adaptor's array (a view, refreshed in place by CollectData).
        order = [n.Id for n in spheres.Nodes]
        velocity = KM.TensorAdaptors.HistoricalVariableTensorAdaptor(spheres.Nodes, KM.VELOCITY)
        forces = KM.TensorAdaptors.HistoricalVariableTensorAdaptor(spheres.Nodes, KM.TOTAL_FORCES)
        collect_velocity, collect_forces = velocity.CollectData, forces.CollectData
        collect_velocity()
        collect_forces()
        v, f = velocity.data, forces.data
        a, b = self.a, self.b
        ia = order.index(a.Id)
        append = self.states.append
        if b is not None:
            ib = order.index(b.Id)
            contact = self.run["R1"] + self.run["R2"]

            def record():
                collect_velocity()
                collect_forces()
                append((contact - (b.X - a.X), v.item(ia, 0) - v.item(ib, 0), -f.item(ia, 0)))
        else:
            R1 = self.run["R1"]

            def record():
                collect_velocity()
                collect_forces()
                append((R1 + a.X, v.item(ia, 0), -f.item(ia, 0)))

        if not self.recording:
            def record():
                pass
        record()
        # solver.AdvanceInTime sets the time in the ProcessInfo of the four model parts and
        # solver.Predict moves the meshes of three: of those that hold something. The clusters'
        # and the inlet's are empty here (and the walls' between two spheres): nothing reads
        # their ProcessInfo, and they have no mesh to move.
        timed = [part for part in (spheres, clusters, inlet, faces) if not empty(part)]
        moved = [part for part in (spheres, inlet, faces) if not empty(part)]
        time = self.time
        for _ in range(int(self.run["steps"])):
            time += dt
            for part in timed:
                update_time(part, time, dt, False)
            for part in moved:
                move_meshes(part, time, dt)
            reset_flags()
            initialize()
            solve()
            finalize()
            # AnalysisStage.FinalizeSolutionStep: solver.FinalizeSolutionStep (processes: none)
            record()
        self.time = time


def simulate(run):
    stage, folder = make_stage(run)
    stage.Run()
    write_record(run, stage.states)
    shutil.rmtree(folder)


def make_stage(run, parameters_of=project_parameters, materials_of=materials, model_of=write_model, stage=Recorder):
    """(the run's Recorder, the folder of its Kratos inputs). oblique.py passes its own writers of the
    project parameters, materials and model parts, and its Recorder: the same folder, files and order."""
    folder = run["out"] + ".d"
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    with open(os.path.join(folder, "ProjectParametersDEM.json"), "w") as f:
        json.dump(parameters_of(run), f, indent=1)
    with open(os.path.join(folder, "MaterialsDEM.json"), "w") as f:
        json.dump(materials_of(run), f, indent=1)
    model_of(run, folder)
    with open(os.path.join(folder, "ProjectParametersDEM.json")) as f:
        parameters = KM.Parameters(f.read())
    return stage(KM.Model(), parameters, run, folder), folder


def write_record(run, s):
    """<out> from the states after each step (Recorder.states)."""
    steps, dt, M = int(run["steps"]), run["dt"], run["M"]
    if len(s) != steps + 1:
        raise RuntimeError("recorded %d states, expected %d" % (len(s), steps + 1))
    rows = []
    for n in range(steps):  # x_n from state n; F_n and the half-step rate from state n + 1
        force = s[n + 1][2]
        rows.append("%.17g,%.17g,%.17g,%.17g" % (n * dt, s[n][0], s[n + 1][1] + force * dt / (2.0 * M), force))
    with open(run["out"], "w") as f:
        f.write("time,overlap,normal_velocity,normal_force\n")
        f.write("\n".join(rows) + "\n")


def version():
    return "KratosMultiphysics %s DEMApplication %s (kernel %s)" % (
        importlib.metadata.version("KratosMultiphysics"), importlib.metadata.version("KratosDEMApplication"),
        KM.Kernel.Version().replace('"', ""))  # the kernel says 10.4."4"--0-Release-x86_64


def sweep(job, simulate_run):
    """Every run of the job through simulate_run(run), in order, then <status> (JSON): the build line and
    per run {"ok": True, "seconds"} or {"ok": False, "error"}. This deck's sweep and oblique.py's (which
    runs this file up to SWEEP_MARKER and passes its oblique simulate)."""
    # Kratos prints a page per run at INFO; warnings and errors are what the log needs.
    KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
    status = {"engine_version": version(), "runs": {}}
    # The log (stdout) tells the host the build and the run in progress if Kratos hangs or crashes.
    print(status["engine_version"], flush=True)
    for run in job["runs"]:
        print("RUN %s" % run["name"], flush=True)
        started = time.time()
        try:
            simulate_run(run)
            status["runs"][run["name"]] = {"ok": True, "seconds": time.time() - started}
        except Exception as err:  # report per run; the host fails that run with this log
            status["runs"][run["name"]] = {"ok": False, "error": "%s: %s" % (type(err).__name__, err)}
            print("RUN FAILED %s: %s" % (run["name"], err), flush=True)
    with open(job["status"], "w") as f:
        json.dump(status, f, indent=1)


# The sweep (benchmarks/engine_overheads.py runs this file up to this line, for its functions).
sweep(JOB, simulate)
