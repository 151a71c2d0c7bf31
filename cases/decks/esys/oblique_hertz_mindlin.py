# ESyS-Particle 2.3.5 check deck: oblique collisions of two rotational spheres with the HertzMindlin
# interaction (friction, no damping), one row per step of each body's position, velocity and spin.
#
#   mpirun -np 2 esysparticle oblique_hertz_mindlin.py <job.json>      (one master, one worker)
#
# Runs under ESyS's own Python (esys.lsm and the standard library). Written for the tangential-defect
# checks (engines/esys_oblique.py, tests/test_engine_tangential_defects.py) and the study's oblique runs
# (engines/esys_oblique.py, run_esys_oblique_sweep): it records what the engine does, the host computes
# what that means (the study's 8 columns). Every number comes from the job file; every string in it is
# data (file names only). Optional numbers (the study's; the checks leave them out): y2, vx2, vy2 (body 2's
# start), w1 (body 1's spin about +z) and fixed2 (1: body 2 is non-dynamic, the plane's stand-in sphere).
#
# Contact: HertzMindlinPrms(name, youngsModulus=E, poissonsRatio=nu, dynamicMu=mu)
# (Model/HertzMindlinInteraction.cpp in the 2.3.5 source, danielfrascarelli/esys-particle@ced39b6):
#   F_n = 4/3 E sqrt(R*) delta^{3/2}            (E stands for E*: the host writes E*),
#   F_t += (16/3) E/(2(1 + nu)) sqrt(R* delta) ds, ds = (v2 - v1) dt, tangential part (no spin),
#   |F_t| <= mu F_n, both applied with CParticle::applyForce (no moment).
# The bodies are RotSpheres, so that a torque, if any were applied, would show in their spins.
#
# Geometry (the study's conventions, engines/oblique_run.py): body 1 at x1 < 0 moves +x (and +y),
# body 2 at x2 > 0 is at rest; the host offsets y1 so that the centres lie on the x axis when the
# spheres touch. Runs are placed on lines z = k PITCH (PITCH: three diameters of the largest sphere)
# so that no two runs' bodies meet; each run has its own interaction group, removed when it ends,
# after which its bodies are made non-dynamic.
#
# Time: ESyS integrates with symplectic Euler (Model/Particle.cpp, CParticle::integrate): the force of
# step n is computed from x_n and v_n, then v_{n+1} = v_n + F_n dt/m, x_{n+1} = x_n + v_{n+1} dt. Row n
# holds x_n, v_n and w_n before step n: F_n = m (v_{n+1} - v_n)/dt on the host.
import json
import sys
import time

from esys.lsm import HertzMindlinPrms, LsmMpi, RotSphere
from esys.lsm.util import BoundingBox, Vec3
import esys.lsm.util.InstallInfo as install_info

with open(sys.argv[1]) as f:
    JOB = json.load(f)
RUNS = JOB["runs"]
LARGEST = max(max(run["R1"], run["R2"]) for run in RUNS)
PITCH = 6.0 * LARGEST
COLUMNS = "x1,y1,x2,y2,vx1,vy1,vx2,vy2,wx1,wy1,wz1,wx2,wy2,wz2"


def simulation():
    smallest = min(min(run["R1"], run["R2"]) for run in RUNS)
    sim = LsmMpi(numWorkerProcesses=1, mpiDimList=[1, 1, 1])
    # ESyS's HertzMindlin loses its friction force m_Ffric when the neighbour list is rebuilt during the
    # contact (a body moved about a Verlet distance since the last build): the force restarts from 0
    # (measured: tests/test_engine_esys_oblique.py, docs/tangential.md). A study run gives its bodies'
    # largest travel over the run ("travel" [m]); the Verlet distance is then twice that, so that no
    # rebuild falls inside a contact and the contact law is what is measured. "verlet" [m] (a check's
    # knob) sets it outright.
    verlet, grid = 0.1 * smallest, 2.2 * LARGEST
    if any("travel" in run for run in RUNS):
        verlet = max(verlet, 2.0 * max(run.get("travel", 0.0) for run in RUNS))
        grid += verlet
    if any("verlet" in run for run in RUNS):
        verlet = min(run["verlet"] for run in RUNS if "verlet" in run)
    sim.initNeighbourSearch(particleType="RotSphere", gridSpacing=grid, verletDist=verlet)
    half = 4.0 * LARGEST
    sim.setSpatialDomain(BoundingBox(Vec3(-half, -half, -PITCH), Vec3(half, half, len(RUNS) * PITCH)))
    return sim


def run_one(sim, k, run):
    a, b = 2 * k, 2 * k + 1
    z = k * PITCH
    sim.setTimeStepSize(run["dt"])
    pa = RotSphere(id=a, posn=Vec3(run["x1"], run["y1"], z), radius=run["R1"], mass=run["m1"])
    pa.setLinearVelocity(Vec3(run["vx1"], run["vy1"], 0.0))
    pa.setAngularVelocity(Vec3(0.0, 0.0, run.get("w1", 0.0)))
    pa.setTag(2 * k + 1)
    pb = RotSphere(id=b, posn=Vec3(run["x2"], run.get("y2", 0.0), z), radius=run["R2"], mass=run["m2"])
    pb.setLinearVelocity(Vec3(run.get("vx2", 0.0), run.get("vy2", 0.0), 0.0))
    pb.setTag(2 * k + 2)
    sim.createParticle(pa)
    sim.createParticle(pb)
    if run.get("fixed2"):
        sim.setParticleNonDynamic(2 * k + 2)  # takes a tag: the plane's stand-in does not move
    group = "run%d" % k
    sim.createInteractionGroup(HertzMindlinPrms(name=group, youngsModulus=run["E"], poissonsRatio=run["nu"],
                                                dynamicMu=run["mu"]))
    rows = []
    try:
        for n in range(int(run["steps"]) + 1):
            ps = sim.getParticleList([a, b])
            p1, p2 = (ps[0], ps[1]) if ps[0].getId() == a else (ps[1], ps[0])
            x1, x2 = p1.getPosn(), p2.getPosn()
            v1, v2 = p1.getVelocity(), p2.getVelocity()
            w1, w2 = p1.getAngularVelocity(), p2.getAngularVelocity()
            rows.append(",".join("%.17g" % q for q in (x1[0], x1[1], x2[0], x2[1], v1[0], v1[1], v2[0], v2[1],
                                                       w1[0], w1[1], w1[2], w2[0], w2[1], w2[2])))
            if n < int(run["steps"]):
                sim.runTimeStep()
    finally:
        sim.removeInteractionGroup(group)
        sim.setParticleNonDynamic(2 * k + 1)
        sim.setParticleNonDynamic(2 * k + 2)
    with open(run["out"], "w") as f:
        f.write(COLUMNS + "\n" + "\n".join(rows) + "\n")


status = {"engine_version": "%s %s" % (install_info.pkgName, install_info.version), "runs": {}}
print(status["engine_version"], flush=True)
sim = simulation()
for k, run in enumerate(RUNS):
    print("RUN %s" % run["name"], flush=True)
    started = time.time()
    try:
        run_one(sim, k, run)
        status["runs"][run["name"]] = {"ok": True, "seconds": time.time() - started}
    except Exception as err:  # per run: the host fails that run, naming this error
        status["runs"][run["name"]] = {"ok": False, "error": "%s: %s" % (type(err).__name__, err)}
with open(JOB["status"], "w") as f:
    json.dump(status, f, indent=1)
sim.exit()
print("ESYS DONE", flush=True)
