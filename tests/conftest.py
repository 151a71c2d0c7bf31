"""Every Snakemake the tests start imports this checkout's packages (engines/, postprocess/, ...),
also from the copied projects in tmp folders, which hold only the workflow: put the project first
on PYTHONPATH, ahead of whatever `pip install -e` the venv points at."""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])


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
