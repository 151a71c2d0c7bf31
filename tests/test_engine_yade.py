"""YADE, run for real: the viscoelastic Hertz contact (added to Hertz-Mindlin) against the
reference solver and the out-of-the-box law (a missing engine, a crash and a run that misses the
collision: test_engine_drivers, for every code). All runs of a test share one YADE process, as the
study does."""

import pytest

from engine_cases import TOLERANCE, VELOCITY, dump_metrics, relative_errors, require_engine, steel_pair
from engines import RunSpec
from engines import yade
from reference import solve_collision

GEOMETRIES = ("sphere-sphere", "sphere-plane")


@pytest.fixture(autouse=True)
def _needs_yade(runs_engine):
    require_engine("yade", "yade")


@pytest.fixture(scope="module")
def sweep(tmp_path_factory, runs_engine):
    require_engine("yade", "yade")
    eps = solve_collision(0.1)["eps_F0"]
    specs = [RunSpec("steel", "yade", law, steel_pair(g), VELOCITY)
             for g in GEOMETRIES for law in ("viscoelastic", "viscoelastic_clipped")]
    specs += [RunSpec("steel", "yade", "viscoelastic", steel_pair("sphere-sphere", K=0.0), VELOCITY)]
    specs += [RunSpec("steel", "yade", "default", steel_pair(g), v, matched_restitution=eps)
              for g in GEOMETRIES for v in (VELOCITY, 0.01 * VELOCITY)]
    sweep = yade.run_yade(specs, tmp_path_factory.mktemp("yade")).raise_first()
    dumps = [sweep.dumps[s.name] for s in specs]
    return {(s.law, s.pair.geometry, s.K > 0, s.velocity): (s, *dump_metrics(d)) for s, d in zip(specs, dumps)}


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_viscoelastic_matches_reference_both_criteria(sweep, geometry):
    spec, meta, m = sweep[("viscoelastic", geometry, True, VELOCITY)]
    assert meta["engine"] == "yade" and meta["engine_version"].startswith("YADE 2023.02a")
    assert len(meta["deck_sha256"]) == 64 and meta["represents"] == ["x0", "F0"]
    assert m.samples_in_contact >= 200
    for q, e in relative_errors(m, spec).items():
        assert abs(e) < TOLERANCE, (q, e)


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_clipped_force_matches_reference_F0(sweep, geometry):
    spec, meta, m = sweep[("viscoelastic_clipped", geometry, True, VELOCITY)]
    errors = relative_errors(m, spec)
    for q in ("A", "T_F0", "eps_F0"):
        assert abs(errors[q]) < TOLERANCE, (q, errors[q])


def test_elastic_contact_is_hertz(sweep):
    spec, _, m = sweep[("viscoelastic", "sphere-sphere", False, VELOCITY)]
    errors = relative_errors(m, spec)
    assert abs(errors["eps_x0"]) < 1e-5
    for q in ("A", "T_x0"):
        assert abs(errors[q]) < 1e-4, (q, errors[q])


@pytest.mark.parametrize("geometry", GEOMETRIES)
def test_default_law_restitutes_what_the_user_asked_at_every_velocity(sweep, geometry):
    """Hertz-Mindlin with en: eps_F0 ~ en (Thornton's fit, within 1e-3 here) at both velocities,
    while the viscoelastic eps moves from 0.905 (K = 0.1) to 0.96 (K = 0.04)."""
    asked = solve_collision(0.1)["eps_F0"]
    fast = sweep[("default", geometry, True, VELOCITY)][2]
    slow = sweep[("default", geometry, True, 0.01 * VELOCITY)][2]
    assert fast.eps_F0 == pytest.approx(asked, abs=1e-3)
    assert slow.eps_F0 == pytest.approx(fast.eps_F0, abs=1e-5)
    assert solve_collision(0.1 * 0.01 ** 0.2)["eps_F0"] - slow.eps_F0 > 0.05


def test_yade_2025_wrapper_reads_and_writes_wherever_the_project_is_cloned(tmp_path):
    """make yade-2025's wrapper runs Debian 13's yade in its own root; the host's directories must
    appear there at their own paths. CI clones the project under /check, not /work: a wrapper that
    bound /work and /tmp only ran nothing there. Here a script and its output live in the user's
    home (outside /work and /tmp) and YADE runs from tmp_path."""
    import subprocess
    import tempfile
    from pathlib import Path

    import yaml

    from engines.builds import load_builds
    from engines.codes import CODES
    from engine_cases import missing

    root = Path(__file__).resolve().parents[1]
    builds = load_builds(yaml.safe_load((root / "config" / "config.yaml").read_text())["builds"], root)
    build = next(b for b in builds if b.id == "yade-2025")
    if not Path(build.executable).exists():
        missing(f"{build.executable} is not installed; {CODES['yade'].install_hint}")
    with tempfile.TemporaryDirectory(dir=Path.home(), prefix=".hertz-wrapper-") as elsewhere:
        script, out = Path(elsewhere) / "script.py", Path(elsewhere) / "out.txt"
        script.write_text("import os, sys\nopen(sys.argv[1], 'w').write(os.getcwd())\n")
        run = subprocess.run([build.executable, "-n", "-x", str(script), str(out)], cwd=tmp_path,
                             capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, run.stderr[-2000:]
        assert out.read_text() == str(tmp_path)  # its output on the host, and its cwd kept
