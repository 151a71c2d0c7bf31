"""The reference rows the plan hands on agree with the solver the project started from: the steel
case's K = 0.01, 0.1, 0.2 in both geometries against a stored copy of the scipy DOP853 solver's
rows (commit 0c17100), to 1e-12 relative in every field.

tests/data/speed_baseline/baseline.json holds the copy, keyed by K. (Until the time-step ladders
this module also held the engines' dumps bit for bit against the copy; the ladders changed every
run's time step, start phase and printed digits on purpose, and that check went with them.)
"""

import json
from pathlib import Path


from contact_model import load_case
from engines.plan import plan_runs

ROOT = Path(__file__).resolve().parents[1]
BASELINE = Path(__file__).parent / "data" / "speed_baseline" / "baseline.json"


def test_reference_handed_on_by_the_plan_agrees_with_the_old_solver():
    old = {float(K): row for K, row in json.loads(BASELINE.read_text())["reference"].items()}
    plan = plan_runs(load_case(ROOT / "cases" / "steel.yaml"), ["lammps"], K_grid=[0.01, 0.1, 0.2],
                     laws=["viscoelastic", "viscoelastic_clipped", "default"])
    rows = {r.K: r.reference for r in plan.runs if r.law != "default"}  # a keyword's row is its own equation's
    assert set(rows) == set(old)  # the same velocities, hence the same K to the last bit
    worst = 0.0
    for K, row in rows.items():
        for field, value in old[K].items():
            if field == "energy_residual":
                continue  # a round-off figure (~1e-15), not a result
            worst = max(worst, abs(row[field] / value - 1))
    assert worst <= 1e-12
