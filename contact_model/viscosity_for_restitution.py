"""The viscosity eta whose viscoelastic collision restitutes the eps you want, from a case file.

    python -m contact_model.viscosity_for_restitution cases/mine.yaml --restitution 0.8 --velocity "3.9 m/s"
    python -m contact_model.viscosity_for_restitution cases/mine.yaml --restitution 0.8 0.5 --criterion x0

The restitution of the viscoelastic law falls with the impact velocity (K ~ eta V^{1/5}): eta is
set at one velocity. For each geometry of the case, each velocity (--velocity, else the case's
own `impact: velocity`) and each restitution it prints eta [Pa s] at full precision (to paste
into a case file's `viscosity:` or an engine's input), in P, and the K it gives; the reference
solver restitutes eps to round-off with it under the criterion asked for (F0, where the force
vanishes, by default; x0, where the overlap does). A case file may instead say
`impact: {restitution: [0.8], velocity: [3.9 m/s]}`: the study then sets eta itself.
"""

from __future__ import annotations

import argparse
import sys

from reference.dissipation_for_restitution import dissipation_for_restitution

from .case_file import load_case
from .collision_scales import viscosity_for_dissipation
from .quantities import POISE, CaseError, quantity


def viscosity_rows(case, restitutions, velocities, criterion: str = "F0") -> list[dict]:
    """One row per geometry, velocity and restitution: K, eta in [Pa s] and in [P].

    Parameters
    ----------
    case : Case
        The case, whose pairs give E* [Pa], R* [m] and M* [kg].
    restitutions : sequence of float
        The restitution coefficients wanted, each in (0, 1) [-].
    velocities : sequence of float
        The impact velocities [m/s].
    criterion : str
        The end of contact the restitution refers to, 'F0' or 'x0' [-].

    Returns
    -------
    list of dict
        geometry, V [m/s], eps [-], criterion, K [-], eta_Pa_s [Pa s], eta_P [P].

    Raises
    ------
    ValueError
        From `reference.dissipation_for_restitution`, for a restitution no K reaches.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the Hertz scales and K, eqs. 1 and 3.
    Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
    granular gases. Phys. Rev. E 53, 5382.
    """
    rows = []
    for eps in restitutions:
        K = dissipation_for_restitution(eps, criterion)
        for p in case.pairs:
            for V in velocities:
                eta = viscosity_for_dissipation(p.E, p.R, p.M, V, K)
                rows.append({"geometry": p.geometry, "V": V, "eps": eps, "criterion": criterion, "K": K,
                             "eta_Pa_s": eta, "eta_P": eta / POISE})
    return rows


def main(argv=None) -> int:
    """The command line: the viscosity eta that restitutes each coefficient at each impact velocity.

    Parameters
    ----------
    argv : list of str or None
        The command-line arguments without the program name (None: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0, or 2 for a case or an argument it refuses.
    """
    parser = argparse.ArgumentParser(prog="python -m contact_model.viscosity_for_restitution",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("case", help="a case file (cases/*.yaml)")
    parser.add_argument("--restitution", type=float, nargs="+", required=True,
                        help="the restitution coefficients wanted, each in (0, 1)")
    parser.add_argument("--velocity", nargs="+", default=None,
                        help="impact velocities with their unit, e.g. '3.9 m/s': the relative normal velocity of "
                             "the two bodies (default: the case's own)")
    parser.add_argument("--criterion", choices=("F0", "x0"), default="F0",
                        help="the end of contact the restitution refers to (default F0, where the force vanishes)")
    args = parser.parse_args(argv)
    try:
        case = load_case(args.case)
        velocities = ([quantity(v, "velocity", "--velocity") for v in args.velocity] if args.velocity
                      else list(case.velocities))
    except CaseError as err:
        print(err, file=sys.stderr)
        return 2
    if not velocities:
        print(f"--velocity: {args.case} gives no impact velocity: give one, e.g. --velocity '1 m/s' (eta restitutes "
              "eps at one velocity only)", file=sys.stderr)
        return 2
    try:
        rows = viscosity_rows(case, args.restitution, velocities, args.criterion)
    except ValueError as err:
        print(f"--restitution: {err}", file=sys.stderr)
        return 2
    print(f"{case.name} ({args.case}): the viscosity eta whose viscoelastic collision restitutes each eps "
          f"(criterion {args.criterion})")
    print(f"{'geometry':>14} {'V [m/s]':>10} {'eps':>8} {'K':>20} {'eta [Pa s]':>24} {'eta [P]':>24}")
    for r in rows:
        print(f"{r['geometry']:>14} {r['V']:>10.6g} {r['eps']:>8.6g} {r['K']!r:>20} {r['eta_Pa_s']!r:>24} "
              f"{r['eta_P']!r:>24}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
