"""The case report's "Physical results" table: every row gives what its builds' runs delivered.

A model law's equation is one in every build (one row); a keyword law (``default`` and the other
keywords) runs in each build its own keyword's equation, told e, so each keyword has its own row
with its own equation's T, delta_max, F_max, A and eps at what it was told, and its builds'
deviation from that. The expected numbers are computed here independently of the report, from
`contact_model.keywords` (`promised_restitution`, `keyword_reference`) and the case's own
material, and compared with the table as printed, to its printed digits.
"""

import math
from pathlib import Path

import pandas as pd
import pytest

from contact_model import Body, ContactPair
from contact_model.keywords import KEYWORDS, keyword_reference, promised_restitution
from engines.codes import keyword_of
from analysis.comparison import comparison_rows
from records.quantities import readable
from report.report import PHYSICAL, _physical_section
from records.collision_metrics import CollisionMetrics
from reference import HERTZ_TAU, solve_collision

DATA = Path(__file__).resolve().parent / "data" / "physical_results"
#: tests/data/physical_results/: the ladder limits of a real run (its header says which).
RECORDED = DATA / "restitution_0.7_lammps-2021_liggghts-3.8.csv"


def physical_rows(lines: list[str], geometry: str) -> list[dict]:
    """The rows of the physical-results table of `geometry`, as {column: printed cell}."""
    text = "\n".join(lines)
    section = text.split(f"### {geometry}\n", 1)[1].strip("\n").split("\n\n", 1)[0]
    table = section.splitlines()
    assert all(line.startswith("|") for line in table), section
    head = [c.strip() for c in table[0].strip("|").split("|")]
    return [dict(zip(head, (c.strip() for c in line.strip("|").split("|")))) for line in table[2:]]


def row_of(rows: list[dict], law: str, build: str) -> dict:
    """The one row of `law` whose builds include `build`."""
    mine = [r for r in rows if r["law"].split(" ")[0] == law
            and (build in r["builds"].split(", ") or r["builds"].startswith("all "))]
    assert len(mine) == 1, (law, build, rows)
    return mine[0]


def printed(q: str, value: float, err: float) -> str:
    """A cell as the table prints it: the value in its unit, the deviation to one digit."""
    return f"{readable(q, value)} (±{abs(err):.0e})"


def expected_keyword_row(keyword: str, told: float, criterion: str, scales: dict, R: float, M: float,
                         V: float) -> dict:
    """T, delta_max, F_max, A and eps [SI] of `keyword`'s own equation told `told`, from its
    reference row in the Hertz scales of the case (T_e, delta_e; F_e = M* V^2 / delta_e)."""
    r = keyword_reference(keyword, told)
    tau = r["tau_0"] if criterion == "x0" else r["tau_f"]
    delta = r["x_max"] * scales["delta_e"]
    eps = promised_restitution(keyword, told)
    assert eps == pytest.approx(r[f"eps_{criterion}"], abs=1e-12)
    return {"T": tau / HERTZ_TAU * scales["T_e"], "delta_max": delta,
            "F_max": r["force_max"] * M * V**2 / scales["delta_e"], "A": math.pi * R * delta, "eps": eps}


def test_a_recorded_two_build_restitution_case_gives_each_keyword_its_own_row():
    """cases: {restitution: [0.7], velocity: [1.5 m/s]}, run in lammps-2021 (damping tsuji) and
    liggghts-3.8 (coefficientRestitution): the `default` law is two equations. Its rows give each
    build's own: LAMMPS's tsuji restitutes 0.777669 told 0.7, LIGGGHTS's 0.7, each with its own T,
    delta_max, F_max and A and that build's deviation; the viscoelastic rows, one equation, stay
    one row for both builds."""
    limits = pd.read_csv(RECORDED, comment="#")
    lines = _physical_section(limits, ["lammps-2021", "liggghts-3.8"])
    rows = physical_rows(lines, "sphere-sphere")
    assert [(r["law"], r["builds"], r["criterion"]) for r in rows] == [
        ("viscoelastic", "all 2", "x0"), ("viscoelastic", "all 2", "F0"),
        ("default `lammps:tsuji`", "lammps-2021", "x0"),
        ("default `liggghts:hertz-coefficientRestitution`", "liggghts-3.8", "x0")]
    # The case, independently of the summary: steel spheres of 0.635 cm, E* = 109 GPa, at 1.5 m/s.
    radius, density, V = 0.635e-2, 7800.0, 1.5
    sphere = Body(radius, density)
    pair = ContactPair("sphere-sphere", sphere, sphere, 109e9, 0.0)
    scales, R, M = pair.scales(V), pair.R, pair.M
    assert M == pytest.approx(4 / 3 * math.pi * radius**3 * density / 2, rel=1e-14) and R == radius / 2
    for build, keyword, eps_printed in (("lammps-2021", "lammps:tsuji", "0.777669"),
                                        ("liggghts-3.8", "liggghts:hertz-coefficientRestitution", "0.7")):
        assert keyword_of("default", limits[limits.build == build].engine.iloc[0]) == keyword
        own = expected_keyword_row(keyword, 0.7, "x0", scales, R, M, V)
        run = limits[(limits.build == build) & (limits.law == "default")].iloc[0]
        row = row_of(rows, "default", build)
        for q in PHYSICAL:
            assert row[q] == printed(q, own[q], run[f"err_{q}"]), (build, q, row[q])
        assert row["eps"].startswith(f"{eps_printed} (±")
        k = KEYWORDS[keyword]
        assert row["coefficient"] == f"b = {k.b(0.7):.4g}"
        assert row["asked"] == (f"e = 0.7; gated against its own equation; its equation's eps - e = "
                                f"{promised_restitution(keyword, 0.7) - 0.7:+.2e}")
    assert row_of(rows, "default", "lammps-2021")["eps"] == "0.777669 (±2e-08)"  # tsuji: +0.0777 off e
    assert row_of(rows, "default", "liggghts-3.8")["eps"] == "0.7 (±3e-08)"
    # The model's law: the viscoelastic equation at the eta that restitutes 0.7 under F0, both builds.
    visco = solve_collision(float(limits[limits.law == "viscoelastic"].K.iloc[0]))
    F0 = [r for r in rows if r["law"] == "viscoelastic" and r["criterion"] == "F0"][0]
    worst = limits[(limits.law == "viscoelastic") & (limits.criterion == "F0")].err_eps.abs().max()
    assert F0["eps"] == printed("eps", visco["eps_F0"], worst) and F0["eps"].startswith("0.7 (±")
    assert F0["asked"] == "-" and F0["coefficient"].startswith("K = 0.378")


