"""Planning refuses, before any engine starts, a case the engines cannot run honestly."""

import math
from pathlib import Path

import pytest

from contact_model import CaseError, load_case
from contact_model.keywords import keyword_reference
from engines.plan import ROUNDOFF_LIMIT, PlanError, ladder_roundoff, plan_runs, rungs_of
from engines.run_spec import RunSpec

STEEL = """name: s
effective_modulus: 109 GPa
radius: 0.635 cm
viscosity: 6.7e5 P
density: 7800 kg/m^3
"""


def plan(tmp_path, impact, text=STEEL):
    path = tmp_path / "case.yaml"
    path.write_text(text + impact + "\n")
    return path, lambda: plan_runs(load_case(path), ["lammps"], laws=["viscoelastic"])


@pytest.mark.parametrize("impact, field, words", [
    ("impact: {velocity: [1 m/s, 1e-12 m/s]}", "impact.velocity[1]", "double-precision positions"),
    ("impact: {K: [10]}", "impact.K", "nothing to run"),
    ("impact: {velocity: [1e5 m/s]}", "impact.velocity", "nothing to run"),
    ("impact: {velocity: [1e200 m/s]}", "impact.velocity[0]", "overflow"),
])
def test_unrunnable_cases_are_refused_when_planned(tmp_path, impact, field, words):
    path, run = plan(tmp_path, impact)
    with pytest.raises(PlanError) as err:
        run()
    assert isinstance(err.value, CaseError) and err.value.field == field
    assert str(path) in str(err.value) and words in str(err.value)
    # A refused velocity says what `velocity` means: the bodies' relative normal velocity.
    assert ("`velocity` is the relative normal velocity of the two bodies" in str(err.value)) == \
        field.startswith("impact.velocity")


def test_extreme_moduli_are_refused_not_crashed(tmp_path):
    path, run = plan(tmp_path, "impact: {K: [0.1]}", STEEL.replace("109 GPa", "1e-300 Pa"))
    with pytest.raises(PlanError) as err:
        run()
    assert err.value.field == "impact.K[0]" and str(path) in str(err.value)


def test_elastic_case_needs_velocities(tmp_path):
    path, run = plan(tmp_path, "", STEEL.replace("6.7e5 P", "0 P"))
    with pytest.raises(PlanError) as err:
        run()
    assert err.value.field == "impact" and "elastic" in str(err.value)


def test_an_elastic_case_says_it_runs_one_law_in_its_plan(tmp_path):
    from engines.plan import plan_listing

    path = tmp_path / "case.yaml"
    path.write_text(STEEL.replace("6.7e5 P", "0 P") + "impact: {velocity: [1 m/s]}\n")
    case = load_case(path)
    planned = plan_runs(case, ["lammps"], laws=["viscoelastic", "elastic", "default"])
    assert {r.law for r in planned.runs} == {"elastic"}
    assert planned.notes == ["s: the viscosity is 0, an elastic contact: only the law 'elastic' runs; viscoelastic, "
                             "default left out (give a positive `viscosity:` to run them)"]
    assert plan_listing(case, planned)["notes"] == planned.notes
    assert plan_runs(load_case(path), ["lammps"], laws=["elastic"]).notes == []  # nothing left out: no note


def test_roundoff_floor_matches_the_measured_miss_and_the_ladder_weighs_its_rungs():
    """Steel, sphere-plane, 1e-12 m/s (dt = T_e/1000): all engines missed T by 7e-3; the floor
    sqrt(N) u X / delta_max gives ~6.7e-3. A ladder's round-off is its rungs' floors weighed by
    the Richardson weights: about 5 times the finest rung's for the four-rung ladder."""
    case = load_case(Path(__file__).resolve().parents[1] / "cases" / "steel.yaml")
    spec = RunSpec("steel", "lammps", "viscoelastic", case.pair("sphere-plane"), 1e-12)
    assert 5e-3 < spec.roundoff_floor() < 9e-3
    at_1_m_s = RunSpec("steel", "lammps", "viscoelastic", case.pair("sphere-plane"), 1.0)
    rungs = rungs_of(at_1_m_s)
    assert [r.time_step_factor for r in rungs] == [250, 500, 1000, 2000]
    assert 4 * rungs[-1].roundoff_floor() < ladder_roundoff(rungs) < 6 * rungs[-1].roundoff_floor()
    assert ladder_roundoff(rungs) < ROUNDOFF_LIMIT / 1000


