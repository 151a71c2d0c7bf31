"""The time-step advisor's map (reference.engine_map, analysis.timestep) stands in for every
build at the steps users run: each build runs each law it has at dt = 0.05, 0.1, 0.2 and 0.3 of the
Rayleigh time, the contact starting at two phases of the step grid, and its T, A and eps equal the
map's replay at that dt and phase to the rounding of positions stored at the radius's magnitude
(analysis.map_reference), at every one. (The ladders' runs are compared at every rung of the
study the same way: summary.csv `map_err_*`.)"""

import shutil
from dataclasses import replace
from pathlib import Path

import pytest
import yaml

from contact_model.keywords import missing_in
from contact_model.laws import LAWS
from engine_cases import VELOCITY, dump_metrics, missing, steel_pair
from engines import RunSpec, run_sweep
from engines.builds import check_build, load_builds
from engines.codes import CODES, keyword_of, law_unavailable
from analysis.map_reference import map_errors
from records.dump_file import read_dump

ROOT = Path(__file__).resolve().parents[1]
BUILDS = load_builds(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"], ROOT)
FRACTIONS_OF_T_R = (0.05, 0.1, 0.2, 0.3)
PHASES = (0.2, 0.7)
#: engine / map - 1 at production steps: the rounding of positions (1e-16 of R over ~60 steps,
#: relative to delta_max ~ 1e-3 R) and of ESyS's forces read back from velocity jumps.
AGREEMENT = 1e-10  # measured: at most 8e-13 (Kratos) to 7e-13 (LAMMPS), every law and phase


def production_runs(build) -> list[RunSpec]:
    """Every law `build` has, at each fraction of T_R and each start phase, unaligned."""
    banner = check_build(build)
    runs = []
    for law in LAWS:
        keyword = keyword_of(law, build.code)
        if law_unavailable(build.code, law) or (keyword and missing_in(keyword, banner)):
            continue
        geometry = "sphere-plane" if build.code == "liggghts" else "sphere-sphere"
        pair = steel_pair(geometry, 0.0 if law == "elastic" else 0.1)
        base = RunSpec("advisor", build.code, law, pair, VELOCITY, build=build.id,
                       matched_restitution=0.8 if keyword else None)
        T_e, T_R = base.scales["T_e"], pair.rayleigh_time()
        runs += [replace(base, time_step_factor=T_e / (f * T_R), start_phase=phase, aligned=False)
                 for f in FRACTIONS_OF_T_R for phase in PHASES]
    return runs


@pytest.mark.parametrize("build", BUILDS, ids=[b.id for b in BUILDS])
def test_every_build_follows_the_map_at_production_steps_and_phases(build, tmp_path):
    if shutil.which(build.executable) is None:
        missing(f"{build.executable} is not installed ({build.code}); {CODES[build.code].install_hint}")
    runs = production_runs(build)
    sweep = run_sweep(build, runs, tmp_path / build.id, timeout_floor_s=120)
    assert not sweep.failures, sweep.failures
    worst = {}
    for spec in runs:
        meta, m = dump_metrics(sweep.dumps[spec.name])
        assert meta["start_phase"] == spec.start_phase
        assert spec.time_step == pytest.approx(meta["T_e"] / spec.time_step_factor, rel=1e-15)  # unaligned
        samples = len(read_dump(sweep.dumps[spec.name])[1]["time"]) - 1
        errors = map_errors(meta, m, samples)
        assert set(errors) == set(spec.represents), spec.name
        for criterion, e in errors.items():
            for q, value in e.items():
                key = (spec.law, criterion, q)
                worst[key] = max(worst.get(key, 0.0), abs(value))
    assert {law for law, _, _ in worst} >= {"elastic", "default"}
    print(build.id, len(runs), "runs; worst engine / map - 1:", f"{max(worst.values()):.1e}")
    assert max(worst.values()) < AGREEMENT, {k: f"{v:.1e}" for k, v in worst.items() if v >= AGREEMENT}
