"""The oblique gate's resolution (analysis.oblique.oblique_limit, limit_rows): the stated resolution
bounds the distance of the extrapolated value from the true limit, on ladders built from closed forms
e(h) = L + c h^p, and on a real ladder that the default rungs do not resolve (Chung & Ooi test 5 at
20 deg, LAMMPS 2025 and YADE 2025, twelve rungs to T_e/2048000: tests/data/oblique_ladders/, its
provenance in the file's header).

Measured there (docs/tangential.md, "The full set", finding 1): the rungs' order of e_t rises from 0.83
to 0.98 between T_e/1000 and T_e/2048000; the Richardson limit of the finest five rungs is -1.8e-11
(LAMMPS) and -7.0e-11 (YADE) for e_t, every tangential quantity within 2e-9 of 0. Over the default
rungs (T_e/1000 ... /16000) the gate used to claim e_t = +4.0e-6 +- 2.0e-6 and +4.9e-6 +- 1.6e-6 (an
engine error where there is none); it now states +2.1e-5 +- 2.6e-5, unresolved.
"""

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analysis.oblique import OBLIQUE_POWERS, OBLIQUE_QUANTITIES, limit_rows, oblique_checks, oblique_limit
from engines.ladder import RESOLUTION_FLOOR, extrapolate

DATA = Path(__file__).parent / "data" / "oblique_ladders" / "chung_ooi_test5_20deg.csv"
#: The study's default oblique rungs (config oblique.ladder): h = dt / T_e.
DEFAULT_H = 1.0 / np.array([1000.0, 2000.0, 4000.0, 8000.0, 16000.0])
TOLERANCE = 1e-6
LIMIT = 3e-7  # the closed forms' limit [-]: inside the tolerance, above RESOLUTION_FLOOR
#: For a pure power c h^p (p < 1) the first-order limits' tail at the rungs' own order is the error
#: itself: the bound holds with equality, to round-off.
ROUNDOFF = 1e-9


def _stated(h, y):
    lim = oblique_limit(h, y)
    return lim, max(lim["estimate"], RESOLUTION_FLOOR)


@pytest.mark.parametrize("p", [2.0, 1.0, 0.88, 0.5])
def test_the_resolution_bounds_the_error_of_a_closed_form_ladder(p):
    # c such that the coarsest rung is off by 1e-3, as the force-history ladders are at T_e/1000.
    c = 1e-3 / DEFAULT_H[0] ** p
    y = LIMIT + c * DEFAULT_H ** p
    lim, res = _stated(DEFAULT_H, y)
    assert abs(lim["value"] - LIMIT) <= res * (1 + ROUNDOFF)
    if p >= 1.0:  # the expansion's own powers: resolved to the floor, as before
        assert res == RESOLUTION_FLOOR and abs(lim["value"] - LIMIT) < 1e-12
    else:  # slower than any power the expansion eliminates: stated unresolved, never a PASS
        assert lim["method"] != "extrapolated"
        assert abs(lim["value"]) + res > TOLERANCE


def test_richardson_alone_understates_a_sub_first_order_ladder():
    # Why the gate checks its estimates: on h^0.88 the expansion's extrapolation (powers 1, 3/2, 2, 5/2)
    # claims an estimate several times smaller than its own error.
    y = LIMIT + 0.437 * DEFAULT_H ** 0.88
    e = extrapolate(DEFAULT_H, y, OBLIQUE_POWERS)
    assert abs(e.value - LIMIT) > 3 * e.estimate
    lim, res = _stated(DEFAULT_H, y)
    assert abs(lim["value"] - LIMIT) <= res * (1 + ROUNDOFF)


def test_a_series_of_the_expansions_powers_keeps_its_richardson_limit():
    # Terms h, h^{3/2}, h^2 of opposite signs: the rungs show order 0.945 (within ORDER_SLACK of 1) and the
    # extrapolation, exact here, is kept.
    y = LIMIT + 0.5 * DEFAULT_H - 3.0 * DEFAULT_H ** 1.5 + 4.0 * DEFAULT_H ** 2
    lim, res = _stated(DEFAULT_H, y)
    assert lim["method"] == "extrapolated" and abs(lim["value"] - LIMIT) < 1e-15 and res == RESOLUTION_FLOOR


@pytest.fixture(scope="module")
def ladders():
    rungs = pd.read_csv(DATA, comment="#")
    assert set(rungs.build) == {"lammps-2025", "yade-2025"} and rungs.groupby("build").size().eq(12).all()
    return rungs


def _truth(g, q):
    """The Richardson limit of the finest five rungs (T_e/128000 ... /2048000, orders 0.95-0.98)."""
    g = g.sort_values("h", ascending=False)
    return extrapolate(g.h.to_numpy()[-5:], g[f"err_{q}"].to_numpy()[-5:], OBLIQUE_POWERS)


def test_the_finest_rungs_meet_the_reference(ladders):
    for _, g in ladders.groupby("build"):
        for q in ("e_t", "omega_after", "rebound_angle", "vt_after", "Ft_max", "T"):
            e = _truth(g, q)
            assert abs(e.value) < 3e-9 and e.estimate < 3e-10, (g.build.iloc[0], q, e)


def test_the_default_rungs_state_test_5_at_20_deg_unresolved(ladders):
    # Before: e_t +4.0e-6 +- 2.0e-6 (LAMMPS), a FAIL that read as an engine error of 4e-6. Now each
    # tangential check fails as unresolved: its error lies within its resolution.
    default = ladders[ladders.time_step_factor <= 16000]
    checks = oblique_checks(limit_rows(default), TOLERANCE)
    tangential = checks[checks.quantity.isin(["e_t", "omega_after", "rebound_angle", "Ft_max", "vt_after"])]
    assert len(tangential) == 10
    assert (tangential.status == "FAIL").all()
    assert (tangential.error.abs() <= tangential.resolution).all()
    assert tangential.detail.str.contains("unresolved").all()
    normal = checks[checks.quantity.isin(["T", "eps"])]
    assert (normal.status == "PASS").all()


