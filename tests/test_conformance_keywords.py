"""The conformance kit's keywords of codes the study does not run, and of keywords told no restitution:
a plan exported for the keyword, run by a velocity-Verlet integrator written here in the code's own
notation (not the plan's `law_equation`, not the project's `reference.engine_map`), gates PASS; the
same integrator with its damping coefficient b 1e-4 too large FAILs, naming the eps checks.

- `chrono:smc_hertz`: Chrono's ChSystemSMC default Hertz (material properties),
  S_n = 2 E* sqrt(R* delta), F = (2/3) S_n delta + 2 sqrt(5/6) |beta(e)| sqrt(S_n M*) d(delta)/dt,
  clipped at F >= 0 (ChContactSMC.cpp:94-104, 170-178 @7689fbc0), i.e. the quarter form at
  b = (5/2)|beta(e)|, beta(e) = ln e / sqrt(ln^2 e + pi^2). Chrono is no engine of the study: the
  keyword is exported by the kit and never planned into the study's builds.
- `yade:betan` given a damping ratio (--beta): YADE's Hertz-Mindlin, c_n = 2 beta sqrt(M* k_t),
  k_t = 2 E* sqrt(R* delta), clipped, i.e. the quarter form at b = sqrt(15/2) beta, the beta as given
  (no restitution asked, no promise), named `told_beta` in plan.json, plan.csv and README.md.

And what the kit cannot export is refused in words (exit 2, no plan written).

Unit tier: in-process (`conformance.__main__.main`), the report without its figures.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from conformance.__main__ import main

import plan_verlet

ROOT = Path(__file__).resolve().parents[1]
STEEL = str(ROOT / "cases" / "steel.yaml")
#: The relative change of a damping coefficient the gate must see: eps moves by ~1e-4 b/2 ~ 4e-6 (b ~ 0.08).
PERTURBATION = 1e-4


def load(folder: Path) -> dict:
    return json.loads((folder / "plan.json").read_text())


def verdict(folder: Path) -> dict:
    return json.loads((folder / "verdict.json").read_text())


def integrate(run: dict, force) -> np.ndarray:
    """`plan_verlet.integrate` of `force(delta, rate)` [N]: one row per step, time, overlap,
    d(delta)/dt, force (SI)."""
    s = plan_verlet.integrate(run, force)
    return np.column_stack([s["time"], s["overlap"], s["rate"], s["force"]])


def write_dumps(folder: Path, law) -> None:
    """Every run of the plan, `law(run)` giving its force(delta, rate), in the study's dump format."""
    plan = load(folder)
    for run in plan["runs"]:
        rows = integrate(run, law(run))
        head = (f"# hertz-dem-dump: 1\n# plan_id: \"{plan['plan_id']}\"\n# run: \"{run['name']}\"\n"
                "# engine_version: \"tests/test_conformance_keywords.py\"\ntime,overlap,normal_velocity,normal_force\n")
        (folder / run["dump"]).write_text(head + "".join("%.17g,%.17g,%.17g,%.17g\n" % tuple(r) for r in rows))


def abs_log_beta(e: float) -> float:
    """|beta(e)| = |ln e| / sqrt(ln^2 e + pi^2), written here (not contact_model.keywords.log_beta)."""
    return abs(math.log(e)) / math.sqrt(math.log(e) ** 2 + math.pi**2)


def chrono_hertz(scale: float = 1.0):
    """Chrono's default Hertz in its own notation, told the run's e; `scale` multiplies its damping
    (b = (5/2)|beta(e)| scale): S_n = 2 E* sqrt(R* delta), k_n = (2/3) S_n,
    g_n = 2 sqrt(5/6) |beta(e)| sqrt(S_n M*), F = k_n delta + g_n d(delta)/dt, clipped at F >= 0."""
    def law(run):
        E, R, M = run["effective"]["E_star_Pa"], run["effective"]["R_star_m"], run["effective"]["M_star_kg"]
        beta = scale * abs_log_beta(run["told_e"])

        def force(d, rate):
            Sn = 2.0 * E * math.sqrt(R * d)
            return max(2.0 / 3.0 * Sn * d + 2.0 * math.sqrt(5.0 / 6.0) * beta * math.sqrt(Sn * M) * rate, 0.0)
        return force
    return law