#: Each build's code and the keyword laws it runs (the default study's, every code's default).
BUILDS = {"liggghts-3.8": ("liggghts", ("viscoelastic", "default")),
          "yade-2023": ("yade", ("default", "betan")),
          "lammps-2021": ("lammps", ("viscoelastic", "default")),
          "lammps-2025": ("lammps", ("viscoelastic", "default", "coeff_restitution", "velocity")),
          "esys-2.3.5": ("esys", ("viscoelastic", "default")),
          "kratos-10.4": ("kratos", ("default",))}


def synthetic_limits(told: float, V: float) -> pd.DataFrame:
    """Ladder limits of every build of `BUILDS`: summary rows (`analysis.comparison.comparison_rows`)
    of engine runs that deliver their law's reference (a keyword's own equation told `told`, the
    viscoelastic law at K = 0.3) times (1 + a deviation of their own), as dt = 0 rows."""
    sphere = Body(0.005, 7800.0)
    pair = ContactPair("sphere-plane", sphere, Body(math.inf, math.inf), 100e9, 0.0)
    s = pair.scales(V)
    K = 0.3
    rows = []
    for i, (build, (code, laws)) in enumerate(BUILDS.items()):
        for j, law in enumerate(laws):
            keyword = keyword_of(law, code)
            r = keyword_reference(keyword, told, K) if keyword else solve_collision(K)
            criteria = (KEYWORDS[keyword].criterion,) if keyword else ("x0", "F0")
            err = (i + 1) * 1e-8 + j * 1e-9  # a deviation of each build and law
            to_t, F_e = s["delta_e"] / V, pair.M * V**2 / s["delta_e"]
            metrics = CollisionMetrics(0.0, r["x_max"] * s["delta_e"] * (1 + err), r["tau_max"] * to_t,
                                       r["tau_0"] * to_t * (1 + err), r["eps_x0"] * (1 + err),
                                       r["tau_f"] * to_t * (1 + err), r["eps_F0"] * (1 + err), 1000,
                                       force_max=r["force_max"] * F_e * (1 + err))
            meta = {"case": "mine", "build": build, "engine": code, "engine_version": "x", "law": law,
                    "geometry": pair.geometry, "represents": list(criteria), "impact_velocity": V, "K": K,
                    "time_step": s["T_e"] / 1000, "T_e": s["T_e"], "A_e": s["A_e"], "delta_e": s["delta_e"],
                    "effective_radius": pair.R, "effective_mass": pair.M}
            if keyword:
                meta["matched_restitution"] = told
            rows += comparison_rows(meta, metrics, r)
    return pd.DataFrame(rows).assign(dt=0.0), pair, s


