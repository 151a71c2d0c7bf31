"""LAMMPS (GRANULAR), run for real: the viscoelastic Hertz contact against the reference solver,
and the fix wall/gran hertz/material defect of the Debian version as a regression case."""

import pytest

from engine_cases import TOLERANCE, VELOCITY, dump_metrics, relative_errors, require_engine, steel_pair
from engines import RunSpec
from engines.lammps import run_lammps, wall_modulus_regression

GEOMETRIES = ("sphere-sphere", "sphere-plane")


@pytest.fixture(autouse=True)
def _needs_lammps():
    require_engine("lmp", "lammps")


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    require_engine("lmp", "lammps")
    specs = [RunSpec("steel", "lammps", law, steel_pair(g), VELOCITY)
             for g in GEOMETRIES for law in ("viscoelastic", "viscoelastic_clipped")]
    done = run_lammps(specs, tmp_path_factory.mktemp("lammps")).raise_first()
    return {(s.law, s.pair.geometry): (s, *dump_metrics(done.dumps[s.name])) for s in specs}


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_viscoelastic_matches_reference(sweep, geometry):
    spec, meta, m = sweep[("viscoelastic", geometry)]
    assert meta["engine_version"].startswith("LAMMPS (29 Sep 2021")
    for q, e in relative_errors(m, spec).items():
        assert abs(e) < TOLERANCE, (q, e)
    clipped_spec, _, clipped = sweep[("viscoelastic_clipped", geometry)]
    errors = relative_errors(clipped, clipped_spec)
    for q in ("A", "T_F0", "eps_F0"):
        assert abs(errors[q]) < TOLERANCE, (q, errors[q])


def test_wall_hertz_material_is_stiffer_by_one_plus_nu(tmp_path):
    """E/(2(1 - nu)) instead of E/(2(1 - nu^2)): the stiffness is (1 + nu) = 1.3 times too high,
    so overlap and contact time shrink by 1.3^{-2/5} (Hertz: delta_e ~ E^{-2/5})."""
    (explicit, material), sweep = wall_modulus_regression(tmp_path)
    sweep.raise_first()
    _, right = dump_metrics(sweep.dumps[explicit.name])
    _, wrong = dump_metrics(sweep.dumps[material.name])
    assert abs(relative_errors(right, explicit)["A"]) < 1e-5
    assert wrong.delta_max / right.delta_max == pytest.approx(1.3 ** -0.4, rel=1e-5)
    assert wrong.T_x0 / right.T_x0 == pytest.approx(1.3 ** -0.4, rel=1e-5)
