"""The damping keywords' registry (contact_model.keywords): each keyword's map from what the user
writes to its coefficient, and what its own equation restitutes, checked against an independent
ODE solution (contact_model.constant_restitution, scipy's DOP853) and the closed forms."""

import math

import pytest

from contact_model.constant_restitution import restitution_of_damping
from contact_model.keywords import (KEYWORDS, kratos_gamma, log_beta, promised_restitution, restitution_keywords,
                                    thornton_beta)

GRID = (0.05, 0.1, 0.3, 0.5, 0.8, 0.9, 0.95, 0.99)


def test_every_keyword_is_complete_and_names_its_source():
    for name, k in KEYWORDS.items():
        assert name == k.name and name.startswith(f"{k.code}:") and k.form in ("quarter", "half", "velocity")
        assert k.told in ("e", "beta", "alpha", "eta") and k.source and k.releases and k.written
        assert k.criterion == ("F0" if k.clipped else "x0")
    assert set(restitution_keywords()) == {n for n, k in KEYWORDS.items() if k.told == "e"}


@pytest.mark.parametrize("name", ["liggghts:hertz-coefficientRestitution", "lammps:coeff_restitution"])
@pytest.mark.parametrize("e", GRID)
def test_the_beta_map_keeps_its_promise_exactly_without_the_clip(name, e):
    assert promised_restitution(name, e) == pytest.approx(e, rel=1e-13)


@pytest.mark.parametrize("name", sorted(n for n in KEYWORDS if KEYWORDS[n].told == "e"))
@pytest.mark.parametrize("e", (0.3, 0.5, 0.8, 0.95))
def test_the_promise_agrees_with_an_independent_ode_solution(name, e):
    k = KEYWORDS[name]
    if k.form == "half":  # Brilliantov's law at its K: the tests' own scipy solver of the viscoelastic ODE
        from scipy_solver import solve_collision as scipy_collision

        independent = scipy_collision(k.b(e))[f"eps_{k.criterion}"]
    else:
        independent = restitution_of_damping(k.b(e), k.criterion)
    assert promised_restitution(name, e) == pytest.approx(independent, abs=1e-9)


def test_yade_en_vn_is_brilliantov_at_the_k_of_its_pade():
    """YADE's en + vn (2024.02a and later): beta = v*(e)^2 vn^(-1/5), v* the root of its [3/6] Pade;
    read in the installed 2025.2.0 (en = 0.8, vn = 1: phys.beta = 0.2011368512, and eps measured
    0.86672 at V = 0.1, 0.75957 at V = 3). Its promise holds to 2e-4 at e = 0.3, 1e-6 above 0.8."""
    from contact_model.keywords import yade_en_vn_K, yade_vstar

    assert yade_vstar(0.8) ** 2 == pytest.approx(0.2011368512, rel=1e-9)  # vn = 1
    assert yade_vstar(1.0) == 0.0
    assert yade_en_vn_K(0.8) == pytest.approx(1.25**0.6 * 0.2011368512, rel=1e-9)
    from reference import solve_collision

    assert solve_collision(yade_en_vn_K(0.8, 0.1))["eps_F0"] == pytest.approx(0.86672, abs=2e-5)
    assert solve_collision(yade_en_vn_K(0.8, 3.0))["eps_F0"] == pytest.approx(0.75957, abs=5e-5)
    assert abs(promised_restitution("yade:en-vn", 0.3) - 0.3) == pytest.approx(2.0e-4, abs=1e-5)
    for e in (0.8, 0.9, 0.95, 0.99):
        assert abs(promised_restitution("yade:en-vn", e) - e) < 1e-6


def test_lammps_tsuji_restitutes_what_the_study_measured_and_the_sqrt2_would_mend():
    """Told e = 0.9049, LAMMPS's tsuji restitutes 0.9320 (both builds, tests/test_engine_lammps.py);
    with the development branch's sqrt(2) its fit is within 3e-4 of e there."""
    told = 0.9049
    assert promised_restitution("lammps:tsuji", told) == pytest.approx(0.93200, abs=1e-4)
    from reference.quarter_power_damping import restitution_quarter_power

    mended = restitution_quarter_power(math.sqrt(2) * KEYWORDS["lammps:tsuji"].b(told), "x0")
    assert abs(mended - told) < 3e-4
    assert "PR #5113" in KEYWORDS["lammps:tsuji"].known_defect


