"""The conformance kit (conformance/, docs/conformance.md): a plan exported by the study's planner,
run by an integrator written here (not the project's `reference.engine_map`), gates PASS; the same
integrator with a stiffness 1e-5 off FAILs, naming the checks; the same runs written as positions
and velocities in mm and mm/s through a column map PASS; every unusable input is refused (exit 2)
naming the file, the row and the column; and the guide's walk-through script runs as it stands.

Unit tier: everything runs in-process (`conformance.__main__.main`), the report without its
figures (--no-plots) except once; but `test_the_gate_as_a_process_exits_0_1_and_2`, which starts
`python -m conformance gate` as a process (workflow tier, by its `runs_workflow` fixture). One
plan (steel, the viscoelastic law, both geometries, K = 0.1: two ladders of four runs) serves every
test.
"""

from __future__ import annotations

import functools
import json
import math
import runpy
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from conformance.__main__ import main

import plan_verlet

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "conformance.md"


@pytest.fixture(scope="module")
def plan_folder(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("plan")
    assert main(["export", str(ROOT / "cases" / "steel.yaml"), "--law", "viscoelastic", "--K", "0.1",
                 "--out", str(out)]) == 0
    return out


def load(folder: Path) -> dict:
    return json.loads((folder / "plan.json").read_text())


def integrate(run: dict, stiffness: float = 1.0) -> dict[str, np.ndarray]:
    """`plan_verlet.integrate` of the viscoelastic law written from the material: F = (4/3) E* sqrt(R*)
    d^(3/2) + 2 eta sqrt(R*) d^(1/2) d', the tail kept; `stiffness` multiplies the Hertz term."""
    E, R, eta = run["effective"]["E_star_Pa"], run["effective"]["R_star_m"], run["eta_Pa_s"]
    kn, gn = stiffness * 4.0 / 3.0 * E * math.sqrt(R), 2.0 * eta * math.sqrt(R)
    return plan_verlet.integrate(run, lambda d, rate: kn * d**1.5 + gn * math.sqrt(d) * rate)


def write_dumps(folder: Path, stiffness: float = 1.0) -> None:
    """Every run of the plan, in the study's dump format."""
    plan = load(folder)
    for run in plan["runs"]:
        (folder / run["dump"]).write_text(dump_text(plan["plan_id"], json.dumps(run, sort_keys=True), stiffness))


@functools.cache
def dump_text(plan_id: str, run_json: str, stiffness: float) -> str:
    """One run's dump in the study's format. Cached by the run's content: the pure-Python integrator and
    the %.17g text of its samples cost seconds a run, and most tests here write the same plan's dumps."""
    run = json.loads(run_json)
    s = integrate(run, stiffness)
    head = (f"# hertz-dem-dump: 1\n# plan_id: \"{plan_id}\"\n# run: \"{run['name']}\"\n"
            "# engine_version: \"tests/test_conformance.py\"\ntime,overlap,normal_velocity,normal_force\n")
    rows = np.column_stack([s["time"], s["overlap"], s["rate"], s["force"]])
    return head + "".join("%.17g,%.17g,%.17g,%.17g\n" % tuple(r) for r in rows)


def write_mapped(folder: Path) -> None:
    """Every run as positions and velocities in mm and mm/s, time in ms, renamed columns, no force;
    and the columns.yaml that says so."""
    plan = load(folder)
    for run in plan["runs"]:
        (folder / run["dump"]).write_text(mapped_text(json.dumps(run, sort_keys=True)))
    (folder / "columns.yaml").write_text(yaml.safe_dump({
        "time": {"column": "t_ms", "unit": "ms"}, "x1": {"column": "pos A", "unit": "mm"},
        "v1": {"column": "vel A", "unit": "mm/s"}, "x2": {"column": "pos B", "unit": "mm"},
        "v2": {"column": "vel B", "unit": "mm/s"}, "plan_id": plan["plan_id"]}))


@functools.cache
def mapped_text(run_json: str) -> str:
    """One run as write_mapped writes it, cached by the run's content as `dump_text` is."""
    s = integrate(json.loads(run_json))
    cols = [s["time"] * 1e3, s["x1"] * 1e3, s["v1"] * 1e3, s["x2"] * 1e3, s["v2"] * 1e3]
    text = "# written by a code of our own\nt_ms,pos A,vel A,pos B,vel B\n"
    return text + "".join(",".join("%.17g" % c for c in r) + "\n" for r in np.column_stack(cols))


@pytest.fixture
def folder(plan_folder, tmp_path) -> Path:
    """A fresh copy of the exported plan."""
    out = tmp_path / "check"
    shutil.copytree(plan_folder, out)
    return out


@pytest.fixture(scope="module")
def dumped(plan_folder, tmp_path_factory) -> Path:
    """The plan with the integrator's dumps, written once: the refusal tests each spoil a copy."""
    out = tmp_path_factory.mktemp("dumped") / "check"
    shutil.copytree(plan_folder, out)
    write_dumps(out)
    return out


def verdict(folder: Path) -> dict:
    return json.loads((folder / "verdict.json").read_text())


def test_export_writes_the_plan_in_si(plan_folder):
    plan = load(plan_folder)
    assert len(plan["runs"]) == 8 and {r["geometry"] for r in plan["runs"]} == {"sphere-sphere", "sphere-plane"}
    assert plan["tolerance"] == {"T": 1e-6, "A": 1e-6, "eps": 1e-6}
    run = plan["runs"][0]
    # the study's own run: its name, its dt and its start (half a step after sample 20)
    from conformance.gate import spec_of

    spec = spec_of(run)
    assert spec.initial_state()["x1"] == run["initial"]["x1_m"] and spec.steps() == run["steps"]
    assert run["law_equation"]["damping_coefficient_SI"] == pytest.approx(
        2 * run["eta_Pa_s"] * math.sqrt(run["effective"]["R_star_m"]), rel=1e-12)
    header = (plan_folder / "plan.csv").read_text().splitlines()[0].split(",")
    assert {"dt_s", "R1_m", "E_star_Pa", "k_n_N_m1.5", "x1_m", "v1_m_s", "steps", "dump"} <= set(header)
    assert plan["plan_id"] in (plan_folder / "README.md").read_text()


def test_round_trip_passes(folder, capsys):
    write_dumps(folder)
    assert main(["gate", str(folder)]) == 0, capsys.readouterr().out
    v = verdict(folder)
    assert v["verdict"] == "PASS" and v["checked"] == 12 and v["plan_id"] == load(folder)["plan_id"]
    for name in ("report.md", "report.html", "junit.xml", "checks.csv", "summary.csv", "plots/errors.png"):
        assert (folder / name).is_file(), name
    assert "**Verdict: PASS**" in (folder / "report.md").read_text()


def test_a_stiffness_1e_5_off_fails_naming_the_checks(folder, capsys):
    write_dumps(folder, stiffness=1 + 1e-5)
    assert main(["gate", str(folder), "--no-plots"]) == 1
    v = verdict(folder)
    assert v["verdict"] == "FAIL"
    named = {f.split(":")[0] for f in v["failures"]}
    for geometry in ("sphere-sphere", "sphere-plane"):
        for criterion in ("x0", "F0"):
            assert f"your_code viscoelastic {geometry} {criterion} T" in named, named
    assert "FAIL" in capsys.readouterr().out
    assert "<failure" in (folder / "junit.xml").read_text()


def test_column_map_of_positions_in_mm_passes(folder, capsys):
    write_mapped(folder)
    assert main(["gate", str(folder), "--no-plots"]) == 0, capsys.readouterr().out
    assert verdict(folder)["checked"] == 12
    # --no-plots draws no figure (report.write_report once drew them all the same: its plots folder's
    # Path had taken the name of its `plots` flag); the reports are written, their image links dangling.
    assert not list((folder / "plots").glob("*.png")) and "plots/errors.png" in (folder / "report.md").read_text()


def test_the_guide_walkthrough_runs_as_written(folder, monkeypatch, capsys):
    script = _walkthrough_script()
    assert len(script.splitlines()) <= 35  # "a ~30-line script"
    path = folder / "run_plan.py"
    path.write_text(script)
    monkeypatch.setattr(sys, "argv", [str(path), str(folder)])
    runpy.run_path(str(path), run_name="__main__")
    assert main(["gate", str(folder), "--no-plots"]) == 0, capsys.readouterr().out
    assert "PASS: 12 of 12 checks pass (8 runs)" in capsys.readouterr().out or verdict(folder)["pass"]


# The refusals: each spoils one file of a copy of the dumped plan; the gate exits 2, names the file
# (and the row and column where one is at fault), and leaves no verdict.

FIRST = 0  # the run whose dump is spoiled: the plan's first


def _dump(folder: Path, i: int = FIRST) -> Path:
    return folder / load(folder)["runs"][i]["dump"]


def _edit_row(path: Path, row: int, column: int, value: str) -> None:
    """Set data row `row` (1-based) cell `column` (0-based) of a study dump."""
    lines = path.read_text().splitlines(keepends=True)
    start = next(i for i, line in enumerate(lines) if line.startswith("time,")) + 1
    cells = lines[start + row - 1].rstrip("\n").split(",")
    cells[column] = value
    lines[start + row - 1] = ",".join(cells) + "\n"
    path.write_text("".join(lines))


def _nan(folder):
    _edit_row(_dump(folder), 10, 1, "nan")
    return ["row 10", "'overlap'", "not a finite number"]


def _time_back(folder):
    path = _dump(folder)
    _edit_row(path, 50, 0, "0")
    return ["row 50", "'time'", "does not increase"]


def _missing_column(folder):
    path = _dump(folder)
    text = path.read_text().replace("time,overlap,normal_velocity,normal_force\n", "time,overlap,normal_velocity\n")
    path.write_text("\n".join(",".join(line.split(",")[:3]) if line[:1] not in "#" else line
                              for line in text.splitlines()) + "\n")
    return ["no column 'normal_force'"]


def _few_in_contact(folder):
    path = _dump(folder)
    lines = path.read_text().splitlines(keepends=True)
    start = next(i for i, line in enumerate(lines) if line.startswith("time,")) + 1
    rows = [line.split(",") for line in lines[start:]]
    touching = [i for i, r in enumerate(rows) if float(r[1]) > 0]
    for i in touching[3:]:  # three samples in contact left
        rows[i][1] = "-1e-9"
    path.write_text("".join(lines[:start]) + "".join(",".join(r) for r in rows))
    return [f"row {touching[0] + 1}", "'overlap'", "3 samples in contact"]


def _missing_run(folder):
    _dump(folder, 3).unlink()
    return ["missing", load(folder)["runs"][3]["name"]]


def _other_plan(folder):
    path = _dump(folder)
    path.write_text(path.read_text().replace(load(folder)["plan_id"], "0" * 64))
    return ["another plan's"]


def _stray_file(folder):
    (folder / "dumps" / "your_code-viscoelastic-sphere-sphere-K0.3-V1e+00-dt250.csv").write_text("x")
    return ["not a dump of this plan", "K0.3"]


def _bad_unit(folder):
    write_mapped(folder)
    columns = yaml.safe_load((folder / "columns.yaml").read_text())
    columns["x1"]["unit"] = "smoots per fortnightly"
    (folder / "columns.yaml").write_text(yaml.safe_dump(columns))
    return ["columns.yaml", "'x1'", "smoots per fortnightly"]


def _wrong_dimension(folder):
    write_mapped(folder)
    columns = yaml.safe_load((folder / "columns.yaml").read_text())
    columns["v1"]["unit"] = "mm"
    (folder / "columns.yaml").write_text(yaml.safe_dump(columns))
    return ["columns.yaml", "'v1'", "not [length] / [time]"]


def _csv_missing_column(folder):
    write_mapped(folder)
    columns = yaml.safe_load((folder / "columns.yaml").read_text())
    columns["x2"]["column"] = "pos C"
    (folder / "columns.yaml").write_text(yaml.safe_dump(columns))
    return ["no column 'pos C'", "x2 in columns.yaml"]


def _csv_nan(folder):
    write_mapped(folder)
    path = _dump(folder)
    lines = path.read_text().splitlines(keepends=True)
    cells = lines[2 + 7].split(",")  # the comment, the header, then data row 8
    cells[2] = "NaN"
    lines[2 + 7] = ",".join(cells)
    path.write_text("".join(lines))
    return ["row 8 (line 10)", "'vel A'"]


def _csv_other_step(folder):
    write_mapped(folder)
    plan = load(folder)
    # the first run's file replaced by the second's (another dt)
    _dump(folder).write_text(_dump(folder, 1).read_text())
    return ["'t_ms'", f"dt = {plan['runs'][FIRST]['dt_s']:.9g} s"]


REFUSALS = [_nan, _time_back, _missing_column, _few_in_contact, _missing_run, _other_plan, _stray_file, _bad_unit,
            _wrong_dimension, _csv_missing_column, _csv_nan, _csv_other_step]


@pytest.mark.parametrize("spoil", REFUSALS, ids=[f.__name__.strip("_") for f in REFUSALS])
def test_unusable_input_is_refused_naming_file_row_and_column(spoil, dumped, tmp_path, capsys):
    folder = tmp_path / "check"
    shutil.copytree(dumped, folder)
    (folder / "verdict.json").write_text('{"verdict": "PASS"}')  # an earlier gate's: must not stand
    expected = spoil(folder)
    assert main(["gate", str(folder), "--no-plots"]) == 2
    out = capsys.readouterr().out
    assert "UNUSABLE" in out and "nothing was gated" in out
    problem = next(line for line in out.splitlines() if all(e in line for e in expected))
    assert str(folder) in problem  # the file is named by its path
    assert not (folder / "verdict.json").exists()


def test_an_edited_plan_is_refused(dumped, tmp_path, capsys):
    folder = tmp_path / "check"
    shutil.copytree(dumped, folder)
    plan = load(folder)
    plan["tolerance"]["T"] = 1e-2
    (folder / "plan.json").write_text(json.dumps(plan))
    assert main(["gate", str(folder), "--no-plots"]) == 2
    assert "edited after it was exported" in capsys.readouterr().out


def test_export_refuses_what_it_cannot_plan(tmp_path, capsys):
    assert main(["export", str(ROOT / "cases" / "steel.yaml"), "--keyword", "nobody:nothing",
                 "--out", str(tmp_path)]) == 2
    assert "unknown keyword" in capsys.readouterr().err


def _walkthrough_script() -> str:
    text = DOC.read_text()
    return text.split("<!-- conformance-walkthrough -->", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]


def test_a_keyword_round_trip_passes_and_reports_its_promise(tmp_path, monkeypatch, capsys):
    """Generic over laws: a keyword's plan (LIGGGHTS's coefficientRestitution, Tsuji's form) run by the
    guide's script from the plan's own law_equation gates PASS, its promise in verdict.json."""
    folder = tmp_path / "keyword"
    assert main(["export", str(ROOT / "cases" / "steel.yaml"), "--keyword", "liggghts:hertz-coefficientRestitution",
                 "--K", "0.1", "--out", str(folder)]) == 0
    plan = load(folder)
    assert {r["law"] for r in plan["runs"]} == {"default"} and plan["runs"][0]["told_e"] > 0
    assert plan["runs"][0]["law_equation"]["damping_power"] == 0.25
    path = folder / "run_plan.py"
    path.write_text(_walkthrough_script())
    monkeypatch.setattr(sys, "argv", [str(path), str(folder)])
    runpy.run_path(str(path), run_name="__main__")
    assert main(["gate", str(folder), "--no-plots"]) == 0, capsys.readouterr().out
    promise = verdict(folder)["promise"]
    assert {p["keyword"] for p in promise} == {"liggghts:hertz-coefficientRestitution"}
    assert all(abs(p["eps_dumps_dt0"] - p["eps_its_equation"]) < 1e-6 for p in promise)


def test_the_study_layers_are_imported_in_one_module_of_the_kit():
    """conformance/study.py re-exports what the kit takes from analysis/, verdict/ and report/: a move of
    their modules changes that file alone."""
    import ast

    importers = set()
    for path in (ROOT / "conformance").glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module] if isinstance(node, ast.ImportFrom) and node.module else [])
            if any(n.split(".")[0] in ("analysis", "verdict", "report", "postprocess") for n in names):
                importers.add(path.name)
    assert importers == {"study.py"}


