# YADE driver of oblique collisions (2023.02a and 2025.2.0): Hertz-Mindlin with its tangential law.
#
#   yade -n -x oblique.py job=<job.json>
#
# Runs under YADE's own Python: yade, the standard library and nothing else. The job file (written by
# engines/yade_oblique.py on the host) lists runs; every number in it comes from the host. For each run
# this script writes <out> (one row per step, the 8 columns of records.dump_file.OBLIQUE_COLUMNS, %.17g)
# and, at the end, <status> (JSON). It prints its build first and "RUN <name>" when a run starts.
#
# Conventions (engines/oblique_run.py): normal +x from body 1 (the sphere at x1 < 0, moving +x) to
# body 2 (a sphere at x2 > 0, or the plane x = 0), tangential +y, spins about +z.
#
# Contact: Ip2_FrictMat_FrictMat_MindlinPhys + Law2_ScGeom_MindlinPhys_Mindlin, each body's FrictMat
# with its own Young's modulus and Poisson's ratio and frictionAngle = atan(mu) (YADE takes
# tan(min(angle_1, angle_2))). Its stiffnesses (HertzMindlin.cpp, Ip2_..._MindlinPhys::go):
#   k_no = 4/3 E* sqrt(R*), E* = E1 E2 / ((1 - nu1^2) E2 + (1 - nu2^2) E1): the study's E*;
#   k_so = 2 sqrt(4 R*) G / (2 - nu), G = (G1 + G2)/2, nu = (nu1 + nu2)/2, k_s = k_so sqrt(delta):
#   Mindlin's 8 G* sqrt(R* delta) for two bodies of one material (G* = G / (2 (2 - nu))); for two
#   materials YADE averages G and nu, which is not Mindlin's G* (a YADE specific, not corrected here).
# Normal law: `elastic` only (betan = 0: no normal damping). The study's viscoelastic force is, in
# YADE 2023, a Python force added beside Law2 (collisions.py), which Law2's Coulomb limit
# mu |normalForce| does not see (it would cap at mu F_el, not mu (F_el + F_d)); YADE 2025's own
# Brilliantov damping (MindlinPhys.beta) clips the total force at zero. Neither is the study's
# viscoelastic oblique contact, so a non-elastic run is refused.
# Tangential damping: betas = the run's damping ratio (YADE's fraction of the critical 2 sqrt(m ks));
# 0 (no damping) unless the run asks for it.
#
# The plane: a Wall at x = 0 with Ig2_Wall_Sphere_ScGeom(hertzian=True). Without hertzian YADE gives
# the wall the sphere's radius (refR1 = R), so Hertz-Mindlin takes R* = R/2 for a sphere-wall
# contact (measured: k_no and k_so both give R*/R = 0.5 in 2023.02a and 2025.2.0); with it the wall's
# radius is 1e8 R and R* = R (1 - 1e-8) (measured: 0.99999999).
#
# Lever arm: Law2 applies the contact force at ScGeom.contactPoint. For the wall that is the sphere's
# centre projected onto the wall, an arm R - delta; for two spheres the middle of the overlap,
# R_i - delta/2. The spin change therefore differs from a lever arm R by the overlap (relative
# ~delta/R): measured on the plane, -2.0e-3 for alumina at 60 deg, the arm R - delta to 4e-12
# (tests/test_engine_yade_oblique.py). The slip velocity's arm (ScGeom::getIncidentVel: R_i with the
# ratcheting correction, the default) matters only while the contact sticks; not measured here.
#
# Two spheres: the centres start offset in y (the host's y1, y2) so that they lie on the x axis when
# the spheres touch (engines/oblique_run.py, ObliqueRun.initial_positions); the contact normal then
# turns with the centres' relative motion (by ~ v_t T / (R1 + R2)), as the reference's does. The columns
# are the lab frame's x and y components (the
# conventions' normal +x and tangent +y), the overlap YADE's own R1 + R2 - |x2 - x1|.
#
# Time: YADE's leapfrog keeps velocities at half steps. At the recorder after the InteractionLoop of
# iteration k, positions and forces are at t_k = k dt and velocities at t_k - dt/2: the record carries
# the full-step velocities v(t_k) = v(t_k - dt/2) + a_k dt/2 (and w likewise, with the torque over
# the sphere's inertia 2/5 m R^2).
#
# Speed: as collisions.py, the script sub-steps the scene itself (O.subStepping) and records between
# the InteractionLoop and the NewtonIntegrator; it stores floats and formats the rows once at the end.
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
ENGINES = ["ForceResetter", "InsertionSortCollider", "InteractionLoop", "NewtonIntegrator"]


