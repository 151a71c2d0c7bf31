"""The viscosity eta that gives a material the dissipation K you want, from its case file.

    python -m contact_model.viscosity_for_k cases/mine.yaml --K 0.05 0.5
    python -m contact_model.viscosity_for_k cases/mine.yaml --K 0.1 --velocity "2 m/s" "5 m/s"

K grows with the impact velocity, K = 2 eta sqrt(R*) delta_e^{3/2} / (M* V) ~ eta V^{1/5}
(docs/physics.md): for each geometry of the case and each velocity (the case's own
`impact: velocity`, else --velocity, default 1 m/s) it prints eta [Pa s] and [P] for each target K,
and the K range the case's own viscosity gives over those velocities. A K above ~1 dissipates most
of the impact energy (eps < 0.5): see `python -m reference`.
"""

from __future__ import annotations

import argparse
import sys

from .case_file import load_case
from .collision_scales import viscosity_for_dissipation
from .quantities import POISE, CaseError, quantity


def viscosity_table(case, K_values, velocities) -> list[dict]:
    """One row per geometry, velocity and target K: eta in [Pa s] and in [P].

    Parameters
    ----------
    case : Case
        The case, whose pairs give E* [Pa], R* [m] and M* [kg].
    K_values : sequence of float
        The target dissipation parameters [-].
    velocities : sequence of float
        The impact velocities [m/s].

    Returns
    -------
    list of dict
        geometry, V [m/s], K [-], eta_Pa_s [Pa s], eta_P [P].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    """
    return [{"geometry": p.geometry, "V": V, "K": K, "eta_Pa_s": viscosity_for_dissipation(p.E, p.R, p.M, V, K),
             "eta_P": viscosity_for_dissipation(p.E, p.R, p.M, V, K) / POISE}
            for p in case.pairs for V in velocities for K in K_values]


def main(argv=None) -> int:
    """The command line: the viscosity eta giving each K at each impact velocity.

    Parameters
    ----------
    argv : list of str or None
        The command-line arguments without the program name (None: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0, or 2 for a case or an argument it refuses.
    """
    parser = argparse.ArgumentParser(prog="python -m contact_model.viscosity_for_k",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("case", help="a case file (cases/*.yaml)")
    parser.add_argument("--K", type=float, nargs="+", required=True, help="the target dissipation parameters")
    parser.add_argument("--velocity", nargs="+", default=None,
                        help="impact velocities with their unit, e.g. '1 m/s' (default: the case's, else 1 m/s)")
    args = parser.parse_args(argv)
    try:
        case = load_case(args.case)
        if args.velocity:
            velocities = [quantity(v, "velocity", "--velocity") for v in args.velocity]
        else:
            velocities = list(case.velocities) or [1.0]
    except CaseError as err:
        print(err, file=sys.stderr)
        return 2
    if any(not k > 0 for k in args.K):
        print(f"--K: the dissipation parameters must be positive, got {args.K}", file=sys.stderr)
        return 2
    print(f"{case.name} ({args.case}): the viscosity eta giving each K at each impact velocity")
    print(f"{'geometry':>14} {'V [m/s]':>10} {'K':>8} {'eta [Pa s]':>12} {'eta [P]':>12}")
    for r in viscosity_table(case, args.K, velocities):
        print(f"{r['geometry']:>14} {r['V']:>10.4g} {r['K']:>8.4g} {r['eta_Pa_s']:>12.4g} {r['eta_P']:>12.4g}")
    for p in case.pairs:
        low, high = (p.dissipation_parameter(v) for v in (min(velocities), max(velocities)))
        print(f"The case's own viscosity, {p.eta:.4g} Pa s ({p.eta / POISE:.4g} P), gives K = {low:.4g} to "
              f"{high:.4g} over these velocities ({p.geometry}).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
