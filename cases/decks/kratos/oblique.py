# Kratos Multiphysics 10.4 DEMApplication driver of oblique collisions: DEM_D_Hertz_viscous_Coulomb
# with friction and rotation, in one Python process (the Kratos venv's interpreter, OMP_NUM_THREADS=1).
#
#   .venv-kratos/bin/python oblique.py <job.json>
#
# Runs under the Kratos venv's Python: KratosMultiphysics, its DEMApplication and the standard library.
# The head-on driver collisions.py (beside this file) is run up to its sweep (the line of SWEEP_MARKER,
# as benchmarks/engine_overheads.py runs it) for its functions: the inputs it writes (project parameters,
# model parts), its Recorder (a DEMAnalysisStage that records after every solution step), the stage it
# makes of a run's inputs (make_stage, given this file's writers and Recorder), its build line and its
# sweep (the runs in turn, a failure reported per run, the status file). This file changes what an
# oblique run needs and nothing else:
#
# - rotation on (RotationOption, Kratos's default rotational scheme "Direct_Integration", i.e. the
#   translational Symplectic_Euler: w_{n+1} = w_n + M_n dt / I, I = (2/5) m R^2 for a sphere);
# - each body's own YOUNG_MODULUS and POISSON_RATIO (the head-on deck gives Y = 2 E*, nu = 0, which
#   leaves G* wrong): Kratos forms E* = E1 E2 / (E2 (1 - nu1^2) + E1 (1 - nu2^2)) and
#   G* = 1 / ((2 - nu1)/G1 + (2 - nu2)/G2), G_i = E_i / (2 (1 + nu_i)), the wall's E, nu its own
#   (DEM_D_Hertz_viscous_Coulomb_CL.cpp, InitializeContact and InitializeContactWithFEM);
# - STATIC_FRICTION = DYNAMIC_FRICTION = mu (the friction decay then multiplies zero), restitution 1
#   (DAMPING_GAMMA = 0: no normal and no tangential dashpot; the oblique cases are elastic);
# - the bodies move in the x-y plane and spin about z; body 2 (a sphere) starts at y2 as the host says.
#
# The record (one row per step, the 8 columns of records.dump_file.OBLIQUE_COLUMNS, %.17g, space-separated
# under a header line, as engines/oblique_record.py reads the other decks' records): Kratos's
# Symplectic_Euler step n -> n+1 computes the forces and moments F_n, M_n from the positions x_n (and the
# step's displacement increments), then v_{n+1} = v_n + F_n dt / m. After step n+1 a node holds x_{n+1},
# v_{n+1} = v(t_n + dt/2), TOTAL_FORCES = F_n and PARTICLE_MOMENT = M_n. Row n pairs x_n with F_n and
# gives the full-step velocities v(t_n) = v(t_n + dt/2) - F_n dt / (2 m) (and w likewise with M_n / I).
# Two spheres: the overlap is R1 + R2 - |x2 - x1| (3-D), the velocities and forces are the lab frame's
# x and y components (the line of centres turns during the contact, as the reference's does).
import math
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEP_MARKER = "# The sweep (benchmarks/engine_overheads.py runs this file up to this line"
HEAD_ON = os.path.join(HERE, "collisions.py")
with open(HEAD_ON) as _f:
    _text = _f.read()
# collisions.py reads its job from argv[1] when run: this file's job (the same file format) is read twice.
exec(compile(_text[:_text.index(SWEEP_MARKER)], HEAD_ON, "exec"))

KM_ = KM  # noqa: F821  (KratosMultiphysics, imported by collisions.py; named here once for the linter)


def oblique_parameters(run):
    """ProjectParametersDEM.json: the head-on deck's, with rotation on."""
    p = project_parameters(run)  # noqa: F821
    p["RotationOption"] = True
    return p


def oblique_materials(run):
    """MaterialsDEM.json: each body's Young's modulus, Poisson's ratio (and density); Coulomb's mu."""
    two = run["geometry"] == "sphere-sphere"
    bodies = [("sphere_a", 1, run["young1"], run["poisson1"], {"PARTICLE_DENSITY": run["rho1"]}),
              (("sphere_b" if two else "wall"), 2, run["young2"], run["poisson2"],
               {"PARTICLE_DENSITY": run["rho2"]} if two else {})]
    relation = {"COEFFICIENT_OF_RESTITUTION": run["restitution"], "STATIC_FRICTION": run["friction"],
                "DYNAMIC_FRICTION": run["friction"], "FRICTION_DECAY": 500.0, "ROLLING_FRICTION": 0.0,
                "ROLLING_FRICTION_WITH_WALLS": 0.0, "DEM_DISCONTINUUM_CONSTITUTIVE_LAW_NAME": LAW}  # noqa: F821
    names = {i: n for n, i, *_ in bodies}
    return {
        "materials": [{"material_name": n, "material_id": i,
                       "Variables": {"YOUNG_MODULUS": E, "POISSON_RATIO": nu, **v}} for n, i, E, nu, v in bodies],
        "material_relations": [{"material_names_list": [names[a], names[b]], "material_ids_list": [a, b],
                                "Variables": relation} for a, b in ((1, 1), (1, 2), (2, 2))],
        "material_assignation_table": [["SpheresPart.spheres", "sphere_a"]]
        + ([["SpheresPart.spheres_b", "sphere_b"]] if two else [["RigidFacePart.plane", "wall"]]),
    }