@pytest.fixture(scope="module")
def chrono_plan(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("chrono") / "plan"
    assert main(["export", STEEL, "--keyword", "chrono:smc_hertz", "--K", "0.1", "--out", str(out)]) == 0
    return out


def copy_of(plan: Path, tmp_path: Path) -> Path:
    import shutil

    out = tmp_path / "check"
    shutil.copytree(plan, out)
    return out


def test_chrono_plan_is_the_clipped_quarter_form_at_five_halves_beta(chrono_plan):
    plan = load(chrono_plan)
    assert plan["carrier_code"] == "chrono" and plan["laws"] == ["default"] and len(plan["runs"]) == 8
    for run in plan["runs"]:
        eq = run["law_equation"]
        assert run["keyword"] == "chrono:smc_hertz" and run["represents"] == ["F0"]
        assert eq["clipped"] and eq["damping_power"] == 0.25
        # b = (5/2)|beta(e)|, to round-off, from the e the plan tells the code
        assert eq["dimensionless_coefficient"] == pytest.approx(2.5 * abs_log_beta(run["told_e"]), rel=1e-14)
        # g = 2 sqrt(5/6) |beta| sqrt(2 E* sqrt(R*) M*) [N s m^-1.25]: Chrono's g_n over delta^(1/4)
        E, R, M = run["effective"]["E_star_Pa"], run["effective"]["R_star_m"], run["effective"]["M_star_kg"]
        g = 2 * math.sqrt(5 / 6) * abs_log_beta(run["told_e"]) * math.sqrt(2 * E * math.sqrt(R) * M)
        assert eq["damping_coefficient_SI"] == pytest.approx(g, rel=1e-12)


def test_chrono_round_trip_passes(chrono_plan, tmp_path, capsys):
    folder = copy_of(chrono_plan, tmp_path)
    write_dumps(folder, chrono_hertz())
    assert main(["gate", str(folder), "--no-plots"]) == 0, capsys.readouterr().out
    v = verdict(folder)
    assert v["verdict"] == "PASS" and v["checked"] == 6  # 2 geometries x F0 x (T, A, eps)
    assert {p["keyword"] for p in v["promise"]} == {"chrono:smc_hertz"}
    # its promise: clipped, the quarter form restitutes more than the e it is told
    assert all(p["eps_its_equation"] > p["told_e"] for p in v["promise"])
    assert "chrono:smc_hertz" in (folder / "report.md").read_text()


def test_chrono_with_b_1e_4_too_large_fails_naming_the_eps_checks(chrono_plan, tmp_path, capsys):
    folder = copy_of(chrono_plan, tmp_path)
    write_dumps(folder, chrono_hertz(1 + PERTURBATION))
    assert main(["gate", str(folder), "--no-plots"]) == 1
    v = verdict(folder)
    named = {f.split(":")[0] for f in v["failures"]}
    for geometry in ("sphere-sphere", "sphere-plane"):
        assert f"your_code default {geometry} F0 eps" in named, named
    assert "FAIL" in capsys.readouterr().out and "<failure" in (folder / "junit.xml").read_text()


def test_chrono_is_never_planned_into_the_studys_builds():
    """A code of the kit alone: no build can name it, no study code runs its keyword, and the study's
    own laws are refused in it by name."""
    import yaml

    from engines.codes import CODES, KIT_CODES, code, law_unavailable

    assert KIT_CODES == {"chrono": "chrono:smc_hertz"} and "chrono" not in CODES
    with pytest.raises(ValueError, match="unknown engine code 'chrono'"):
        code("chrono")
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    assert all(b["code"] in CODES for b in config["builds"])
    assert "no engine" in law_unavailable("chrono", "viscoelastic")
    assert all(law_unavailable(c, "default") is None for c in CODES)


# yade:betan told a damping ratio (--beta): YADE's Hertz-Mindlin in its own notation,
# c_n = 2 beta sqrt(M* k_t), k_t = 2 E* sqrt(R* delta) the tangent stiffness (HertzMindlin.cpp:352-356
# @2023.02a), F = (4/3) E* sqrt(R*) delta^(3/2) + c_n d(delta)/dt clipped at F >= 0 (:389-402): the
# quarter form at b = sqrt(15/2) beta. PFC's hertz with dp_nratio = beta maps to it where PFC uses the
# tangent stiffness and a no-tension dashpot (docs/other_codes.md).
BETA = 0.1


def yade_betan(beta: float, scale: float = 1.0):
    """YADE's betan force told `beta`; `scale` multiplies its damping (b = sqrt(15/2) beta scale)."""
    def law(run):
        E, R, M = run["effective"]["E_star_Pa"], run["effective"]["R_star_m"], run["effective"]["M_star_kg"]

        def force(d, rate):
            k_t = 2.0 * E * math.sqrt(R * d)
            return max(4.0 / 3.0 * E * math.sqrt(R) * d**1.5 + scale * 2.0 * beta * math.sqrt(M * k_t) * rate, 0.0)
        return force
    return law


@pytest.fixture(scope="module")
def betan_plan(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("betan") / "plan"
    assert main(["export", STEEL, "--keyword", "yade:betan", "--beta", str(BETA), "--K", "0.1", "--out", str(out)]) == 0
    return out


def test_betan_plan_names_the_beta_it_is_given(betan_plan):
    import csv

    plan = load(betan_plan)
    assert plan["laws"] == ["betan"] and plan["told_beta"] == BETA and len(plan["runs"]) == 8
    for run in plan["runs"]:
        assert run["told_beta"] == BETA and run["told_e"] is None and run["name"].endswith(f"-beta{BETA:.6f}")
        # b = sqrt(15/2) beta, the coefficient of YADE's own equation (no Thornton map: beta as given)
        assert run["law_equation"]["dimensionless_coefficient"] == pytest.approx(math.sqrt(7.5) * BETA, rel=1e-14)
    rows = list(csv.DictReader((betan_plan / "plan.csv").open()))
    assert {float(r["told_beta"]) for r in rows} == {BETA} and {r["told_e"] for r in rows} == {""}
    assert f"told beta = {BETA:g} (`told_beta`" in (betan_plan / "README.md").read_text()


def test_betan_round_trip_passes(betan_plan, tmp_path, capsys):
    folder = copy_of(betan_plan, tmp_path)
    write_dumps(folder, yade_betan(BETA))
    assert main(["gate", str(folder), "--no-plots"]) == 0, capsys.readouterr().out
    v = verdict(folder)
    assert v["verdict"] == "PASS" and v["checked"] == 6 and v["promise"] == []  # no restitution asked: no promise
    assert f"beta = {BETA:g}, given as it stands" in (folder / "report.md").read_text()


def test_betan_with_b_1e_4_too_large_fails_naming_the_eps_checks(betan_plan, tmp_path, capsys):
    folder = copy_of(betan_plan, tmp_path)
    write_dumps(folder, yade_betan(BETA, 1 + PERTURBATION))
    assert main(["gate", str(folder), "--no-plots"]) == 1
    named = {f.split(":")[0] for f in verdict(folder)["failures"]}
    for geometry in ("sphere-sphere", "sphere-plane"):
        assert f"your_code betan {geometry} F0 eps" in named, named


@pytest.mark.parametrize("args, words", [
    (["--keyword", "yade:betan"], "told a damping ratio beta, not a restitution: give it with --beta"),
    (["--keyword", "lammps:velocity"], "it cannot be exported"),
    (["--keyword", "yade:en", "--beta", "0.1"], "--beta is for keywords told beta"),
    (["--beta", "0.1"], "--beta is the damping ratio of a keyword told one"),
    (["--keyword", "yade:betan", "--beta", "0.1", "--told", "0.5"], "exclude each other"),
])
def test_what_cannot_be_exported_is_refused_in_words(args, words, tmp_path, capsys):
    assert main(["export", STEEL, *args, "--out", str(tmp_path / "out")]) == 2
    assert words in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
