# YADE driver (2023.02a and 2025.2.0): a sequence of head-on collisions in one YADE process.
#
#   yade -n -x collisions.py job=<job.json>
#
# Runs under YADE's own Python: yade + the standard library only. The job file (written by
# engines/yade.py on the host) lists runs; every number in it comes from the host's contact
# model. For each run this script writes <out> (one row per step: time, overlap,
# d(overlap)/dt at full steps, normal force) and, at the end, <status> (JSON). It prints its
# build first and "RUN <name>" when a run starts.
#
# Contact law (the host picks one per run):
#   viscoelastic   Hertz-Mindlin elastic part (k_no = 4/3 E* sqrt(R*), from young = 2E*,
#                  poisson = 0) with betan = 0, plus the dissipative force
#                  F_d = c sqrt(delta) d(delta)/dt added with O.forces.addF between the
#                  InteractionLoop and the NewtonIntegrator; the attractive tail is kept.
#   viscoelastic_clipped   the same, total force clipped at >= 0 (what YADE's own damping does);
#                  in YADE 2024.02a and later YADE's own: MindlinPhys.beta set so that its
#                  c_n = A k_n is c sqrt(delta) (native(); no Python force).
#   default        Hertz-Mindlin with its restitution damping (Ip2 en), as a user would set it.
#
# Geometry (as in the LIGGGHTS decks): body A, a sphere at x1 < 0, moves +x; body B is a sphere
# at x2 > 0 moving -x, or the plane x = 0 (a Wall with hertzian=True, so that R* = R; YADE
# represents the wall's radius as 1e8 R, which makes R* = R (1 - 1e-8)).
#
# Time: YADE's leapfrog keeps velocities at half steps. At the recorder after the
# InteractionLoop of iteration k, positions and forces are at t_k = k dt and velocities at
# t_k - dt/2: the dissipative force uses that velocity (as YADE's own damping does), and the
# record carries the full-step velocity v(t_k) = v(t_k - dt/2) + a_k dt/2.
#
# Speed: the recorder is not a PyRunner. A PyRunner runs in O.run's simulation thread, which takes
# the GIL from the waiting script and compiles its command at every step: ~100 us a step against
# YADE's own ~10 us. Instead the script steps the scene itself with O.subStepping (one O.step()
# runs one sub-step: the prologue, one engine, or the epilogue; Scene::moveToNextTimeStep runs the
# same engines in the same order as O.run) and calls the recorder between the InteractionLoop and
# the NewtonIntegrator, where the PyRunner was. The recorder keeps the run's numbers and the
# bodies' State objects in locals, stores floats and formats the rows once at the end.
import json
import math
import sys
import time

import yade
import yade.config
from yade import utils

args = dict(a.split("=", 1) for a in sys.argv[1:])
with open(args["job"]) as f:
    JOB = json.load(f)

S = {}
#: YADE 2024.02a and later damp a Hertz contact as Brilliantov's law themselves (MindlinPhys.beta).
NATIVE_BETA = "beta" in dir(MindlinPhys())


def build(run):
    O.reset()
    young = run["young"]
    mat = O.materials.append(FrictMat(young=young, poisson=0.0, density=run["rho1"], frictionAngle=0.0))
    a = O.bodies.append(utils.sphere((run["x1"], 0, 0), run["R1"], material=mat))
    O.bodies[a].state.vel = (run["v1"], 0, 0)
    if run["geometry"] == "sphere-sphere":
        mat2 = O.materials.append(FrictMat(young=young, poisson=0.0, density=run["rho2"], frictionAngle=0.0))
        b = O.bodies.append(utils.sphere((run["x2"], 0, 0), run["R2"], material=mat2))
        O.bodies[b].state.vel = (run["v2"], 0, 0)
    else:
        b = O.bodies.append(utils.wall(0.0, axis=0, sense=-1, material=mat))
    if "vn" in run:  # its restitution at a velocity (2024.02a and later): Brilliantov's law by Mueller & Poeschel's Pade
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(en=MatchMaker(algo="val", val=run["en"]),
                                                vn=MatchMaker(algo="val", val=run["vn"]))
    elif "en" in run:  # its restitution keyword
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(en=MatchMaker(algo="val", val=run["en"]))
    elif "betan" in run:  # its damping ratio
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(betan=MatchMaker(algo="val", val=run["betan"]))
    else:
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys()  # betan unset: no built-in damping
    # run_steps() sub-steps these four, in this order, and records after the InteractionLoop
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
        InteractionLoop(
            [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(hertzian=True)],
            [ip2],
            [Law2_ScGeom_MindlinPhys_Mindlin(neverErase=native(run))]),
        NewtonIntegrator(damping=0.0, gravity=(0, 0, 0)),  # YADE's default damping is 0.2
    ]
    O.dt = run["dt"]
    S.clear()
    S.update(run=run, a=a, b=b, two=run["geometry"] == "sphere-sphere")
    if native(run):
        # YADE's own damping, c_n = A k_n with k_n = (3/2) k_no sqrt(delta) and A from MindlinPhys.beta
        # (A = (2/3) beta (k_no / mbar)^(-2/5), HertzMindlin.cpp:469-470 @2025.2.0): beta is set on the
        # interaction before the bodies touch (created now; neverErase keeps it through the approach,
        # where Law2 gives no force), so that c_n sqrt(delta)... is c sqrt(delta) from the first step.
        i = utils.createInteraction(a, b)
        kno = i.phys.kno
        i.phys.beta = run["c"] / kno * (kno / run["M"]) ** 0.4


