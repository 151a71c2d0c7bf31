"""The conformance kit run end to end on a real code: LAMMPS, driven as a user of the kit would.

A plan is exported in-process (steel, both geometries, K = 0.1; the viscoelastic law with its
attractive tail, which LAMMPS's `damping viscoelastic` keeps, and the clipped law, which its
`limit_damping` clips: two ladders of four runs each per law). A LAMMPS input deck is written
here from the plan's numbers alone (bodies, dt, steps, initial state, the law's k_n and g in SI;
not by the study's driver, engines/lammps.py), run by Debian's `lmp`, and its `dump custom`
(x, vx, fx of every atom, every step, %.17g) converted into plain CSVs and a columns.yaml
(positions and velocities). `python -m conformance gate` must PASS; and its checks' errors must
be those of the study's own LAMMPS run of the same RunSpecs (the study's driver, then the rows,
extrapolation and checks of workflow/scripts/case_summary.py and case_verdict.py, without
Snakemake), to `SAME_ERROR`; and the study's own dumps, gated by the kit, give the study's checks
exactly. The same deck with the modulus 1e-5 too large FAILs, naming the T checks.

Engine tier (`runs_engine`): it starts LAMMPS.
"""

from __future__ import annotations

import io
import json
import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

import processes
from conformance.__main__ import main
from conformance.dumps import load_column_map, read_mapped_csv
from conformance.gate import spec_of
from conformance.study import comparison_rows, extrapolated_rows, gate_checks, map_errors
from engine_cases import require_engine
from engines.lammps import run_lammps
from records.collision_metrics import collision_metrics
from records.dump_file import read_dump

ROOT = Path(__file__).resolve().parents[1]
LAWS = ("viscoelastic", "viscoelastic_clipped")
#: How far the kit's errors (and resolutions) of a check may be from the study's own run's, absolutely
#: (both relative errors, ~1e-9 here, resolutions ~1e-7). The two LAMMPS runs compute the same
#: collision bit for bit and both record 17 digits (the study's decks recorded 15 until this test found
#: it: LAMMPS passes an equal-style variable `v_name` through its %.15g text; the checks then differed
#: by up to ~1.4e-14); what remains is the kit's overlap, computed in Python from positions.
SAME_ERROR = 1e-15
#: How far a sample (time, overlap, d(delta)/dt, force) of the kit's LAMMPS run may be from the
#: study's, relatively: the same collision, both recorded at 17 digits.
SAME_SAMPLE = 1e-16
#: The gated checks of the plan: (x0 and F0 of viscoelastic, F0 of viscoelastic_clipped) x 2 geometries x (T, A, eps).
CHECKS = 18
#: The columns the gate and the study must agree on, per check.
COMPARED = ("max_rel_error", "resolution")
KEY = ["law", "geometry", "criterion", "quantity"]


@pytest.fixture(scope="module")
def lmp(runs_engine) -> str:
    require_engine("lmp", "lammps")
    return shutil.which("lmp")


