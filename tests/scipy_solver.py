r"""The first reference solver (scipy's DOP853), kept as the slow cross-check of `collision_ode`.

`reference.collision_ode` solves the same four phases with a compiled Taylor method; this module
is the solver it replaced, unchanged apart from this paragraph and its import, so that the tests
can compare the two (same API: `solve_collisions`, `solve_collision`, `collision_trajectory`).
Only the tests use it, so it lives with them.

High-accuracy solution of the dimensionless viscoelastic Hertz collision.

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

from reference.collision_ode import CollisionTable  # the same result type as the compiled solver

#: Tolerances handed to DOP853. The stacked systems use an RMS error norm over all K of a
#: batch, so one component may carry sqrt(batch) times more error than rtol: 1e-13 keeps the
#: results within about 1e-12, two orders inside the 1e-10 the study needs.
RTOL = 1e-13
ATOL = 1e-15
BATCH = 128
K_RANGE = (0.0, 10.0)

ELASTIC = 1.25  # the 5/4 of (5/4) x^{3/2}
V2_FRACTION = 0.25  # where phase B2 hands over to phase C (see _solve_batch)


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


@dataclass
class _Phase:
    """One integrated phase of a batch: the independent variable w (u = sqrt(x), or v) runs
    from `start` to `stop` (one value per K) as s runs over [0, 1]; `sol` is the stacked
    DOP853 solution in s with the state (3, n) flattened."""

    kind: str  # "u" (state v, tau, D) or "v" (state x, tau, D)
    start: np.ndarray
    stop: np.ndarray
    sol: object

    def physical(self, s, y, k):
        """(x, v, tau, D) from the position s, the phase state y (3, ...) and batch index k."""
        w = self.start[k] + s * (self.stop[k] - self.start[k])
        if self.kind == "u":
            return w * w, y[0], y[1], y[2]
        return y[0], w, y[1], y[2]

    def state(self, s, k):
        """(x, v, tau, D) at positions s (m,) for batch members k (m,)."""
        s = np.where(np.isfinite(s), s, 0.0)
        m = len(s)
        y = self.sol.sol(s).reshape(3, -1, m)[:, k, np.arange(m)]
        return self.physical(s, y, k)

    def end(self):
        """(x, v, tau, D) at s = 1 for the whole batch (the integrator's last step: exact)."""
        k = np.arange(len(self.start))
        return self.physical(1.0, self.sol.y[:, -1].reshape(3, -1), k)

    def first_root(self, g):
        """First zero from above of g(x, v, k) along the phase, for every K of the batch.

        Returns (s_root, found); found is False where g does not drop from > 0 to <= 0.
        The sign change is bracketed on the integrator's steps, then refined on the dense
        output with Chandrupatla's method.
        """
        n = len(self.start)
        k = np.arange(n)
        grid = self.sol.t
        y = self.sol.sol(grid).reshape(3, n, len(grid))
        with np.errstate(divide="ignore", invalid="ignore"):  # g may be singular at x = 0
            x, v, _, _ = self.physical(grid[None, :], y, k[:, None])
            gv = g(x, v, k[:, None])
        crossed = (gv[:, :-1] > 0) & (gv[:, 1:] <= 0)
        found = crossed.any(axis=1)
        if not found.any():
            return np.full(n, np.nan), found
        idx = crossed.argmax(axis=1)

        def g_at(s, k):  # find_root passes only the elements still iterating, with their k
            x, v, _, _ = self.state(s, k)
            return g(x, v, k)

        with np.errstate(divide="ignore", invalid="ignore"):
            res = find_root(g_at, (grid[idx], grid[idx + 1]), args=(k,),
                            tolerances={"xatol": 1e-16, "xrtol": 4e-16})
        return np.where(found, res.x, np.nan), found


def _integrate(kind, start, stop, y0, K) -> _Phase:
    """Integrate one phase for a batch, w = start + s (stop - start), s in [0, 1]."""
    n = len(K)
    span = stop - start
    rhs = _rhs_sqrt_overlap if kind == "u" else _rhs_velocity

    def f(s, y):
        return (rhs(start + s * span, y.reshape(3, n), K) * span).ravel()

    sol = solve_ivp(f, (0.0, 1.0), np.asarray(y0, float).ravel(), method="DOP853",
                    rtol=RTOL, atol=ATOL, dense_output=True)
    if sol.status != 0:
        raise FloatingPointError(f"reference ODE integration failed: {sol.message}")
    return _Phase(kind, start, stop, sol)


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


def _integrate_phases(K: np.ndarray) -> tuple[_Phase, _Phase, _Phase, _Phase]:
    """The four phases A, B1, B2, C of the module docstring for a batch of K."""
    n = len(K)
    zeros, ones = np.zeros(n), np.ones(n)

    # A: approach, u from 0 to u_s.
    u_s = np.sqrt(0.5 * _x_max_lower_bound(K))
    a = _integrate("u", zeros, u_s, np.stack([ones, zeros, zeros]), K)
    _, v1, tau1, D1 = a.end()

    # B1: v from v1 down to 0, ending at the maximum compression.
    b1 = _integrate("v", v1, zeros, np.stack([u_s**2, tau1, D1]), K)
    x_max, _, tau_max, D_max = b1.end()

    # B2: v from 0 down to v2. The force must stay positive in B2: 5/4 x + K v > 0. The
    # force vanishes at v = -eps_F0 >= 0.45 min(v1, 5/4 x_max / K) for all K in [0, 10]
    # (measured on a grid of 1000 K; the minimum, 0.457, is near K = 0.93): a quarter of that
    # bound keeps a margin of almost 2 and keeps phase C away from the maximum compression.
    with np.errstate(divide="ignore"):
        v2 = -V2_FRACTION * np.minimum(v1, np.where(K > 0, ELASTIC * x_max / K, np.inf))
    b2 = _integrate("v", zeros, v2, np.stack([x_max, tau_max, D_max]), K)
    x2, _, tau2, D2 = b2.end()
    bad = (ELASTIC * x2 + K * v2 <= 0) | (x2 <= 0)
    if np.any(bad):
        raise FloatingPointError(f"reference ODE: the force vanished before v2 for K = {K[bad]}")

    # C: separation, u from sqrt(x2) down to 0, ending at x = 0 (criterion x0).
    c = _integrate("u", np.sqrt(x2), zeros, np.stack([v2, tau2, D2]), K)
    return a, b1, b2, c


def _solve_batch(K: np.ndarray) -> CollisionTable:
    a, b1, b2, c = _integrate_phases(K)
    x_max, _, tau_max, D_max = b1.end()
    _, v_end, tau_0, D_0 = c.end()

    # F0: the force 5/4 x + K v (times x^{1/2} > 0) first drops to zero in phase C.
    s_f, found = c.first_root(lambda x, v, k: ELASTIC * x + K[k] * v)
    k = np.arange(len(K))
    _, v_f, tau_f, D_f = c.state(s_f, k)
    # Where the force never changes sign (K = 0, force ~ x^{3/2}) it vanishes at x = 0;
    # for K < 0 the force is negative from the first contact and F0 means nothing.
    no_sign_change = np.where(K < 0, np.nan, 1.0)
    tau_f = np.where(found, tau_f, tau_0 * no_sign_change)
    v_f = np.where(found, v_f, v_end * no_sign_change)
    D_f = np.where(found, D_f, D_0 * no_sign_change)

    # Maximum force: dF/dtau drops through zero during A or B1 (at the end of B1 when K = 0).
    rate = lambda x, v, k: _force_rate(x, v, K[k])  # noqa: E731
    s_fa, in_a = a.first_root(rate)
    s_fb, in_b = b1.first_root(rate)
    xa, va, ta, _ = a.state(s_fa, k)
    xb, vb, tb, _ = b1.state(s_fb, k)
    x_fm = np.where(in_a, xa, np.where(in_b, xb, x_max))
    v_fm = np.where(in_a, va, np.where(in_b, vb, 0.0))
    tau_fm = np.where(in_a, ta, np.where(in_b, tb, tau_max))

    residual = np.max(np.abs(np.stack([
        x**2.5 + v**2 + D for x, v, _, D in (p.end() for p in (a, b1, b2, c))
    ]) - 1.0), axis=0)

    return CollisionTable(
        K=K.copy(), x_max=x_max, tau_max=tau_max, tau_f=tau_f, eps_F0=-v_f,
        tau_0=tau_0, eps_x0=-v_end, force_max=_force(x_fm, v_fm, K), tau_force_max=tau_fm, x_force_max=x_fm,
        dissipated_at_max=D_max, dissipated_F0=D_f, dissipated_x0=D_0, energy_residual=residual,
    )


def collision_trajectory(K: float, points_per_phase: int = 200) -> dict[str, np.ndarray]:
    """The trajectory of one collision up to x = 0 and its energy partition.

    Sampled uniformly in each phase's own variable (denser where x changes fast), sorted in
    tau. Returns arrays tau, x, v (= x'), force (x^{1/2}(5/4 x + K x')), kinetic (v^2),
    elastic (x^{5/2}) and dissipated (D), energies as fractions of (1/2) M* V^2.
    """
    K_arr = np.array([float(K)])
    if not K_RANGE[0] <= K <= K_RANGE[1]:
        raise ValueError(f"K must lie in [{K_RANGE[0]}, {K_RANGE[1]}], got {K}")
    s = np.linspace(0.0, 1.0, points_per_phase)
    k = np.zeros(points_per_phase, dtype=int)
    parts = [p.state(s, k) for p in _integrate_phases(K_arr)]
    x, v, tau, D = (np.concatenate([p[i] for p in parts]) for i in range(4))
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