def native(run):
    """Whether YADE damps the run's viscoelastic force itself: the clipped law in a release whose
    MindlinPhys has `beta` (2024.02a and later; Law2 clips the total normal force at zero)."""
    return run["law"] == "viscoelastic_clipped" and NATIVE_BETA


def run_steps(steps):
    """Run `steps` iterations of the scene build() made, the recorder after the InteractionLoop of
    each (iteration 0 included); {column: list of floats} of the rows recorded (one per iteration
    that got to its recorder). The arithmetic, and its order, is the PyRunner's that it replaces:
    the recorded numbers are the same doubles."""
    run, a, b, two = S["run"], S["a"], S["b"], S["two"]
    A = O.bodies[a].state
    B = O.bodies[b].state if two else None
    R1 = run["R1"]
    R12 = run["R1"] + run["R2"] if two else None
    c = run["c"]
    # Whether the study adds the dissipative force (YADE damps the en, betan and native runs itself).
    python_force = "en" not in run and "betan" not in run and not native(run)
    clipped = run["law"] == "viscoelastic_clipped"
    dt = O.dt
    two_M = 2.0 * run["M"]
    forces, interactions = O.forces, O.interactions
    addF, f, has = forces.addF, forces.f, interactions.has
    sqrt = math.sqrt
    step = O.step
    overlaps, rates, normal_forces = [], [], []
    put_overlap, put_rate, put_force = overlaps.append, rates.append, normal_forces.append
    if O.iter != 0:
        raise RuntimeError("the scene starts at iteration %d, not 0" % O.iter)
    if [type(e).__name__ for e in O.engines] != ["ForceResetter", "InsertionSortCollider", "InteractionLoop",
                                                  "NewtonIntegrator"]:
        raise RuntimeError("the sub-steps below are build()'s four engines, not %s" % O.engines)
    O.subStepping = True
    try:
        for _ in range(steps):
            step()  # the prologue
            step()  # ForceResetter
            step()  # the collider
            step()  # the InteractionLoop
            if two:
                overlap = R12 - (B.pos[0] - A.pos[0])
                rate_half = A.vel[0] - B.vel[0]
            else:
                overlap = R1 + A.pos[0]
                rate_half = A.vel[0]
            if overlap > 0 and python_force:
                f_d = c * sqrt(overlap) * rate_half
                if clipped and has(a, b):
                    f_el = interactions[a, b].phys.kno * overlap ** 1.5
                    f_d = max(f_d, -f_el)
                addF(a, (-f_d, 0, 0))
                if two:
                    addF(b, (f_d, 0, 0))
            force = -f(a)[0]  # the repulsive normal force on A points to -x
            put_overlap(overlap)
            put_rate(rate_half - force * dt / two_M)
            put_force(force)
            step()  # the NewtonIntegrator
            step()  # the epilogue: O.iter + 1
    finally:
        O.subStepping = False
    # k dt, not O.time: YADE adds dt to O.time every step, a sum that drifts from k dt by rounding
    return {"time": [k * dt for k in range(len(overlaps))], "overlap": overlaps, "normal_velocity": rates,
            "normal_force": normal_forces}


status = {"engine_version": "YADE %s (%s)" % (yade.config.version, yade.config.highPrecisionName),
          "runs": {}}
# The log (stdout) tells the host the build and the run in progress if YADE hangs or crashes.
print(status["engine_version"], flush=True)
for run in JOB["runs"]:
    print("RUN %s" % run["name"], flush=True)
    started = time.time()
    try:
        build(run)
        cols = run_steps(int(run["steps"]))
        rows = len(cols["time"])
        if O.iter != int(run["steps"]) or rows != int(run["steps"]):
            raise RuntimeError("stopped at iteration %d of %d with %d rows (the recorder missed iterations)" % (O.iter, run["steps"], rows))
        with open(run["out"], "w") as f:
            f.write("time,overlap,normal_velocity,normal_force\n")
            f.write("\n".join(map("%.17g,%.17g,%.17g,%.17g".__mod__,
                                   zip(cols["time"], cols["overlap"], cols["normal_velocity"], cols["normal_force"]))))
            f.write("\n")
        status["runs"][run["name"]] = {"ok": True, "seconds": time.time() - started}
    except Exception as err:  # report per run; the host fails that run with this log
        status["runs"][run["name"]] = {"ok": False, "error": "%s: %s" % (type(err).__name__, err)}
        print("RUN FAILED %s: %s" % (run["name"], err), flush=True)
with open(JOB["status"], "w") as f:
    json.dump(status, f, indent=1)
