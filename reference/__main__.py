"""Command line of the reference solver.

    python -m reference 0.1 0.5            a readable table, one row per K
    python -m reference 0.1 0.5 --json     one JSON object per line and K
    python -m reference --series           the computed Taylor coefficients beside the paper's
"""

from __future__ import annotations

import argparse
import json
import sys

from .collision_ode import K_RANGE, solve_collisions
from .series import compare_with_paper

COLUMNS = ("K", "x_max", "tau_max", "tau_f", "eps_F0", "tau_0", "eps_x0", "force_max",
           "dissipated_at_max", "dissipated_x0", "energy_residual")


def _print_table(rows: list[dict]) -> None:
    print("  ".join(f"{c:>18}" for c in COLUMNS))
    for r in rows:
        print("  ".join(f"{r[c]:18.15g}" for c in COLUMNS))


def _print_series(order: int) -> None:
    table = compare_with_paper(order)
    print("Taylor coefficients in K, criterion x0 (computed from the solver) beside the paper's")
    print(f"{'quantity':>8} {'order':>5} {'paper':>9} {'eq.':>4} {'computed':>20} "
          f"{'uncertainty':>11} {'paper-computed':>15}")
    for r in table.itertuples():
        has_paper = r.paper == r.paper  # not NaN
        paper = f"{r.paper:9.4f}" if has_paper else f"{'-':>9}"
        eq = f"{r.equation:>4}" if has_paper else f"{'':>4}"
        diff = f"{r.difference:15.2e}" if has_paper else f"{'':>15}"
        print(f"{r.quantity:>8} {r.order:5d} {paper} {eq} {r.computed:20.12f} "
              f"{r.uncertainty:11.1e} {diff}")
    print("The paper prints 4 decimals: |paper-computed| > 5e-5 is a real difference.")


def main(argv: list[str] | None = None) -> int:
    """Run the reference solver's command line (the module docstring lists its forms).

    Parameters
    ----------
    argv : list of str or None
        The command-line arguments without the program name (None: ``sys.argv[1:]``) [-].

    Returns
    -------
    int
        The exit status, 0 on success (argparse exits with 2 on a usage error) [-].
    """
    parser = argparse.ArgumentParser(prog="python -m reference", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("K", nargs="*", type=float,
                        help=f"dissipation parameter(s) in [{K_RANGE[0]}, {K_RANGE[1]}]")
    parser.add_argument("--json", action="store_true", help="one JSON object per line and K")
    parser.add_argument("--series", action="store_true",
                        help="print the Taylor coefficients beside the paper's series")
    parser.add_argument("--order", type=int, default=6, help="highest order with --series")
    args = parser.parse_args(argv)
    if not args.K and not args.series:
        parser.error("give at least one K, or --series")
    if args.K:
        try:
            rows = solve_collisions(args.K).rows()
        except ValueError as err:
            parser.error(str(err))
        if args.json:
            for r in rows:
                print(json.dumps(r))
        else:
            _print_table(rows)
    if args.series:
        _print_series(args.order)
    return 0


if __name__ == "__main__":
    sys.exit(main())
