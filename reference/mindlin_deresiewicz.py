r"""Mindlin–Deresiewicz partial slip in Thornton's incremental form: the oblique impact of elastic
spheres as the theory gives it, beside what the codes compute (`reference.oblique_collision`).

The codes' Mindlin models keep the tangential stiffness at its no-slip value k_t = 8 G* a until the
whole contact slides (Coulomb's cap). Mindlin & Deresiewicz (1953, J. Appl. Mech. 20:327) let an
annulus of the contact circle slip first: at a constant normal force N [N] a tangential load P [N]
(the load transmitted from body 2 to body 1 against the slip displacement xi [m]) leaves a stuck
core of radius c = a theta and a slipping annulus c < r < a with traction mu p(r), where

    theta^3 = 1 - P/(mu N),   dP/dxi = 8 G* a theta                                   (1)

(Cattaneo–Mindlin). Integrated from P = 0 at xi = 0 this is the monotonic law

    P(xi) = mu N [1 - (1 - 16 G* a xi / (3 mu N))^{3/2}],   0 <= xi <= 3 mu N/(16 G* a),   (2)

`monotonic_tangential_load` (tests/test_mindlin_deresiewicz.py checks the integration of (1)
against (2)). Thornton (1991, J. Appl. Mech. 58:383) and Thornton & Yin (1991, Powder Technol.
65:153) write the law for a varying N as increments. An increment (dN, dP) is split into
(dN, mu dN dir), which adds a ring of traction mu dp (dp the Hertz pressure increment, of the
flat-punch form) and so displaces the contact rigidly by mu dN/(8 G* a) without new slip, and a
constant-N increment dP - mu dN dir of stiffness (1). Their sum is Thornton's law, continuous in
time here (' = d/dt; derived from these statements, not copied from any code):

    P' = 8 G* a theta v_s + dir mu N' (1 - theta),    v_s = dxi/dt the slip velocity [m/s],   (3)

on a branch of slip direction dir = +-1 that started at the reversal point P_r [N]:

    virgin loading (no reversal yet):  theta^3 = 1 - dir P / (mu N)
    after a reversal (unloading, reloading):  theta^3 = 1 - dir (P - P_r) / (2 mu N)     (Masing)

Thornton's T* (the point where loading turned into unloading) and T** (unloading into reloading)
are the first two reversal points. The memory is Masing's: a branch that comes back to the reversal
point before its own (reloading reaching T*) continues the older branch, and an unloading that
reaches -T* continues as virgin loading in its direction (at both points theta is continuous; a
third reversal pushes a third point, where Thornton's stepwise scheme would overwrite T*).
Thornton's rules, kept:

- where the normal load grows faster than the tangential one, |P'| < mu N' (the new rings stick:
  Mindlin–Deresiewicz's no-slip case), theta = 1: P' = 8 G* a v_s. At the switch both forms give
  P' = dir mu N', so P' is continuous; this is also the start of a contact with Psi_1 < 1 (below);
- |P| <= mu N: where |P| reaches mu N the whole contact slides (gross sliding), P = mu N sign(P),
  and the memory is wiped; on either side (a load held behind a turning point meets the falling
  cap too: it slides back, against the branch's slip, only while the cap falls faster than the
  no-slip spring unloads, 8 G* a |v_s| <= mu |N'|, as the codes' cap scales their spring; else
  it turns at the cap, unloading from T* = sign(P) mu N). Sliding (dir = sign(P)) ends where
  the stuck law would carry |P| back inside the cap, 8 G* a dir v_s < mu N' (the codes'
  criterion with their k_t = 8 G* a): after a reversal of the slip (dir v_s < 0) as unloading
  from T* = dir mu N, else (the cap growing faster than the spring, N' > 0) as loading under the
  theta = 1 rule;
- theta is kept in [0, 1].

Left out, with the measured reason: Thornton moves the reversal points with the cap while N
changes (T* += mu dN, T** -= mu dN). Those moves are of size mu dN whatever the branch's own
annulus, so they do not vanish as mu -> inf: with them the law at mu = 100 and 0.5 deg (Psi_1 = 1e-4)
gave e_t = -96 (alumina on a plane, here), nowhere near its no-slip limit. Without them the law has
a limit as Psi_1 -> 0, below.

The small-angle limit. As mu -> inf theta -> 1 but mu (1 - theta) -> dir (P - P_r)/(3 c N) (c = 1
virgin, 2 after a reversal), so while N grows P' = 8 G* a v_s (the codes' no-slip incremental law)
and while it falls

    P' = 8 G* a v_s + N' (P - P_r) / (3 c N),                                            (4)

the tangential traction released by the receding edge of the contact (on the virgin branch
N'/(3N) = a'/a: LAMMPS's ``mindlin_rescale/force`` unloading, PR #2196). So the theory does NOT
tend to the codes' no-slip law as the incidence goes to zero: for alumina on a plane its e_t tends
to 0.8464 where the codes' no-slip law gives 1.0135 (tests/test_mindlin_deresiewicz.py integrates
(4) apart). With mu = inf the law here is the codes' no-slip law itself (theta = 1 throughout, no
release), not that limit.

The sphere's motion: body 1 (radius R1, mass m1, moment of inertia I1) meets body 2 (a plane, or a
sphere R2, m2, I2 at rest) with normal velocity v_n > 0, tangential velocity v_t and spin w1; the
conventions are docs/physics.md's (n = +x from body 1 to body 2, tangent +y, spins about +z). The
force on body 1 is F_t = -P along +y, its torque R1 F_t, body 2's -F_t and R2 F_t (arms R: the
theory's rigid bodies); the slip of the contact point v_s = (v_y1 + R1 w1) - (v_y2 - R2 w2) obeys

    v_s' = -P / m_t,    1/m_t = 1/m1 + R1^2/I1 + 1/m2 + R2^2/I2    (a plane: 1/m2 = R2^2/I2 = 0).

The normal force is Hertz's, elastic (K = 0: no normal dissipation, eps = 1), N = k_n delta^{3/2},
k_n = (4/3) E* sqrt(R*), with the normal of the theory fixed (two spheres: the line of centres does
not turn; the codes' reference follows it, ~delta/R). Energy conservation gives
delta' = +-v_n (1 - (delta/delta_m)^{5/2})^{1/2}, delta_m = (5 M* v_n^2 / (4 k_n))^{2/5}; with the
independent variable psi in [0, pi],

    delta = delta_m sin^2 psi,   dt/dpsi = (2 delta_m / v_n) s ((1 + s)/(1 + s + s^2 + s^3 + s^4))^{1/2},

s = sin psi, so that delta' = v_n cos psi ((1 + s + ... + s^4)/(1 + s))^{1/2}, a = sqrt(R* delta_m) s
and N = k_n delta_m^{3/2} s^3 are analytic in psi through both ends and the maximum compression:
the contact is psi from 0 to pi, and no square root of delta is left for the integrator.

Maw, Barber & Fawcett's scaling (1976, Wear 38:101; Chung & Ooi 2011 plot the codes on it): with
kappa = 4 G*/E* (the ratio k_t/k_n of the no-slip stiffnesses, 8 G* a / (2 E* a); kappa =
2(1 - nu)/(2 - nu) for a sphere on a rigid plane or two equal spheres),

    Psi_1 = kappa v_s / (mu v_n),   Psi_2 = kappa v_s' / (mu v_n')   (v_n' = eps v_n),

and the contact slides from the start iff Psi_1 >= 1 (P/(mu N) -> Psi_1 along the stuck start);
while it slides throughout, Psi_2 = (Psi_1 - kappa (1 + eps) M*/m_t)/eps, the rigid-body line
(`reference.rigid_body_sliding`; a solid sphere on a plane: M*/m_t = 7/2).

How it is integrated: DOP853 at rtol 1e-12 in psi on scaled variables (t, v_s, P and the reversal
points), each mode (a branch, or gross sliding) a piece; the mode changes (reversal of the slip,
the cap reached, a Masing return, the end of sliding) are terminal events located on the dense
output, and the integration restarts there. The first 1e-7 of psi is the closed form of the stuck
(Psi_1 < 1) or sliding start (P = Psi_1 mu N or mu N; the slip changes by ~psi^5 there), and in the
last 1e-6 of psi (N < 1e-18 of its maximum) no mode change is followed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14
#: Where the integration starts [rad of psi]: the closed form of the start before it.
PSI_START = 1e-7
#: Within this of psi = pi no mode change is followed (N < PSI_END^6 of its maximum).
PSI_END = 1e-6
#: A mode change this close to the piece's start [rad of psi] is round-off: kept off for GRACE.
GRACE = 1e-9
#: More pieces than this means the modes chatter (or a bug): refused.
MAX_PIECES = 400


@dataclass(frozen=True)
class MDResult:
    r"""One oblique impact under Mindlin–Deresiewicz partial slip (`solve_mindlin_deresiewicz`), SI.

    Attributes
    ----------
    T : float
        Contact time [s] (elastic Hertz: the overlap's return to zero).
    eps : float
        Normal restitution [-] (1: elastic).
    vt_after, omega_after : float
        Body 1's centre velocity along +y [m/s] and spin about +z [rad/s] after the contact.
    vt2_after, omega2_after : float
        Body 2's (0 for a plane).
    e_t : float
        Tangential restitution of the contact point v_s'/v_s [-] (nan without initial slip).
    rebound_angle : float
        atan2(v_s', eps v_n) [deg].
    psi1, psi2 : float
        Maw, Barber & Fawcett's normalised incidence kappa v_s/(mu v_n) and rebound
        kappa v_s'/(mu eps v_n) [-], kappa = 4 G*/E* (module docstring).
    Ft_max : float
        Largest |P| over the contact [N].
    phases : tuple of (str, float)
        (mode, start time [s]): "slide" (gross sliding), "load", "unload" or "reload" (Thornton's
        k = 0, 1, 2: virgin loading, a branch after an odd or an even number of reversals).
    """

    T: float
    eps: float
    vt_after: float
    omega_after: float
    vt2_after: float
    omega2_after: float
    e_t: float
    rebound_angle: float
    psi1: float
    psi2: float
    Ft_max: float
    phases: tuple


def stiffness_ratio(E_star: float, G_star: float) -> float:
    """kappa = 4 G*/E* [-]: the no-slip tangential over the normal stiffness, 8 G* a / (2 E* a).

    Parameters
    ----------
    E_star, G_star : float
        Effective Young's and shear moduli [Pa] (docs/physics.md).
    """
    return 4.0 * G_star / E_star


def normalised_incidence(v_s: float, v_n: float, mu: float, E_star: float, G_star: float) -> float:
    r"""Maw, Barber & Fawcett's Psi = kappa v_s / (mu v_n) [-], kappa = 4 G*/E* (2(1 - nu)/(2 - nu) for
    one material on a rigid plane). Psi_1 with the approach's slip and normal velocities, Psi_2 with
    the rebound's (v_n' = eps v_n).

    Parameters
    ----------
    v_s : float
        The contact point's slip velocity [m/s].
    v_n : float
        The normal velocity [m/s], > 0.
    mu : float
        Friction coefficient [-].
    E_star, G_star : float
        Effective moduli [Pa].
    """
    return stiffness_ratio(E_star, G_star) * v_s / (mu * v_n)


def monotonic_tangential_load(xi, N: float, a: float, G_star: float, mu: float):
    r"""Mindlin's tangential load for a monotonic displacement at a constant normal force (eq. 2):

        P = mu N [1 - (1 - 16 G* a xi / (3 mu N))^{3/2}],   and mu N beyond xi_s = 3 mu N / (16 G* a).

    Derivation: at constant N the stuck core has c/a = theta = (1 - P/(mu N))^{1/3} and the
    compliance is dxi/dP = 1/(8 G* a theta) (Mindlin 1949); with u = 1 - P/(mu N),
    dxi = mu N du / (8 G* a u^{1/3}) integrates to xi = (3 mu N / (16 G* a)) (1 - u^{2/3}).

    Parameters
    ----------
    xi : float or ndarray
        Tangential displacement [m], >= 0 (loading from P = 0).
    N : float
        Normal force [N], > 0.
    a : float
        Contact radius [m].
    G_star : float
        Effective shear modulus [Pa].
    mu : float
        Friction coefficient [-], > 0.

    Returns
    -------
    float or ndarray
        P [N].
    """
    xi = np.asarray(xi, dtype=float)
    x = np.clip(1.0 - 16.0 * G_star * a * xi / (3.0 * mu * N), 0.0, None)
    return mu * N * (1.0 - x ** 1.5)


def theta_of(P: float, N: float, mu: float, direction: float, reversals: tuple) -> tuple[float, float]:
    r"""The stuck core's share theta = c/a [-] of a branch, and the argument theta^3 [-] before it
    is kept in [0, 1] (module docstring):

        virgin:  theta^3 = 1 - dir P/(mu N);   after a reversal P_r:  theta^3 = 1 - dir (P - P_r)/(2 mu N).

    Parameters
    ----------
    P : float
        Tangential load [N].
    N : float
        Normal force [N], > 0.
    mu : float
        Friction coefficient [-] (``math.inf``: theta = 1).
    direction : float
        The branch's slip direction, +1 or -1.
    reversals : tuple of float
        The reversal points [N], oldest first (empty: the virgin branch).
    """
    if math.isinf(mu):
        return 1.0, 1.0
    if not N > 0.0:  # at the ends of the contact the cap is 0: nothing is stuck
        return 0.0, 0.0
    if reversals:
        arg = 1.0 - direction * (P - reversals[-1]) / (2.0 * mu * N)
    else:
        arg = 1.0 - direction * P / (mu * N)
    return float(np.cbrt(min(max(arg, 0.0), 1.0))), arg


def load_rate(P: float, v_s: float, N: float, dN: float, a: float, G_star: float, mu: float, direction: float,
              reversals: tuple) -> tuple[float, bool]:
    r"""Thornton's incremental law, continuous in time (eq. 3): dP/dt [N/s] on a branch, and whether
    the slip annulus is active (0 < theta < 1 from the branch's formula).

        P' = 8 G* a theta v_s + dir mu N' (1 - theta),  and P' = 8 G* a v_s where |that| < mu N'.

    Parameters
    ----------
    P : float
        Tangential load [N] (the force on body 1 is -P).
    v_s : float
        Slip velocity [m/s].
    N, dN : float
        Normal force [N] and its rate [N/s].
    a : float
        Contact radius [m].
    G_star : float
        Effective shear modulus [Pa].
    mu : float
        Friction coefficient [-].
    direction : float
        The branch's slip direction, +1 or -1.
    reversals : tuple of float
        The branch's reversal points [N], oldest first.

    Returns
    -------
    rate : float
        dP/dt [N/s].
    slipping : bool
        False where the whole contact sticks (mu = inf, the theta = 1 rule, or theta^3 >= 1): the
        reversal points then stay where they are (module docstring).
    """
    k0 = 8.0 * G_star * a
    if math.isinf(mu):
        return k0 * v_s, False
    # Mindlin-Deresiewicz: where the normal load grows faster than mu times the tangential one, the
    # new rings stick and nothing slips (Thornton's theta = 1); P' is continuous across the switch
    if dN > 0.0 and direction * v_s >= 0.0 and k0 * direction * v_s <= mu * dN:
        return k0 * v_s, False
    theta, arg = theta_of(P, N, mu, direction, reversals)
    return k0 * theta * v_s + direction * mu * dN * (1.0 - theta), arg < 1.0


class _Contact:
    """The constants, and the normal motion as a function of psi (module docstring)."""

    def __init__(self, p: dict):
        self.__dict__.update(p)
        self.k_n = 4.0 / 3.0 * self.E_star * math.sqrt(self.R_star)
        self.delta_m = (5.0 * self.M_star * self.v_n ** 2 / (4.0 * self.k_n)) ** 0.4
        self.a_m = math.sqrt(self.R_star * self.delta_m)
        self.N_m = self.k_n * self.delta_m ** 1.5
        self.t_e = self.delta_m / self.v_n
        inv = 1.0 / self.m1 + self.R1 ** 2 / self.I1
        if not self.plane:
            inv += 1.0 / self.m2 + self.R2 ** 2 / self.I2
        self.inv_mt = inv

    def normal(self, psi: float) -> tuple[float, float, float, float]:
        """(dt/dpsi [s], a [m], N [N], dN/dpsi [N]) at psi."""
        s, c = math.sin(psi), math.cos(psi)
        s = max(s, 0.0)
        q = 1.0 + s + s * s + s ** 3 + s ** 4
        dt = 2.0 * self.t_e * s * math.sqrt((1.0 + s) / q)
        return dt, self.a_m * s, self.N_m * s ** 3, 3.0 * self.N_m * s * s * c

    def rates(self, psi, y, mode) -> np.ndarray:
        """d/dpsi of y = (t, v_s, P, reversal points...) in mode ('slide' | 'branch', dir)."""
        kind, direction = mode
        dt, a, N, dN_psi = self.normal(psi)
        v_s, P = y[1], y[2]
        reversals = tuple(y[3:])
        if kind == "slide":
            dP = direction * self.mu * dN_psi
            P = direction * self.mu * N
        else:
            dN = dN_psi / dt if dt > 0.0 else 0.0
            rate, _ = load_rate(P, v_s, N, dN, a, self.G_star, self.mu, direction, reversals)
            dP = rate * dt
        out = np.zeros_like(y)
        out[0] = dt
        out[1] = -P * self.inv_mt * dt
        out[2] = dP
        # the reversal points stay where they were set (module docstring: Thornton's moves left out)
        return out


def _phase_name(kind: str, reversals: int) -> str:
    if kind == "slide":
        return "slide"
    if reversals == 0:
        return "load"
    return "unload" if reversals % 2 else "reload"


def solve_mindlin_deresiewicz(*, geometry: str, R1: float, m1: float, R2: float, m2: float, E_star: float,
                              G_star: float, R_star: float, M_star: float, mu: float, v_n: float, v_t: float,
                              w1: float = 0.0, I1: float | None = None, I2: float | None = None) -> MDResult:
    r"""One oblique impact of elastic spheres (or a sphere on a plane) under Mindlin–Deresiewicz
    partial slip in Thornton's incremental form, Hertz normal force without dissipation.

    The arguments are `reference.solve_oblique`'s (no normal viscosity, no tangential form: the
    law is the theory's, module docstring).

    Parameters
    ----------
    geometry : str
        ``"sphere-sphere"`` or ``"sphere-plane"``.
    R1, m1 : float
        Body 1's radius [m] and mass [kg].
    R2, m2 : float
        Body 2's radius [m] and mass [kg] (ignored on a plane).
    E_star, G_star : float
        Effective Young's and shear moduli [Pa].
    R_star, M_star : float
        Effective radius [m] and mass [kg].
    mu : float
        Friction coefficient [-] (``math.inf``: no slip at all; then P' = 8 G* a v_s throughout).
    v_n, v_t : float
        Body 1's normal (> 0) and tangential velocity at touching [m/s].
    w1 : float, optional
        Body 1's spin about +z [rad/s].
    I1, I2 : float, optional
        Moments of inertia [kg m^2]; default (2/5) m R^2.

    Returns
    -------
    MDResult
        The lab-frame outputs of `reference.solve_oblique` (vt_after, omega_after, e_t,
        rebound_angle, ...), Psi_1 and Psi_2.

    Raises
    ------
    ValueError
        For a geometry other than the two, v_n <= 0 or mu < 0.
    RuntimeError
        Where the modes chatter (more than MAX_PIECES pieces).
    """
    if geometry not in ("sphere-sphere", "sphere-plane"):
        raise ValueError(f"geometry must be 'sphere-sphere' or 'sphere-plane', got {geometry!r}")
    if not v_n > 0.0:
        raise ValueError(f"v_n must be > 0 (body 1 approaches), got {v_n}")
    if not mu >= 0.0:
        raise ValueError(f"mu must be >= 0, got {mu}")
    plane = geometry == "sphere-plane"
    I1 = 0.4 * m1 * R1 * R1 if I1 is None else I1
    if not plane and I2 is None:
        I2 = 0.4 * m2 * R2 * R2
    c = _Contact(dict(plane=plane, R1=R1, m1=m1, R2=0.0 if plane else R2, m2=m2, I1=I1, I2=I2, E_star=E_star,
                      G_star=G_star, R_star=R_star, M_star=M_star, mu=mu, v_n=v_n))
    v_s0 = v_t + R1 * w1
    kappa = stiffness_ratio(E_star, G_star)
    if v_s0 == 0.0 or mu == 0.0:
        # no slip, or no friction: no tangential force at all
        P_history, v_s_after, T, phases = [0.0], v_s0, _contact_time(c), (("slide" if v_s0 else "load", 0.0),)
    else:
        v_s_after, T, P_history, phases = _integrate(c, v_s0)
    J = (v_s_after - v_s0) / c.inv_mt  # the tangential impulse on body 1 [N s]
    vt_after, omega_after = v_t + J / m1, w1 + R1 * J / I1
    vt2_after, omega2_after = (0.0, 0.0) if plane else (-J / m2, R2 * J / I2)
    eps = 1.0
    psi1 = kappa * v_s0 / (mu * v_n) if mu > 0 else math.inf
    psi2 = kappa * v_s_after / (mu * eps * v_n) if mu > 0 else math.inf
    return MDResult(T=T, eps=eps, vt_after=vt_after, omega_after=omega_after, vt2_after=vt2_after,
                    omega2_after=omega2_after, e_t=v_s_after / v_s0 if v_s0 else math.nan,
                    rebound_angle=math.degrees(math.atan2(v_s_after, eps * v_n)), psi1=psi1, psi2=psi2,
                    Ft_max=float(max(abs(p) for p in P_history)), phases=tuple(phases))


def _contact_time(c: _Contact) -> float:
    sol = solve_ivp(lambda psi, y: [c.normal(psi)[0]], (0.0, math.pi), [0.0], method="DOP853", rtol=RTOL,
                    atol=ATOL * c.t_e)
    return float(sol.y[0, -1])


def _integrate(c: _Contact, v_s0: float):
    """(v_s', T, [|P| maxima per piece], phases) of the contact (module docstring)."""
    direction = math.copysign(1.0, v_s0)
    psi = PSI_START
    _, a, N, _ = c.normal(psi)
    t0 = c.t_e * psi * psi  # dt/dpsi = 2 t_e psi (1 + O(psi)) at the start
    kappa = stiffness_ratio(c.E_star, c.G_star)
    psi1 = kappa * abs(v_s0) / (c.mu * c.v_n)
    if psi1 >= 1.0:  # the stuck start would need |P| = Psi_1 mu N > mu N: it slides from touching
        kind = "slide"
        P0 = direction * c.mu * N
    else:  # P = 8 G* v_s int a dt = Psi_1 mu N along the stuck start (theta = 1 rule)
        kind = "branch"
        if math.isfinite(c.mu):
            P0 = direction * psi1 * c.mu * N
        else:  # 8 G* v_s int a dt, a = a_m psi, dt = 2 t_e psi dpsi
            P0 = 8.0 * c.G_star * v_s0 * a * c.t_e * psi ** 2 * 2.0 / 3.0
    y = np.array([t0, v_s0, P0])
    phases = [(_phase_name(kind, 0), 0.0)]
    P_scale = max(c.N_m * (c.mu if math.isfinite(c.mu) else 1.0), 8.0 * c.G_star * c.a_m * abs(v_s0) * c.t_e)
    tops = [abs(P0)]
    muted = set()
    graces = 0
    for _ in range(MAX_PIECES):
        reversals = tuple(y[3:])
        mode = (kind, direction)
        scale = np.array([c.t_e, abs(v_s0)] + [P_scale] * (len(y) - 2))

        def rhs(w, Y, mode=mode, scale=scale):
            return c.rates(w, Y * scale, mode) / scale

        events, names = [], []

        def add(name, fun, sense):
            if name in muted:
                return

            def ev(w, Y, scale=scale):
                return fun(w, Y * scale)
            ev.terminal, ev.direction = True, sense
            events.append(ev)
            names.append(name)

        if kind == "slide":
            def leave(w, yy, d=direction):
                dt, a_, N_, dN_psi = c.normal(w)
                return 8.0 * c.G_star * a_ * d * yy[1] * dt - c.mu * dN_psi
            add("stick", leave, -1.0)
        else:
            add("reverse", lambda w, yy, d=direction: d * yy[1], -1.0)
            if math.isfinite(c.mu):
                add("cap", lambda w, yy, d=direction: c.mu * c.normal(w)[2] - d * yy[2], -1.0)
                # the turning points stay put, so while N falls the cap can come down onto a load
                # held on the other side (the elastic recoil): the contact then slides that way
                add("cap behind", lambda w, yy, d=direction: c.mu * c.normal(w)[2] + d * yy[2], -1.0)
                if len(reversals) >= 2:  # back at the reversal before its own: the older branch goes on
                    add("return", lambda w, yy, d=direction: d * (yy[2] - yy[-2]), 1.0)
                elif len(reversals) == 1:  # back at -T*: virgin loading in this direction
                    add("return", lambda w, yy, d=direction: d * (yy[2] + yy[-1]), 1.0)
        w_end = math.pi - PSI_END if psi < math.pi - PSI_END else math.pi
        if psi >= math.pi - PSI_END:
            events, names = [], []
        if muted:
            w_end = min(w_end, psi + GRACE)
        sol = solve_ivp(rhs, (psi, w_end), y / scale, method="DOP853", rtol=RTOL, atol=ATOL, events=events or None,
                        dense_output=False)
        if sol.status == -1:
            raise RuntimeError(f"solve_mindlin_deresiewicz: the integration failed ({sol.message})")
        if kind == "branch":
            tops.append(float(np.max(np.abs(sol.y[2] * P_scale))))
        else:  # sliding: |P| = mu N, largest at the piece's maximum of N = N_m sin^3 psi
            lo, hi = psi, float(sol.t[-1])
            tops.append(c.mu * (c.N_m if lo <= math.pi / 2 <= hi else max(c.normal(lo)[2], c.normal(hi)[2])))
        fired = [(sol.t_events[i][0], names[i], sol.y_events[i][0]) for i in range(len(events))
                 if len(sol.t_events[i])]
        if not fired:
            psi, y = sol.t[-1], sol.y[:, -1] * scale
            muted = set()
            if psi >= math.pi:
                break
            continue
        w_ev, name, Y_ev = min(fired, key=lambda e: e[0])
        if w_ev - psi <= 1e-12 * max(1.0, psi):
            # a mode just entered that wants to leave at its first point: round-off on an event that
            # starts at zero; kept off for GRACE
            graces += 1
            if graces > 50:
                raise RuntimeError(f"solve_mindlin_deresiewicz: the modes chatter at psi = {psi:.12g}")
            muted = {name}
            continue
        muted = set()
        psi, y = w_ev, Y_ev * scale
        t = y[0]
        _, a, N, _ = c.normal(psi)
        if name == "stick":  # the slide ends: a reversal, or loading under the theta = 1 rule
            P = direction * c.mu * N
            if direction * y[1] < 0.0:
                y = np.array([y[0], y[1], P, P])
                direction = -direction
            else:
                y = np.array([y[0], y[1], P])
            kind = "branch"
        elif name == "reverse":
            y = np.append(y, y[2])
            direction = -direction
        elif name == "cap":
            kind = "slide"
            y = np.array([y[0], y[1], direction * c.mu * N])
        elif name == "cap behind":
            # The falling cap meets the load held on the far side, P = -dir mu N. It slides that
            # way (towards sign P, against this branch's slip) only while the cap falls faster than
            # the no-slip spring unloads, 8 G* a |v_s| <= mu |N'|: the end-of-sliding rule, which
            # at the cap already holds otherwise (the branch's annulus let P fall slower than the
            # cap, its no-slip spring does not). Then the load turns at the cap: unloading from
            # T* = -dir mu N, memory wiped, the branch's direction kept.
            dt_psi, _, _, dN_psi = c.normal(psi)
            P = -direction * c.mu * N
            if 8.0 * c.G_star * a * abs(y[1]) * dt_psi <= -c.mu * dN_psi:
                kind, direction = "slide", -direction
                y = np.array([y[0], y[1], P])
            else:
                y = np.array([y[0], y[1], P, P])
        elif name == "return":
            drop = 2 if len(reversals) >= 2 else 1
            y = y[:len(y) - drop]
        phases.append((_phase_name(kind, len(y) - 3), float(t)))
    else:
        raise RuntimeError(f"solve_mindlin_deresiewicz: more than {MAX_PIECES} pieces (chattering modes?)")
    return float(y[1]), float(y[0]), tops, phases
