# ESyS-Particle 2.3.5 driver: a sequence of head-on collisions in one ESyS process.
#
#   mpirun -np 2 esysparticle collisions.py <job.json>      (one master, one worker)
#
# Runs under ESyS's own Python (esysparticle): esys.lsm, the standard library and numpy only.
# The job file (written by engines/esys.py on the host) lists runs; every number in it comes
# from the host's contact model (contact_model.engine_parameters). For each run this script
# writes <out> (one row per step: time, overlap, d(overlap)/dt at full steps, normal force)
# and, at the end, <status> (JSON). It prints its version first and "RUN <name>" when a run
# starts, and writes the same line to <progress>, so that the host can name the run in
# progress if ESyS hangs or crashes (in the log, mpirun may splice a rank's stderr into it).
#
# One process, many runs: a second LsmMpi cannot be made after sim.exit() (the worker has
# left; the master waits for it forever), so the whole sweep shares one LsmMpi. The Hertzian
# interaction groups cannot be tagged (createInteractionGroupTagged takes only the linear and
# frictional groups), so every run has its own place instead: run k's bodies sit on the line
# y = k * PITCH (PITCH: three times the largest body radius of the sweep, so no two runs'
# bodies ever touch), with their own particle ids (2k, 2k+1) and tags (2k+1, 2k+2) and their
# own interaction group, created when the run starts and removed when it ends; then its
# particles are made non-dynamic (they stay where they are, touching nothing). The time step
# is set per run (LsmMpi.setTimeStepSize). A run that fails is cleaned up the same way: an
# interaction group left behind would act on every later run's bodies too.
#
# Contact laws (the host picks one per run):
#   viscoelastic_clipped  HertzianViscoElasticPrms(A, E, nu) (Model/HertzianViscoElasticInteraction.cpp):
#                         F = 2 E sqrt(R*) / (3 (1 - nu^2)) (delta^{3/2} + A delta^{1/2} d(delta)/dt),
#                         set to 0 where it is negative (ESyS clips: criterion F0 only).
#   elastic               the same with A = 0.
#   default               HertzMindlinViscoPrms(E, nu, mu, e) (Model/HertzMindlinViscoInteraction.cpp):
#                         F = 4/3 E sqrt(R*) delta^{3/2} - 2 sqrt(5/3) beta sqrt(M* E) R*^{1/4} delta^{1/4} v_n,
#                         beta = ln e / sqrt(ln^2 e + pi^2), not clipped (the tail is kept).
#
# Geometry: body A, a sphere at x1 < 0, moves +x; body B is a sphere at x2 > 0 moving -x, or
# the plane x = 0, represented by a non-dynamic sphere of radius R_wall centred at x = R_wall
# (ESyS has no Hertzian wall: its walls are linear springs). The host scales the modulus so
# that the force is exactly the plane's for this head-on impact (see engines/esys.py).
#
# Overlap: r1 + r2 - (x2 - x1), with ESyS's positions. The host starts the bodies half a step
# more than a whole number of steps apart (engines.ladder.START_PHASE, for every engine): a
# sample exactly at touching would carry a rounding-level overlap whose force (~delta^{3/2})
# changes no velocity by even one ulp.
#
# Time: ESyS integrates with symplectic Euler (Model/Particle.cpp, CParticle::integrate):
# F_n = F(x_n, v_n); v_{n+1} = v_n + F_n dt / m; x_{n+1} = x_n + v_{n+1} dt. So v_n is the
# velocity at t_n - dt/2 and the force of step n (taken from x_n) is recovered from the
# velocity jump (to the rounding of the velocities: 1e-10 of the force a step into contact), F_n = M* (w_n - w_{n+1}) / dt with w = d(overlap)/dt (M* = m1 m2 / (m1 + m2),
# m1 for the plane). Row n of the record: t_n = n dt, overlap x_n, the full-step rate
# (w_n + w_{n+1}) / 2 and F_n.
import json
import math
import sys
import time

from esys.lsm import HertzMindlinViscoPrms, HertzianViscoElasticPrms, LsmMpi, NRotSphere
from esys.lsm.util import BoundingBox, Vec3
import esys.lsm.util.InstallInfo as install_info

with open(sys.argv[1]) as f:
    JOB = json.load(f)
RUNS = JOB["runs"]


def radii(run):
    return [run["R1"], run["R2"] if run["geometry"] == "sphere-sphere" else run["R_wall"]]


LARGEST = max(max(radii(run)) for run in RUNS)
PITCH = 3.0 * LARGEST


