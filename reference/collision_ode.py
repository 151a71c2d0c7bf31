r"""High-accuracy solution of the dimensionless viscoelastic Hertz collision.

The ODE (the paper's eq. 2, with x = delta/delta_e and tau = t V/delta_e)::

    x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,

is integrated to a relative accuracy of about 1e-12 for K in [0, 10].

Why it is not integrated in tau from tau = 0 to the end
-------------------------------------------------------
x^{1/2} is not differentiable at x = 0, so x(tau) is a series in tau^{1/2} there and every
fixed-order integrator in tau loses its order near both ends of the contact. With u = sqrt(x)
as the independent variable (dx = 2u du) the same motion reads::

    dv/du   = -2 K u^2 - (5/2) u^4 / v        (v = x')
    dtau/du = 2 u / v
    dD/du   = 4 K u^2 v                        (D: dissipated energy, fraction of (1/2) M* V^2)

which is smooth wherever v != 0, i.e. everywhere but at the maximum compression, where v(u) has
a square-root branch point. Away from x = 0 the motion in tau is smooth, the maximum compression
and the force zero included::

    dx/dtau = v,   dv/dtau = -x^{1/2} (K v + 5/4 x),   dD/dtau = 2 K x^{1/2} v^2

The collision is therefore split into four phases, none of which meets a singularity, so that
the maximum compression and both ends are integration end points:

    A  u = sqrt(x) from 0 to u_s        (approach; x_s is 0.7 times a lower bound of x_max)
    B1 tau from tau(x_s) to v = 0       (ends at the maximum compression, located on the last
                                         step's polynomial)
    B2 tau from tau_max to x <= x_c     (the first step end with x <= 0.7 x_max)
    C  u = sqrt(x) from sqrt(x_c) to 0  (ends at x = 0: the x0 criterion)

Phase C starts well away from the branch point at the maximum compression, where the steps in u
are short (an earlier B2 in v, which has the force zero as a singularity, had to hand over next
to it: 35 to 65 steps a K where this takes 19 to 42).

Each phase is integrated with a compiled (numba) Taylor-series method of degree 22 (module
`reference._taylor`): both phase systems are polynomials, square roots and quotients, whose
Taylor coefficients follow from short recurrences (unrolled to straight-line code by
`reference._generate_coefficients`), and the step is chosen from the decay of the last
coefficients so that the first neglected term is ~1e-16 of the state. The step polynomials
are the dense output: the maximum compression, the force zero (F0 criterion) and the maximum force
are found on them with Brent's method, and `collision_trajectory` samples them. K values are solved one after the other
in compiled code (no stacking), so a batch costs what its K cost one at a time. The first call in
a fresh checkout compiles the kernel (several seconds) and caches it in reference/__pycache__;
later processes load it from there. The DOP853 solver this replaced is kept as
`tests/scipy_solver.py`, the slow cross-check of the tests.

Energies are fractions of the impact kinetic energy (1/2) M* V^2: kinetic v^2, elastic x^{5/2}
and dissipated D = 2 K int x^{1/2} x'^2 dtau. D is integrated on its own, so that
v^2 + x^{5/2} + D = 1 is a genuine check of the integration, not an identity.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

#: Kept for callers of solve_collisions(batch=...): the compiled solver groups K values by itself
#: (eight at a time, bit-identical to one at a time), so the batch size changes nothing.
BATCH = 128
K_RANGE = (0.0, 10.0)

ELASTIC = 1.25  # the 5/4 of (5/4) x^{3/2}


@dataclass(frozen=True)
class CollisionTable:
    """Characteristics of the dimensionless collision, one entry per K (all numpy arrays).

    Lengths are in units of delta_e, times of delta_e/V, velocities of V, forces of
    M* V^2/delta_e and energies of (1/2) M* V^2.

    Attributes
    ----------
    K : dissipation parameter.
    x_max : maximum compression delta_max/delta_e (= A/A_e, the same under both criteria).
    tau_max : time of the maximum compression.
    tau_f, eps_F0 : end time and restitution coefficient when the contact force first
        returns to zero (criterion F0, Schwager & Poeschel). For K = 0 they equal the x0 values.
    tau_0, eps_x0 : end time and restitution coefficient when the overlap returns to zero
        (criterion x0: the ODE as written, with its small attractive tail).
    force_max, tau_force_max, x_force_max : maximum of the force x^{1/2}(5/4 x + K x'), its time
        and the compression at that time.
    dissipated_at_max, dissipated_F0, dissipated_x0 : dissipated energy at the maximum
        compression and at either end of the collision.
    energy_residual : largest |kinetic + elastic + dissipated - 1| over the phase end points.
    """

    K: np.ndarray
    x_max: np.ndarray
    tau_max: np.ndarray
    tau_f: np.ndarray
    eps_F0: np.ndarray
    tau_0: np.ndarray
    eps_x0: np.ndarray
    force_max: np.ndarray
    tau_force_max: np.ndarray
    x_force_max: np.ndarray
    dissipated_at_max: np.ndarray
    dissipated_F0: np.ndarray
    dissipated_x0: np.ndarray
    energy_residual: np.ndarray

    def row(self, i: int) -> dict:
        """The i-th entry as a dict of floats.

        Parameters
        ----------
        i : int
            The index of the entry, 0 <= i < len(K) [-].

        Returns
        -------
        dict of str to float
            Every field of the table at entry i, in the table's dimensionless units (lengths of delta_e,
            times of delta_e/V, velocities of V, forces of M* V^2/delta_e, energies of (1/2) M* V^2).
        """
        return {f.name: float(getattr(self, f.name)[i]) for f in fields(self)}

    def rows(self) -> list[dict]:
        """Every entry as a dict of floats, in the order of K.

        Returns
        -------
        list of dict
            `row` (i) for each i, in the table's dimensionless units.
        """
        return [self.row(i) for i in range(len(self.K))]


def _kernel():
    """The compiled kernel, imported on first use: numba's import (~0.3 s) is paid only by
    processes that solve, not by every `import reference`."""
    from . import _taylor
    return _taylor


def _force(x, v, K):
    """Dimensionless contact force x^{1/2} (5/4 x + K x') (units of M* V^2/delta_e)."""
    return np.sqrt(x) * (ELASTIC * x + K * v)


def _raise_on_failure(status, K) -> None:
    kernel = _kernel()
    bad = status != kernel.OK
    if np.any(bad):
        raise FloatingPointError(f"reference ODE integration failed for K = {K[bad]}")


def _solve_batch(K: np.ndarray) -> CollisionTable:
    table, status = _kernel().solve_batch(np.ascontiguousarray(K, dtype=float))
    _raise_on_failure(status, K)
    return CollisionTable(*(table[:, i].copy() for i in range(table.shape[1])))


def collision_trajectory(K: float, points_per_phase: int = 200) -> dict[str, np.ndarray]:
    """The trajectory of one collision up to x = 0 and its energy partition.

    Sampled uniformly in each phase's own variable (denser where x changes fast), sorted in
    tau, evaluated on the Taylor polynomials of the integration steps (as accurate as the step
    ends).

    Parameters
    ----------
    K : float
        The dissipation parameter, in [0, 10] [-].
    points_per_phase : int
        The samples taken in each of the four phases of the integration [-].

    Returns
    -------
    dict of str to numpy.ndarray
        tau [delta_e/V], x [delta_e], v (= x') [V], force (x^{1/2}(5/4 x + K x')) [M* V^2/delta_e],
        kinetic (v^2), elastic (x^{5/2}) and dissipated (D), the energies as fractions of
        (1/2) M* V^2 [-].

    Raises
    ------
    ValueError
        For K outside [0, 10].

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the dimensionless equation of motion, eq. 2.
    Kuwabara, G. & Kono, K. (1987), the dissipative force (cited as [Kuwabara87] by He & Wettlaufer).
    Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
    granular gases. Phys. Rev. E 53, 5382.
    """
    if not K_RANGE[0] <= K <= K_RANGE[1]:
        raise ValueError(f"K must lie in [{K_RANGE[0]}, {K_RANGE[1]}], got {K}")
    s = np.linspace(0.0, 1.0, points_per_phase)
    out, status = _kernel().trajectory(float(K), np.ascontiguousarray(np.tile(s, (4, 1))))
    _raise_on_failure(np.array([status]), np.array([K]))
    x, v, tau, D = (out[:, :, i].ravel() for i in range(4))
    order = np.argsort(tau, kind="stable")
    x, v, tau, D = x[order], v[order], tau[order], D[order]
    return {"tau": tau, "x": x, "v": v, "force": _force(np.maximum(x, 0.0), v, K),
            "kinetic": v * v, "elastic": np.maximum(x, 0.0) ** 2.5, "dissipated": D}


def solve_collisions(K, *, batch: int = BATCH, allow_negative: bool = False) -> CollisionTable:
    """Solve the dimensionless collision for every value in `K`.

    Parameters
    ----------
    K : float or array_like
        Dissipation parameter(s), K = 2 eta sqrt(R*) delta_e^{3/2} / (M* V), in [0, 10].
    batch : int
        Unused, kept so that callers stay unchanged: the compiled solver takes the K values
        one after the other, so there is nothing to stack.
    allow_negative : bool
        Accept K in [-0.5, 0) (energy gain). Only the x0 quantities are meaningful there;
        it exists so that Taylor coefficients in K can be fitted on an interval around 0.

    Returns
    -------
    CollisionTable
        One entry per K, in input order.

    Examples
    --------
    >>> t = solve_collisions([0.1, 1.0])
    >>> [round(float(e), 12) for e in t.eps_x0]
    [0.904885783492, 0.380838630487]
    """
    K = np.atleast_1d(np.asarray(K, dtype=float))
    if K.ndim != 1 or not np.all(np.isfinite(K)):
        raise ValueError(f"K must be a finite number or a 1-D list of them, got {K!r}")
    low = -0.5 if allow_negative else K_RANGE[0]
    if np.any(K < low) or np.any(K > K_RANGE[1]):
        raise ValueError(f"K must lie in [{low}, {K_RANGE[1]}], got {K[(K < low) | (K > K_RANGE[1])]}")
    return _solve_batch(K)


def solve_collision(K: float) -> dict:
    """Characteristics of one collision as a dict of floats (see `CollisionTable`).

    Parameters
    ----------
    K : float
        The dissipation parameter, in [0, 10] [-].

    Returns
    -------
    dict of str to float
        The fields of `CollisionTable` for this K, in its dimensionless units.

    References
    ----------
    He, A. & Wettlaufer, J. S. "Hertz beyond expectations":
    the dimensionless equation of motion, eq. 2.
    Schwager, T. & Poeschel, T. (2008), the F0 criterion: the bodies separate where the force
    vanishes (cited as [Schwager08] by He & Wettlaufer).
    """
    return solve_collisions([K]).row(0)
