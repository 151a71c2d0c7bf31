"""The dissipation parameter K whose viscoelastic collision restitutes a given eps.

eps_x0(K) and eps_F0(K) (`reference.collision_ode`) fall monotonically from 1 at K = 0 to their
values at the solver's largest K (K_RANGE): `dissipation_for_restitution` inverts them by Brent's
method on the reference solver itself, to 1e-14 in K, so that the K it gives restitutes eps to
round-off under the criterion asked for.
"""

from __future__ import annotations

from scipy.optimize import brentq

from .collision_ode import K_RANGE, solve_collision

CRITERIA = ("x0", "F0")


def dissipation_for_restitution(eps: float, criterion: str = "F0") -> float:
    """The K of x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0 whose restitution under `criterion` is `eps`.

    Parameters
    ----------
    eps : float
        The restitution coefficient to reach, 0 < eps < 1 [-].
    criterion : str
        'F0' (where the force vanishes, the physical separation) or 'x0' (where the overlap does)
        [-].

    Returns
    -------
    float
        The dissipation parameter K, to 1e-14 [-].

    Raises
    ------
    ValueError
        For eps outside (0, 1), an unknown criterion, or an eps below what the largest K of the
        solver restitutes (no K reaches it).

    References
    ----------
    Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
    granular gases. Phys. Rev. E 53, 5382.
    Kuwabara, G. & Kono, K. (1987), the dissipative force (cited as [Kuwabara87] by He & Wettlaufer).
    """
    if criterion not in CRITERIA:
        raise ValueError(f"unknown criterion {criterion!r}; known: {', '.join(CRITERIA)}")
    if not 0.0 < eps < 1.0:
        raise ValueError(f"a restitution coefficient must lie in (0, 1), got {eps!r}")
    key = f"eps_{criterion}"
    least = solve_collision(K_RANGE[1])[key]
    if eps <= least:
        raise ValueError(f"no K in [0, {K_RANGE[1]:g}] restitutes {eps:g} under {criterion}: the viscoelastic "
                         f"collision restitutes at least {least:.4g} there")
    return brentq(lambda K: solve_collision(K)[key] - eps, 0.0, K_RANGE[1], xtol=1e-14, rtol=8.9e-16)