def test_shipped_cases_plan_and_the_study_grid_skips_what_cannot_be_resolved():
    folder = Path(__file__).resolve().parents[1] / "cases"
    for path in sorted(folder.glob("*.yaml")):
        p = plan_runs(load_case(path), ["lammps"], laws=["viscoelastic"])
        assert p.runs, path
        for skipped in p.skipped:
            assert "R*" in skipped["reason"] and math.isfinite(skipped["V"])
    cork = plan_runs(load_case(folder / "cork.yaml"), ["lammps"], laws=["viscoelastic"])
    # Cork's tiny overlaps at small K: double-precision positions would limit the extrapolated
    # errors beyond ROUNDOFF_LIMIT (the two spheres' overlap is half the plane's at one K).
    assert sorted((s["geometry"], round(s["K"], 6)) for s in cork.skipped) == [
        ("sphere-plane", 0.01), ("sphere-plane", 0.03), ("sphere-sphere", 0.01), ("sphere-sphere", 0.03),
        ("sphere-sphere", 0.1)]
    assert all("double-precision" in s["reason"] and "extrapolated" in s["reason"] for s in cork.skipped)


def test_plan_listing_hands_on_runs_and_their_reference_and_refuses_a_stale_plan(tmp_path, monkeypatch):
    import json

    from engines import plan as plan_module
    from engines.plan import plan_listing, runs_from_listing

    path, _ = plan(tmp_path, "impact: {K: [0.1, 0.2]}")
    case = load_case(path)
    listing = json.loads(json.dumps(plan_listing(case, plan_runs(case, ["lammps", "yade"]))))  # as plan.json
    # The engine job rebuilds its runs without solving the ODE again.
    monkeypatch.setattr("engines.run_spec.solve_collision", lambda K: pytest.fail("solved again"))
    runs = runs_from_listing(case, listing, "yade")
    assert [r.name for r in runs] == [e["name"] for e in listing["runs"] if e["engine"] == "yade"]
    # geometries x K x rungs of the laws (viscoelastic 4, clipped 4, elastic 3, its keywords en, betan and
    # en + vn 4 each: the plan of every release; cases.smk leaves en + vn out of a release before 2024.02a)
    assert len(runs) == 2 * 2 * (4 + 4 + 3 + 4 + 4 + 4)
    assert {e["ladder"] for e in listing["runs"] if e["engine"] == "yade"} == {r.ladder for r in runs}
    for r in runs:
        assert r.steps() == next(e["steps"] for e in listing["runs"] if e["name"] == r.name)
        if r.keyword is not None:  # YADE's en or betan: its own equation's row, at the b its code computes
            assert r.reference == keyword_reference(r.keyword, r.matched_restitution, r.K)
            assert r.keyword == {"default": "yade:en", "betan": "yade:betan", "en_vn": "yade:en-vn"}[r.law]
        else:
            assert r.reference == plan_module.solve_collisions([r.K]).row(0)  # the plan's batch, bit for bit
    # An engine job rebuilds the same runs from the listing alone (no case file parsed, no pint).
    alone = runs_from_listing(None, listing, "yade")
    assert [r.name for r in alone] == [r.name for r in runs] and [r.pair for r in alone] == [r.pair for r in runs]
    # A plan made for other numbers (here: another density) no longer names the case's runs.
    path.write_text(path.read_text().replace("7800 kg/m^3", "7850 kg/m^3"))
    with pytest.raises(ValueError, match=r"changed after its plan was made: the plan is stale: rerun the study"):
        runs_from_listing(None, listing, "yade")
    with pytest.raises(ValueError, match=r"the plan is stale: rerun the study"):
        runs_from_listing(load_case(path), listing, "yade")


