"""The conformance kit's command line (docs/conformance.md).

    python -m conformance export CASE... [--law L]... [--keyword K] [--told E | --beta B] [--K K...] --out DIR
    python -m conformance gate DIR [--columns FILE] [--no-plots]

export: exit 0, or 2 when the case cannot be planned. gate: 0 PASS, 1 FAIL, 2 unusable input.
"""

from __future__ import annotations

import argparse
import sys

USAGE_ERROR = 2


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m conformance",
                                description="Does your code's Hertz collision do what its manual says? Export the "
                                            "study's runs, run them in your code, gate its dumps as the study gates "
                                            "its engines (docs/conformance.md).")
    sub = p.add_subparsers(dest="command", required=True)
    e = sub.add_parser("export", help="write a plan (plan.json, plan.csv, README.md) of the study's runs of CASEs")
    e.add_argument("cases", nargs="+", metavar="CASE", help="case files (cases/steel.yaml)")
    e.add_argument("--law", action="append", dest="laws", metavar="L",
                   help="a law of contact_model/laws.py (repeatable; default viscoelastic)")
    e.add_argument("--keyword", metavar="K", help="an engine keyword told e or beta (contact_model/keywords.py), e.g. "
                                                  "liggghts:hertz-coefficientRestitution")
    e.add_argument("--told", type=float, metavar="E", help="the restitution a keyword is told (default: the "
                                                           "study's, the reference eps at default_law_match_K)")
    e.add_argument("--beta", type=float, metavar="B", help="the damping ratio a keyword told one is given, as it "
                                                           "stands (yade:betan; no restitution asked)")
    e.add_argument("--K", type=float, nargs="+", metavar="K",
                   help="the K grid for cases without impacts of their own (default: config K_grid)")
    e.add_argument("--out", required=True, metavar="DIR")
    g = sub.add_parser("gate", help="gate DIR/dumps/ against DIR/plan.json")
    g.add_argument("folder", metavar="DIR")
    g.add_argument("--no-plots", action="store_true", help="leave the report's figures undrawn (faster)")
    g.add_argument("--columns", metavar="FILE", help="the column map of plain CSV dumps (default DIR/columns.yaml)")
    return p


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    if args.command == "export":
        from contact_model.case_file import CaseError

        from .export import ExportError, export_plan, write_plan

        if args.keyword and args.laws:
            print("--law and --keyword exclude each other: a keyword is its own law", file=sys.stderr)
            return USAGE_ERROR
        try:
            plan = export_plan(args.cases, args.laws or ["viscoelastic"], args.keyword, args.K, args.told,
                               beta=args.beta)
        except (ExportError, CaseError, ValueError) as err:
            print(f"cannot export: {err}", file=sys.stderr)
            return USAGE_ERROR
        write_plan(plan, args.out)
        print(f"{args.out}: plan {plan['plan_id'][:12]}, {len(plan['runs'])} runs in "
              f"{len({r['ladder'] for r in plan['runs']})} ladders (plan.json, plan.csv, README.md; dumps/ to fill)")
        return 0
    from .gate import gate

    return gate(args.folder, args.columns, log=print, plots=not args.no_plots).status


if __name__ == "__main__":
    sys.exit(main())
