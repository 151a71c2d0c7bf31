"""Reproducing the paper: claims, Table 1, the fracture curve and the energy partition of a dump."""

import math

import numpy as np
import pytest

from analysis.energy import energy_partition
from report.paper.claims import claims, hertz_Q_constants
from report.paper.fracture import DEFINITIONS, fracture_velocity_ratios, pressure_ratio
from report.paper.table1 import paper_table_1, recompute_table_1, rule_prefactor
from reference import solve_collision
from test_collision_metrics import sampled_reference


@pytest.fixture(scope="module")
def table():
    return claims().set_index(["claim", "criterion"])


def test_hertz_constants_and_the_rule_prefactor():
    q1, q2 = hertz_Q_constants()
    assert q1 == pytest.approx(14.39, abs=5e-3) and q2 == pytest.approx(1.0674, abs=5e-5)
    assert rule_prefactor() == pytest.approx(3.7, abs=0.01)  # (2.5/1.924)^5


def test_claim_verdicts(table):
    assert table.loc[("T/T_e: coefficient of K^2", "x0"), "verdict"] == "disagrees"
    assert table.loc[("eps: coefficient of K^2", "x0"), "verdict"] == "agrees"
    assert table.loc[("Q1e = 14.39 M/E", "-"), "verdict"] == "agrees"
    k1 = table.loc[("phi_1, phi_2 < 1 % for K <~ 0.25", "x0"), "computed"]
    assert k1 == pytest.approx(0.2652, abs=1e-4)
    assert table.loc[("phi_1, phi_2 < 1 % for K <~ 0.25", "F0"), "verdict"].startswith("depends on criterion")


def test_table_1_scales_with_density_squared():
    t = recompute_table_1("cases")
    assert len(t) == len(paper_table_1()) * 2 * 2
    steel = t[(t.case == "steel") & (t.beta == 0.01)].set_index("geometry")
    # M* doubles and R* doubles from two spheres to sphere-plane: V_D = M*^2 E^3/(R* eta^5) doubles.
    assert steel.loc["sphere-plane", "V_D_cm_s"] == pytest.approx(2 * steel.loc["sphere-sphere", "V_D_cm_s"], rel=1e-12)
    row = steel.loc["sphere-sphere"]
    assert row.Vc_paper_rule_cm_s == pytest.approx(rule_prefactor() * 0.01**2.5 * row.V_D_cm_s, rel=1e-12)
    assert row.density_for_paper_value_rule == pytest.approx(7800 / math.sqrt(row.ratio_rule_to_paper), rel=1e-12)


def test_fracture_pressure_and_velocity():
    for d in DEFINITIONS:
        assert pressure_ratio([1e-6], d)[0] == pytest.approx(1.0, abs=1e-5)  # elastic limit: Hertz
    y = fracture_velocity_ratios([1e-2, 1.0, 1e8], 0.0236, "sphere-sphere", DEFINITIONS[0])
    assert y[0] > y[1] > y[2] > 1.0 and y[2] < 1.01  # larger bodies: V_F -> V_P
    # At the root, the Hertz pressure at max compression equals P0.
    r = solve_collision(0.1)
    assert math.sqrt(r["x_max"]) == pytest.approx(pressure_ratio([0.1], DEFINITIONS[0])[0], rel=1e-12)
    total = fracture_velocity_ratios([1e-2], 0.0236, "sphere-sphere", "total at max force")
    assert total[0] < 1.0  # the viscous stress adds: the opposite size effect


def test_energy_partition_of_a_sampled_reference():
    K = 0.4
    t, x, v, F = sampled_reference(K)
    # Hertz units: delta_e = V = M* = 1, so E* sqrt(R*) = 15/16 and the force unit M* V^2/delta_e = 1.
    meta = {"effective_modulus": 15 / 16, "effective_radius": 1.0, "effective_mass": 1.0, "impact_velocity": 1.0,
            "delta_e": 1.0}
    e = energy_partition(meta, {"time": t, "overlap": x, "normal_velocity": v, "normal_force": F})
    inside = (x > 0) & (t > 0)
    assert np.max(np.abs(e["total"][inside] - 1.0)) < 1e-3
    r = solve_collision(K)
    end = np.argmax(t > r["tau_0"])
    assert e["dissipated"][end] == pytest.approx(r["dissipated_x0"], abs=1e-3)


def test_figure_3_draws_a_study_of_more_cases_than_it_has_markers(tmp_path):
    """Fig. 3 gives each case a marker; with a user's own cases beside the six shipped (ten here)
    the markers cycle (it failed with a KeyError at the eighth case)."""
    import pandas as pd

    from report.paper.figures import figure_3

    rows = [{"case": f"case{i}", "build": "b", "law": "viscoelastic", "criterion": c, "dt": 0.0, "K": 0.1,
             "eps": solve_collision(0.1)[f"eps_{c}"]} for i in range(10) for c in ("x0", "F0")]
    figure_3(pd.DataFrame(rows), tmp_path / "fig3.png")
    assert (tmp_path / "fig3.png").stat().st_size > 10_000
