"""The recipe of records/quantities.py holds for every quantity of `QUANTITIES`: `quantity_recipe_problems`
checks each place a quantity must reach (its table entry with its unit, its extraction from a dump
in records/, its reference value from the reference row, the comparison's err_ column, the
extrapolation's limit, the gate if gated, the docs naming it), so that a quantity that misses one
fails naming it, a dummy added to the table alone fails at every place, and a dummy added with
its extraction and its reference (half the maximum overlap) gets through."""

import dataclasses
import math
import re
import tempfile
from functools import lru_cache
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from engines.ladder import START_PHASE
from analysis.comparison import comparison_rows
from analysis.extrapolation import extrapolated_rows
from verdict.gate import gate_checks
from records.collision_metrics import collision_metrics, quantities_of
from records.dump_file import read_dump, write_dump
from records.quantities import QUANTITIES, Quantity, gated_quantities, reference_values
from reference import HERTZ_TAU, solve_collision
from test_collision_metrics import sampled_reference
from test_comparison import exact_metrics, meta_for
from test_gate import no_failures, plan

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["tolerance"]
DOCS = {name: (ROOT / "docs" / name).read_text() for name in ("physics.md", "verdict.md")}
K = 0.2
RUNGS = (250, 500, 1000, 2000)


@lru_cache(maxsize=1)
def dumped_metrics():
    """The metrics records/ reads off a dump of the reference trajectory at K (dimensionless:
    V = delta_e = 1, so t = tau and the force is x^{1/2} (5/4 x + K x')), written and read back."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.csv"
        write_dump(path, {"engine": "test", "case": "recipe", "time_step": 1e-3}, np.column_stack(sampled_reference(K)))
        _, cols = read_dump(path)
    return collision_metrics(cols["time"], cols["overlap"], cols["normal_velocity"], cols["normal_force"], 1.0)


def ladder_rows():
    """The summary rows of a four-rung ladder of runs that reproduce the reference exactly."""
    base = meta_for(K=K)
    m = dataclasses.replace(exact_metrics(base), start_phase=START_PHASE, end_phase=0.3)
    rows = []
    for f in RUNGS:
        meta = {**base, "ladder": "L", "time_step_factor": f, "time_step": base["T_e"] / f, "roundoff_floor": 1e-12}
        rows += comparison_rows(meta, m)
    return pd.DataFrame(rows)


def quantity_recipe_problems(q: Quantity) -> list[str]:
    """Every place quantity `q` misses, one sentence each naming the place; empty when it follows
    the recipe of records/quantities.py."""
    problems = []
    name = q.name

    def check(place, condition, what):
        if not condition:
            problems.append(f"{place}: {what}")

    def finite(x):
        try:
            return math.isfinite(float(x))
        except (TypeError, ValueError):
            return False

    # 1. Its entry in the table, with a title and a unit, read off the collision or derived.
    check("records/quantities.py", QUANTITIES.get(name) is q, f"{name} is not an entry of QUANTITIES")
    check("records/quantities.py", bool(q.title and q.unit), f"{name} has no title or no unit")
    direct = q.derive is None
    # 2. Its extraction from a dump (records/), against 3. its reference from the reference row:
    #    the dump is the reference trajectory, so the two agree to the sampling's few 1e-5.
    r = solve_collision(K)
    scales = {"T_e": HERTZ_TAU, "delta_e": 1.0, "F_e": 1.0}
    check("records/quantities.py (extract)", not direct or q.extract is not None,
          f"{name} has no extraction from a run's metrics (nor a derivation)")
    check("records/quantities.py (reference)", not direct or q.reference is not None,
          f"{name} has no reference from the reference row (nor a derivation)")
    for criterion in ("x0", "F0"):
        try:
            got = quantities_of(dumped_metrics(), criterion, 1.0, 1.0).get(name)
        except Exception as e:  # noqa: BLE001 - the place is named, whatever broke
            got = f"{type(e).__name__}: {e}"
        try:
            ref = reference_values(r, criterion, scales, 1.0, 1.0).get(name)
        except Exception as e:  # noqa: BLE001
            ref = f"{type(e).__name__}: {e}"
        check("records/collision_metrics.py (quantities_of)", finite(got),
              f"{name} is not extracted from a dump under {criterion} (got {got})")
        check("records/quantities.py (reference_values)", finite(ref),
              f"{name} has no reference value under {criterion} (got {ref})")
        if finite(got) and finite(ref):
            check("records/quantities.py", abs(float(got) / float(ref) - 1) < 1e-3,
                  f"{name} from the dump ({got:.6g}) differs from its reference ({ref:.6g}) under {criterion}")
    # 4. The comparison's err_ column, and 5. the extrapolation's limit of it.
    rungs = ladder_rows()
    check("analysis/comparison.py", f"err_{name}" in rungs.columns and rungs[f"err_{name}"].map(finite).all(),
          f"the summary rows have no finite err_{name}")
    try:
        limits = extrapolated_rows(rungs)
        limit_ok = f"err_{name}" in limits.columns and limits[f"err_{name}"].map(finite).all()
    except Exception as e:  # noqa: BLE001
        limits, limit_ok = pd.DataFrame(), False
        problems.append(f"analysis/extrapolation.py: {type(e).__name__}: {e}")
    check("analysis/extrapolation.py", limit_ok, f"the limit rows (dt -> 0) have no finite err_{name}")
    # 6. The gate, for a gated quantity: its tolerance and a check of it.
    if q.gated:
        check("config/config.yaml", name in TOLERANCE, f"tolerance: has no {name}")
        check("records/quantities.py (gated_quantities)", name in gated_quantities(), f"{name} is not gated")
        try:
            checks = gate_checks(limits, plan(("L", "liggghts", "viscoelastic", "sphere-plane")), no_failures(),
                                 TOLERANCE)
            judged = checks[checks.quantity == name]
            gate_ok = len(judged) > 0 and judged["pass"].all()
            what = f"no passing check of {name} for an exact run ({len(judged)} checks)"
        except Exception as e:  # noqa: BLE001
            gate_ok, what = False, f"judging {name} raised {type(e).__name__}: {e}"
        check("verdict/gate.py", gate_ok, what)
    # 7. The docs name it (by its name or its symbol).
    words = {w for w in (name, q.symbol) if w}
    check("docs/physics.md or docs/verdict.md",
          any(re.search(rf"(?<!\w){re.escape(w)}(?!\w)", text) for w in words for text in DOCS.values()),
          f"neither names {' or '.join(sorted(words))}")
    return problems


@pytest.mark.parametrize("name", list(QUANTITIES))
def test_every_quantity_follows_the_recipe(name):
    assert quantity_recipe_problems(QUANTITIES[name]) == []


def test_a_quantity_added_to_the_table_alone_fails_at_every_place(monkeypatch):
    dummy = Quantity("dummy", "a dummy", "m", True, None, ("m", 1.0))
    monkeypatch.setitem(QUANTITIES, "dummy", dummy)
    problems = quantity_recipe_problems(dummy)
    places = {p.split(": ", 1)[0] for p in problems}
    assert places >= {"records/quantities.py (extract)", "records/quantities.py (reference)",
                      "records/collision_metrics.py (quantities_of)", "records/quantities.py (reference_values)",
                      "analysis/comparison.py", "analysis/extrapolation.py", "config/config.yaml",
                      "verdict/gate.py", "docs/physics.md or docs/verdict.md"}, problems
    assert all("dummy" in p for p in problems), problems


def test_a_quantity_added_with_its_extraction_and_reference_gets_through(monkeypatch):
    """Half the maximum overlap, gated: its entry with its extraction and its reference, its
    tolerance and a line of the docs; the extraction, the comparison, the extrapolation and the
    gate pick it up from the table with no other change."""
    half = Quantity("half_delta", "half the maximum overlap", "m", True, None, ("µm", 1e6), "δ_max/2",
                    extract=lambda m, criterion: m.delta_max / 2,
                    reference=lambda row, criterion, scales: row["x_max"] * scales["delta_e"] / 2)
    monkeypatch.setitem(QUANTITIES, "half_delta", half)
    # Without its tolerance the gate cannot judge it; without a line of the docs no reader knows it.
    assert [p.split(": ", 1)[0] for p in quantity_recipe_problems(half)] == [
        "config/config.yaml", "verdict/gate.py", "docs/physics.md or docs/verdict.md"]
    monkeypatch.setitem(TOLERANCE, "half_delta", 1e-6)
    monkeypatch.setitem(DOCS, "physics.md", DOCS["physics.md"] + "\nhalf_delta: half the maximum overlap\n")
    assert quantity_recipe_problems(half) == []


def test_the_derived_names_are_the_table():
    from records.quantities import GATED_QUANTITIES

    assert GATED_QUANTITIES == gated_quantities() == ("T", "A", "eps")
    assert list(QUANTITIES) == ["T", "A", "eps", "Q1", "Q2", "delta_max", "F_max"]
