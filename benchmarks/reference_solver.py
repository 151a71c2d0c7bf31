"""Speed of the reference solver's compiled kernel against an earlier version of it, in one run.

The earlier kernel (reference/_taylor.py at --baseline, default the commit before the speed work,
with the generated reference/_coefficients.py of that revision where it has one) is copied out of
git into a temporary folder and imported next to the current one, so that both are timed in the same \
process on the same, possibly
busy, machine. Printed, for the current (new) and the earlier (old) kernel and their ratio:

- one K a call [ms]: solve_collision(K) through the public API, median over repeats of the mean
  over 41 K in [0, 10];
- batch [K/s]: solve_collisions on 2000 random K in [0, 10], median over repeats, old and new
  interleaved; wall clock and process CPU time (the CPU figure is less affected by other jobs on
  the machine);
- first call [s]: import plus the first solve in a fresh process with an empty numba cache (the
  compile), and with the cache filled (what later processes pay), one run each;
- accuracy: the largest relative difference new vs old over the batch sample, field by field, and
  new vs the independent mpmath solution (tests/independent_solver.py) at a few K.

Targets of the speed issue: <= 1 ms per single K, >= 1e5 K/s in a batch on one core. Run with
`make bench` (pinned to one core there).
"""

import argparse
import importlib
import os
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from dataclasses import fields
from pathlib import Path

import numpy as np

from reference import collision_ode

ROOT = Path(__file__).resolve().parents[1]
BASELINE = "b0fd1fc"  # the branch point of the speed work
REPEATS = 9
BATCH = 2000
MPMATH_K = ("0.1", "0.37", "1")  # where tests/independent_solver.py applies


def load_kernel(rev):
    """reference/_taylor.py at git revision `rev`, imported with the generated
    reference/_coefficients.py it imports (where that revision has one) as a package of its own,
    reference_kernel_<sha> in a temporary folder (where its numba cache lives, so that a second
    run loads it)."""
    parsed = subprocess.run(["git", "rev-parse", "--short", "--verify", f"{rev}^{{commit}}"], cwd=ROOT,
                            capture_output=True, text=True)
    if parsed.returncode != 0:
        raise SystemExit(f"--baseline {rev}: not a git revision of {ROOT}")
    sha = parsed.stdout.strip()
    package = f"reference_kernel_{sha}"
    folder = Path(tempfile.gettempdir()) / package
    folder.mkdir(exist_ok=True)
    for name in ("__init__.py", "_taylor.py", "_coefficients.py"):
        shown = subprocess.run(["git", "show", f"{sha}:reference/{name}"], cwd=ROOT,
                               capture_output=True, text=True)
        source = "" if name == "__init__.py" else shown.stdout
        if shown.returncode != 0 and name != "_coefficients.py":
            raise SystemExit(f"--baseline {rev}: no reference/{name} there ({shown.stderr.strip()})")
        path = folder / name
        if not path.exists() or path.read_text() != source:  # rewriting would void numba's cache
            path.write_text(source)
    sys.path.insert(0, str(folder.parent))
    try:
        return importlib.import_module(f"{package}._taylor"), sha
    finally:
        sys.path.remove(str(folder.parent))


@contextmanager
def kernel(module):
    """The public API (collision_ode) running on `module`."""
    saved = collision_ode._kernel
    collision_ode._kernel = lambda: module
    try:
        yield
    finally:
        collision_ode._kernel = saved


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - w, time.process_time() - c


def first_call_seconds(cache_dir, rev=None):
    """Wall time of `import reference; solve_collisions([0.3])` in a fresh process, with the
    kernel of this checkout or (rev) the old one."""
    old = (f"from benchmarks.reference_solver import load_kernel; from reference import collision_ode; "
           f"m = load_kernel({rev!r})[0]; collision_ode._kernel = lambda: m; ") if rev else ""
    code = ("import time; t = time.perf_counter(); from reference import solve_collisions; " + old +
            "solve_collisions([0.3]); print(time.perf_counter() - t)")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True, cwd=ROOT)
    return float(out.stdout.split()[-1])