@pytest.fixture(scope="module")
def plan_folder(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("plan") / "kit"
    laws = [w for law in LAWS for w in ("--law", law)]
    assert main(["export", str(ROOT / "cases" / "steel.yaml"), *laws, "--K", "0.1", "--out", str(out)]) == 0
    return out


def load(folder: Path) -> dict:
    return json.loads((folder / "plan.json").read_text())


def deck(run: dict, dump: Path, modulus: float = 1.0) -> str:
    """One run of the plan as LAMMPS commands, from the plan's numbers only. LAMMPS's `hertz kn`
    is F = kn a delta, a = sqrt(R* delta), so kn = k_n / sqrt(R*); `damping viscoelastic` is
    eta_n0 a m_eff d(delta)/dt (m_eff = M*), so eta_n0 = g / (sqrt(R*) M*) for the plan's
    g delta^(1/2) d(delta)/dt; `limit_damping` clips the force at zero. `modulus` scales kn."""
    law, b1, b2, eff = run["law_equation"], run["body_1"], run["body_2"], run["effective"]
    assert law["damping_power"] == 0.5, law  # the viscoelastic form: what damping viscoelastic computes
    sqrt_r = math.sqrt(eff["R_star_m"])
    kn = modulus * law["k_n_N_per_m1.5"] / sqrt_r
    eta_n0 = law["damping_coefficient_SI"] / (sqrt_r * eff["M_star_kg"])
    model = (f"hertz {kn!r} {eta_n0!r} damping viscoelastic tangential linear_nohistory 0 0"
             + (" limit_damping" if law["clipped"] else ""))
    init, R1 = run["initial"], b1["radius_m"]
    plane = b2["plane"]
    box = 4.0 * max(R1, R1 if plane else b2["radius_m"])
    lines = ["clear", "units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off",
             "comm_modify vel yes", f"region domain block {-box!r} {box!r} {-box!r} {box!r} {-box!r} {box!r} units box",
             "create_box 1 domain", f"neighbor {0.25 * R1!r} bin", "neigh_modify delay 0",
             f"create_atoms 1 single {init['x1_m']!r} 0.0 0.0 units box",
             f"set atom 1 diameter {2 * R1!r}", f"set atom 1 density {b1['density_kg_m3']!r}",
             f"set atom 1 vx {init['v1_m_s']!r}"]
    if plane:
        lines.append(f"fix plane all wall/gran granular {model} xplane NULL 0.0")
    else:
        lines += [f"create_atoms 1 single {init['x2_m']!r} 0.0 0.0 units box",
                  f"set atom 2 diameter {2 * b2['radius_m']!r}", f"set atom 2 density {b2['density_kg_m3']!r}",
                  f"set atom 2 vx {init['v2_m_s']!r}", "pair_style granular", f"pair_coeff * * {model}"]
    lines += ["fix integrate all nve/sphere", f"timestep {run['dt_s']!r}",
              f"dump d all custom 1 {dump} id x vx fx", "dump_modify d sort id format float %.17g",
              "thermo 1000000", f"run {run['steps']}", "undump d"]
    return "\n".join(lines) + "\n"


def read_lammps_dump(path: Path) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """(steps, {atom id: rows of x, vx, fx}) of a `dump custom ... id x vx fx`."""
    steps, atoms, lines, i = [], {}, path.read_text().splitlines(), 0
    while i < len(lines):
        assert lines[i] == "ITEM: TIMESTEP", (path, i, lines[i])
        steps.append(int(lines[i + 1]))
        n = int(lines[i + 3])
        assert lines[i + 8] == "ITEM: ATOMS id x vx fx", lines[i + 8]
        for row in lines[i + 9:i + 9 + n]:
            atom, *values = row.split()
            atoms.setdefault(int(atom), []).append([float(v) for v in values])
        i += 9 + n
    return np.array(steps), {a: np.array(v) for a, v in atoms.items()}


def run_plan_in_lammps(folder: Path, lmp: str, modulus: float = 1.0) -> None:
    """Every run of the plan in one LAMMPS process; each dump converted into dumps/<run>.csv (SI,
    positions and velocities of both bodies, the force on body 2: repulsive positive) and the
    columns.yaml that says so."""
    plan = load(folder)
    work = folder / "lammps"
    work.mkdir()
    deck_text = "".join(deck(run, work / f"{i}.dump", modulus) for i, run in enumerate(plan["runs"]))
    (work / "in.plan").write_text(deck_text)
    done = processes.run([lmp, "-in", "in.plan", "-log", "log.lammps", "-screen", "none"], cwd=work,
                         capture_output=True, timeout=120)
    assert done.returncode == 0, (done.stderr.decode()[-2000:], (work / "log.lammps").read_text()[-2000:])
    for i, run in enumerate(plan["runs"]):
        steps, atoms = read_lammps_dump(work / f"{i}.dump")
        assert list(steps) == list(range(run["steps"] + 1)), run["name"]
        x1, v1, f1 = atoms[1].T
        if run["body_2"]["plane"]:
            x2, v2, force = np.zeros_like(x1), np.zeros_like(x1), -f1
        else:
            x2, v2, force = atoms[2][:, 0], atoms[2][:, 1], atoms[2][:, 2]
        table = np.column_stack([steps * run["dt_s"], x1, v1, x2, v2, force])
        (folder / run["dump"]).write_text("# LAMMPS dump custom, converted\nt,x1,vx1,x2,vx2,Fn\n"
                                          + "".join(",".join(map(repr, r)) + "\n" for r in table.tolist()))
    (folder / "columns.yaml").write_text(yaml.safe_dump({
        "time": {"column": "t", "unit": "s"}, "x1": {"column": "x1", "unit": "m"},
        "v1": {"column": "vx1", "unit": "m/s"}, "x2": {"column": "x2", "unit": "m"},
        "v2": {"column": "vx2", "unit": "m/s"}, "normal_force": {"column": "Fn", "unit": "N"},
        "plan_id": plan["plan_id"]}))


def gated(folder: Path, capsys) -> tuple[int, list[str], pd.DataFrame]:
    """(exit status of `python -m conformance gate DIR --no-plots`, the lines it printed, its checks.csv)."""
    capsys.readouterr()
    status = main(["gate", str(folder), "--no-plots"])
    said = capsys.readouterr().out.splitlines()
    checks = pd.read_csv(folder / "checks.csv") if (folder / "checks.csv").is_file() else pd.DataFrame()
    return status, said, checks


def study_specs(plan: dict) -> dict:
    """{plan run name: the study's RunSpec of it for its LAMMPS build}: the RunSpec the plan was made
    from (as the kit's gate rebuilds it, `conformance.gate.spec_of`), run by the code `lammps`."""
    return {run["name"]: replace(spec_of(run), engine="lammps", build="lammps") for run in plan["runs"]}


def study_checks(plan: dict, dumps: dict) -> pd.DataFrame:
    """The study's own checks of its dumps {plan run name: dump}: the rows of
    workflow/scripts/case_summary.py, the checks of case_verdict.py (Snakemake-free), as checks.csv
    holds them (`verdict.gate.write_verdict_files`: %.12g)."""
    specs = study_specs(plan)
    rows = []
    for run in plan["runs"]:
        meta, c = read_dump(dumps[run["name"]])
        m = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                              impact_velocity=meta["impact_velocity"])
        on_map = map_errors(meta, m, len(c["time"]))
        for row in comparison_rows(meta, m, run["reference"]):
            rows.append({**row, "run": specs[run["name"]].name,
                         **{f"map_err_{q}": e for q, e in on_map.get(row["criterion"], {}).items()}})
    table = pd.DataFrame(rows)
    table = pd.concat([table, extrapolated_rows(table)], ignore_index=True)
    planned = pd.DataFrame([{"case": s.case, "name": s.name, "engine": s.engine, "build": s.build, "law": s.law,
                             "geometry": s.pair.geometry, "represents": list(s.represents), "ladder": s.ladder}
                            for s in specs.values()])
    checks = gate_checks(table, planned, pd.DataFrame(), plan["tolerance"])
    return pd.read_csv(io.StringIO(checks.to_csv(index=False, float_format="%.12g")))