def test_the_gate_as_a_process_exits_0_1_and_2(dumped, tmp_path, runs_workflow):
    """What a company's CI runs: `.venv/bin/python -m conformance gate DIR` as a process of its own
    (tests/processes.py), its exit status the verdict: 0 and PASS in report.md, report.html,
    verdict.json and junit.xml; 1 and FAIL in each; 2 on unusable input, with none of them left to
    claim a PASS (an earlier gate's files, planted first, are removed)."""
    import processes

    python = ROOT / ".venv" / "bin" / "python"

    def gate(folder):
        return processes.run([str(python), "-m", "conformance", "gate", str(folder), "--no-plots"], cwd=ROOT,
                             capture_output=True, text=True, timeout=300)

    def claims(folder) -> dict[str, str]:
        """What each verdict file of `folder` says: PASS, FAIL, or '' (no verdict it states)."""
        out = {}
        md, html = (folder / "report.md").read_text(), (folder / "report.html").read_text()
        out["report.md"] = "PASS" if "**Verdict: PASS**" in md else "FAIL" if "**Verdict: FAIL**" in md else ""
        out["report.html"] = "PASS" if "Verdict: PASS" in html else "FAIL" if "Verdict: FAIL" in html else ""
        out["verdict.json"] = verdict(folder)["verdict"]
        junit = (folder / "junit.xml").read_text()
        out["junit.xml"] = "FAIL" if "<failure" in junit else "PASS" if "<testcase" in junit else ""
        return out

    good = tmp_path / "good"
    shutil.copytree(dumped, good)
    done = gate(good)
    assert done.returncode == 0 and "PASS" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    assert claims(good) == dict.fromkeys(("report.md", "report.html", "verdict.json", "junit.xml"), "PASS")
    off = tmp_path / "off"
    shutil.copytree(dumped, off)
    write_dumps(off, stiffness=1 + 1e-5)
    done = gate(off)
    assert done.returncode == 1 and "FAIL" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    assert claims(off) == dict.fromkeys(("report.md", "report.html", "verdict.json", "junit.xml"), "FAIL")
    spoiled = tmp_path / "spoiled"
    shutil.copytree(good, spoiled)  # with the good gate's PASS files: a refused gate must not leave them
    _nan(spoiled)
    done = gate(spoiled)
    assert done.returncode == 2 and "UNUSABLE" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    left = [n for n in ("report.md", "report.html", "verdict.json", "junit.xml") if (spoiled / n).exists()]
    assert not any("PASS" in (spoiled / n).read_text() for n in left), left
    assert left == []
