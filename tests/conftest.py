"""Every Snakemake the tests start imports this checkout's packages (engines/, postprocess/, ...),
also from the copied projects in tmp folders, which hold only the workflow: put the project first
on PYTHONPATH, ahead of whatever `pip install -e` the venv points at.

Every test is in one tier, by its file (`TIERS`): `unit` needs no engine and starts no workflow
(`make test-unit`, on any machine, in under 30 s), `engine` runs real engines, `workflow` runs
Snakemake (with real engines, and the SLURM cluster for test_slurm). `make test` runs all three.
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])


#: The test files of the two tiers above `unit` (every other file is `unit`).
TIERS = {
    "engine": {"test_engine_esys.py", "test_engine_kratos.py", "test_engine_lammps.py", "test_engine_liggghts.py",
               "test_engine_stops.py", "test_engine_yade.py", "test_unequal_spheres.py", "test_engine_drivers.py"},
    "workflow": {"test_workflow.py", "test_study_failures.py", "test_slurm.py", "test_resolution.py", "test_builds.py",
                 "test_readme.py"},
}


def pytest_collection_modifyitems(config, items):
    import pytest

    for item in items:
        name = item.path.name
        tier = next((t for t, files in TIERS.items() if name in files), "unit")
        item.add_marker(getattr(pytest.mark, tier))


def pytest_collection_finish(session):
    """Refuse to run when pytest-xdist's `--dist loadgroup` does not group: the tests marked
    `xdist_group` (one SLURM cluster, one shared study) must run one after another on one worker,
    and pytest 9.2 with pytest-xdist 3.8 silently stopped grouping them (pyproject pins pytest)."""
    if not session.config.getoption("loadgroup", default=False):
        return
    ungrouped = [item.nodeid for item in session.items
                 if item.get_closest_marker("xdist_group") and "@" not in item.nodeid]
    if ungrouped:
        import pytest

        raise pytest.UsageError(f"pytest-xdist's loadgroup did not group {ungrouped[0]} (and {len(ungrouped) - 1} "
                                "more): this pytest and pytest-xdist do not work together; install the versions "
                                "pyproject.toml pins (make test)")
