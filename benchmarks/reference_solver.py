"""Throughput of the reference solver: a sweep of 1,000 K values in [0, 1] at full accuracy.

Prints the median wall time over repeats, the K values per second, and for comparison the
rate of solving the same K values one at a time (batch of one). Goal: >= 1,000 K/s on one core.
Run with `make bench` (pinned to one core there).
"""

import statistics
import time

import numpy as np

from reference.collision_ode import solve_collisions

REPEATS = 7
GOAL = 1000.0


def median_seconds(fn, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), max(times)


def main():
    K = np.linspace(0.0, 1.0, 1000)
    solve_collisions(K[:10])  # warm-up (imports, first compilation of numpy paths)
    med, lo, hi = median_seconds(lambda: solve_collisions(K))
    rate = len(K) / med
    single_K = K[::50]
    med1, _, _ = median_seconds(lambda: [solve_collisions([k]) for k in single_K], repeats=3)
    rate1 = len(single_K) / med1
    print("reference solver, sweep of 1000 K in [0, 1], rtol 1e-13 (DOP853, batches of 128)")
    print(f"  batch sweep : median {med * 1e3:8.1f} ms (min {lo * 1e3:.1f}, max {hi * 1e3:.1f}, "
          f"{REPEATS} runs) -> {rate:8.0f} K/s")
    print(f"  one K a call: median {med1 / len(single_K) * 1e3:8.2f} ms per K"
          f"                      -> {rate1:8.0f} K/s")
    print(f"  batch / single speed-up: {rate / rate1:.1f}x; goal >= {GOAL:.0f} K/s: "
          f"{'met' if rate >= GOAL else 'NOT met'}")


if __name__ == "__main__":
    main()
