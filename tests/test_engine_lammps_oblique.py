"""LAMMPS (GRANULAR) oblique impacts, run for real in both builds (29 Sep 2021, 22 Jul 2025):
friction off leaves the tangential motion alone; gross sliding of alumina on alumina meets the
rigid-body closed form over a ladder of time steps; one and two MPI ranks (the box split at the
contact) give the same dump; and k_t reaches omega_after of a sticking-dominated impact.

Measured here (both builds alike, sphere-plane, `mindlin`, 60 deg, V = 3.9 m/s, 0.07-0.11 s a collision
within a sweep): the rungs' dv_t and dw miss the closed form with eps_n = 1 by -1.7e-9 (T_e/250),
-1.5e-10, -1.4e-11, -1.0e-12 (T_e/2000), the orders of successive rung differences 3.5 and 3.4
(the normal restitution's own error, eps_n - 1, has the same rungs: the tangential impulse is
mu times the normal one to 5e-14 at every rung, and the wall's torque arm is R); extrapolated over
the four rungs (powers 3.5, 4.5, 5.5) both are within 2e-12. One and two ranks: every column
bitwise identical (largest difference 0) in both builds, for two spheres on different ranks.
k_t x (1 + 1e-4) moves omega_after at 10 deg by -1.0e-4 relative (omega_after ~ k_t there).
"""

import math

import numpy as np
import pytest

from contact_model import Body, ContactPair
from analysis.oblique import reference_of
from engines import RunSpec
from engines.ladder import extrapolate
from engines.lammps_oblique import run_lammps_oblique
from engines.oblique_run import ObliqueRun
from oblique_gate import LAMMPS_BUILDS, lammps_executable
from records.dump_file import read_dump
from records.oblique_metrics import oblique_metrics_of_dump

#: Alumina (the gross-sliding case): E, nu, rho, R, mu, V, incidence.
E, NU, RHO, R, MU, V, ANGLE = 380e9, 0.23, 4000.0, 2.5e-3, 0.092, 3.9, 60.0
LADDER = (250, 500, 1000, 2000)
#: The ladder's powers: the rungs' differences shrink as h^3.5 (measured, both builds).
POWERS = (3.5, 4.5, 5.5)
SPHERE = Body(R, RHO, E, NU)
PLANE = Body(math.inf, math.inf, E, NU)


def oblique(geometry, angle, factor=1000, ranks=1, mu=MU, model="lammps:mindlin", build="lammps-2021"):
    pair = ContactPair.from_bodies(SPHERE, PLANE if geometry == "sphere-plane" else SPHERE, 0.0)
    normal = RunSpec("alumina", "lammps", "elastic", pair, V * math.cos(math.radians(angle)),
                     time_step_factor=factor, build=build)
    return ObliqueRun(normal, model, mu, V * math.sin(math.radians(angle)), ranks=ranks)


def runs_of(build):
    ladder = [oblique("sphere-plane", ANGLE, f, build=build) for f in LADDER]
    ranks = [oblique(g, a, ranks=n, build=build) for g, a in (("sphere-plane", ANGLE), ("sphere-sphere", ANGLE),
                                                              ("sphere-sphere", 0.0)) for n in (1, 2)]
    frictionless = [oblique(g, 45.0, mu=0.0, build=build) for g in ("sphere-plane", "sphere-sphere")]
    sticking = [oblique("sphere-plane", 10.0, build=build)]
    return {r.name: r for r in ladder + ranks + frictionless + sticking}, ladder, ranks, frictionless, sticking


@pytest.fixture(scope="module", params=sorted(LAMMPS_BUILDS))
def sweep(request, tmp_path_factory, runs_engine):
    build = request.param
    exe = lammps_executable(build)
    runs, ladder, ranks, frictionless, sticking = runs_of(build)
    done = run_lammps_oblique(list(runs.values()), tmp_path_factory.mktemp(build), exe).raise_first()
    return {"build": build, "exe": exe, "dumps": done.dumps, "ladder": ladder, "ranks": ranks,
            "frictionless": frictionless, "sticking": sticking, "seconds": done.engine_seconds / len(runs)}


def test_frictionless_leaves_tangential_motion_alone(sweep):
    """mu = 0 at 45 deg: on the plane vt_after = v_t to round-off and no spin. Two spheres spin
    neither, but the line of centres turns by ~ v_t T / (R1 + R2) (-4.15e-3 rad here) while they
    slide past each other, so the normal force gets a y component: v_y1 - v_y2 gains 4.14e-3 and
    eps (lab x) is 0.99584, as the reference's planar motion has it (`reference.solve_oblique`):
    measured at T_e/1000 (both builds), vt_after -1.5e-9 V and eps -1.7e-8 from it."""
    for run in sweep["frictionless"]:
        m = oblique_metrics_of_dump(sweep["dumps"][run.name])
        assert m["omega_after"] == 0.0 and m["omega_2_after"] == 0.0
        if run.pair.body_2.is_plane:
            assert m["vt_after"] == pytest.approx(run.tangential_velocity, rel=1e-14, abs=0)
            assert m["Ft_max"] == 0.0
        else:
            ref = reference_of(run)
            assert m["vt_after"] / run.tangential_velocity - 1 == pytest.approx(4.14e-3, rel=0.01)
            assert abs(m["vt_after"] - ref["vt_after"]) < 1e-8 * V
            assert abs(m["eps_x0"] / ref["eps"] - 1) < 1e-7