def build(run):
    if run["law"] != "elastic":
        raise ValueError("law %r: YADE's oblique deck runs the elastic normal law only (see oblique.py)"
                         % run["law"])
    O.reset()
    angle = math.atan(run["friction"])
    mat1 = O.materials.append(FrictMat(young=run["young1"], poisson=run["poisson1"], density=run["rho1"],
                                       frictionAngle=angle))
    mat2 = O.materials.append(FrictMat(young=run["young2"], poisson=run["poisson2"],
                                       density=run.get("rho2", run["rho1"]), frictionAngle=angle))
    two = run["geometry"] == "sphere-sphere"
    a = O.bodies.append(utils.sphere((run["x1"], run["y1"], 0), run["R1"], material=mat1))
    O.bodies[a].state.vel = (run["v1"], run["vy1"], 0)
    O.bodies[a].state.angVel = (0, 0, run["w1"])
    if two:
        b = O.bodies.append(utils.sphere((run["x2"], run["y2"], 0), run["R2"], material=mat2))
        O.bodies[b].state.vel = (run["v2"], run["vy2"], 0)
        O.bodies[b].state.angVel = (0, 0, run["w2"])
    else:
        b = O.bodies.append(utils.wall(0.0, axis=0, sense=-1, material=mat2))
    if run["betas"]:
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(betan=MatchMaker(algo="val", val=0.0),
                                                betas=MatchMaker(algo="val", val=run["betas"]))
    else:
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys()  # betan, betas unset: 0, no damping
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
        InteractionLoop(
            # hertzian: R* = R. "wall_hertzian": false is a check's knob (engines/yade_oblique.py), YADE's
            # default wall, R* = R/2; a study run never sets it.
            [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(hertzian=run.get("wall_hertzian", True))],
            [ip2],
            [Law2_ScGeom_MindlinPhys_Mindlin(neverErase="kso_scale" in run)]),
        NewtonIntegrator(damping=0.0, gravity=(0, 0, 0)),  # YADE's default damping is 0.2
    ]
    O.dt = run["dt"]
    if "kso_scale" in run:
        # A check's knob (engines/yade_oblique.py, stiffness_scale): the contact is created now, before
        # the bodies touch (neverErase keeps it through the approach, where Law2 gives no force), so that
        # its k_so, scaled here, holds from the first step of contact.
        i = utils.createInteraction(a, b)
        i.phys.kso = i.phys.kso * run["kso_scale"]
    S.clear()
    S.update(run=run, a=a, b=b, two=two)


def run_steps(steps):
    """Run `steps` iterations, the recorder after the InteractionLoop of each; {column: floats}."""
    run, a, b, two = S["run"], S["a"], S["b"], S["two"]
    A = O.bodies[a].state
    B = O.bodies[b].state if two else None
    R1 = run["R1"]
    R12 = run["R1"] + run["R2"] if two else None
    dt = O.dt
    half_dt = 0.5 * dt
    m1 = A.mass
    m2 = B.mass if two else None
    inv_m = 1.0 / m1 + (1.0 / m2 if two else 0.0)  # relative acceleration per unit force on body 1
    I1 = A.inertia[2]
    I2 = B.inertia[2] if two else None
    forces = O.forces
    f, t = forces.f, forces.t
    sqrt = math.sqrt
    step = O.step
    cols = {k: [] for k in ("overlap", "normal_velocity", "normal_force", "tangential_velocity", "omega_1",
                            "omega_2", "tangential_force")}
    put = [cols[k].append for k in ("overlap", "normal_velocity", "normal_force", "tangential_velocity",
                                    "omega_1", "omega_2", "tangential_force")]
    p_overlap, p_rate, p_fn, p_vt, p_w1, p_w2, p_ft = put
    if O.iter != 0:
        raise RuntimeError("the scene starts at iteration %d, not 0" % O.iter)
    if [type(e).__name__ for e in O.engines] != ENGINES:
        raise RuntimeError("the sub-steps below are build()'s four engines, not %s" % O.engines)
    O.subStepping = True
    try:
        for _ in range(steps):
            step()  # the prologue
            step()  # ForceResetter
            step()  # the collider
            step()  # the InteractionLoop
            pa, va, wa = A.pos, A.vel, A.angVel
            fa = f(a)
            if two:
                pb, vb = B.pos, B.vel
                dx, dy, dz = pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]
                overlap = R12 - sqrt(dx * dx + dy * dy + dz * dz)
                rate_half = va[0] - vb[0]
                vt_half = va[1] - vb[1]
                p_w2(B.angVel[2] + t(b)[2] * half_dt / I2)
            else:
                overlap = R1 + pa[0]
                rate_half = va[0]
                vt_half = va[1]
                p_w2(0.0)
            fx, fy = fa[0], fa[1]
            p_overlap(overlap)
            p_rate(rate_half + fx * half_dt * inv_m)  # fx on body 1 is -(the normal force)
            p_fn(-fx)
            p_vt(vt_half + fy * half_dt * inv_m)
            p_w1(wa[2] + t(a)[2] * half_dt / I1)
            p_ft(fy)
            step()  # the NewtonIntegrator
            step()  # the epilogue: O.iter + 1
    finally:
        O.subStepping = False
    # k dt, not O.time (a running sum that drifts from k dt by rounding)
    cols["time"] = [k * dt for k in range(len(cols["overlap"]))]
    return cols


COLUMNS = ("time", "overlap", "normal_velocity", "normal_force", "tangential_velocity", "omega_1", "omega_2",
           "tangential_force")
status = {"engine_version": "YADE %s (%s)" % (yade.config.version, yade.config.highPrecisionName), "runs": {}}
print(status["engine_version"], flush=True)
for run in JOB["runs"]:
    print("RUN %s" % run["name"], flush=True)
    started = time.time()
    try:
        build(run)
        cols = run_steps(int(run["steps"]))
        rows = len(cols["time"])
        if O.iter != int(run["steps"]) or rows != int(run["steps"]):
            raise RuntimeError("stopped at iteration %d of %d with %d rows" % (O.iter, run["steps"], rows))
        with open(run["out"], "w") as out:
            out.write(",".join(COLUMNS) + "\n")
            row = ",".join(["%.17g"] * len(COLUMNS))
            out.write("\n".join(map(row.__mod__, zip(*(cols[c] for c in COLUMNS)))))
            out.write("\n")
        status["runs"][run["name"]] = {"ok": True, "seconds": time.time() - started}
    except Exception as err:  # report per run; the host fails that run with this log
        status["runs"][run["name"]] = {"ok": False, "error": "%s: %s" % (type(err).__name__, err)}
        print("RUN FAILED %s: %s" % (run["name"], err), flush=True)
with open(JOB["status"], "w") as f:
    json.dump(status, f, indent=1)