def relative_difference(a, b):
    return np.abs(a - b) / np.where(b == 0, 1.0, np.abs(b))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", default=BASELINE, help="git revision of the old kernel")
    parser.add_argument("--no-compile", action="store_true", help="skip the first-call timing")
    args = parser.parse_args()

    new = collision_ode._kernel()
    old, sha = load_kernel(args.baseline)
    rng = np.random.default_rng(2024)
    sample = rng.uniform(0.0, 10.0, BATCH)
    singles = np.linspace(0.0, 10.0, 41)
    modules = {"new": new, "old": old}
    for module in modules.values():  # compile or load numba's cache: not timed
        with kernel(module):
            collision_ode.solve_collisions([0.3])

    single = {name: [] for name in modules}
    wall = {name: [] for name in modules}
    cpu = {name: [] for name in modules}
    for _ in range(REPEATS):  # interleaved, so that both see the same load
        for name, module in modules.items():
            with kernel(module):
                w, _ = timed(lambda: [collision_ode.solve_collision(float(k)) for k in singles])
                single[name].append(w / len(singles) * 1e3)
                w, c = timed(lambda: collision_ode.solve_collisions(sample))
                wall[name].append(BATCH / w)
                cpu[name].append(BATCH / c if c > 0 else np.nan)
    med = {key: {name: statistics.median(v[name]) for name in modules}
           for key, v in (("single", single), ("wall", wall), ("cpu", cpu))}

    first = {}
    if not args.no_compile:
        for name, rev in (("new", None), ("old", args.baseline)):
            with tempfile.TemporaryDirectory() as cache:
                first[name] = (first_call_seconds(cache, rev), first_call_seconds(cache, rev))

    table_new = collision_ode.solve_collisions(sample)
    with kernel(old):
        table_old = collision_ode.solve_collisions(sample)
    worst = {f.name: float(np.max(relative_difference(getattr(table_new, f.name),
                                                      getattr(table_old, f.name))))
             for f in fields(table_new) if f.name not in ("K", "energy_residual")}
    sys.path.insert(0, str(ROOT / "tests"))
    from independent_solver import solve_high_precision
    worst_mp = {}
    for K in MPMATH_K:
        exact = solve_high_precision(K, dps=25)
        fast = collision_ode.solve_collision(float(K))
        for key, value in exact.items():
            worst_mp[key] = max(worst_mp.get(key, 0.0), abs(fast[key] / float(value) - 1.0))

    print(f"reference solver kernel: new (this checkout) vs old ({sha}), K in [0, 10], one process")
    print(f"  {'':30s} {'new':>11s} {'old':>11s} {'new/old':>8s}")
    s = med["single"]
    print(f"  {'one K a call [ms]':30s} {s['new']:11.4f} {s['old']:11.4f} {s['new'] / s['old']:8.3f}"
          f"   (median of {REPEATS}, mean over {len(singles)} K)")
    for key, label in (("wall", "batch [K/s], wall clock"), ("cpu", "batch [K/s], process CPU")):
        r = med[key]
        print(f"  {label:30s} {r['new']:11.4g} {r['old']:11.4g} {r['new'] / r['old']:8.2f}"
              f"   (median of {REPEATS} batches of {BATCH} random K)")
    if first:
        (new_compile, new_cached), (old_compile, old_cached) = first["new"], first["old"]
        print(f"  {'first call, empty cache [s]':30s} {new_compile:11.1f} {old_compile:11.1f} "
              f"{new_compile / old_compile:8.2f}   (compile; import included)")
        print(f"  {'first call, cache filled [s]':30s} {new_cached:11.2f} {old_cached:11.2f} "
              f"{new_cached / old_cached:8.2f}")
    name = max(worst, key=worst.get)
    print(f"  largest relative difference new vs old over the batch sample: {worst[name]:.1e} ({name})")
    name = max(worst_mp, key=worst_mp.get)
    print(f"  largest relative difference new vs mpmath at K = {', '.join(MPMATH_K)}: "
          f"{worst_mp[name]:.1e} ({name})")
    print(f"  targets: <= 1 ms one K a call: {'met' if s['new'] <= 1.0 else 'NOT met'}; "
          f">= 1e5 K/s in a batch: {'met' if med['wall']['new'] >= 1e5 else 'NOT met'}"
          f" (wall clock; CPU time: {'met' if med['cpu']['new'] >= 1e5 else 'NOT met'})")


if __name__ == "__main__":
    main()