@pytest.fixture(scope="module")
def study_run(plan_folder, tmp_path_factory, lmp) -> dict:
    """The study's own LAMMPS run of the plan's runs (engines.lammps.run_lammps, its decks
    cases/decks/lammps/): {plan run name: its dump}."""
    plan = load(plan_folder)
    specs = study_specs(plan)
    sweep = run_lammps(list(specs.values()), tmp_path_factory.mktemp("study"), lmp).raise_first()
    return {name: sweep.dumps[spec.name] for name, spec in specs.items()}


def paired(kit: pd.DataFrame, study: pd.DataFrame) -> pd.DataFrame:
    both = kit.merge(study, on=KEY, suffixes=("_kit", "_study"), validate="one_to_one")
    assert len(both) == len(kit) == len(study) == CHECKS, (len(both), len(kit), len(study))
    for column in ("pass", "planned", "landed", "failed", "tolerance"):
        assert (both[f"{column}_kit"] == both[f"{column}_study"]).all(), column
    return both


def test_lammps_through_the_kit_passes_with_the_studys_own_errors(plan_folder, study_run, tmp_path, lmp, capsys):
    """LAMMPS driven from the plan alone, dumped at 17 digits: PASS, each check's error and
    resolution within SAME_ERROR of the study's own LAMMPS run's."""
    folder = tmp_path / "kit"
    shutil.copytree(plan_folder, folder)
    run_plan_in_lammps(folder, lmp)
    status, said, kit = gated(folder, capsys)
    assert status == 0, said
    assert said[0].startswith(f"PASS: {CHECKS} of {CHECKS} checks pass (16 runs)"), said
    plan = load(folder)
    assert json.loads((folder / "verdict.json").read_text())["plan_id"] == plan["plan_id"]

    # The same collisions: LAMMPS computed from the plan's numbers what it computes from the study's.
    columns = load_column_map(folder / "columns.yaml")
    for run in plan["runs"]:
        ours = read_mapped_csv(folder / run["dump"], run, columns)
        _, theirs = read_dump(study_run[run["name"]])
        for q in theirs:
            np.testing.assert_allclose(getattr(ours, q), theirs[q], rtol=SAME_SAMPLE, atol=0, err_msg=q)

    study = study_checks(plan, study_run)
    assert study["pass"].all(), study[~study["pass"]][[*KEY, "reason"]]
    both = paired(kit, study)
    for column in COMPARED:
        difference = (both[f"{column}_kit"] - both[f"{column}_study"]).abs()
        worst = both.loc[difference.idxmax()]
        assert difference.max() <= SAME_ERROR, (column, difference.max(), worst[KEY].to_dict(),
                                                worst[f"{column}_kit"], worst[f"{column}_study"])


