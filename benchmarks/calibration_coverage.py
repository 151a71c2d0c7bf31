"""Benchmark: is the calibration's 95 % interval honest, and how long does one fit take?

    python -m benchmarks.calibration_coverage [N_SETS]

Prints the coverage of the profile-likelihood interval over N_SETS (default 1000) synthetic
Gugan-like sets fitted with the exact solver (10 points over a decade in V, K(V_max) = 0.3,
noise 0.005 on eps), with the uncertainty estimated from the scatter and with it given (right,
and understated 1.5 and 3 times), each beside what the interval rule gives in a linear model
(`calibration.synthetic.expected_coverage`: 95 % from the scatter; 97.1 %, 95.2 %, 95.0 % with
stated sigma, conservative where they are right), and the median time of fitting one 10-point
set with its interval (one core).
"""

from __future__ import annotations

import statistics
import sys
import time

from calibration.fit import fit_restitution
from contact_model import CRITERIA
from calibration.synthetic import NOISE, coverage, expected_coverage, synthetic_sets


def main(n_sets: int = 1000) -> None:
    V, _, observed = synthetic_sets(20, seed=99)
    fit_restitution(V, observed[0])  # load the compiled solver first
    times = []
    for eps in observed:
        t0 = time.perf_counter()
        fit = fit_restitution(V, eps)
        times.append(time.perf_counter() - t0)
    print(f"one 10-point fit with its 95 % interval (exact solver, x0): median {1e3 * statistics.median(times):.1f} ms "
          f"over {len(times)} sets ({fit.evaluations} model evaluations in the last)")
    for criterion in CRITERIA:
        for kind, sigma_given, understated in (("sigma estimated (profile-t)", False, 1.0),
                                               ("sigma given, right", True, 1.0),
                                               ("sigma given, understated 1.5x", True, 1.5),
                                               ("sigma given, understated 3x", True, 3.0)):
            t0 = time.perf_counter()
            c = coverage(n_sets, seed=2024, sigma_given=sigma_given, criterion=criterion,
                         stated_noise=NOISE / understated)
            expected = expected_coverage(understated) if sigma_given else 0.95
            se = c.standard_error_at(expected)
            print(f"coverage {criterion}, {kind}: {100 * c.fraction:.1f} % of {c.sets - c.refused} sets "
                  f"(refused {c.refused}); the rule gives {100 * expected:.1f} %, binomial s.e. {100 * se:.1f} % "
                  f"({(c.fraction - expected) / se:+.1f} s.e.); median k {c.median_k:.5f} (true {c.k_true}); "
                  f"{time.perf_counter() - t0:.1f} s")

if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
