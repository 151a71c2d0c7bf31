"""LIGGGHTS 3.8.0 oblique impacts (`tangential history`), run for real in Debian's build: the
unmodified model meets its own equations (the reference with the registry's form,
`liggghts:history`) in both geometries; a deck whose k_t or mu is 1e-4 off FAILs naming the checks;
one and two MPI ranks give the same dump, the contact's history crossing the processor boundary.

Cases: Chung & Ooi's test 4 (alumina on a plane, V = 3.9 m/s, mu = 0.092) at 10 deg (stick, then
micro-slip) and 60 deg (gross sliding); test 8 (an aluminium sphere spinning onto one 5 times larger,
1000 times denser and stiffer, v_n = 0.2 m/s, mu = 0.4) at a contact-point incidence of 10 deg. The
ladder is the study's four coarsest rungs (T_e/1000 ... /8000; see LADDER); the file takes ~55 s here
(6 tests, with another engine process sharing the 2 cores).

Measured (docs/tangential.md, the study's five rungs on the reduced set): every check passes with |error|
<= 3.3e-8 and resolution <= 7.6e-8; on two ranks every column of every dump equals the serial one bitwise
(the plane's sphere moves from rank 0 to rank 1 in mid-contact, the two spheres sit on different ranks).
At T_e/8000, k_t x (1 + 1e-4) moves omega' by -1.0e-4 and e_t by -2.0e-3 (relative) at 10 deg on the
plane, v_t' by -1.9e-3 between the spheres; mu x (1 + 1e-4) moves omega' and F_t,max by 1.0e-4 at 60 deg.
"""

from pathlib import Path

import pytest
import yaml

from analysis.oblique import processor_boundary_checks, rung_rows
from contact_model import load_case
from engines.liggghts_oblique import contact_variables, run_liggghts_oblique
from engines.oblique_plan import ObliquePlan, oblique_plan
from oblique_gate import config_build, gate, ladders, named_failures
from records.dump_file import read_dump

ROOT = Path(__file__).resolve().parents[1]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
#: The study's four coarsest rungs (T_e/1000 ... /8000). Three leave the sticking impact's e_t unresolved
#: (measured: error -2.3e-6, resolution 1.1e-6 at 10 deg on the plane: its stick-slip transition converges
#: at first order); four resolve it.
LADDER = CONFIG["oblique"]["ladder"][:4]
MODEL = "liggghts:history"
TEST4 = load_case(ROOT / "cases" / "oblique" / "chung_ooi_test4.yaml")
TEST8 = load_case(ROOT / "cases" / "oblique" / "chung_ooi_test8.yaml")
#: (case, contact-point incidence [deg]) of the ladders run here.
IMPACTS = ((TEST4, 10.0), (TEST4, 60.0), (TEST8, 10.0))
#: The quantities a k_t 1e-4 too stiff must move beyond the tolerance at 10 deg (omega' ~ k_t there).
SEEN_KT = {"omega_after", "vt_after", "e_t", "rebound_angle"}
#: ... and a mu 1e-4 too large at 60 deg (gross sliding: the tangential impulse is mu times the normal one).
SEEN_MU = {"omega_after", "vt_after", "e_t", "rebound_angle", "Ft_max"}


@pytest.fixture(scope="module")
def study(tmp_path_factory, runs_engine):
    b = config_build("liggghts-3.8", "liggghts")
    runs = ladders(b, MODEL, IMPACTS, LADDER, ranks=(1, 2))  # every rung on one rank, the coarsest on two
    every = [r for rs in runs.values() for r in rs]
    sweep = run_liggghts_oblique(every, tmp_path_factory.mktemp("liggghts"), b.executable).raise_first()
    return b, runs, sweep


def test_the_unmodified_model_meets_its_own_equation_in_both_geometries(study):
    """Every quantity of every ladder passes: |error| + resolution <= 1e-6 (the plane at 10 and 60 deg,
    the unequal spheres at 10 deg), the normal half (T, eps) to 1e-9."""
    _, runs, sweep = study
    for (case, angle), ladder in runs.items():
        serial = [r for r in ladder if r.ranks == 1]
        assert len(serial) == len(LADDER)
        checks, _ = gate(serial, sweep)
        assert len(checks) == 7 and (checks.status == "PASS").all(), checks.to_string()
        assert set(checks.quantity) == {"T", "eps", "vt_after", "omega_after", "e_t", "rebound_angle", "Ft_max"}
        normal = checks[checks.quantity.isin(["T", "eps"])]
        assert (normal.error.abs() < 1e-9).all(), (case, angle, normal.to_string())


