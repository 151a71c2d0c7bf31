r"""Compiled (numba) Taylor-series integrator of the four collision phases; see `collision_ode`.

Both phase systems are built from polynomials, square roots and quotients, so their Taylor
coefficients follow from the usual recurrences of automatic differentiation (Cauchy products,
series reciprocal, series square root), one order at a time, in O(ORDER^2) operations a step.

Phase "u" (u = sqrt(x) independent, state y = (v, tau, D))::

    v' = -2 K u^2 - (5/2) u^4 / v,   tau' = 2 u / v,   D' = 4 K u^2 v

Phase "v" (v = x' independent, state y = (x, tau, D); a = -x^{1/2} (K v + 5/4 x))::

    x' = v / a,   tau' = 1 / a,   D' = 2 K x^{1/2} v^2 / a

Step size: the last two coefficients c_j (j = ORDER-1, ORDER) of each component give a radius
estimate rho = min_j (S / |c_j|)^{1/j}, S the component's scale (|v| or x, max(|tau|, 1),
max(|D|, |K|)); the step is rho TOL^{1/ORDER}, so that the first neglected term is ~TOL S. A
component whose last two coefficients vanish uses its last nonzero one among the last six: at
K = 0 and u = 0 most coefficients vanish (v = 1 - u^5/2 + ..., powers of u^5 only). The step
ending a phase is shortened to land on it. The step is bounded by the distance to the nearest
singularity (v = 0 for phase u: the maximum compression; x = 0 and the force zero for phase v),
so the steps near a phase end that lies close to one grow geometrically, ~1.2 times a step.

The dense output is the step's Taylor polynomial itself, as accurate as the step ends: the
force zero and the force maximum are found on it with Brent's method, and the trajectory
samples are evaluated on it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

ORDER = 22  # degree of the Taylor polynomials
TOL = 1e-16  # first neglected term relative to the component's scale
LOG_TOL = math.log(TOL)
MAX_STEPS = 100_000
ELASTIC = 1.25
XS_FRACTION = 0.7  # phase A ends at x_s = XS_FRACTION times a lower bound of x_max
V2_FRACTION = 0.4  # phase B2 ends at v_2 = -V2_FRACTION min(v_1, 5/4 x_max / K)
N_OUT = 14  # columns of the batch result, in CollisionTable's field order

KIND_U, KIND_V = 0, 1
ROOT_NONE, ROOT_FORCE, ROOT_RATE = 0, 1, 2

# status codes of _solve_one
OK, STEP_FAILURE, FORCE_VANISHED = 0, 1, 2

_jit = njit(cache=True, error_model="numpy", fastmath=False)
_jit_fast = njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"})


@_jit_fast
def _coefficients_u(u0, y, K, c, w):
    """Taylor coefficients in h = u - u0 of (v, tau, D) into c (3, ORDER+1); w: scratch 1/v.
    One Cauchy product an order (the reciprocal of v); u^2 and u^4 are short polynomials."""
    N = c.shape[1] - 1
    cv, ct, cd = c[0], c[1], c[2]
    cv[0], ct[0], cd[0] = y[0], y[1], y[2]
    e0, e1 = u0 * u0, 2.0 * u0  # u^2 = e0 + e1 h + h^2
    f0, f1, f2, f3 = e0 * e0, 2.0 * e0 * e1, e1 * e1 + 2.0 * e0, 2.0 * e1  # u^4 (+ h^4)
    inv_v0 = 1.0 / y[0]
    w[0] = inv_v0
    for n in range(N):
        if n > 0:
            acc = 0.0
            for j in range(1, n + 1):
                acc += cv[j] * w[n - j]
            w[n] = -acc * inv_v0
        u4w = f0 * w[n]
        u2v = e0 * cv[n]
        uw = u0 * w[n]
        if n >= 1:
            u4w += f1 * w[n - 1]
            u2v += e1 * cv[n - 1]
            uw += w[n - 1]
        if n >= 2:
            u4w += f2 * w[n - 2]
            u2v += cv[n - 2]
        if n >= 3:
            u4w += f3 * w[n - 3]
        if n >= 4:
            u4w += w[n - 4]
        u2 = e0 if n == 0 else (e1 if n == 1 else (1.0 if n == 2 else 0.0))
        inv = 1.0 / (n + 1)
        cv[n + 1] = (-2.0 * K * u2 - 2.5 * u4w) * inv
        ct[n + 1] = 2.0 * uw * inv
        cd[n + 1] = 4.0 * K * u2v * inv


@_jit_fast
def _coefficients_v(v0, y, K, c, s, p, ip, b):
    """Taylor coefficients in h = v - v0 of (x, tau, D) into c; s, p, ip, b: scratch series of
    sqrt(x), p = K v + 5/4 x, 1/p and 1/a = -1/(sqrt(x) p). Three Cauchy products an order:
    x' = v b, tau' = b and D' = 2 K x^{1/2} v^2 b = -2 K v^2 / p."""
    N = c.shape[1] - 1
    c[0, 0], c[1, 0], c[2, 0] = y[0], y[1], y[2]
    s[0] = math.sqrt(y[0])
    for n in range(N):
        if n > 0:
            acc = c[0, n]
            for j in range(1, n):
                acc -= s[j] * s[n - j]
            s[n] = acc / (2.0 * s[0])
        p[n] = ELASTIC * c[0, n] + (K * v0 if n == 0 else (K if n == 1 else 0.0))
        acc = 1.0 if n == 0 else 0.0
        for j in range(1, n + 1):
            acc -= p[j] * ip[n - j]
        ip[n] = acc / p[0]
        acc = -ip[n]
        for j in range(1, n + 1):
            acc -= s[j] * b[n - j]
        b[n] = acc / s[0]
        v2ip = v0 * v0 * ip[n]
        if n >= 1:
            v2ip += 2.0 * v0 * ip[n - 1]
        if n >= 2:
            v2ip += ip[n - 2]
        inv = 1.0 / (n + 1)
        c[0, n + 1] = (v0 * b[n] + (b[n - 1] if n >= 1 else 0.0)) * inv
        c[1, n + 1] = b[n] * inv
        c[2, n + 1] = -2.0 * K * v2ip * inv


