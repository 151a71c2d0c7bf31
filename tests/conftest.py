"""Every Snakemake the tests start imports this checkout's packages (engines/, postprocess/, ...),
also from the copied projects in tmp folders, which hold only the workflow: put the project first
on PYTHONPATH, ahead of whatever `pip install -e` the venv points at.

Every test is in one tier, by its file (`TIERS`) unless it is marked with a tier of its own:
`unit` needs no engine and starts no workflow (`make test-unit`, on any machine, in under 30 s),
`engine` runs real engines, `workflow` runs Snakemake (with real engines, and the SLURM cluster
for test_slurm) or a browser. `make test` runs all three.
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])


#: The test files of the two tiers above `unit` (every other file is `unit`). Every
#: test_engine_*.py is an engine test (`tier_of`): a new code's own tests need no entry here.
TIERS = {
    "engine": {"test_engine_*.py", "test_unequal_spheres.py"},
    "workflow": {"test_workflow.py", "test_study_failures.py", "test_slurm.py", "test_resolution.py", "test_builds.py",
                 "test_readme.py"},
}


def pytest_collection_modifyitems(config, items):
    import pytest

    for item in items:
        if not any(item.get_closest_marker(tier) for tier in ("unit", *TIERS)):  # a test's own tier holds
            item.add_marker(getattr(pytest.mark, tier_of(item.path.name)))


def tier_of(file_name: str) -> str:
    """The tier of a test file: the first of TIERS with a pattern it matches, else 'unit'."""
    from fnmatch import fnmatch

    return next((t for t, patterns in TIERS.items() if any(fnmatch(file_name, p) for p in patterns)), "unit")


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
