"""The oblique gate end to end in real engines (issue 'Oblique impacts'): Chung & Ooi's test 4
at 10 deg (stick and slip inside the contact) in LAMMPS `mindlin` and YADE's Hertz-Mindlin, a
ladder each, against the model's own reference (analysis.oblique):

- unmodified, every check passes (|error| + resolution <= 1e-6);
- a deck whose tangential stiffness k_t is scaled by 1 + 1e-4 fails, naming the checks;
- the classic wall hertz/history of LAMMPS 22 Jul 2025 crashes (gamman = 0): FAIL naming the
  engine's message, or KNOWN DEFECT where the config declares it (never PASS).
"""

import shutil
from pathlib import Path

import pandas as pd
import pytest
import yaml

from contact_model import load_case
from engines.builds import load_builds
from engines.codes import CODES
from engines.lammps_oblique import run_lammps_oblique
from engines.oblique_plan import oblique_plan
from engines.yade_oblique import run_yade_oblique

from engine_cases import missing
from oblique_gate import gate, named_failures

ROOT = Path(__file__).resolve().parents[1]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
CASE = load_case(ROOT / "cases" / "oblique" / "chung_ooi_test4.yaml")
LADDER = CONFIG["oblique"]["ladder"]
#: The quantities a k_t 1e-4 too stiff must move beyond the tolerance at 10 deg (measured: omega'
#: by about 1e-4 relative, 100 times the tolerance).
SEEN = {"omega_after", "vt_after", "e_t", "rebound_angle"}


def build(build_id: str):
    b = next(b for b in load_builds(CONFIG["builds"], ROOT) if b.id == build_id)
    if shutil.which(b.executable) is None and not Path(b.executable).exists():
        missing(f"{b.executable} ({build_id}) is not installed; {CODES[b.code].install_hint}")
    return b


def runs(b, model: str, angle: float):
    from engines.builds import check_build

    plan = oblique_plan([CASE], b.code, b.id, check_build(b), LADDER)
    return [r for r in plan.runs if r.model == model and abs(r.angle - angle) < 1e-9]


RUNNERS = {"lammps": lambda runs, work, exe, scale: run_lammps_oblique(runs, work, exe, stiffness_factor=scale),
           "yade": lambda runs, work, exe, scale: run_yade_oblique(runs, work, exe,
                                                                    stiffness_scale=None if scale == 1 else scale)}


@pytest.mark.parametrize("build_id, model", [("lammps-2025", "lammps:mindlin"), ("yade-2023", "yade:mindlin")])
def test_a_tangential_stiffness_off_by_1e_4_fails_naming_the_checks(build_id, model, tmp_path, runs_engine):
    b = build(build_id)
    ladder = runs(b, model, 10.0)
    assert len(ladder) == len(LADDER)
    run = RUNNERS[b.code]
    good, _ = gate(ladder, run(ladder, tmp_path / "good", b.executable, 1.0))
    assert len(good) >= 6 and (good.status == "PASS").all(), good[good.status != "PASS"].to_string()
    bad, _ = gate(ladder, run(ladder, tmp_path / "stiff", b.executable, 1.0 + 1e-4))
    # Each failure names what failed and by how much against what.
    failed, passed = named_failures(bad, build_id, model)
    assert SEEN <= failed, bad.to_string()
    # The normal half does not see the tangential stiffness: T and eps still pass.
    assert passed >= {"T", "eps"}, bad.to_string()


def test_the_classic_wall_crash_fails_unless_declared_and_is_never_a_pass(tmp_path, runs_engine):
    b = build("lammps-2025")
    ladder = runs(b, "lammps:hertz/history", 60.0)
    sweep = run_lammps_oblique(ladder, tmp_path, b.executable)
    assert sweep.failures, "22 Jul 2025's classic wall with gamman = 0 no longer crashes: the known defect is fixed"
    plain, _ = gate(ladder, sweep)
    assert list(plain.status) == ["FAIL"] and "Non-numeric atom coords" in plain.detail.iloc[0]
    declared = [d for d in CONFIG["oblique"]["known_defects"] if d["model"] == "lammps:hertz/history"]
    assert declared, "config oblique.known_defects no longer declares the classic wall's crash"
    known, _ = gate(ladder, sweep, declared)
    assert list(known.status) == ["KNOWN DEFECT"] and declared[0]["reference"] in known.detail.iloc[0]
    # A declaration whose failure text does not match is no excuse: FAIL.
    other = [{**declared[0], "fails": "Lost atoms"}]
    assert list(gate(ladder, sweep, other)[0].status) == ["FAIL"]


def test_named_failures_refuses_a_fail_that_does_not_name_what_it_failed():
    """The helper the 1e-4-off tests assert with (tests/oblique_gate.py): a FAIL row naming its build,
    model and '> tolerance', and exceeding it, gives (failed, passed); a FAIL of another build, one
    without the tolerance in its detail (a ladder that did not land) or one within the tolerance is
    an AssertionError naming the row. Rows as `analysis.oblique.oblique_checks` writes them."""
    fail = {"build": "lammps-2025", "model": "lammps:mindlin", "quantity": "e_t", "status": "FAIL",
            "error": 2e-6, "resolution": 1e-7, "detail": "|2e-06| + 1e-07 > 1e-06"}
    ok = {**fail, "quantity": "T", "status": "PASS", "error": 1e-9, "detail": "|1e-09| + 1e-07 <= 1e-06"}
    assert named_failures(pd.DataFrame([fail, ok]), "lammps-2025", "lammps:mindlin", 1e-6) == ({"e_t"}, {"T"})
    for wrong, words in (({"build": "lammps-2021"}, "does not name lammps-2025, lammps:mindlin and > 1e-06"),
                         ({"detail": "the ladder did not land: no dump"}, "does not name"),
                         ({"error": 5e-7}, "within the tolerance 1e-06")):
        with pytest.raises(AssertionError, match=words):
            named_failures(pd.DataFrame([{**fail, **wrong}]), "lammps-2025", "lammps:mindlin", 1e-6)
