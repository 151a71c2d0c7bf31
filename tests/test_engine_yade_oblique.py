"""YADE's oblique impacts, run for real in both builds (2023.02a, 2025.2.0): Hertz-Mindlin's tangential
law against the closed forms of a frictionless and a grossly sliding impact, and a check that the
deck's tangential stiffness reaches the result. All runs of a build share one YADE process.

Measured here (both builds give the same doubles):
- frictionless, 60 deg: the plane keeps v_t exactly and omega = 0; two spheres keep omega_1 = omega_2 = 0
  to round-off (1e-17 rad/s), and their v_y1 - v_y2 and eps (lab frame) are the reference's planar
  motion's (the line of centres turns: `SPHERES_TURN`).
- gross sliding, alumina on alumina at 60 deg: dv_t = -mu (1 + eps_n) v_n to 2e-14 at every rung;
  the spin's lever arm is R - delta (the wall's contact point is the centre projected on the wall), so
  dw is (5/2) mu (1 + eps_n) v_n / R times 1 - (1/2) B(7/5, 1/2) delta_max / R: -2.0048e-3 against the
  arm R. Over the ladder (dt = T_e/250 ... T_e/2000, orders 3.4 for dv_t and eps_n, 2.0 for dw) the
  limits meet the closed forms to 4e-13 (dv_t, eps_n = 1) and 3.6e-12 (dw with the arm R - delta).
- 10 deg, k_so x (1 + 1e-4): omega_after moves by -9.9e-5 relative (the contact sticks in part).
- a collision costs 6-38 ms (363-2 550 steps, ~14 us a step) in either build, after YADE's ~1.5 s start.
"""

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.special import beta as beta_function

from analysis.oblique import reference_of
from contact_model import Body, ContactPair
from engine_cases import missing
from engines import RunSpec
from engines.ladder import ELASTIC_POWERS, extrapolate
from engines.oblique_run import ObliqueRun
from engines.yade_oblique import run_yade_oblique
from records.dump_file import read_dump

ROOT = Path(__file__).resolve().parents[1]
BUILDS = ("yade-2023", "yade-2025")
VERSION = {"yade-2023": "YADE 2023.02a", "yade-2025": "YADE 2025.2.0"}
#: Alumina on alumina (the issue's gross-sliding case).
RADIUS, DENSITY, YOUNG, POISSON, FRICTION, SPEED = 2.5e-3, 4000.0, 380e9, 0.23, 0.092, 3.9
LADDER = (250, 500, 1000, 2000)
#: Two frictionless spheres at 60 deg: the line of centres turns during the contact (the centres aligned
#: at touching), so the normal force gets a y component; the reference follows the planar motion
#: (`reference.solve_oblique`) and the dump's v_y1 - v_y2 [V] and eps meet it to this at dt = T_e/1000.
SPHERES_TURN = 1e-8
ROUNDOFF = 1e-12