@_jit
def _step_size(c, scale):
    """rho TOL^{1/ORDER}, rho the smallest radius estimate (S / |c_j|)^{1/j} over the components
    and the last two orders; a component whose last two coefficients vanish uses its last
    nonzero one among the last six."""
    N = c.shape[1] - 1
    log_rho = np.inf
    for i in range(3):
        if scale[i] <= 0.0:
            continue
        log_s = math.log(scale[i])
        used = 0
        for j in range(N, N - 6, -1):
            cj = abs(c[i, j])
            if cj > 0.0:
                r = (log_s - math.log(cj)) / j
                if r < log_rho:
                    log_rho = r
                used += 1
                if used == 2 or j < N - 1:
                    break
    return math.exp(log_rho + LOG_TOL / N)


@_jit
def _horner(c, i, h):
    N = c.shape[1] - 1
    acc = c[i, N]
    for n in range(N - 1, -1, -1):
        acc = acc * h + c[i, n]
    return acc


@_jit
def _g(root, x, v, K):
    """The function whose first zero from above is wanted: the force factor 5/4 x + K v
    (ROOT_FORCE) or the force rate dF/dtau (ROOT_RATE)."""
    f = ELASTIC * x + K * v
    if root == ROOT_FORCE:
        return f
    sx = math.sqrt(x)
    return v * f / (2.0 * sx) + sx * (ELASTIC * v - K * sx * f)


@_jit
def _g_at(kind, root, c, w0, h, K):
    if kind == KIND_U:
        u = w0 + h
        return _g(root, u * u, _horner(c, 0, h), K)
    return _g(root, _horner(c, 0, h), w0 + h, K)


