"""Speed of the reference solver (compiled Taylor method) against the DOP853 solver it replaced.

Prints medians over repeated runs in one process (after a warm-up call, so numba's compilation
or cache load is not timed): one K per call (ms), batch throughput on one core for sweeps of
1,000 and 10,000 K in [0, 10], the ratio new/old, and the largest relative deviation between
the two solvers over the 1,000-K sweep. The old solver is timed on fewer K (it is slow); its
rates are K per second all the same. Run with `make bench` (pinned to one core there).
Targets of the speed issue: <= 1 ms per single K, >= 1e5 K/s in a batch.
"""

import statistics
import time
from dataclasses import fields

import numpy as np

from reference import collision_ode, collision_ode_scipy

REPEATS = 7


def median_seconds(fn, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def single_ms(module, Ks, repeats):
    """Median over `repeats` of the mean time of solve_collision(K) over Ks, in ms."""
    return median_seconds(lambda: [module.solve_collision(float(k)) for k in Ks], repeats) / len(Ks) * 1e3


def rate(module, K, repeats):
    return len(K) / median_seconds(lambda: module.solve_collisions(K), repeats)


def max_deviation(K):
    new, old = collision_ode.solve_collisions(K), collision_ode_scipy.solve_collisions(K)
    worst = {}
    for f in fields(new):
        if f.name in ("K", "energy_residual"):
            continue
        a, b = getattr(new, f.name), getattr(old, f.name)
        worst[f.name] = float(np.max(np.abs(a - b) / np.where(b == 0, 1.0, np.abs(b))))
    return worst


def main():
    sweep_1k, sweep_10k = np.linspace(0.0, 10.0, 1000), np.linspace(0.0, 10.0, 10000)
    singles = np.linspace(0.0, 10.0, 41)
    collision_ode.solve_collisions([0.3])  # compile or load numba's cache: not timed
    collision_ode_scipy.solve_collisions([0.3])

    new_1 = single_ms(collision_ode, singles, REPEATS)
    old_1 = single_ms(collision_ode_scipy, singles[::4], 3)
    new_1k, new_10k = rate(collision_ode, sweep_1k, REPEATS), rate(collision_ode, sweep_10k, 3)
    old_1k = rate(collision_ode_scipy, sweep_1k, 3)
    old_10k = old_1k  # the stacked DOP853 runs in batches of 128: its rate does not depend on the sweep
    worst = max_deviation(sweep_1k)

    print("reference solver: compiled Taylor method (new) vs scipy DOP853 (old), K in [0, 10], one core")
    print(f"  {'':24s} {'new':>12s} {'old':>12s} {'new/old':>9s}")
    print(f"  {'one K a call [ms]':24s} {new_1:12.4f} {old_1:12.2f} {new_1 / old_1:9.4f}   "
          f"(median of {REPEATS}, mean over {len(singles)} K)")
    print(f"  {'batch 1000 K [K/s]':24s} {new_1k:12.4g} {old_1k:12.4g} {new_1k / old_1k:9.1f}")
    print(f"  {'batch 10000 K [K/s]':24s} {new_10k:12.4g} {old_10k:12.4g} {new_10k / old_10k:9.1f}   "
          f"(old: its 1000-K rate)")
    name = max(worst, key=worst.get)
    print(f"  largest relative deviation new vs old over the 1000-K sweep: {worst[name]:.1e} ({name})")
    print(f"  targets: <= 1 ms one K a call: {'met' if new_1 <= 1.0 else 'NOT met'}; "
          f">= 1e5 K/s in a batch: {'met' if min(new_1k, new_10k) >= 1e5 else 'NOT met'}")


if __name__ == "__main__":
    main()