def executable(build_id: str) -> str:
    from engines.builds import load_builds
    from engines.codes import CODES

    import shutil

    builds = load_builds(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"], ROOT)
    build = next(b for b in builds if b.id == build_id)
    if shutil.which(build.executable) is None:
        missing(f"{build.executable} ({build_id}) is not installed; {CODES['yade'].install_hint}")
    return build.executable


def alumina_pair(geometry: str) -> ContactPair:
    sphere = Body(RADIUS, DENSITY, YOUNG, POISSON)
    other = sphere if geometry == "sphere-sphere" else Body(math.inf, math.inf, YOUNG, POISSON)
    return ContactPair.from_bodies(sphere, other, 0.0)


def oblique(build: str, geometry: str, angle_deg: float, friction: float, factor: float = 1000) -> ObliqueRun:
    a = math.radians(angle_deg)
    normal = RunSpec("alumina", "yade", "elastic", alumina_pair(geometry), SPEED * math.cos(a),
                     time_step_factor=factor, build=build)
    return ObliqueRun(normal, "yade:mindlin", friction, SPEED * math.sin(a))


def tangential_change(path) -> dict:
    """What an oblique dump says of its collision: the normal restitution and the changes of the
    tangential velocity and the spins, from the first sample (before contact) to the last (after)."""
    meta, c = read_dump(path, oblique=True)
    vn, vt, w1, w2 = c["normal_velocity"], c["tangential_velocity"], c["omega_1"], c["omega_2"]
    assert c["overlap"][0] < 0 and c["overlap"][-1] < 0  # free flight at both ends
    return {"meta": meta, "eps_n": -vn[-1] / vn[0], "vt_before": vt[0], "vt_after": vt[-1], "dvt": vt[-1] - vt[0],
            "w1_after": w1[-1], "w2_after": w2[-1], "dw1": w1[-1] - w1[0], "columns": c}


@pytest.fixture(scope="module", params=BUILDS)
def sweep(request, tmp_path_factory, runs_engine):
    build = request.param
    exe = executable(build)
    runs = {("frictionless", g): oblique(build, g, 60.0, 0.0) for g in ("sphere-plane", "sphere-sphere")}
    runs.update({("sliding", f): oblique(build, "sphere-plane", 60.0, FRICTION, f) for f in LADDER})
    workdir = tmp_path_factory.mktemp(f"{build}-oblique")
    out = run_yade_oblique(list(runs.values()), workdir / "main", exe).raise_first()
    ten = oblique(build, "sphere-plane", 10.0, FRICTION)
    scaled = {s: run_yade_oblique([ten], workdir / f"scale{s}", exe, stiffness_scale=s).raise_first()
              for s in (1.0, 1.0 + 1e-4)}
    result = {k: tangential_change(out.dumps[r.name]) for k, r in runs.items()}
    result.update({("ks", s): tangential_change(sw.dumps[ten.name]) for s, sw in scaled.items()})
    result.update({("ks", None): tangential_change(run_yade_oblique([ten], workdir / "ten", exe)
                                                   .raise_first().dumps[ten.name])})
    return build, runs, result


def test_dumps_name_the_build_and_the_run(sweep):
    build, runs, result = sweep
    meta = result[("sliding", 1000)]["meta"]
    assert meta["engine"] == "yade" and meta["engine_version"].startswith(VERSION[build])
    assert meta["deck"] == "oblique.py" and len(meta["deck_sha256"]) == 64
    assert meta["friction"] == FRICTION and meta["tangential_model"] == "yade:mindlin"
    assert meta["angle"] == pytest.approx(60.0)
    assert list(result[("sliding", 1000)]["columns"]) == ["time", "overlap", "normal_velocity", "normal_force",
                                                         "tangential_velocity", "omega_1", "omega_2",
                                                         "tangential_force"]


@pytest.mark.parametrize("geometry", ("sphere-plane", "sphere-sphere"))
def test_frictionless_impact_keeps_the_tangential_velocity_and_no_spin(sweep, geometry):
    _, runs, result = sweep
    r = result[("frictionless", geometry)]
    v_t = runs[("frictionless", geometry)].tangential_velocity
    assert r["vt_before"] == pytest.approx(v_t, rel=ROUNDOFF)
    spin_roundoff = ROUNDOFF * v_t / RADIUS  # the torque of a force along the normal, in rounding
    assert abs(r["w1_after"]) < spin_roundoff and abs(r["w2_after"]) < spin_roundoff
    if geometry == "sphere-plane":  # two spheres: the normal force has a y component as the normal turns
        assert np.all(r["columns"]["tangential_force"] == 0.0)
        assert abs(r["vt_after"] / v_t - 1) < ROUNDOFF, r["vt_after"] / v_t - 1
        return
    ref = reference_of(runs[("frictionless", geometry)])
    assert r["vt_after"] / v_t - 1 > 1e-3  # deflected by the turn of the line of centres
    assert abs(r["vt_after"] - ref["vt_after"]) < SPHERES_TURN * SPEED, (r["vt_after"] - ref["vt_after"]) / SPEED
    assert abs(r["eps_n"] / ref["eps"] - 1) < 10 * SPHERES_TURN, r["eps_n"] / ref["eps"] - 1


def test_gross_sliding_meets_coulomb_at_every_rung_and_in_the_limit(sweep):
    """dv_t = -mu (1 + eps_n) v_n: to round-off at each rung with the rung's own eps_n (the Coulomb
    limit holds at every step of the contact), and in the limit dt -> 0 with eps_n = 1."""
    _, runs, result = sweep
    v_n = runs[("sliding", 1000)].normal.velocity
    for f in LADDER:
        r = result[("sliding", f)]
        assert abs(r["dvt"] / (-FRICTION * (1 + r["eps_n"]) * v_n) - 1) < 1e-12, f
    h = [1.0 / f for f in LADDER]
    dvt = extrapolate(h, [result[("sliding", f)]["dvt"] for f in LADDER], ELASTIC_POWERS)
    assert abs(dvt.value / (-2 * FRICTION * v_n) - 1) < 1e-9, dvt


def test_gross_sliding_spin_has_the_lever_arm_r_minus_the_overlap(sweep):
    """dw = -(5/2) mu (1 + eps_n) v_n / R with YADE's lever arm R - delta, weighted by the force over the
    contact: (1/2) B(7/5, 1/2) delta_max (Hertz), 2.0e-3 R here. Measured on the ladder (dt -> 0)."""
    _, runs, result = sweep
    run = runs[("sliding", 1000)]
    v_n = run.normal.velocity
    delta_max = run.normal.scales["delta_e"]  # Hertz's maximal overlap (x_max = 1 at K = 0)
    arm = 1 - 0.5 * beta_function(1.4, 0.5) * delta_max / RADIUS
    h = [1.0 / f for f in LADDER]
    dw = extrapolate(h, [result[("sliding", f)]["dw1"] for f in LADDER], ELASTIC_POWERS)
    with_arm_r = -2.5 * FRICTION * 2 * v_n / RADIUS
    assert abs(dw.value / (with_arm_r * arm) - 1) < 1e-9, (dw, dw.value / (with_arm_r * arm) - 1)  # 3.6e-12
    assert dw.value / with_arm_r - 1 == pytest.approx(-2.0e-3, abs=0.05e-3)


def test_tangential_stiffness_reaches_the_spin_at_10_degrees(sweep):
    _, _, result = sweep
    own, unscaled, scaled = (result[("ks", s)]["w1_after"] for s in (None, 1.0, 1.0 + 1e-4))
    assert unscaled == pytest.approx(own, rel=1e-12)  # creating the contact early changes nothing
    assert abs(scaled / unscaled - 1) > 1e-6, scaled / unscaled - 1


def test_a_viscoelastic_oblique_run_is_refused_naming_the_law(sweep, tmp_path):
    """The deck runs the elastic normal law only (Law2's Coulomb limit would not see the study's
    dissipative force): a viscoelastic run fails, and says why."""
    build, runs, _ = sweep
    normal = runs[("sliding", 1000)].normal
    damped = ContactPair(normal.pair.geometry, normal.pair.body_1, normal.pair.body_2, normal.pair.E, 1e3)
    run = ObliqueRun(RunSpec("alumina", "yade", "viscoelastic", damped, normal.velocity, build=build),
                     "yade:mindlin", FRICTION, 1.0)
    failed = run_yade_oblique([run], tmp_path, executable(build))
    assert "elastic normal law only" in failed.failures[run.name].problem
