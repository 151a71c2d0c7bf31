"""records.quantities: one table of the quantities, each with what a reader and the gate need,
and the Hertz closed forms of the elastic collision in SI through `characteristics`."""

import math

import pytest
import yaml
from pathlib import Path

from records.quantities import GATED_QUANTITIES, QUANTITIES, characteristics, readable
from reference import solve_collision

ROOT = Path(__file__).resolve().parents[1]


def test_every_quantity_has_its_unit_title_and_value_and_the_gated_ones_a_tolerance():
    tolerance = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["tolerance"]
    values = characteristics(1e-5, 1e-6, 0.9, 10.0, 0.01, 1.0)
    for name, q in QUANTITIES.items():
        assert q.title and q.unit and name in values and math.isfinite(values[name])
        assert (name in tolerance) == q.gated, name
    assert GATED_QUANTITIES == ("T", "A", "eps")


def test_hertz_elastic_collision_in_si():
    """Steel on steel at 1 m/s (E* = 1.1e11 Pa, R* = 5 mm, M* = 2.05 g): Hertz's closed forms,
    t_c = 2.8683 (M*^2 / (R* E*^2 V))^(1/5), delta_max = (15 M* V^2 / (16 E* sqrt(R*)))^(2/5),
    F_max = (4/3) E* sqrt(R*) delta_max^(3/2), against the dimensionless solution times the scales."""
    E, R, M, V = 1.1e11, 5e-3, 2.05e-3, 1.0
    delta_e = (15 * M * V**2 / (16 * E * math.sqrt(R))) ** 0.4
    r = solve_collision(0.0)
    F_e = M * V**2 / delta_e
    q = characteristics(r["tau_0"] * delta_e / V, r["x_max"] * delta_e, r["eps_x0"], r["force_max"] * F_e, R, V)
    assert q["T"] == pytest.approx(2.8683 * (M**2 / (R * E**2 * V)) ** 0.2, rel=2e-5)  # the constant's digits
    assert q["delta_max"] == pytest.approx(delta_e, rel=1e-12)
    assert q["F_max"] == pytest.approx(4 / 3 * E * math.sqrt(R) * delta_e**1.5, rel=1e-12)
    assert q["A"] == pytest.approx(math.pi * R * delta_e, rel=1e-12)
    assert readable("T", q["T"]).endswith(" µs") and readable("F_max", 2500.0) == "2.5 kN"


def test_a_case_report_opens_with_its_collisions_in_physical_units():
    """The physical-results section of a case report: the reference's values in readable units
    with the engines' largest difference, and the elastic rows beside Hertz's closed forms with the
    exact constant C = tau_e (15/16)^(2/5) = 2.86826...."""
    import pandas as pd
    from test_comparison import exact_metrics, meta_for

    from analysis.comparison import comparison_rows
    from report.report import HERTZ_CONSTANT, _physical_section

    assert HERTZ_CONSTANT == pytest.approx(2.8683, abs=5e-5)
    rows = []
    for K, law in ((0.1, "viscoelastic"), (0.0, "elastic")):
        meta = {**meta_for(K=K, represents=("x0",)), "law": law}
        rows += comparison_rows(meta, exact_metrics(meta))
    limits = pd.DataFrame(rows).assign(dt=0.0, build="b")
    text = "\n".join(_physical_section(limits))
    elastic = limits[limits.law == "elastic"].iloc[0]
    assert readable("T", elastic.T_ref) in text and " µs (±" in text and " kN (±" in text or " N (±" in text
    assert f"C = tau\\_e (15/16)^(2/5) = {HERTZ_CONSTANT:.10f} gives {readable('T', elastic.T_ref)}" in text
    assert "t\\_c = C (M\\*^2 / (R\\* E\\*^2 V))^(1/5)" in text  # the asterisks print, not italics