def test_gross_sliding_meets_the_rigid_body_closed_form(sweep):
    """dv_t = -mu (1 + eps_n) v_n and dw = -(5/2) mu (1 + eps_n) v_n / R (elastic: eps_n = 1 as
    dt -> 0); the wall's torque arm is R in both builds (fix_wall_gran.cpp 2021; granular_model.cpp
    2025: scale3(radi, torquesi) for a wall), so nothing of the arm shows."""
    vn = V * math.cos(math.radians(ANGLE))
    dvt_exact, dw_exact = -MU * 2 * vn, -2.5 * MU * 2 * vn / R
    h, dvt, dw = [], [], []
    for run in sweep["ladder"]:
        m = oblique_metrics_of_dump(sweep["dumps"][run.name])
        assert m["vs_after"] > 0  # sliding to the end
        # The tangential impulse is mu times the normal one, step by step: exact at every rung.
        assert m["vt_after"] - m["vt_before"] == pytest.approx(-MU * (1 + m["eps_x0"]) * vn, rel=1e-12)
        assert m["omega_after"] == pytest.approx(-2.5 * MU * (1 + m["eps_x0"]) * vn / R, rel=1e-12)
        h.append(run.normal.time_step)
        dvt.append(m["vt_after"] - m["vt_before"])
        dw.append(m["omega_after"])
    for values, exact in ((dvt, dvt_exact), (dw, dw_exact)):
        errors = np.array(values) / exact - 1
        assert abs(errors[0]) < 5e-9 and abs(errors[-1]) < 5e-12
        steps = np.diff(values)
        orders = np.log2(np.abs(steps[:-1] / steps[1:]))
        assert np.all((orders > 3.2) & (orders < 3.8)), orders
        x = extrapolate(h, values, POWERS)
        assert abs(x.value / exact - 1) < 1e-11, (x.value / exact - 1, x.estimate)


def test_one_and_two_ranks_give_the_same_dump(sweep):
    """Two ranks, the box (symmetric about 0) split at the contact: two spheres split along x start
    on different ranks; the sphere on the plane (split along y) starts on rank 0 and ends on rank 1,
    having crossed y = 0 in the middle of the contact with the wall's history. Measured: every
    column bitwise identical in both builds."""
    runs = sweep["ranks"]
    for one, two in zip(runs[::2], runs[1::2]):
        meta_1, c1 = read_dump(sweep["dumps"][one.name], oblique=True)
        meta_2, c2 = read_dump(sweep["dumps"][two.name], oblique=True)
        if one.pair.geometry == "sphere-sphere":
            assert meta_2["owners"] == {"1": 0, "2": 1} and meta_1["owners"] == {"1": 0, "2": 0}
        else:
            assert meta_2["owners"] == {"1": 0} and meta_2["owners_end"] == {"1": 1}, meta_2["owners_end"]
            assert meta_1["owners_end"] == {"1": 0}
        for column in c1:
            scale = float(np.abs(c1[column]).max())
            assert np.max(np.abs(c1[column] - c2[column])) <= 1e-14 * scale, column


def test_tangential_stiffness_is_seen_in_omega_after(sweep, tmp_path):
    """k_t x (1 + 1e-4) in the generated deck moves omega_after of a 10 deg impact (sticking
    first, then micro-slip) by more than 1e-6 relative: a later gate at 1e-6 can see k_t."""
    (run,) = sweep["sticking"]
    base = oblique_metrics_of_dump(sweep["dumps"][run.name])
    stiffer = run_lammps_oblique([run], tmp_path, sweep["exe"], stiffness_factor=1 + 1e-4).raise_first()
    meta, _ = read_dump(stiffer.dumps[run.name], oblique=True)
    assert meta["tangential_stiffness"] == pytest.approx((1 + 1e-4) * 8 * shear_modulus_alumina(), rel=1e-15)
    changed = oblique_metrics_of_dump(stiffer.dumps[run.name])
    assert abs(changed["omega_after"] / base["omega_after"] - 1) > 1e-6


def shear_modulus_alumina() -> float:
    return 1.0 / (2 * 2 * (2 - NU) * (1 + NU) / E)
