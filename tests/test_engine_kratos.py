"""Kratos DEM 10.4 (the PyPI wheels in .venv-kratos, `make kratos-10.4`), run for real.

- 'elastic' (DEM_D_Hertz_viscous_Coulomb with restitution 1: gamma = 0) against the reference
  solver's Hertz collision in both geometries: measured T -5.1e-7, A +4.6e-7, eps -6e-11 at
  dt = T_e / 1000 (the time-step error of the symplectic Euler scheme, ~ (dt/T)^2); asserted
  within 2e-6 (eps 1e-8), and the recorded force equals (4/3) E* sqrt(R*) delta^{3/2} of the
  same row to round-off, which checks the force/position re-pairing and Y = 2E*, nu = 0.
- 'default' (the same law with the matched restitution e): eps_F0 equals the restitution of the
  law's own equation of motion with the gamma Kratos derives from e (Thornton's fit), solved here
  with scipy (measured 1.2e-5 at e = 0.905; asserted 5e-5), and e itself to within that fit's
  accuracy (the fit is off by -1.0e-4 at e = 0.905, -1.9e-3 at 0.95, -1.1e-2 at 0.99; asserted 3e-4
  at the study's e = 0.905), independent of the impact velocity (Hertz with delta^{1/4} damping
  restitutes the same at any velocity), the force never negative (the law clips it).
- the missing venv, a run that fails inside Kratos, laws Kratos cannot express.
The hung and crashed Kratos process are in test_engine_stops.py. All runs of the sweep fixture
share one Kratos process, as the study does.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from engine_cases import VELOCITY, VERSIONS, dump_metrics, relative_errors, steel_pair
from engines import EngineMissing, RunSpec, kratos
from engines.builds import Build, BuildError, check_build
from records.dump_file import read_dump
from reference import solve_collision

GEOMETRIES = ("sphere-sphere", "sphere-plane")
KRATOS = Path(kratos.EXECUTABLE)
#: Elastic runs: the scheme's time-step error at dt = T_e / 1000 (measured 5e-7).
ELASTIC_TOLERANCE = 2e-6
#: Default law: eps_F0 against the restitution asked for, absolute (Thornton's fit; measured 8.9e-5).
THORNTON_FIT = 3e-4


def require_kratos():
    if not KRATOS.exists():
        pytest.skip(f"Kratos is not installed ({KRATOS} is missing); install it with: make kratos-10.4 "
                    "(make test does this)")


@pytest.fixture(autouse=True)
def _needs_kratos(runs_engine):
    require_kratos()


@pytest.fixture(scope="module")
def sweep(tmp_path_factory, runs_engine):
    require_kratos()
    eps = solve_collision(0.1)["eps_F0"]
    specs = [RunSpec("steel", "kratos", "elastic", steel_pair(g), VELOCITY) for g in GEOMETRIES]
    specs += [RunSpec("steel", "kratos", "default", steel_pair(g), v, matched_restitution=eps)
              for g in GEOMETRIES for v in (VELOCITY, 0.01 * VELOCITY)]
    result = kratos.run_kratos(specs, tmp_path_factory.mktemp("kratos")).raise_first()
    return {(s.law, s.pair.geometry, s.velocity): (s, result.dumps[s.name], *dump_metrics(result.dumps[s.name]))
            for s in specs}


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_elastic_contact_is_hertz(sweep, geometry):
    spec, _, meta, m = sweep[("elastic", geometry, VELOCITY)]
    assert meta["engine"] == "kratos" and meta["engine_version"].startswith(VERSIONS["kratos-10.4"])  # + kernel
    assert len(meta["deck_sha256"]) == 64 and meta["represents"] == ["x0"]
    assert meta["engine_variables"]["restitution"] == 1.0 and meta["engine_variables"]["poisson"] == 0.0
    assert m.samples_in_contact >= 900  # T_e / dt = 1000 steps, tau = 2.94 delta_e / V
    errors = relative_errors(m, spec)
    assert abs(errors["eps_x0"]) < 1e-8, errors
    for q in ("A", "T_x0"):
        assert abs(errors[q]) < ELASTIC_TOLERANCE, (q, errors[q])


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_recorded_force_is_hertz_of_the_same_row(sweep, geometry):
    """Row n pairs x_n with the force Kratos computed from x_n (the symplectic Euler record is
    re-paired): F_n = (4/3) E* sqrt(R*) delta_n^{3/2} to 1e-12 wherever delta_n > 1e-3 delta_e;
    one row of misalignment would be off by ~3 dt/T ~ 3e-3 at mid-contact."""
    spec, dump, _, _ = sweep[("elastic", geometry, VELOCITY)]
    _, c = read_dump(dump)
    p = spec.pair
    touching = c["overlap"] > 1e-3 * spec.scales["delta_e"]
    assert touching.sum() > 900
    hertz = 4 / 3 * p.E * math.sqrt(p.R) * c["overlap"][touching] ** 1.5
    np.testing.assert_allclose(c["normal_force"][touching], hertz, rtol=1e-12)
    assert np.all(c["normal_force"][c["overlap"] < 0] == 0)  # free flight: no force


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_default_law_restitutes_what_the_user_asked_at_every_velocity(sweep, geometry):
    """DEM_D_Hertz_viscous_Coulomb with e: eps_F0 = e to Thornton's fit (3e-4) at both velocities,
    equal at both to 1e-6, while the viscoelastic eps moves from 0.905 (K = 0.1) to 0.96 (K = 0.04)."""
    asked = solve_collision(0.1)["eps_F0"]
    fast_spec, fast_dump, meta, fast = sweep[("default", geometry, VELOCITY)]
    slow = sweep[("default", geometry, 0.01 * VELOCITY)][3]
    assert meta["represents"] == ["F0"] and meta["engine_variables"]["restitution"] == asked
    assert fast.eps_F0 == pytest.approx(asked, abs=THORNTON_FIT)
    assert slow.eps_F0 == pytest.approx(fast.eps_F0, abs=1e-6)
    assert solve_collision(0.1 * 0.01 ** 0.2)["eps_F0"] - slow.eps_F0 > 0.05
    _, c = read_dump(fast_dump)
    assert c["normal_force"].min() == 0.0 and np.sum(c["normal_force"] > 0) > 900  # clipped at zero, never attractive


def thornton_gamma(e: float) -> float:
    """The damping ratio gamma Kratos sets for restitution e: Thornton, Cummins & Cleary's fit
    (Powder Technol. 233 (2013) 30-46), gamma = sqrt(1 / (1 - (1 + e)^2 exp(alpha(e))) - 1), alpha a
    degree-10 polynomial in e (Kratos: sphere_strategy.py, GammaForHertzThornton; YADE's Ip2 en uses
    the same fit); 0 above e = 0.999."""
    if e > 0.999:
        return 0.0
    h = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757, -1489.915)
    alpha = 0.0
    for c in reversed(h):
        alpha = e * (c + alpha)
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(alpha)) - 1.0)


def law_restitution(gamma: float) -> float:
    """eps_F0 of DEM_D_Hertz_viscous_Coulomb with damping ratio gamma: M* x'' = -(4/3) E* sqrt(R*) x^{3/2}
    - 2 gamma sqrt(M* kn) x', kn = 2 E* sqrt(R* x), until the force vanishes. In units where M* = 1 and
    (4/3) E* sqrt(R*) = 1 (eps depends on gamma alone): x'' = -x^{3/2} - 2 gamma sqrt(3/2) x^{1/4} x',
    x(0) = 0, x'(0) = 1; eps = -x'(t_F0)."""
    c = 2.0 * gamma * math.sqrt(1.5)

    def force(x, v):
        return x**1.5 + c * x**0.25 * v if x > 0 else 0.0

    def vanishes(t, y):
        return force(*y) if t > 1e-3 else 1.0
    vanishes.terminal, vanishes.direction = True, -1
    sol = solve_ivp(lambda t, y: [y[1], -force(*y)], (0.0, 20.0), [0.0, 1.0], events=vanishes,
                    rtol=1e-12, atol=1e-14, max_step=1e-3, first_step=1e-6)
    return -float(sol.y_events[0][0][1])


def test_law_restitution_solver_is_hertz_at_gamma_zero():
    assert law_restitution(0.0) == pytest.approx(1.0, abs=1e-9)
    assert thornton_gamma(1.0) == 0.0


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_default_law_is_kratos_law_with_thornton_gamma(sweep, geometry):
    """Kratos restitutes what its law's equation gives with gamma = Thornton's fit of e (5e-5; measured
    1.2e-5, the scheme's first-order error of the lagged damping velocity), which is e to the fit's
    -1.0e-4 here."""
    asked = solve_collision(0.1)["eps_F0"]
    m = sweep[("default", geometry, VELOCITY)][3]
    expected = law_restitution(thornton_gamma(asked))
    assert expected == pytest.approx(asked - 1.0e-4, abs=1e-5)  # the fit's own error at e = 0.905
    assert m.eps_F0 == pytest.approx(expected, abs=5e-5)


def test_both_geometries_give_the_same_dimensionless_collision(sweep):
    """Same K (0 or the case's), same law: the plane (a RigidFace3D3N triangle) and the second sphere
    give the same T / T_e, A / A_e and eps (to 1e-9): the plane is an exact R* = R, M* = m contact."""
    for law, v in (("elastic", VELOCITY), ("default", VELOCITY)):
        scaled = []
        for g in GEOMETRIES:
            spec, _, _, m = sweep[(law, g, v)]
            s = spec.scales
            scaled.append(np.array([m.T_F0 * v / s["delta_e"], m.delta_max / s["delta_e"], m.eps_F0]))
        np.testing.assert_allclose(scaled[0], scaled[1], rtol=1e-9)


def test_laws_kratos_cannot_express_are_refused_before_it_starts(tmp_path):
    spec = RunSpec("steel", "kratos", "viscoelastic", steel_pair("sphere-plane"), VELOCITY)
    with pytest.raises(ValueError, match="kratos cannot run law 'viscoelastic'"):
        kratos.run_kratos([spec], tmp_path)
    assert not (tmp_path / "kratos.log").exists()


def test_missing_venv_names_the_make_target(tmp_path):
    spec = RunSpec("steel", "kratos", "elastic", steel_pair("sphere-plane"), VELOCITY)
    with pytest.raises(EngineMissing, match=r"make kratos-10\.4"):
        kratos.run_kratos([spec], tmp_path, executable=str(tmp_path / ".venv-kratos" / "bin" / "python"))
    with pytest.raises(BuildError, match=r"build 'kratos-10.4' \(kratos\): .*does not exist; run `make kratos-10\.4`"):
        check_build(Build("kratos-10.4", "kratos", str(tmp_path / ".venv-kratos" / "bin" / "python")))


def test_version_is_read_from_the_venv_and_a_python_without_kratos_is_refused():
    assert check_build(Build("kratos-10.4", "kratos", str(KRATOS))) == VERSIONS["kratos-10.4"]
    with pytest.raises(BuildError, match=r"cannot report its version .*No module named 'KratosMultiphysics'"):
        check_build(Build("kratos-mine", "kratos", "python3"))


def test_an_error_inside_kratos_fails_that_run_only(tmp_path, monkeypatch):
    """A material file Kratos cannot read (YOUNG_MODULUS a string: Kratos raises 'Argument must be a
    number' from ReadMaterialsUtility): the driver reports that run as failed (RUN FAILED, its
    status), and the next run in the same process lands."""
    bad = RunSpec("steel", "kratos", "elastic", steel_pair("sphere-plane"), VELOCITY, label="bad")
    good = RunSpec("steel", "kratos", "elastic", steel_pair("sphere-sphere"), VELOCITY)
    real_entry = kratos.job_entry

    def entry(spec, out):
        e = real_entry(spec, out)
        return {**e, "young": "not a number"} if spec is bad else e

    monkeypatch.setattr(kratos, "job_entry", entry)
    sweep = kratos.run_kratos([bad, good], tmp_path)
    assert list(sweep.dumps) == [good.name]
    err = sweep.failures[bad.name]
    assert f"{bad.name}: kratos: RuntimeError: Error: Argument must be a number" in str(err)
    assert "kratos.log" in str(err)
    assert f"RUN FAILED {bad.name}: " in (tmp_path / "kratos.log").read_text()


def test_time_step_convergence_runs_hertz_alone_at_second_order(tmp_path):
    """The convergence extra (plan_at_velocity) gives Kratos its K = 0 runs only, with the law
    'elastic'; they converge at second order (measured 2.00 in T, 2.01 in A over dt = T_e/250 ..
    T_e/1000; asserted 1.9 .. 2.1)."""
    from contact_model import load_case
    from engines.plan import plan_at_velocity
    from analysis.convergence import observed_order

    case = load_case(Path(__file__).resolve().parents[1] / "cases" / "steel.yaml")
    runs = plan_at_velocity(case, "kratos", [0.0, 0.1, 0.5], [250, 500, 1000], 1.0, "convergence",
                            build="kratos-10.4")
    assert {(r.law, r.K, r.time_step_factor) for r in runs} == {("elastic", 0.0, f) for f in (250, 500, 1000)}
    assert len(runs) == 2 * 3  # both geometries
    plane = [r for r in runs if r.pair.geometry == "sphere-plane"]
    sweep = kratos.run_kratos(plane, tmp_path).raise_first()
    errors = [relative_errors(dump_metrics(sweep.dumps[r.name])[1], r) for r in plane]
    dt = [1.0 / r.time_step_factor for r in plane]
    for q in ("T_x0", "A"):
        assert 1.9 < observed_order(dt, [e[q] for e in errors]) < 2.1, q
