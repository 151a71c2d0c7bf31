r"""High-accuracy solution of the dimensionless viscoelastic Hertz collision.

The ODE (the paper's eq. 2, with x = delta/delta_e and tau = t V/delta_e)::

    x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,

is integrated to a relative accuracy of about 1e-12 for K in [0, 10].

Why it is not integrated in tau from tau = 0
--------------------------------------------
x^{1/2} is not differentiable at x = 0, so x(tau) is a series in tau^{1/2} there and every
fixed-order integrator in tau loses its order near both ends of the contact. With u = sqrt(x)
as the independent variable (dx = 2u du) the same motion reads::

    dv/du   = -2 K u^2 - (5/2) u^4 / v        (v = x')
    dtau/du = 2 u / v
    dD/du   = 4 K u^2 v                        (D: dissipated energy, fraction of (1/2) M* V^2)

which is smooth wherever v != 0, i.e. everywhere but at the maximum compression. Around the
maximum compression the velocity is the smooth variable instead: v decreases strictly as long
as the contact force is positive (dv/dtau = -F), so with v as independent variable::

    dx/dv = v / a,   dtau/dv = 1 / a,   dD/dv = 2 K x^{1/2} v^2 / a,   a = -x^{1/2} (K v + 5/4 x)

The collision is therefore split into four phases, each with a known span, so that the
maximum compression and both ends are integration end points rather than located events:

    A  u = sqrt(x) from 0 to u_s            (approach; x_s is half a lower bound of x_max)
    B1 v from v(x_s) to 0                   (ends at the maximum compression)
    B2 v from 0 to v_2 < 0                  (v_2 is chosen before the force vanishes)
    C  u = sqrt(x) from sqrt(x(v_2)) to 0   (ends at x = 0: the x0 criterion)

Each phase runs for a whole batch of K values at once (one stacked system for scipy's DOP853,
every K mapped onto the same span s in [0, 1]); this is what makes sweeps fast. The force
zero (F0 criterion) and the maximum force are found as roots of the dense output with
Chandrupatla's bracketing method (`scipy.optimize.elementwise.find_root`).

Energies are fractions of the impact kinetic energy (1/2) M* V^2: kinetic v^2, elastic x^{5/2}
and dissipated D = 2 K int x^{1/2} x'^2 dtau. D is integrated on its own, so that
v^2 + x^{5/2} + D = 1 is a genuine check of the integration, not an identity.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize.elementwise import find_root

#: Tolerances handed to DOP853. The stacked systems use an RMS error norm over all K of a
#: batch, so one component may carry sqrt(batch) times more error than rtol: 1e-13 keeps the
#: results within about 1e-12, two orders inside the 1e-10 the study needs.
RTOL = 1e-13
ATOL = 1e-15
BATCH = 128
K_RANGE = (0.0, 10.0)

ELASTIC = 1.25  # the 5/4 of (5/4) x^{3/2}
V2_FRACTION = 0.25  # where phase B2 hands over to phase C (see _solve_batch)


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
    force_max, tau_force_max : maximum of the force x^{1/2}(5/4 x + K x') and its time.
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
    dissipated_at_max: np.ndarray
    dissipated_F0: np.ndarray
    dissipated_x0: np.ndarray
    energy_residual: np.ndarray

    def row(self, i: int) -> dict:
        """The i-th entry as a dict of floats."""
        return {f.name: float(getattr(self, f.name)[i]) for f in fields(self)}

    def rows(self) -> list[dict]:
        return [self.row(i) for i in range(len(self.K))]


# --- right-hand sides, one per phase; y is stacked as (3, n): one column per K --------------

def _rhs_sqrt_overlap(u, y, K):
    """d(v, tau, D)/du with u = sqrt(x); y = (v, tau, D)."""
    v = y[0]
    return np.stack([-2.0 * K * u * u - 2.5 * u**4 / v, 2.0 * u / v, 4.0 * K * u * u * v])


def _rhs_velocity(v, y, K):
    """d(x, tau, D)/dv while the contact force is positive; y = (x, tau, D)."""
    x = y[0]
    sx = np.sqrt(x)
    inv_a = -1.0 / (sx * (K * v + ELASTIC * x))
    return np.stack([v * inv_a, inv_a, 2.0 * K * sx * v * v * inv_a])


def _force(x, v, K):
    """Dimensionless contact force x^{1/2} (5/4 x + K x') (units of M* V^2/delta_e)."""
    return np.sqrt(x) * (ELASTIC * x + K * v)


def _force_rate(x, v, K):
    """dF/dtau along the motion (v' = -F); its zero from above is the force maximum."""
    sx = np.sqrt(x)
    F = sx * (ELASTIC * x + K * v)
    return v * (ELASTIC * x + K * v) / (2.0 * sx) + sx * (ELASTIC * v - K * F)


def _integrate(rhs, start, stop, y0, K):
    """Integrate one phase for a batch: the independent variable w runs from start to stop
    (arrays, one per K) through s in [0, 1], w = start + s (stop - start)."""
    n = len(K)
    span = stop - start

    def f(s, y):
        w = start + s * span
        return (rhs(w, y.reshape(3, n), K) * span).ravel()

    sol = solve_ivp(f, (0.0, 1.0), np.asarray(y0, float).ravel(), method="DOP853",
                    rtol=RTOL, atol=ATOL, dense_output=True)
    if sol.status != 0:
        raise FloatingPointError(f"reference ODE integration failed: {sol.message}")
    return sol


def _first_root(sol, g, n):
    """First zero from above of g(s, y, k) along a phase's dense output, for every K.

    g is elementwise: s, the state y (3, ...) and the batch index k broadcast together.
    Returns (s_root, found); found is False where g does not drop from > 0 to <= 0.
    """
    grid = sol.t
    k = np.arange(n)
    with np.errstate(divide="ignore", invalid="ignore"):  # g may be singular at x = 0 (s = 0)
        gv = g(grid[None, :], sol.sol(grid).reshape(3, n, len(grid)), k[:, None])
    crossed = (gv[:, :-1] > 0) & (gv[:, 1:] <= 0)
    found = crossed.any(axis=1)
    if not found.any():
        return np.full(n, np.nan), found
    idx = crossed.argmax(axis=1)

    def g_at(s, k):
        # find_root passes only the elements still iterating, with their own k.
        return g(s, _state_at(sol, s, k), k)

    res = find_root(g_at, (grid[idx], grid[idx + 1]), args=(k,),
                    tolerances={"xatol": 1e-16, "xrtol": 4e-16})
    return np.where(found, res.x, np.nan), found


def _state_at(sol, s, k):
    """State (3, m) of a phase at positions s (m,) for batch members k (m,)."""
    s = np.where(np.isfinite(s), s, 0.0)
    full = sol.sol(s)  # (3 n, m)
    m = len(s)
    return full.reshape(3, -1, m)[:, k, np.arange(m)]


def _x_max_lower_bound(K):
    """Largest x with x^{5/2} + (4/3) K x^{3/2} <= 1: a lower bound of x_max for K >= 0.

    (Up to the maximum compression D <= 2K int x^{1/2} v dtau <= (4/3) K x^{3/2}, since v <= 1.)
    Newton on y = sqrt(x) from y = 1: the function is convex, so the iterates decrease monotonically.
    """
    c = (4.0 / 3.0) * np.maximum(K, 0.0)
    y = np.ones_like(K)
    for _ in range(60):
        step = (y**5 + c * y**3 - 1.0) / (5 * y**4 + 3 * c * y**2)
        y = y - step
        if np.all(np.abs(step) < 1e-15):
            break
    return y * y


def _solve_batch(K: np.ndarray) -> CollisionTable:
    n = len(K)
    zeros, ones = np.zeros(n), np.ones(n)

    # A: approach, u from 0 to u_s.
    u_s = np.sqrt(0.5 * _x_max_lower_bound(K))
    sol_a = _integrate(_rhs_sqrt_overlap, zeros, u_s, np.stack([ones, zeros, zeros]), K)
    v1, tau1, D1 = sol_a.y[:, -1].reshape(3, n)

    # B1: v from v1 down to 0, ending at the maximum compression.
    sol_b1 = _integrate(_rhs_velocity, v1, zeros, np.stack([u_s**2, tau1, D1]), K)
    x_max, tau_max, D_max = sol_b1.y[:, -1].reshape(3, n)

    # B2: v from 0 down to v2. The force must stay positive in B2: 5/4 x + K v > 0. The
    # force vanishes at v = -eps_F0 >= 0.45 min(v1, 5/4 x_max / K) for all K in [0, 10]
    # (measured on a grid of 1000 K; the minimum, 0.457, is near K = 0.93): a quarter of that
    # bound keeps a margin of almost 2 and keeps phase C away from the maximum compression.
    with np.errstate(divide="ignore"):
        v2 = -V2_FRACTION * np.minimum(v1, np.where(K > 0, ELASTIC * x_max / K, np.inf))
    sol_b2 = _integrate(_rhs_velocity, zeros, v2, np.stack([x_max, tau_max, D_max]), K)
    x2, tau2, D2 = sol_b2.y[:, -1].reshape(3, n)
    if np.any(ELASTIC * x2 + K * v2 <= 0) or np.any(x2 <= 0):
        bad = K[(ELASTIC * x2 + K * v2 <= 0) | (x2 <= 0)]
        raise FloatingPointError(f"reference ODE: the force vanished before v2 for K = {bad}")

    # C: separation, u from sqrt(x2) down to 0, ending at x = 0 (criterion x0).
    u2 = np.sqrt(x2)
    sol_c = _integrate(_rhs_sqrt_overlap, u2, zeros, np.stack([v2, tau2, D2]), K)
    v_end, tau_0, D_0 = sol_c.y[:, -1].reshape(3, n)

    # F0: the force 5/4 x + K v (times x^{1/2} > 0) first drops to zero in phase C.
    def force_sign_c(s, y, k):
        u = u2[k] * (1.0 - s)
        return ELASTIC * u * u + K[k] * y[0]

    s_f, found = _first_root(sol_c, force_sign_c, n)
    k = np.arange(n)
    v_f, tau_f, D_f = _state_at(sol_c, s_f, k)
    # Where the force never changes sign (K = 0, force ~ x^{3/2}) it vanishes at x = 0;
    # for K < 0 the force is negative from the first contact and F0 means nothing.
    no_sign_change = np.where(K < 0, np.nan, 1.0)
    tau_f = np.where(found, tau_f, tau_0 * no_sign_change)
    v_f = np.where(found, v_f, v_end * no_sign_change)
    D_f = np.where(found, D_f, D_0 * no_sign_change)

    # Maximum force: dF/dtau drops through zero during A or B1 (at the end of B1 when K = 0).
    def rate_a(s, y, k):
        u = u_s[k] * s
        return _force_rate(u * u, y[0], K[k])

    def rate_b1(s, y, k):
        return _force_rate(y[0], v1[k] * (1.0 - s), K[k])

    s_fa, in_a = _first_root(sol_a, rate_a, n)
    s_fb, in_b = _first_root(sol_b1, rate_b1, n)
    ya = _state_at(sol_a, s_fa, k)
    yb = _state_at(sol_b1, s_fb, k)
    x_fa, v_fa = (u_s * s_fa) ** 2, ya[0]
    x_fb, v_fb = yb[0], v1 * (1.0 - s_fb)
    x_fm = np.where(in_a, x_fa, np.where(in_b, x_fb, x_max))
    v_fm = np.where(in_a, v_fa, np.where(in_b, v_fb, 0.0))
    tau_fm = np.where(in_a, ya[1], np.where(in_b, yb[1], tau_max))

    residual = np.max(np.abs(np.stack([
        v1**2 + u_s**5 + D1, x_max**2.5 + D_max, v2**2 + x2**2.5 + D2, v_end**2 + D_0,
    ]) - 1.0), axis=0)

    return CollisionTable(
        K=K.copy(), x_max=x_max, tau_max=tau_max, tau_f=tau_f, eps_F0=-v_f,
        tau_0=tau_0, eps_x0=-v_end, force_max=_force(x_fm, v_fm, K), tau_force_max=tau_fm,
        dissipated_at_max=D_max, dissipated_F0=D_f, dissipated_x0=D_0, energy_residual=residual,
    )


def solve_collisions(K, *, batch: int = BATCH, allow_negative: bool = False) -> CollisionTable:
    """Solve the dimensionless collision for every value in `K`.

    Parameters
    ----------
    K : float or array_like
        Dissipation parameter(s), K = 2 eta sqrt(R*) delta_e^{3/2} / (M* V), in [0, 10].
    batch : int
        Number of K values integrated as one stacked system.
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
    >>> [round(e, 12) for e in t.eps_x0]
    [0.904885783492, 0.380838630487]
    """
    K = np.atleast_1d(np.asarray(K, dtype=float))
    if K.ndim != 1 or not np.all(np.isfinite(K)):
        raise ValueError(f"K must be a finite number or a 1-D list of them, got {K!r}")
    low = -0.5 if allow_negative else K_RANGE[0]
    if np.any(K < low) or np.any(K > K_RANGE[1]):
        raise ValueError(f"K must lie in [{low}, {K_RANGE[1]}], got {K[(K < low) | (K > K_RANGE[1])]}")
    parts = [_solve_batch(K[i:i + batch]) for i in range(0, len(K), batch)]
    return CollisionTable(**{
        f.name: np.concatenate([getattr(p, f.name) for p in parts]) for f in fields(CollisionTable)
    })


def solve_collision(K: float) -> dict:
    """Characteristics of one collision as a dict of floats (see `CollisionTable`)."""
    return solve_collisions([K]).row(0)