@_jit
def _brent(kind, root, c, w0, h, K, ga, gb):
    """Zero of g(theta h) for theta in [0, 1] given g(0) = ga > 0 >= g(h) = gb (Brent's zeroin)."""
    a, b, fa, fb = 0.0, 1.0, ga, gb
    cc, fc = a, fa
    d = e = b - a
    for _ in range(200):
        if (fb > 0.0 and fc > 0.0) or (fb < 0.0 and fc < 0.0):
            cc, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, cc = b, cc, b
            fa, fb, fc = fb, fc, fb
        tol = 4e-16 * abs(b) + 1e-18
        m = 0.5 * (cc - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == cc:
                pp = 2.0 * m * s
                q = 1.0 - s
            else:
                q = fa / fc
                r = fb / fc
                pp = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if pp > 0.0:
                q = -q
            else:
                pp = -pp
            if 2.0 * pp < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e = d
                d = pp / q
            else:
                d = m
                e = m
        else:
            d = m
            e = m
        a, fa = b, fb
        if abs(d) > tol:
            b += d
        else:
            b += tol if m > 0 else -tol
        fb = _g_at(kind, root, c, w0, b * h, K)
    return b


@_jit
def _phase(kind, start, stop, y, K, root, samples, out, c, work):
    """Integrate one phase from w = start to w = stop with initial state y (3,), in place.

    Returns (status, found, xr, vr, taur, Dr): the first zero from above of the ROOT_* function
    along the phase (found = 1.0 if there is one, bracketed on the step ends then refined on
    the step polynomial), with the state there. At `samples` (increasing fractions s in
    [0, 1] of the phase, w = start + s (stop - start)) the step polynomials are evaluated into
    out (m, 4): x, v, tau, D.
    """
    scale = np.empty(3)
    direction = 1.0 if stop >= start else -1.0
    w = start
    m = len(samples)
    k = 0
    found = 0.0
    xr = vr = taur = Dr = np.nan
    g_prev = np.nan
    if root != ROOT_NONE:
        if kind == KIND_U:
            g_prev = _g(root, w * w, y[0], K)
        else:
            g_prev = _g(root, y[0], w, K)
    for _ in range(MAX_STEPS):
        if w == stop:
            while k < m:  # a phase of zero length
                wk = start + samples[k] * (stop - start)
                if kind == KIND_U:
                    out[k, 0], out[k, 1] = wk * wk, y[0]
                else:
                    out[k, 0], out[k, 1] = y[0], wk
                out[k, 2], out[k, 3] = y[1], y[2]
                k += 1
            return 0, found, xr, vr, taur, Dr
        if kind == KIND_U:
            _coefficients_u(w, y, K, c, work[0])
            scale[0] = abs(y[0])
        else:
            _coefficients_v(w, y, K, c, work[0], work[1], work[2], work[3])
            scale[0] = y[0]
        scale[1] = max(abs(y[1]), 1.0)
        scale[2] = max(abs(y[2]), abs(K))
        h = _step_size(c, scale)
        if not h > 0.0:  # nan or zero: the polynomial is degenerate
            return 1, found, xr, vr, taur, Dr
        last = h >= abs(stop - w)
        h = stop - w if last else direction * h
        w_new = stop if last else w + h
        # samples in this step
        while k < m:
            wk = start + samples[k] * (stop - start)
            if not (last or direction * (wk - w_new) <= 0.0):
                break
            hk = wk - w
            if kind == KIND_U:
                out[k, 0], out[k, 1] = wk * wk, _horner(c, 0, hk)
            else:
                out[k, 0], out[k, 1] = _horner(c, 0, hk), wk
            out[k, 2], out[k, 3] = _horner(c, 1, hk), _horner(c, 2, hk)
            k += 1
        for i in range(3):
            y[i] = _horner(c, i, h)
        if root != ROOT_NONE and found == 0.0:
            if kind == KIND_U:
                g_new = _g(root, w_new * w_new, y[0], K)
            else:
                g_new = _g(root, y[0], w_new, K)
            if g_prev > 0.0 and g_new <= 0.0:
                found = 1.0
                if g_new == 0.0:  # the zero is the step end: take its state as it is
                    theta = 1.0
                else:
                    theta = _brent(kind, root, c, w, h, K, g_prev, g_new)
                if theta == 1.0:
                    wr = w_new
                    yr0, taur, Dr = y[0], y[1], y[2]
                else:
                    wr = w + theta * h
                    yr0, taur, Dr = (_horner(c, 0, theta * h), _horner(c, 1, theta * h),
                                     _horner(c, 2, theta * h))
                if kind == KIND_U:
                    xr, vr = wr * wr, yr0
                else:
                    xr, vr = yr0, wr
            g_prev = g_new
        w = w_new
    return 1, found, xr, vr, taur, Dr


@_jit
def _x_max_lower_bound(K):
    """Largest x with x^{5/2} + (4/3) K x^{3/2} <= 1 (see collision_ode)."""
    cK = (4.0 / 3.0) * max(K, 0.0)
    y = 1.0
    for _ in range(60):
        step = (y**5 + cK * y**3 - 1.0) / (5.0 * y**4 + 3.0 * cK * y * y)
        y = y - step
        if abs(step) < 1e-15:
            break
    return y * y


@_jit
def _work(N):
    return np.empty((3, N + 1)), np.empty((4, N + 1))


@_jit
def _phases(K, samples, out, c, work):
    """The four phases A, B1, B2, C of `collision_ode` for one K. Returns (status, row (N_OUT,)).
    With fractions samples (4, m) of each phase, fills out (4, m, 4) with (x, v, tau, D) there.

    One call site of _phase inside a loop over the phases: four call sites would each be
    inlined and optimised by LLVM, which multiplies the (cached, but once per clone) compile time.
    """
    row = np.full(N_OUT, np.nan)
    y = np.empty(3)
    u_s = math.sqrt(XS_FRACTION * _x_max_lower_bound(K))
    v1 = tau1 = D1 = x_max = tau_max = D_max = v2 = np.nan
    in_a = in_b = found = 0.0
    xa = va = ta = xb = vb = tb = v_f = tau_f = D_f = np.nan
    res = 0.0
    v2_fraction = V2_FRACTION
    ph = 0
    while ph < 4:
        if ph == 0:  # A: u from 0 to u_s
            kind, start, stop, root = KIND_U, 0.0, u_s, ROOT_RATE
            y[0], y[1], y[2] = 1.0, 0.0, 0.0
        elif ph == 1:  # B1: v from v1 to 0, ending at the maximum compression
            kind, start, stop = KIND_V, v1, 0.0
            root = ROOT_NONE if in_a == 1.0 else ROOT_RATE
            y[0], y[1], y[2] = u_s * u_s, tau1, D1
        elif ph == 2:  # B2: v from 0 to v2, before the force vanishes
            lim = ELASTIC * x_max / K if K > 0 else np.inf
            v2 = -v2_fraction * min(v1, lim)
            kind, start, stop, root = KIND_V, 0.0, v2, ROOT_NONE
            y[0], y[1], y[2] = x_max, tau_max, D_max
        else:  # C: u from sqrt(x(v2)) to 0 (criterion x0), with the force zero (criterion F0)
            kind, start, stop, root = KIND_U, math.sqrt(y[0]), 0.0, ROOT_FORCE
            y[0] = v2  # tau, D carry over
        st, hit, xr, vr, tr, Dr = _phase(kind, start, stop, y, K, root, samples[ph], out[ph],
                                         c, work)
        if ph == 2 and (st or not (ELASTIC * y[0] + K * v2 > 0.0 and y[0] > 0.0)):
            # The force vanished before v2 (or the integration met its zero): B2 again with a
            # smaller v2. Never seen for K in [-0.5, 10]; a safeguard of the bound on eps_F0.
            v2_fraction *= 0.5
            if v2_fraction < 0.01:
                return FORCE_VANISHED, row
            continue
        if st:
            return STEP_FAILURE, row
        if ph == 0:
            v1, tau1, D1 = y[0], y[1], y[2]
            in_a, xa, va, ta = hit, xr, vr, tr
            res = abs((u_s * u_s) ** 2.5 + v1 * v1 + D1 - 1.0)
        elif ph == 1:
            x_max, tau_max, D_max = y[0], y[1], y[2]
            in_b, xb, vb, tb = hit, xr, vr, tr
            res = max(res, abs(x_max**2.5 + D_max - 1.0))
        elif ph == 2:
            res = max(res, abs(y[0] ** 2.5 + v2 * v2 + y[2] - 1.0))
        else:
            found, v_f, tau_f, D_f = hit, vr, tr, Dr
        ph += 1
    v_end, tau_0, D_0 = y[0], y[1], y[2]
    res = max(res, abs(v_end * v_end + D_0 - 1.0))
    if found == 0.0:  # K = 0: the force vanishes at x = 0; K < 0: F0 means nothing
        no_sign_change = np.nan if K < 0 else 1.0
        tau_f, v_f, D_f = tau_0 * no_sign_change, v_end * no_sign_change, D_0 * no_sign_change

    if in_a == 1.0:
        x_fm, v_fm, tau_fm = xa, va, ta
    elif in_b == 1.0:
        x_fm, v_fm, tau_fm = xb, vb, tb
    else:
        x_fm, v_fm, tau_fm = x_max, 0.0, tau_max

    row[0], row[1], row[2], row[3], row[4] = K, x_max, tau_max, tau_f, -v_f
    row[5], row[6] = tau_0, -v_end
    row[7] = math.sqrt(x_fm) * (ELASTIC * x_fm + K * v_fm)
    row[8], row[9] = tau_fm, x_fm
    row[10], row[11], row[12], row[13] = D_max, D_f, D_0, res
    return OK, row


@_jit
def solve_batch(K):
    """One row of N_OUT characteristics per K (CollisionTable's field order); status per K."""
    n = len(K)
    table = np.empty((n, N_OUT))
    status = np.zeros(n, dtype=np.int64)
    c, work = _work(ORDER)
    samples = np.empty((4, 0))
    out = np.empty((4, 0, 4))
    for i in range(n):
        st, row = _phases(K[i], samples, out, c, work)
        status[i] = st
        for j in range(N_OUT):  # not table[i] = row: its shape check alone compiles for seconds
            table[i, j] = row[j]
    return table, status


@_jit
def trajectory(K, samples):
    """(x, v, tau, D) at samples (4, m) of each phase's own variable: out (4, m, 4); status."""
    c, work = _work(ORDER)
    out = np.empty((4, samples.shape[1], 4))
    st, _ = _phases(K, samples, out, c, work)
    return out, st
