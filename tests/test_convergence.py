"""The convergence study's tables: observed orders, the largest time step meeting a threshold
(in T_e and in Rayleigh times) and the builds' spread, on errors of known form."""

import math

import numpy as np
import pandas as pd
import pytest

from contact_model import load_case
from engines.ladder import observed_order
from analysis.convergence import build_spread, convergence_table, largest_dt, largest_dt_table

FACTORS = np.array([10, 20, 50, 100, 250, 500, 1000, 2000])


def test_order_of_a_power_law():
    dt = 1.0 / FACTORS
    assert observed_order(dt, 3.0 * dt**2) == pytest.approx(2.0, abs=1e-12)
    assert observed_order(dt, -0.5 * dt) == pytest.approx(1.0, abs=1e-12)
    assert np.isnan(observed_order(dt, np.full(8, 1e-14)))  # round-off only: no order


def test_largest_dt_interpolates_a_power_law_and_says_how():
    """err = 0.3 dt: the threshold 1e-3 is met from dt = 1e-3 / 0.3 on, found between the sweep's
    steps T_e/250 and T_e/500 to rounding (a power law is a line in log-log); every step passes
    1; 1e-4 needs dt = 3.3e-4, below the sweep's finest step, carried on with the last slope."""
    h = 1.0 / FACTORS
    assert largest_dt(h, 0.3 * h, 1e-3) == (pytest.approx(1e-3 / 0.3, rel=1e-12), "interpolated")
    assert largest_dt(h, 0.3 * h, 1.0) == (pytest.approx(0.1), "coarsest")
    assert largest_dt(h, 0.3 * h, 1e-4) == (pytest.approx(1e-4 / 0.3, rel=1e-12), "beyond")
    value, how = largest_dt(h, np.full(8, 1.0), 1e-3)  # no slope to carry on
    assert math.isnan(value) and how == "none"
    # A step that fails between passing ones: the largest dt is the one below the first failure
    # from the finest up, not the coarsest that passes.
    bumpy = 0.3 * h
    bumpy[3] = 1.0  # T_e/100 fails
    assert largest_dt(h, bumpy, 0.05)[0] < 1 / 100


def test_tables_per_build_law_K_and_the_rayleigh_time():
    """Two geometries, K = 0.1, errors 0.3 dt (T) and 0.1 dt^2 (A) in T_e units; the Rayleigh
    times 0.5 T_e and 0.4 T_e: the largest dt is the smaller of the two geometries'."""
    rows = []
    for geometry in ("sphere-sphere", "sphere-plane"):
        for f in FACTORS:
            rows.append({"build": "b", "engine": "lammps", "law": "viscoelastic", "geometry": geometry, "K": 0.1,
                         "criterion": "x0", "h": 1 / f, "err_T": 0.3 / f, "err_A": 0.1 / f**2, "err_eps": 0.0})
    errors = pd.DataFrame(rows)
    orders = convergence_table(errors).set_index(["geometry", "quantity"])
    assert orders.loc[("sphere-plane", "T"), "order"] == pytest.approx(1.0)
    assert orders.loc[("sphere-plane", "A"), "order"] == pytest.approx(2.0)
    assert orders.loc[("sphere-plane", "T"), "error at T_e/1000"] == pytest.approx(3e-4)
    table = largest_dt_table(errors, [1e-3], {"sphere-sphere": 0.5, "sphere-plane": 0.4})
    (row,) = table.to_dict("records")
    assert row["dt_over_T_e"] == pytest.approx(1e-3 / 0.3) and row["T_e_over_dt"] == pytest.approx(300)
    assert row["dt_over_T_R"] == pytest.approx(1e-3 / 0.3 / 0.5) and row["how"] == "interpolated"


def test_builds_that_agree_have_no_spread_and_round_off_is_left_out():
    base = {"law": "viscoelastic", "geometry": "sphere-plane", "K": 0.5, "criterion": "x0", "h": 1e-3,
            "err_A": 2e-4, "err_eps": 1e-13}
    errors = pd.DataFrame([{**base, "build": "a", "err_T": 1e-4}, {**base, "build": "b", "err_T": 1.02e-4}])
    spread = build_spread(errors).set_index("quantity")
    assert spread.loc["T", "spread"] == pytest.approx(0.02 / 1.02) and spread.loc["A", "spread"] == 0.0
    assert "eps" not in spread.index  # 1e-13: round-off, no spread to speak of


def test_rayleigh_time_of_steel_and_of_the_engines_material():
    """T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766): steel (Y = 210 GPa, nu = 0.3, rho 7800,
    R = 1 mm) by hand: G = 80.769 GPa, sqrt(rho / G) = 3.1076e-4 s/m, pi 1e-3 x 3.1076e-4 / 0.92553
    = 1.0548e-6 s; a case with E* alone runs Y = 2 E*, nu = 0 (G = E*)."""
    from contact_model.collision_scales import rayleigh_time

    assert rayleigh_time(1e-3, 7800.0, 210e9, 0.3) == pytest.approx(1.0548e-6, rel=1e-4)
    with pytest.raises(ValueError):
        rayleigh_time(1e-3, 7800.0, 210e9, 0.5)
    pair = load_case("cases/steel.yaml").pairs[0]
    expected = math.pi * pair.body_1.radius * math.sqrt(pair.body_1.density / pair.E) / 0.8766
    assert pair.rayleigh_time() == pytest.approx(expected, rel=1e-14)


def test_convergence_plan_hands_its_references_on(monkeypatch):
    """plan_at_velocity solves every run's K in one batch, and a job given those rows
    (`references_of`, a Snakemake param) plans the same runs, steps and set-up bit for bit
    without solving at all: the convergence job need not load the compiled kernel."""
    import engines.plan
    from contact_model import load_case
    from engines.plan import plan_at_velocity, references_of
    from reference import solve_collision

    case = load_case("cases/steel.yaml")
    args = (case, "lammps", [0.0, 0.1, 0.5, 2.0], [250, 1000], 1.0, "convergence")
    planned = plan_at_velocity(*args)
    solved = references_of(planned)
    # each pair's K (a round trip through eta, so not exactly the grid's), K = 0 left out: it
    # needs no solve (the Hertz duration)
    assert set(solved) == {r.K for r in planned if r.K > 0} and len(solved) == 3 * len(case.pairs)
    assert {r.law for r in planned if r.K == 0} == {"elastic"}
    for K, row in solved.items():
        assert row == solve_collision(K)  # the batch rows are the one-K solutions, bit for bit

    def no_solve(K):
        raise AssertionError(f"solved again: {K}")
    monkeypatch.setattr(engines.plan, "solve_collisions", no_solve)
    again = plan_at_velocity(*args, solved=solved)
    assert [r.name for r in again] == [r.name for r in planned]
    assert [r.initial_state() for r in again] == [r.initial_state() for r in planned]
    # a row missing from `solved` is solved, not skipped
    monkeypatch.undo()
    partial = plan_at_velocity(*args, solved={K: r for K, r in solved.items() if K != max(solved)})
    assert references_of(partial) == solved
