"""An oblique deck's record (LAMMPS's, LIGGGHTS's) that cannot become a dump fails its run, named
(`engines.oblique_record.read_oblique_record`): unreadable, too short, of another width, not finite,
or holding no collision; a Python deck's (YADE's, ESyS's: `deck_record`) reported failed by its
status, or unreadable. Each message names the run and what is wrong; nothing is returned."""

from pathlib import Path

import pytest

from contact_model import load_case
from engines.errors import EngineRunFailed
from engines.oblique_plan import oblique_plan
from engines.oblique_record import deck_record, read_oblique_record

ROOT = Path(__file__).resolve().parents[1]
TEST4 = load_case(ROOT / "cases" / "oblique" / "chung_ooi_test4.yaml")
HEADER = "time overlap normal_velocity normal_force tangential_velocity spin_1 spin_2 tangential_force\n"


@pytest.fixture(scope="module")
def run():
    return oblique_plan([TEST4], "lammps", "lammps-2025", "LAMMPS (22 Jul 2025 - Update 4)", [1000, 2000, 4000]).runs[0]


def rows(n: int, width: int = 8, overlap: float = -1e-6) -> str:
    """n rows of free flight (no contact): time, a constant gap, the rest zero."""
    return "".join(" ".join(["%.17g" % (i * 1e-9), "%.17g" % overlap] + ["0"] * (width - 2)) + "\n" for i in range(n))


@pytest.mark.parametrize("text, words", [
    (HEADER + "1 2 three 4 5 6 7 8\n" * 5, "unreadable engine record"),
    (HEADER + rows(2), "has 2 rows of 8 columns, not 8"),
    (HEADER + rows(5, width=7), "has 5 rows of 7 columns, not 8"),
    (HEADER + rows(3) + "4e-9 nan 0 0 0 0 0 0\n" + rows(2), "the engine produced NaN or inf (record row 4)"),
    (HEADER + rows(20), "overlap never becomes positive"),  # the bodies never touch: the extraction says so
], ids=["unreadable", "short", "width", "nan", "no-collision"])
def test_a_record_that_cannot_become_a_dump_fails_its_run_named(run, tmp_path, text, words):
    raw = tmp_path / "record.txt"
    raw.write_text(text)
    with pytest.raises(EngineRunFailed) as failed:
        read_oblique_record(raw, run, tmp_path / "log.lammps")
    assert words in str(failed.value) and run.name in str(failed.value), str(failed.value)


def test_a_missing_record_fails_its_run_named(run, tmp_path):
    with pytest.raises(EngineRunFailed, match="unreadable engine record"):
        read_oblique_record(tmp_path / "none.txt", run, tmp_path / "log.lammps")


@pytest.mark.parametrize("status, text, words", [
    ({"ok": False, "error": "RuntimeError: the deck runs the elastic normal law only"}, None,
     "YADE: RuntimeError: the deck runs the elastic normal law only"),  # the deck's own failure, first
    ({"ok": True}, "x1,y1\n1,two\n", "unreadable engine record"),
    ({"ok": True}, None, "unreadable engine record"),  # the deck said ok, and wrote nothing
], ids=["deck-failed", "unreadable", "missing"])
def test_a_python_deck_s_failed_or_unreadable_run_fails_named(run, tmp_path, status, text, words):
    """YADE's and ESyS's decks (`engines.oblique_record.deck_record`): a run their status reports failed
    fails with the engine's name and the deck's error, before the record is read; a record that cannot
    be read fails naming it."""
    raw = tmp_path / "record.csv"
    if text is not None:
        raw.write_text(text)
    with pytest.raises(EngineRunFailed) as failed:
        deck_record("YADE", run, status, raw, tmp_path / "log.yade")
    assert words in str(failed.value) and run.name in str(failed.value), str(failed.value)


def test_a_python_deck_s_landed_record_is_its_rows(run, tmp_path):
    """One row stays a row (2-D), the header is skipped, the numbers are read to the bit (%.17g)."""
    raw = tmp_path / "record.csv"
    raw.write_text("a,b,c\n%.17g,%.17g,%.17g\n" % (0.1, -2.5e-3, 1.0 / 3.0))
    data = deck_record("ESyS-Particle", run, {"ok": True, "seconds": 0.1}, raw, tmp_path / "log")
    assert data.shape == (1, 3) and data.tolist() == [[0.1, -2.5e-3, 1.0 / 3.0]]
