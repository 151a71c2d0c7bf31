"""Unequal spheres of two materials, in every engine: R1 != R2, rho1 != rho2, E* from two
(Y, nu) pairs. The same viscoelastic law, through the same case-file path as the study."""

import pytest

from contact_model import load_case
from engine_cases import TOLERANCE, dump_metrics, relative_errors, require_engine
from engines import RunSpec
from engines.lammps import run_lammps
from engines.liggghts import run_liggghts
from engines.yade import run_yade

CASE = """
name: unequal
viscosity: 2e4 Pa*s
bodies:
  - {radius: 4 mm, density: 7800 kg/m^3, young: 200 GPa, poisson: 0.3}
  - {radius: 1 cm, density: 2700 kg/m^3, young: 70 GPa, poisson: 0.33}
impact:
  K: [0.2]
"""
ENGINES = {"liggghts": ("liggghts", "liggghts", run_liggghts), "yade": ("yade", "yade", run_yade),
           "lammps": ("lmp", "lammps", run_lammps)}


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_unequal_spheres_match_reference(tmp_path, engine):
    executable, package, run = ENGINES[engine]
    require_engine(executable, package)
    path = tmp_path / "unequal.yaml"
    path.write_text(CASE)
    case = load_case(path)
    (pair,) = case.pairs
    assert pair.R == pytest.approx(0.004 * 0.01 / 0.014, rel=1e-15)
    spec = RunSpec(case.name, engine, "viscoelastic", pair, case.impact_velocities(pair)[0])
    assert spec.K == pytest.approx(0.2, rel=1e-12)
    sweep = run([spec], tmp_path / "run").raise_first()
    meta, m = dump_metrics(sweep.dumps[spec.name])
    assert meta["radius_2"] == 0.01 and meta["density_2"] == 2700
    for q, e in relative_errors(m, spec).items():
        assert abs(e) < TOLERANCE, (q, e)


def test_unequal_spheres_match_reference_in_esys(tmp_path):
    """ESyS cannot keep the tail (engines.codes): its clipped law, under criterion F0."""
    from engines.esys import run_esys

    require_engine("esysparticle", "esys-particle")
    path = tmp_path / "unequal.yaml"
    path.write_text(CASE)
    case = load_case(path)
    (pair,) = case.pairs
    spec = RunSpec(case.name, "esys", "viscoelastic_clipped", pair, case.impact_velocities(pair)[0])
    sweep = run_esys([spec], tmp_path / "run").raise_first()
    meta, m = dump_metrics(sweep.dumps[spec.name])
    assert meta["radius_2"] == 0.01 and meta["density_2"] == 2700
    errors = relative_errors(m, spec)
    for q in ("A", "T_F0", "eps_F0"):
        assert abs(errors[q]) < TOLERANCE, (q, errors[q])
