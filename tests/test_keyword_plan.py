"""One planner: the study's plan, the keywords' promise table (snakemake keywords) and the history
(snakemake history) expand their runs by the same code (engines.plan), with the same refusals."""

import json
import math
from pathlib import Path

import pytest

from contact_model import load_case
from contact_model.keywords import KEYWORDS
from engines.plan import history_plan, keyword_promise_plan, keyword_refusal, keyword_table_plan, plan_runs

ROOT = Path(__file__).resolve().parents[1]
#: What workflow/scripts/keyword_runs.py and history_runs.py expanded, at cce2ba4, before their
#: expansion moved into engines.plan: the default config's `keywords:`, `history:` and `ladder:`, for
#: each build of the default config at its release's banner. Each ladder is [its name, e, its
#: time-step factors, its time steps, and for a keyword its reference's K and b].
RECORDED = json.loads((ROOT / "tests/data/keyword_history_plans.json").read_text())


def close(a, b):
    return a == b or (a is not None and b is not None and math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0))


def assert_ladder(rungs, recorded, keyword=True):
    name, e, factors, steps, *ref = recorded
    assert rungs[0].ladder == name and rungs[0].matched_restitution == e
    assert [r.time_step_factor for r in rungs] == factors
    assert all(close(r.time_step, dt) for r, dt in zip(rungs, steps, strict=True)), name
    assert len({r.ladder for r in rungs}) == 1
    if keyword:
        assert close(rungs[0].reference["K"], ref[0]) and close(rungs[0].reference.get("b"), ref[1]), name


@pytest.mark.parametrize("build", sorted(RECORDED["keywords"]))
def test_the_keywords_table_plans_the_runs_its_script_did(build, monkeypatch):
    monkeypatch.chdir(ROOT)  # the config's case paths are the project's
    old, config = RECORDED["keywords"][build], RECORDED["config"]
    keywords, plan = keyword_table_plan(config["keywords"], old["code"], RECORDED["banners"][build], config["ladder"],
                                        build)
    assert keywords == old["keywords"]
    assert len(plan.ladders) == len(old["ladders"])
    for rungs, recorded in zip(plan.ladders.values(), old["ladders"]):
        assert_ladder(rungs, recorded)
    assert [[n, e, why] for (n, e), why in plan.refused.items()] == old["refused"]


@pytest.mark.parametrize("build", sorted(RECORDED["history"]))
def test_the_history_plans_the_runs_its_script_did(build, monkeypatch):
    monkeypatch.chdir(ROOT)
    old, config = RECORDED["history"][build], RECORDED["config"]
    plan = history_plan(config["history"], old["code"], RECORDED["banners"][build], config["ladder"], build)
    assert list(plan.ladders) == list(old["ladders"])
    for check, (criterion, rungs) in plan.ladders.items():
        assert criterion == old["ladders"][check][0]
        assert_ladder(rungs, old["ladders"][check][1:], keyword=False)
    assert list(plan.keywords) == list(old["promise"])
    for name, recorded in old["promise"].items():
        by_e = plan.promise.of(name)
        assert len(by_e) == len(recorded)
        for rungs, ladder in zip(by_e.values(), recorded):
            assert_ladder(rungs, ladder)
    assert plan.missing == old["missing"]


@pytest.mark.parametrize("e", [0.5, 0.99, 1.0])
def test_a_keyword_told_other_than_e_is_refused_alike_by_the_study_and_the_keywords_plan(e):
    """YADE's betan is told Thornton's beta of e, not e: at e = 1 that is beta = 0, which YADE
    refuses, though e = 1 itself lies in betan's range (0, 1e300]. The keywords' script asked
    `refuses(e)` and would have run it; the study's plan asks `refuses(told_for(e))` and does not.
    Both now ask `keyword_refusal`, and refuse (or run) the same e with the same reason."""
    keyword = KEYWORDS["yade:betan"]
    assert keyword.told_for(e) != e  # told something else than e
    case = load_case(ROOT / "cases/steel.yaml")
    study = plan_runs(case, ["yade"], laws=["viscoelastic", "betan"], told=e)
    refused_by_study = [n["reason"] for n in study.not_available if n["law"] == "betan"]
    pair = case.pair("sphere-sphere")
    promise = keyword_promise_plan("keywords", "yade", {"yade:betan": "betan"}, pair, 1.0, [e])
    why = keyword_refusal("yade:betan", e)
    assert bool(why) == (e == 1.0)
    if why:
        assert refused_by_study and all(r.endswith(why) for r in refused_by_study)
        assert not [r for r in study.runs if r.law == "betan"]
        assert promise.refused == {("yade:betan", e): why} and not promise.ladders
    else:
        assert not refused_by_study and promise.refused == {}
        study_betan = [r for r in study.runs if r.law == "betan" and r.pair.geometry == "sphere-sphere"]
        by_velocity = {}
        for r in study_betan:
            by_velocity.setdefault(r.velocity, []).append(r)
        rungs = promise.ladders[("yade:betan", e)]
        for ladder in by_velocity.values():  # the same ladder and reference row, at each velocity
            assert [r.time_step_factor for r in ladder] == [r.time_step_factor for r in rungs]
            assert {k: v for k, v in ladder[0].reference.items() if k != "K"} == \
                {k: v for k, v in rungs[0].reference.items() if k != "K"}