def write_oblique_model(run, folder):
    """The model parts: sphere A (node 1) and sphere B (node 2), with positions x, y, velocities x, y and
    spins about z; or sphere A and the wall triangle of the head-on deck (write_model)."""
    write_model(run, folder)  # noqa: F821  (the wall; the spheres' file is rewritten below)
    two = run["geometry"] == "sphere-sphere"
    spheres = [(1, run["x1"], run["y1"], run["R1"], run["v1"], run["vy1"], run["w1"])]
    if two:
        spheres.append((2, run["x2"], run["y2"], run["R2"], run["v2"], run["vy2"], run["w2"]))

    def nodal(variable, k):
        return "Begin NodalData %s\n%sEnd NodalData\n\n" % (variable, "".join(" %d 0 %r\n" % (s[0], s[k]) for s in spheres))

    with open(os.path.join(folder, PROBLEM + "DEM.mdpa"), "w") as f:  # noqa: F821
        f.write("Begin ModelPartData\nEnd ModelPartData\n\nBegin Properties 0\nEnd Properties\n\n")
        f.write("Begin Nodes\n%sEnd Nodes\n\n" % "".join(" %d %r %r 0.0\n" % s[:3] for s in spheres))
        f.write("Begin Elements SphericParticle3D\n%sEnd Elements\n\n" % "".join(" %d 0 %d\n" % (s[0], s[0])
                                                                               for s in spheres))
        f.write(nodal("RADIUS", 3) + nodal("VELOCITY_X", 4) + nodal("VELOCITY_Y", 5) + nodal("ANGULAR_VELOCITY_Z", 6))
        f.write(sub_model_part("spheres", [1], [1]))  # noqa: F821
        if two:
            f.write(sub_model_part("spheres_b", [2], [2]))  # noqa: F821


class ObliqueRecorder(Recorder):  # noqa: F821
    """The head-on Recorder through Kratos's stock solution loop, recording what an oblique run needs:
    positions, velocities, forces, spins and moments of both spheres after every step."""

    def Initialize(self):
        super().Initialize()
        self.fast = False  # the head-on fast loop records the normal columns only
        # (2/5) m R^2, set by SphericParticle::Initialize (CalculateMomentOfInertia)
        self.inertia = [n.GetSolutionStepValue(DEM.PARTICLE_MOMENT_OF_INERTIA)  # noqa: F821
                        for n in (self.a, self.b) if n is not None]

    def record(self):
        state = []
        for n in (self.a, self.b):
            if n is None:
                continue
            v = n.GetSolutionStepValue(KM_.VELOCITY)
            w = n.GetSolutionStepValue(KM_.ANGULAR_VELOCITY)
            f = n.GetSolutionStepValue(KM_.TOTAL_FORCES)
            m = n.GetSolutionStepValue(DEM.PARTICLE_MOMENT)  # noqa: F821
            state.append((n.X, n.Y, n.Z, v[0], v[1], w[2], f[0], f[1], m[2]))
        self.states.append(state)


def write_oblique_record(run, s, masses, inertia):
    """<out> from the states after each step (ObliqueRecorder.states): row n pairs x_n (state n) with
    F_n and the half-step velocities of state n + 1, brought to t_n."""
    steps, dt = int(run["steps"]), run["dt"]
    if len(s) != steps + 1:
        raise RuntimeError("recorded %d states, expected %d" % (len(s), steps + 1))
    two = run["geometry"] == "sphere-sphere"
    m1 = masses[0]
    inv_m = 1.0 / m1 + (1.0 / masses[1] if two else 0.0)  # relative acceleration per unit force on body 1
    h = 0.5 * dt
    rows = []
    for n in range(steps):
        a0 = s[n][0]
        a1 = s[n + 1][0]
        fx, fy = a1[6], a1[7]
        if two:
            b0, b1 = s[n][1], s[n + 1][1]
            overlap = run["R1"] + run["R2"] - math.sqrt((b0[0] - a0[0]) ** 2 + (b0[1] - a0[1]) ** 2 + (b0[2] - a0[2]) ** 2)
            rate, vt = a1[3] - b1[3], a1[4] - b1[4]
            w2 = b1[5] - b1[8] * h / inertia[1]
        else:
            overlap = run["R1"] + a0[0]
            rate, vt = a1[3], a1[4]
            w2 = 0.0
        rows.append("%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g" % (
            n * dt, overlap, rate - fx * h * inv_m, -fx, vt - fy * h * inv_m, a1[5] - a1[8] * h / inertia[0], w2, fy))
    with open(run["out"], "w") as f:
        f.write("time overlap normal_velocity normal_force tangential_velocity omega_1 omega_2 tangential_force\n")
        f.write("\n".join(rows) + "\n")


def simulate_oblique(run):
    stage, folder = make_stage(run, oblique_parameters, oblique_materials, write_oblique_model,  # noqa: F821
                               ObliqueRecorder)
    stage.Run()
    nodes = [n for n in (stage.a, stage.b) if n is not None]
    masses = [n.GetSolutionStepValue(KM_.NODAL_MASS) for n in nodes]
    write_oblique_record(run, stage.states, masses, stage.inertia)
    shutil.rmtree(folder)


# The sweep: the head-on deck's (collisions.py's sweep), with the oblique run.
sweep(JOB, simulate_oblique)  # noqa: F821