def test_the_thornton_fit_of_yade_and_kratos_holds_to_3e_4_up_to_0_9_and_drifts_above():
    for e in (0.05, 0.1, 0.3, 0.5, 0.8, 0.9):
        assert abs(promised_restitution("yade:en", e) - e) < 3e-4, e
    assert promised_restitution("yade:en", 0.95) == pytest.approx(0.9481, abs=2e-4)
    assert promised_restitution("kratos:hertz-COEFFICIENT_OF_RESTITUTION", 0.99) == pytest.approx(0.9789, abs=2e-4)
    assert thornton_beta(1.0) == 0.0 and kratos_gamma(0.9995) == 0.0 and kratos_gamma(1e-4) == thornton_beta(1e-3)


def test_esys_writes_pi_as_3_1415926_and_keeps_its_promise_to_1e_7():
    err = promised_restitution("esys:HertzMindlinVisco", 0.5) - 0.5
    assert 0 < abs(err) < 1e-7
    assert log_beta(0.5, pi=3.1415926) != log_beta(0.5)


def test_a_k_beyond_the_reference_solvers_range_is_a_cell_that_says_so_not_a_crash():
    """YADE's en + vn told the shipped config's e = 0.05 at vn reaches K = 11.49 at V = 10 vn, beyond
    the reference solver's [0, 10]: promise_over_velocity gives that row no eps and a note, and
    every other e of the shipped grid its eps (`snakemake -j2 keywords` crashed there)."""
    from pathlib import Path

    import yaml

    from analysis.keyword_promise import over_velocity_cell, promise_over_velocity
    from reference import solve_collision

    grid = yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text())
    restitution = grid["keywords"]["restitution"]
    assert 0.05 in restitution
    table = promise_over_velocity(KEYWORDS.values(), restitution)
    assert set(table.keyword) == {"yade:en-vn"} and len(table) == 6 * len(restitution)
    out = table[table.note != ""]
    assert list(zip(out.e_requested, out.V_over_vn)) == [(0.05, 10.0)]
    row = out.iloc[0]
    assert row.K == pytest.approx(11.48785974, rel=1e-8) and math.isnan(row.eps_own_equation)
    assert row.note == "out of the reference's range: K = 11.5 > 10"
    assert over_velocity_cell(row.eps_own_equation, row.note) == row.note
    inside = table[(table.e_requested == 0.05) & (table.V_over_vn == 3.0)].iloc[0]
    assert inside.eps_own_equation == pytest.approx(solve_collision(inside.K)["eps_F0"], abs=0)
    assert over_velocity_cell(inside.eps_own_equation, inside.note) == f"{inside.eps_own_equation:.5f}"
    assert table.drop(out.index).eps_own_equation.notna().all()


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_the_keywords_target_with_yade_2025_told_e_0_05_tabulates_the_out_of_range_cell(tmp_path):
    """`snakemake -j2 keywords` with YADE 2025 told the shipped grid's smallest e, 0.05 (and 0.5):
    it finishes (it crashed after 57 s with 'ValueError: K must lie in [0.0, 10.0], got [11.48785974]'),
    promise.md's cell at V = 10 vn says why it has no eps, and the log says it too."""
    import subprocess
    import sys
    from pathlib import Path

    import pandas as pd

    from engine_cases import missing
    from workflow_copy import copy_workflow

    root = Path(__file__).resolve().parents[1]
    if not (root / ".yade-2025" / "yade").exists():
        missing("YADE 2025 is not installed; install it with: make yade-2025")
    project = copy_workflow(tmp_path / "project")
    out = subprocess.run([sys.executable, "-m", "snakemake", "-j2", "keywords", "--config",
                          "builds=[{id: yade-2025, code: yade, executable: .yade-2025/yade}]",
                          "keywords={case: cases/steel.yaml, geometry: sphere-sphere, velocity: 1.0, "
                          "restitution: [0.05, 0.5], measured: null}"],
                         cwd=project, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    keywords = project / "results" / "keywords"
    summary = (keywords / "promise.md").read_text()
    row = next(line for line in summary.splitlines() if line.startswith("| 0.05 "))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[-1] == "out of the reference's range: K = 11.5 > 10"
    assert all(float(c) > 0 for c in cells[1:-1])  # the other velocities' eps
    over = pd.read_csv(keywords / "promise_over_velocity.csv")
    assert over.note.fillna("").tolist().count("out of the reference's range: K = 11.5 > 10") == 1
    assert f"## {KEYWORDS['yade:en-vn'].written}: away from the velocity it is told" in summary
    log = (project / "logs" / "keywords" / "summary.log").read_text()
    assert "out of the reference's range: K = 11.5 > 10" in log
    promise = pd.read_csv(keywords / "promise.csv").set_index(["keyword", "e_requested"])
    assert abs(promise.loc[("yade:en-vn", 0.5)].err_own_equation) + promise.loc[("yade:en-vn", 0.5)].resolution <= 1e-6