def test_the_studys_own_dumps_through_the_kit_give_its_checks_exactly(plan_folder, study_run, tmp_path, capsys):
    """The study's own LAMMPS dumps, given the plan's id and run names, gated by the kit: the
    study's checks, every number of checks.csv equal."""
    folder = tmp_path / "kit"
    shutil.copytree(plan_folder, folder)
    plan = load(folder)
    for run in plan["runs"]:
        first, rest = Path(study_run[run["name"]]).read_text().split("\n", 1)
        (folder / run["dump"]).write_text(f"{first}\n# plan_id: {json.dumps(plan['plan_id'])}\n"
                                          f"# run: {json.dumps(run['name'])}\n{rest}")
    status, said, kit = gated(folder, capsys)
    assert status == 0, said
    both = paired(kit, study_checks(plan, study_run))
    for column in ("max_rel_error", "resolution", "at_K", "observed_order", "rung_factors", "rung_errors"):
        same = (both[f"{column}_kit"] == both[f"{column}_study"]) | (both[f"{column}_kit"].isna()
                                                                   & both[f"{column}_study"].isna())
        assert same.all(), both.loc[~same, [*KEY, f"{column}_kit", f"{column}_study"]]


def test_a_modulus_1e5_too_large_fails_naming_the_t_checks(plan_folder, tmp_path, lmp, capsys):
    folder = tmp_path / "kit"
    shutil.copytree(plan_folder, folder)
    run_plan_in_lammps(folder, lmp, modulus=1 + 1e-5)
    status, said, checks = gated(folder, capsys)
    assert status == 1, said
    assert said[0].startswith("FAIL:"), said
    failing = checks[~checks["pass"]]
    t_checks = {(r.law, r.geometry, r.criterion) for r in checks[checks.quantity == "T"].itertuples()}
    assert len(t_checks) == CHECKS // 3
    assert {(r.law, r.geometry, r.criterion) for r in failing[failing.quantity == "T"].itertuples()} == t_checks
    for law, geometry, criterion in t_checks:  # each named in what the gate says
        assert any(line.strip().startswith(f"your_code {law} {geometry} {criterion} T:") for line in said[1:]), said