def test_elastic_law_runs_hertz_alone_and_unavailable_laws_are_listed_with_their_reason(tmp_path, monkeypatch):
    import dataclasses

    from engines import codes

    path, _ = plan(tmp_path, "impact: {K: [0.1, 0.2]}")
    case = load_case(path)
    reason = "this engine damps with a restitution-coefficient law"
    monkeypatch.setitem(codes.CODES, "yade", dataclasses.replace(
        codes.CODES["yade"], unavailable={"viscoelastic": reason, "viscoelastic_clipped": reason}))
    p = plan_runs(case, ["lammps", "yade"], laws=["viscoelastic", "viscoelastic_clipped", "elastic", "default"])
    elastic = [r for r in p.runs if r.law == "elastic"]
    assert len(elastic) == 2 * 2 * 2 * 3  # builds x geometries x velocities x rungs
    for r in elastic:
        assert r.pair.eta == 0 and r.K == 0 and r.represents == ("x0",)
        assert r.reference["eps_x0"] == pytest.approx(1.0, abs=1e-15)
        assert r.reference["tau_0"] == pytest.approx(2.9432751843247, rel=1e-13)  # Hertz: 2 * 1.4716...
        # the same velocities as the viscoelastic runs of its geometry
        assert r.velocity in {v.velocity for v in p.runs
                              if v.law == "viscoelastic" and v.pair.geometry == r.pair.geometry}
    assert {(r.build, r.law) for r in p.runs if r.build == "yade"} == {("yade", "elastic"), ("yade", "default")}
    assert sorted((n["build"], n["law"], n["geometry"]) for n in p.not_available) == [
        ("yade", law, g) for law in ("viscoelastic", "viscoelastic_clipped") for g in ("sphere-plane", "sphere-sphere")]
    assert all(n["reason"] == reason for n in p.not_available)


def test_a_case_of_restitutions_is_planned_once_per_restitution_with_its_own_eta(tmp_path):
    """impact: {restitution: [0.8, 0.5], velocity: [1 m/s]}: the viscoelastic runs of each at the eta
    that restitutes it (F0), the out-of-the-box law told it, Hertz alone once; the listing hands each
    run its eta, and the runs rebuilt from it are the plan's."""
    from engines.plan import plan_listing, runs_from_listing
    from reference import solve_collision

    path = tmp_path / "case.yaml"
    path.write_text(STEEL.replace("viscosity: 6.7e5 P\n", "") + "geometries: [sphere-plane]\n"
                    "impact: {restitution: [0.8, 0.5], velocity: [1 m/s]}\n")
    case = load_case(path)
    planned = plan_runs(case, ["lammps"], laws=["viscoelastic", "elastic", "default"])
    by_law = {}
    for run in planned.runs:
        by_law.setdefault(run.law, []).append(run)
    assert len({r.name for r in planned.runs}) == len(planned.runs)  # no run twice
    assert sorted({round(solve_collision(r.K)["eps_F0"], 9) for r in by_law["viscoelastic"]}) == [0.5, 0.8]
    assert sorted({r.matched_restitution for r in by_law["default"]}) == [0.5, 0.8]
    assert len(by_law["default"]) == 2 * 4  # a ladder each
    assert len(by_law["elastic"]) == 3  # one ladder, whatever the restitutions
    assert len(planned.notes) == 2 and planned.notes[0].startswith("s: restitution 0.8 under F0 at V = 1 m/s: ")
    listing = plan_listing(case, planned)
    rebuilt = runs_from_listing(None, listing, "lammps")
    assert [r.name for r in rebuilt] == [r.name for r in planned.runs]
    assert [r.pair.eta for r in rebuilt] == [r.pair.eta for r in planned.runs]
