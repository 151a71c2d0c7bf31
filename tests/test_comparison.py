"""Comparison rows: a run that reproduces the reference exactly has zero errors, and the
series column is the paper's series times the Hertz scales."""

import math

import pytest

from contact_model import Body, ContactPair
from records.collision_metrics import CollisionMetrics
from analysis.comparison import comparison_rows, hertz_Q, measured
from reference import solve_collision


def meta_for(K=0.2, V=1.0, represents=("x0", "F0")):
    pair = ContactPair("sphere-plane", Body(0.01, 7800), Body(math.inf, math.inf), 100e9, 1e4)
    s = pair.scales(V)
    return {"case": "t", "engine": "liggghts", "engine_version": "x", "law": "viscoelastic",
            "geometry": pair.geometry, "represents": list(represents), "impact_velocity": V, "K": K,
            "time_step": s["T_e"] / 1000, "T_e": s["T_e"], "A_e": s["A_e"], "delta_e": s["delta_e"],
            "effective_radius": pair.R, "effective_mass": pair.M}


def exact_metrics(meta):
    r = solve_collision(meta["K"])
    to_t = meta["delta_e"] / meta["impact_velocity"]
    F_e = meta["effective_mass"] * meta["impact_velocity"] ** 2 / meta["delta_e"]
    return CollisionMetrics(0.0, r["x_max"] * meta["delta_e"], r["tau_max"] * to_t, r["tau_0"] * to_t,
                            r["eps_x0"], r["tau_f"] * to_t, r["eps_F0"], 1000, force_max=r["force_max"] * F_e)


def test_exact_run_has_zero_error_under_both_criteria():
    meta = meta_for()
    rows = comparison_rows(meta, exact_metrics(meta))
    assert [r["criterion"] for r in rows] == ["x0", "F0"]
    for r in rows:
        for q in ("T", "A", "eps", "Q1", "Q2", "delta_max", "F_max"):
            assert abs(r[f"err_{q}"]) < 1e-13, (r["criterion"], q)
        # Hertz's scales: F_max [N] = force_max M* V^2 / delta_e, delta_max [m] = x_max delta_e
        assert r["delta_max_ref"] == pytest.approx(r["A_ref"] / (math.pi * meta["effective_radius"]), rel=1e-15)


def test_series_and_Q_scales():
    meta = meta_for(K=0.1)
    row = comparison_rows(meta, exact_metrics(meta))[0]  # criterion x0
    assert row["eps_series"] == pytest.approx(1 - 1.0089 * 0.1 + 0.6107 * 0.01, rel=1e-14)
    assert row["T_series"] == pytest.approx(meta["T_e"] * (1 + 0.1009 * 0.1 + 0.0576 * 0.01), rel=1e-14)
    # Q1e = 14.39 M/E and Q2e = 1.0674 R (the paper's closed forms, to their printed digits).
    M, E = 4 / 3 * math.pi * 1e-6 * 7800, 100e9
    assert row["Q1e"] == pytest.approx(14.39 * M / E, rel=5e-4)
    assert row["Q2e"] == pytest.approx(1.0674 * 0.01, rel=5e-5)
    q = measured(2.0, 3.0, 0.25, 4.0)
    assert q["Q1"] == pytest.approx(math.sqrt(3) * 4) and q["Q2"] == pytest.approx(3 / (0.5 * 4 * 2))
    assert hertz_Q(2.0, 9.0, 3.0) == {"Q1": 12.0, "Q2": 1.5}
