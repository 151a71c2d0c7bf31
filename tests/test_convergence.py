"""Fitting the observed order of convergence."""

import numpy as np
import pandas as pd
import pytest

from postprocess.convergence import convergence_table, largest_passing_factor, observed_order


def test_order_of_a_power_law():
    dt = 1.0 / np.array([250, 500, 1000, 2000, 4000, 8000])
    assert observed_order(dt, 3.0 * dt**2) == pytest.approx(2.0, abs=1e-12)
    assert observed_order(dt, -0.5 * dt) == pytest.approx(1.0, abs=1e-12)
    assert np.isnan(observed_order(dt, np.full(6, 1e-12)))  # round-off only: no order


def test_largest_passing_dt():
    f = np.array([250, 500, 1000, 2000])
    assert largest_passing_factor(f, np.array([8e-4, 4e-4, 2e-4, 1e-4]), 5e-4) == 500
    assert largest_passing_factor(f, np.array([8e-4, 4e-4, 2e-4, 6e-4]), 5e-4) is None


def test_table():
    f = np.array([250, 500, 1000, 2000, 4000, 8000])
    df = pd.DataFrame({"engine": "e", "geometry": "g", "K": 0.1, "criterion": "x0", "time_step_factor": f,
                       "err_T": 0.1 / f, "err_A": 10 / f**2, "err_eps": 1e-3 / f})
    t = convergence_table(df, {"T": 5e-4, "A": 5e-4, "eps": 5e-4}).set_index("quantity")
    assert t.loc["T", "order"] == pytest.approx(1.0) and t.loc["A", "order"] == pytest.approx(2.0)
    assert t.loc["T", "largest_passing_dt"] == "T_e/250" and t.loc["A", "largest_passing_dt"] == "T_e/250"
    assert t.loc["T", "error_at_T_e/1000"] == pytest.approx(1e-4)


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