def make_simulation():
    """One LsmMpi for the sweep: a neighbour grid wider than the largest body, a domain that
    holds every run's bodies (run k on the line y = k PITCH)."""
    smallest = min(min(radii(run)) for run in RUNS)
    sim = LsmMpi(numWorkerProcesses=1, mpiDimList=[1, 1, 1])
    sim.initNeighbourSearch(particleType="NRotSphere", gridSpacing=2.2 * LARGEST, verletDist=0.1 * smallest)
    half = 2.5 * LARGEST
    sim.setSpatialDomain(BoundingBox(Vec3(-half, -PITCH, -half), Vec3(half, len(RUNS) * PITCH, half)))
    return sim


def run_one(sim, k, run):
    a, b = 2 * k, 2 * k + 1
    tag_a, tag_b = 2 * k + 1, 2 * k + 2
    two = run["geometry"] == "sphere-sphere"
    sim.setTimeStepSize(run["dt"])
    y = k * PITCH
    pa = NRotSphere(id=a, posn=Vec3(run["x1"], y, 0.0), radius=run["R1"], mass=run["m1"])
    pa.setLinearVelocity(Vec3(run["v1"], 0.0, 0.0))
    pa.setTag(tag_a)
    sim.createParticle(pa)
    if two:
        pb = NRotSphere(id=b, posn=Vec3(run["x2"], y, 0.0), radius=run["R2"], mass=run["m2"])
        pb.setLinearVelocity(Vec3(run["v2"], 0.0, 0.0))
        R2 = run["R2"]
    else:
        pb = NRotSphere(id=b, posn=Vec3(run["R_wall"], y, 0.0), radius=run["R_wall"], mass=run["m_wall"])
        R2 = run["R_wall"]
    pb.setTag(tag_b)
    sim.createParticle(pb)
    if not two:
        sim.setParticleNonDynamic(tag_b)  # takes a tag, not an id
    group = "run%d" % k
    if "en" in run:  # its restitution keyword
        prms = HertzMindlinViscoPrms(name=group, youngsModulus=run["E"], poissonsRatio=0.0, dynamicMu=0.0,
                                     restitution=run["en"])
    else:
        prms = HertzianViscoElasticPrms(name=group, A=run["A"], E=run["E"], nu=0.0)
    sim.createInteractionGroup(prms)
    try:
        return record(sim, run, a, b, R2)
    finally:
        sim.removeInteractionGroup(group)
        sim.setParticleNonDynamic(tag_a)  # both bodies stop (else they fly on, out of the domain)
        if two:
            sim.setParticleNonDynamic(tag_b)


def record(sim, run, a, b, R2):
    """Run the collision of particles a and b (contact distance r1 + r2); its record's rows."""
    dt, steps = run["dt"], int(run["steps"])
    two = run["geometry"] == "sphere-sphere"
    M = 1.0 / (1.0 / run["m1"] + 1.0 / run["m2"]) if two else run["m1"]
    contact = run["R1"] + R2

    # One fetch of both bodies from the worker per step (an MPI round trip, about as long as
    # the step itself); the particles come back in no promised order.
    fetch, ids, step = sim.getParticleList, [a, b], sim.runTimeStep

    def overlap_and_rate():
        pa, pb = fetch(ids)
        if pa.getId() != a:
            pa, pb = pb, pa
        return contact - (pb.getPosn()[0] - pa.getPosn()[0]), pa.getVelocity()[0] - pb.getVelocity()[0]

    rows = []
    append = rows.append
    x, w = overlap_and_rate()
    for n in range(steps):
        step()
        x_next, w_next = overlap_and_rate()
        append("%.17g,%.17g,%.17g,%.17g" % (n * dt, x, 0.5 * (w + w_next), M * (w - w_next) / dt))
        x, w = x_next, w_next
    return rows


def write_rows(path, rows):
    with open(path, "w") as f:
        f.write("time,overlap,normal_velocity,normal_force\n")
        f.write("\n".join(rows) + "\n")


# The sweep (benchmarks/engine_overheads.py runs this file up to this line, for its functions).
status = {"engine_version": "%s %s" % (install_info.pkgName, install_info.version), "runs": {}}
print(status["engine_version"], flush=True)
sim = make_simulation()
progress = open(JOB["progress"], "a")
for k, run in enumerate(RUNS):
    progress.write("RUN %s\n" % run["name"])
    progress.flush()
    print("RUN %s" % run["name"], flush=True)
    started = time.time()
    try:
        write_rows(run["out"], run_one(sim, k, run))
        status["runs"][run["name"]] = {"ok": True, "seconds": time.time() - started}
    except Exception as err:  # report per run; the host fails that run with this log
        status["runs"][run["name"]] = {"ok": False, "error": "%s: %s" % (type(err).__name__, err)}
        print("RUN FAILED %s: %s" % (run["name"], err), flush=True)
        progress.write("RUN FAILED %s: %s\n" % (run["name"], str(err).replace("\n", " ")))
        progress.flush()
with open(JOB["status"], "w") as f:
    json.dump(status, f, indent=1)
sim.exit()
print("ESYS DONE", flush=True)