@pytest.mark.parametrize("first", range(8))
def test_every_five_rung_window_bounds_the_limit(ladders, first):
    # Windows T_e/1000-/16000 ... T_e/128000-/2048000: the stated resolution holds against the finest
    # rungs' limit for every gated quantity, in both engines.
    for _, g in ladders.groupby("build"):
        g = g.sort_values("h", ascending=False)
        window = g.iloc[first:first + 5]
        row = limit_rows(window).iloc[0]
        for q in OBLIQUE_QUANTITIES:
            truth = _truth(g, q)
            assert abs(row[f"err_{q}"] - truth.value) <= row[f"resolution_{q}"] + truth.estimate, (
                g.build.iloc[0], first, q, row[f"err_{q}"], row[f"resolution_{q}"], truth.value)


def test_rungs_from_t_e_over_16000_to_256000_pass_every_check(ladders):
    fine = ladders[(ladders.time_step_factor >= 16000) & (ladders.time_step_factor <= 256000)]
    checks = oblique_checks(limit_rows(fine), TOLERANCE)
    assert len(checks) == 14 and (checks.status == "PASS").all(), checks[checks.status != "PASS"]
    assert checks.resolution.max() < 3e-8 and math.isfinite(checks.error.abs().max())


def _config():
    import yaml

    return yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text())["oblique"]


def test_config_gives_the_slow_impacts_their_finer_ladder_as_data():
    from contact_model import load_case
    from engines.oblique_plan import oblique_plan

    o = _config()
    case = load_case(Path(__file__).resolve().parents[1] / "cases" / "oblique" / "chung_ooi_test5.yaml")
    plan = oblique_plan([case], "yade", "yade-2025", "YADE 2025.2.0", o["ladder"], (1,), o["finer_ladders"])
    by_angle = {}
    for r in plan.runs:
        by_angle.setdefault(round(r.contact_angle, 6), []).append(r.normal.time_step_factor)
    assert by_angle[20.0] == [16000.0, 32000.0, 64000.0, 128000.0, 256000.0]
    assert by_angle[5.0] == by_angle[15.0] == by_angle[20.0]
    assert by_angle[10.0] == [float(f) for f in o["ladder"]] == by_angle[60.0]
    # The displacement-history models keep the default rungs at 20 deg.
    lammps = oblique_plan([case], "lammps", "lammps-2025", "LAMMPS (22 Jul 2025 - Update 4)", o["ladder"], (1,),
                          o["finer_ladders"])
    factors = {r.model: [] for r in lammps.runs}
    for r in lammps.runs:
        if round(r.contact_angle, 6) == 20.0:
            factors[r.model].append(r.normal.time_step_factor)
    assert factors["lammps:mindlin/force"][0] == 16000.0 and factors["lammps:mindlin"][0] == 1000.0


@pytest.mark.parametrize("entry, field", [({"case": "chung_ooi_test5", "angles": [20.0]}, "case, angles and ladder"),
                                          ({"case": "chung_ooi_test5", "angles": [20.0], "ladder": [16000, 0, 1]},
                                           "finer_ladders[0].ladder"),
                                          ({"case": "chung_ooi_test5", "angles": "20", "ladder": [1, 2, 3]},
                                           "finer_ladders[0].angles")])
def test_a_malformed_finer_ladder_is_refused_naming_the_field(entry, field):
    from engines.oblique_plan import finer_ladder

    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace("]", r"\]")):
        finer_ladder([entry], "chung_ooi_test5", 20.0, "yade:mindlin")


def test_a_pass_of_test_6_at_20_deg_is_now_stated_unresolved():
    # Test 6 at 20 deg, yade:mindlin (9 rungs to T_e/256000): the default rungs claimed e_t = -3.6e-7 +- 2.3e-7
    # and passed, where the finest five rungs put the limit at +3e-10; the checked estimate bounds it.
    rungs = pd.read_csv(DATA.with_name("chung_ooi_test6_20deg.csv"), comment="#").sort_values("h", ascending=False)
    truth = extrapolate(rungs.h.to_numpy()[-5:], rungs.err_e_t.to_numpy()[-5:], OBLIQUE_POWERS)
    assert abs(truth.value) < 1e-9
    row = limit_rows(rungs[rungs.time_step_factor <= 16000]).iloc[0]
    assert abs(row.err_e_t - truth.value) <= row.resolution_e_t
    assert abs(row.err_e_t) + row.resolution_e_t > TOLERANCE and abs(row.err_e_t) <= row.resolution_e_t
    # One rung finer (T_e/2000 ... /32000) it passes, and the PASS is true (the limit is 3e-10). Its
    # resolution is not a guaranteed bound: e_t -2.5e-8 +- 2.0e-8 misses the limit by 1.3 x the resolution
    # (measured; the one miss in the five windows of this ladder, far inside the tolerance). No estimate from
    # a ladder alone is a bound (engines/ladder.py: the head-on one holds in 97 % of random series).
    finer = limit_rows(rungs[(rungs.time_step_factor >= 2000) & (rungs.time_step_factor <= 32000)]).iloc[0]
    assert abs(finer.err_e_t) + finer.resolution_e_t <= TOLERANCE
    assert abs(finer.err_e_t - truth.value) <= 1.5 * finer.resolution_e_t
