"""Every Snakemake the tests start imports this checkout's packages (engines/, analysis/, ...),
also from the copied projects in tmp folders, which hold only the workflow: put the project first
on PYTHONPATH, ahead of whatever `pip install -e` the venv points at.

Every test is in one tier, by what it starts: its own tier mark if it has one, else the tier of
the fixtures it uses (`TIER_FIXTURES`: `runs_engine`, `runs_workflow`, requested by the fixtures
that start engines, Snakemake, the cluster), else its file's (`TIERS`, for the tests that start
processes themselves), else `unit`:
`unit` runs in-process only, no engine and no process of any kind (`make test-unit`, on any
machine; a unit test that starts a process fails, naming itself: `pytest_runtest_call`),
`engine` runs real engines, `workflow` runs Snakemake (with real engines, and the SLURM cluster
for test_slurm), a browser, or the project's commands as a user types them. `make test` runs all three.

A test run leaves nothing running, however it ends: every process a test starts goes through
tests/processes.py (a session of its own, dying with the test process); pytest and each xdist
worker, told to stop (SIGTERM, SIGHUP: `timeout`, a killed `make test`), first kill those
(`processes.stop_all`); a worker dies with pytest (SIGTERM when pytest is gone, PR_SET_PDEATHSIG);
and the run stops the local SLURM cluster if it started it (`slurm_cluster.release_cluster`).
"""

import atexit
import os
import signal
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])


#: The test files whose tests start processes themselves, without a fixture of TIER_FIXTURES or a
#: tier mark of their own (every other test is in its fixtures' tier, else `unit`): a new file
#: whose tests use those fixtures, or carry their mark, needs no entry here.
TIERS = {
    "engine": {"test_engine_*.py", "test_unequal_spheres.py"},
    "workflow": {"test_workflow.py", "test_study_failures.py", "test_builds.py", "test_readme.py", "test_cli.py"},
}


#: Whether this process is an xdist worker (set by `pytest_configure`), not pytest's own process.
IS_WORKER = False
#: The signals that stop a test run cleanly: its processes are killed first (`stop_test_run`).
STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


def pytest_configure(config):
    """Name the run (slurm_cluster.TEST_RUN) in pytest's own process; make a worker die with it;
    stop what the run started on SIGTERM, SIGHUP and at exit."""
    from engines.engine_process import dies_with
    from slurm_cluster import TEST_RUN, run_id

    global IS_WORKER
    worker = IS_WORKER = hasattr(config, "workerinput")
    if worker:
        dies_with(os.getppid(), signal.SIGTERM)()  # an xdist worker: SIGTERM when pytest is gone
    else:
        os.environ[TEST_RUN] = run_id()
    for sig in STOP_SIGNALS:
        signal.signal(sig, stop_test_run)
    atexit.register(finish_test_run)


def finish_test_run() -> None:
    """Kill what this process's tests started and, in pytest's own process, release the cluster."""
    import processes

    processes.stop_all()
    # Not by PYTEST_XDIST_WORKER: a pytest started by a worker's test inherits that variable, and would
    # then never release the cluster lease it took.
    if not IS_WORKER:
        from slurm_cluster import TEST_RUN, release_cluster, run_id

        if os.environ.get(TEST_RUN) == run_id():
            release_cluster()


def stop_test_run(signum, frame):
    """The handler of STOP_SIGNALS: finish the run (`finish_test_run`), then die of the signal. The
    signals wait meanwhile: a worker stopped with its pytest gets SIGTERM twice (the process
    group's, then its death signal), and the second must not cut the first's clean-up short."""
    signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    try:
        finish_test_run()
    finally:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)


def pytest_sessionfinish(session):
    if not hasattr(session.config, "workerinput"):
        finish_test_run()


#: The fixtures that give a test its tier by what they start, highest tier first: a fixture that
#: starts an engine (or hands one to the test) requests `runs_engine`, one that starts Snakemake, the
#: SLURM cluster or the project's commands `runs_workflow`, and every test that uses it, directly or
#: through other fixtures (`item.fixturenames`), is in that tier, whatever file it is in.
TIER_FIXTURES = {"workflow": "runs_workflow", "engine": "runs_engine"}


@pytest.fixture(scope="session")
def runs_workflow():
    """A test that uses it, directly or through a fixture, is in the `workflow` tier (TIER_FIXTURES)."""


@pytest.fixture(scope="session")
def runs_engine():
    """A test that uses it, directly or through a fixture, is in the `engine` tier (TIER_FIXTURES)."""


def pytest_collection_modifyitems(config, items):
    import pytest

    for item in items:
        if not any(item.get_closest_marker(tier) for tier in ("unit", *TIERS)):  # a test's own tier holds
            item.add_marker(getattr(pytest.mark, tier_of_item(item)))


def tier_of_item(item) -> str:
    """A test's tier by what it starts: the highest tier of TIER_FIXTURES whose fixture it uses, else its
    file's (`tier_of`)."""
    names = set(getattr(item, "fixturenames", ()))
    return next((t for t, fixture in TIER_FIXTURES.items() if fixture in names), None) or tier_of(item.path.name)


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


class UnitTierError(RuntimeError):
    """A test of the unit tier started a process: it belongs to the engine or workflow tier."""


def _refuse_processes(nodeid: str):
    """A replacement of subprocess.Popen.__init__ that refuses, naming the test and the command."""

    def refuse(self, args, *rest, **kwargs):
        shown = args if isinstance(args, str) else " ".join(map(str, args))
        raise UnitTierError(f"{nodeid}: a unit test started a process ({shown[:100]}); the unit tier runs in-process "
                            "only: let the fixture that starts it request `runs_engine` or `runs_workflow` "
                            "(tests/conftest.py TIER_FIXTURES), or mark the test `engine` or `workflow`")

    return refuse


def pytest_runtest_call(item):
    """The unit tier starts no process (engine, Snakemake, SLURM, pip, the project's own commands): a
    unit test that does fails, naming itself (`UnitTierError`), so that `make test-unit` stays fast
    and needs no engine. Tiers are by what a test starts, checked here, not by its file's name."""
    if item.get_closest_marker("unit") is None:
        return
    import subprocess

    item.add_report_section("call", "tier", "unit: processes refused")
    original = subprocess.Popen.__init__
    subprocess.Popen.__init__ = _refuse_processes(item.nodeid)
    item.addfinalizer(lambda: setattr(subprocess.Popen, "__init__", original))