def test_one_and_two_ranks_give_the_same_dump(study):
    """The coarsest rung again on two ranks, the box split at the contact: the plane's sphere starts on
    rank 0 and ends on rank 1 (it crosses y = 0 in mid-contact with the wall's history); the two spheres
    sit on ranks 0 and 1 throughout. Every column equals the serial run's (the gate's check: 1e-12;
    measured: bitwise)."""
    _, runs, sweep = study
    every = [r for rs in runs.values() for r in rs]
    rungs = rung_rows(every, sweep)
    plan = ObliquePlan(runs=every, build=every[0].build)
    checks = processor_boundary_checks(rungs, plan, sweep.failures)
    assert len(checks) == len(IMPACTS) and (checks.status == "PASS").all(), checks.to_string()
    assert (checks.error == 0).all(), checks.to_string()
    for ladder in runs.values():
        (two,) = [r for r in ladder if r.ranks == 2]
        meta, _ = read_dump(sweep.dumps[two.name], oblique=True)
        if two.pair.body_2.is_plane:
            assert meta["owners"] == {"1": 0} and meta["owners_end"] == {"1": 1}, meta["owners_end"]
        else:
            assert meta["owners"] == {"1": 0, "2": 1} == meta["owners_end"]


@pytest.mark.parametrize("knob, impact, seen", [("stiffness_factor", (TEST4.name, 10.0), SEEN_KT),
                                                ("stiffness_factor", (TEST8.name, 10.0), SEEN_KT),
                                                ("friction_factor", (TEST4.name, 60.0), SEEN_MU)])
def test_a_deck_1e_4_off_fails_naming_the_checks(study, tmp_path, knob, impact, seen):
    """k_t x (1 + 1e-4) in the generated deck (a sticking impact, both geometries), or mu x (1 + 1e-4)
    (gross sliding): the tangential checks FAIL, each naming its build, model, error and the tolerance;
    the normal half (T, eps) still passes."""
    b, runs, _ = study
    ladder = [r for r in runs[impact] if r.ranks == 1]
    sweep = run_liggghts_oblique(ladder, tmp_path, b.executable, **{knob: 1.0 + 1e-4})
    variables = read_dump(sweep.dumps[ladder[0].name], oblique=True)[0]["engine_variables"]
    word = "kt" if knob == "stiffness_factor" else "mu"
    assert float(variables[word]) == pytest.approx((1 + 1e-4) * float(contact_variables(ladder[0])[word]), rel=1e-15)
    checks, _ = gate(ladder, sweep)
    failed, passed = named_failures(checks, "liggghts-3.8", MODEL)
    assert seen <= failed, checks.to_string()
    assert passed >= {"T", "eps"}, checks.to_string()


def test_a_run_the_decks_cannot_write_is_refused_before_the_engine_starts(tmp_path):
    """Another code's model, the default law (LIGGGHTS's restitution keyword, which `model
    hertz/stiffness` cannot be) or another engine's run: ValueError naming the run and what is wrong,
    and no engine started (nothing written in the work folder)."""
    import re
    from dataclasses import replace

    (run, *_) = oblique_plan([TEST4], "liggghts", "liggghts-3.8", "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)",
                             LADDER).runs
    other = replace(run, model="lammps:mindlin")
    with pytest.raises(ValueError, match=re.escape(f"{other.name}: LIGGGHTS's oblique decks have no tangential "
                                                   "model 'lammps:mindlin'; known: ('liggghts:history',)")):
        run_liggghts_oblique([other], tmp_path / "model")
    keyword = replace(run, normal=replace(run.normal, law="default", matched_restitution=0.9))
    with pytest.raises(ValueError, match="not the restitution keyword of law 'default'"):
        run_liggghts_oblique([keyword], tmp_path / "keyword")
    lammps = replace(run, normal=replace(run.normal, engine="lammps"))
    with pytest.raises(ValueError, match="is not a LIGGGHTS run \\(engine 'lammps'\\)"):
        run_liggghts_oblique([lammps], tmp_path / "engine")
    assert not any(tmp_path.iterdir())