def test_every_keyword_of_every_build_has_the_row_of_its_own_equation():
    """Six builds told e = 0.8 at 2 m/s: LAMMPS's tsuji (both LAMMPS builds: one row naming both),
    LIGGGHTS's and ESyS's keywords (x0), YADE's en and Kratos's restitution (F0, clipped), and the
    keyword laws betan, coeff_restitution and velocity: each row's T, delta_max, F_max, A and eps are
    its keyword's own equation's at e = 0.8, its deviation the largest of its builds'; the
    viscoelastic law is one row of the builds that run it."""
    told, V = 0.8, 2.0
    limits, pair, s = synthetic_limits(told, V)
    rows = physical_rows(_physical_section(limits, list(BUILDS)), "sphere-plane")
    keyword_rows = [r for r in rows if "`" in r["law"]]
    keywords = {(law, keyword_of(law, code)) for build, (code, laws) in BUILDS.items() for law in laws
                if keyword_of(law, code)}
    assert len(keyword_rows) == len(keywords) == 8
    for build, (code, laws) in BUILDS.items():
        for law in laws:
            keyword = keyword_of(law, code)
            mine = limits[(limits.build == build) & (limits.law == law)]
            if keyword is None:
                continue
            row = row_of(rows, law, build)
            assert row["law"] == f"{law} `{keyword}`" and row["criterion"] == KEYWORDS[keyword].criterion
            sharing = [b for b, (c, ls) in BUILDS.items() if law in ls and keyword_of(law, c) == keyword]
            assert row["builds"] == ", ".join(sharing)
            shared = limits[limits.build.isin(sharing) & (limits.law == law)]
            own = expected_keyword_row(keyword, told, KEYWORDS[keyword].criterion, s, pair.R, pair.M, V)
            for q in PHYSICAL:
                assert row[q] == printed(q, own[q], shared[f"err_{q}"].abs().max()), (build, law, q)
            assert mine.err_eps.abs().max() > 0
            assert row["asked"].startswith(f"e = {told:g}") and "gated against its own equation" in row["asked"]
    tsuji = row_of(rows, "default", "lammps-2025")
    assert tsuji["builds"] == "lammps-2021, lammps-2025"
    # the larger of the two builds' deviations: lammps-2025's 4.1e-8 (lammps-2021's 3.1e-8)
    assert tsuji["eps"] == f"{promised_restitution('lammps:tsuji', told):.6g} (±4e-08)"
    assert tsuji["eps"].startswith("0.85")  # tsuji told 0.8 restitutes 0.853..., not 0.8
    velocity = row_of(rows, "velocity", "lammps-2025")
    assert "as the eta_n restituting it at this V (x0)" in velocity["asked"] and velocity["eps"].startswith("0.8 (")
    betan = row_of(rows, "betan", "yade-2023")
    assert f"as betan = {KEYWORDS['yade:betan'].told_for(told):.6g}" in betan["asked"]
    visco = [r for r in rows if r["law"] == "viscoelastic"]
    assert [r["builds"] for r in visco] == ["liggghts-3.8, lammps-2021, lammps-2025, esys-2.3.5"] * 2
    assert [r["criterion"] for r in visco] == ["x0", "F0"]


CASE = """name: steel
effective_modulus: 109 GPa
radius: 0.635 cm
density: 7800 kg/m^3
geometries: [sphere-sphere]
impact:
  restitution: [0.7]
  velocity: [1.5 m/s]
"""
TWO_BUILDS = ("builds=[{id: lammps-2021, code: lammps, executable: lmp}, "
              "{id: liggghts-3.8, code: liggghts, executable: liggghts}]")


@pytest.mark.workflow  # Snakemake with two real engines (about 30 s): not in make test-unit
def test_a_two_build_restitution_case_through_the_workflow(tmp_path):
    """The case of the issue end to end: `snakemake -j2 steel` in lammps-2021 and liggghts-3.8. The
    case report's physical-results table gives each build's `default` its own row, with the numbers of
    that build's own runs (summary.csv's limits) and of its keyword's equation told 0.7; its reports
    say what is not validated."""
    import sys

    import processes
    from engine_cases import require_engine
    from workflow_copy import copy_workflow

    require_engine("lmp", "lammps")
    require_engine("liggghts", "liggghts")
    project = copy_workflow(tmp_path / "study", CASE)
    out = processes.run([sys.executable, "-m", "snakemake", "-j2", "steel", "--config", TWO_BUILDS,
                         "laws=[viscoelastic,default]", "extras=[]"], cwd=project, capture_output=True, text=True,
                        timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    report = (project / "results" / "steel" / "report.md").read_text()
    assert ("**The tangential half** (tangential force, friction, rotation, oblique impacts) is not "
            "part of this matrix") in report.split("## Physical results")[0]
    summary = pd.read_csv(project / "results" / "steel" / "summary.csv")
    limits = summary[summary.dt == 0]
    rows = physical_rows(report.split("## Physical results", 1)[1].splitlines(), "sphere-sphere")
    assert [r["builds"] for r in rows if r["law"].startswith("default")] == ["lammps-2021", "liggghts-3.8"]
    for build, keyword in (("lammps-2021", "lammps:tsuji"), ("liggghts-3.8", "liggghts:hertz-coefficientRestitution")):
        run = limits[(limits.build == build) & (limits.law == "default")].iloc[0]
        assert run.matched_restitution == 0.7
        row = row_of(rows, "default", build)
        assert row["law"] == f"default `{keyword}`"
        assert row["eps"] == printed("eps", promised_restitution(keyword, 0.7), run.err_eps)
        for q in PHYSICAL:  # what this build's runs were compared with and how far they were off
            assert row[q] == printed(q, run[f"{q}_ref"], run[f"err_{q}"]), (build, q)
        assert row["asked"].startswith("e = 0.7; gated against its own equation")
    assert row_of(rows, "default", "lammps-2021")["eps"].startswith("0.777669 (")
    assert row_of(rows, "default", "liggghts-3.8")["eps"].startswith("0.7 (")
