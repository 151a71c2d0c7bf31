"""LIGGGHTS, run for real: the viscoelastic Hertz contact against the reference solver, and the
errors a user gets for a crash or a run that misses the collision (a missing engine:
test_engine_drivers, for every code)."""

import dataclasses

import pytest

from engine_cases import TOLERANCE, VELOCITY, relative_errors, require_engine, steel_pair
from engines import EngineRunFailed, RunSpec
from engines import liggghts
from records.collision_metrics import collision_metrics
from records.dump_file import read_dump


@pytest.fixture(autouse=True)
def _needs_liggghts(runs_engine):
    require_engine("liggghts", "liggghts")


def run(tmp_path, geometry, law="viscoelastic", K=0.1, **kw):
    spec = RunSpec("steel", "liggghts", law, steel_pair(geometry, K), VELOCITY, **kw)
    meta, cols = read_dump(liggghts.run_liggghts([spec], tmp_path).raise_first().dumps[spec.name])
    return spec, meta, collision_metrics(*(cols[c] for c in ("time", "overlap", "normal_velocity", "normal_force")),
                                         impact_velocity=VELOCITY)


@pytest.mark.parametrize("geometry", ["sphere-sphere", "sphere-plane"])
def test_viscoelastic_matches_reference_both_criteria(tmp_path, geometry):
    spec, meta, m = run(tmp_path, geometry)
    assert meta["engine"] == "liggghts" and "3.8.0" in meta["engine_version"]
    assert meta["K"] == pytest.approx(0.1, rel=1e-12) and len(meta["deck_sha256"]) == 64
    assert m.samples_in_contact >= 200
    errors = relative_errors(m, spec)
    for q, e in errors.items():
        assert abs(e) < TOLERANCE, (q, e)


@pytest.mark.parametrize("geometry", ["sphere-sphere", "sphere-plane"])
def test_clipped_force_matches_reference_F0(tmp_path, geometry):
    spec, meta, m = run(tmp_path, geometry, law="viscoelastic_clipped")
    assert meta["represents"] == ["F0"]
    errors = relative_errors(m, spec)
    for q in ("A", "T_F0", "eps_F0"):
        assert abs(errors[q]) < TOLERANCE, (q, errors[q])
    # After the force zero the bodies fly apart: the x0 values are not the x0 trajectory's.
    assert abs(errors["eps_x0"]) > TOLERANCE


def test_elastic_contact_is_hertz(tmp_path):
    spec, _, m = run(tmp_path, "sphere-plane", K=0.0)
    errors = relative_errors(m, spec)
    assert abs(errors["eps_x0"]) < 1e-5  # energy is conserved to the integrator's accuracy
    for q in ("A", "T_x0"):
        assert abs(errors[q]) < 1e-4, (q, errors[q])


def test_engine_error_names_the_log_and_leaves_no_dump(tmp_path):
    broken = tmp_path / "decks"
    broken.mkdir()
    for deck in liggghts.LIGGGHTS.decks.glob("*.in"):
        (broken / deck.name).write_text(deck.read_text())
    deck = broken / "sphere_plane.in"
    deck.write_text(deck.read_text().replace("atom_style      granular", "atom_style      nonsense"))
    engine = dataclasses.replace(liggghts.LIGGGHTS, decks=broken)
    spec = RunSpec("steel", "liggghts", "viscoelastic", steel_pair("sphere-plane"), VELOCITY)
    before = RunSpec("steel", "liggghts", "viscoelastic", steel_pair("sphere-sphere"), VELOCITY)
    after = RunSpec("steel", "liggghts", "viscoelastic", steel_pair("sphere-sphere", K=0.2), VELOCITY)
    sweep = engine.run([before, spec, after], tmp_path / "out")
    assert list(sweep.dumps) == [before.name]  # the run before the crash landed
    err = sweep.failures[spec.name]
    assert "exited with status" in str(err) and "liggghts.log" in str(err) and "Invalid atom style" in str(err)
    assert "not run: liggghts stopped in" in str(sweep.failures[after.name])
    assert not (tmp_path / "out" / f"{spec.name}.csv").exists()
    with pytest.raises(EngineRunFailed):
        sweep.raise_first()


@pytest.mark.parametrize("steps, words", [(10, "never touch"), (200, "still open")])
def test_runs_that_miss_the_collision_fail(tmp_path, monkeypatch, steps, words):
    real_steps = RunSpec.steps
    monkeypatch.setattr(RunSpec, "steps",
                        lambda self: steps if self.pair.geometry == "sphere-sphere" else real_steps(self))
    spec = RunSpec("steel", "liggghts", "viscoelastic", steel_pair("sphere-sphere"), VELOCITY)
    good = RunSpec("steel", "liggghts", "viscoelastic", steel_pair("sphere-plane"), VELOCITY)
    with pytest.raises(EngineRunFailed, match=words):
        liggghts.run_liggghts([spec, good], tmp_path).raise_first()
    assert not (tmp_path / f"{spec.name}.csv").exists()
    assert (tmp_path / f"{good.name}.csv").exists()


def test_a_sweep_in_one_process_equals_solo_runs(tmp_path):
    """`clear` between runs leaves nothing behind: the dumps' data are identical to solo runs."""
    specs = [RunSpec("steel", "liggghts", law, steel_pair(g), VELOCITY,
                     matched_restitution=0.9 if law == "default" else None)
             for g in ("sphere-plane", "sphere-sphere") for law in ("default", "viscoelastic")]
    swept = liggghts.run_liggghts(specs, tmp_path / "sweep").raise_first().dumps[specs[-1].name]
    solo = liggghts.run_liggghts(specs[-1:], tmp_path / "solo").raise_first().dumps[specs[-1].name]
    assert read_dump(swept)[1]["overlap"].tolist() == read_dump(solo)[1]["overlap"].tolist()
    assert read_dump(swept)[1]["normal_force"].tolist() == read_dump(solo)[1]["normal_force"].tolist()
