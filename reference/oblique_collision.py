r"""One oblique collision with friction and rotation, solved with a model's own equations.

A sphere (body 1) meets a sphere or a plane (body 2) in the x-y plane; the tangential contact
model is a `reference.tangential_forms.TangentialForm`. `solve_oblique` integrates the
continuous limit (dt -> 0) of the model's discrete algorithm to ~1e-10 relative and returns an
`ObliqueResult`; `rigid_body_sliding` is the closed form of a contact that slides throughout.

Conventions (docs/physics.md, "Oblique impacts: sign conventions")
------------------------------------------------------------------
The normal n = +x points from body 1 to body 2 (for two spheres: at touching, and n turns after;
see "Two spheres" below); body 1 approaches with the normal velocity
v_n > 0, so the overlap delta has d(delta)/dt = v_n at touching. The tangent is +y, spins are
about +z (counter-clockwise positive). The contact point lies at +L_1 x from centre 1 and at
-L_2 x from centre 2 (L_i the arms of `TangentialForm.lever_slip`), so its slip velocity is::

    v_s = (v_y1 + L_1 w_1) - (v_y2 - L_2 w_2)                      [m/s]

The tangential force on body 1 is F_t y, on body 2 -F_t y; the torques (arms of `lever_torque`)
are (L_1 x) x (F_t y) = L_1 F_t z on body 1 and (-L_2 x) x (-F_t y) = L_2 F_t z on body 2, so::

    dv_s/dt = F_t (1/m_1 + L_1 L'_1/I_1 + 1/m_2 + L_2 L'_2/I_2) + (dL_1/dt) w_1 + (dL_2/dt) w_2

with a positive factor of F_t: a force against the slip (F_t v_s < 0) reduces |v_s|. A plane has
1/m_2 = 1/I_2 = 0 and does not move.

Normal half: the Hertz force with the Brilliantov dissipative term::

    F_n = k_n delta^{3/2} + eta_n d(delta)/dt,   k_n = (4/3) E* sqrt(R*),   eta_n = 2 eta a,

a = sqrt(R* delta) [m] the contact radius, so eta_n [N s/m] is the coefficient of d(delta)/dt,
2 eta sqrt(R*) delta^{1/2}; M* d^2(delta)/dt^2 = -F_n. ``clipped`` uses max(F_n, 0) (the bodies
separate at F0 and fly apart; the contact itself lasts until delta = 0). The normal motion does
not depend on the tangential one.

Tangential half, sticking: the history H (xi [m] or F_h [N]) follows::

    dxi/dt  = v_s            + r xi (da/dt)/a          F_el = -k_t xi
    dF_h/dt = -k_t v_s       + r F_h (da/dt)/a         F_el = F_h
    F_t = F_el - eta_t v_s

with r = 1 while rescaling (``rescale`` and da/dt < 0), else 0. For both histories the elastic
force moves as::

    dF_el/dt = -k_t v_s + (c_k + r) F_el (da/dt)/a,    (da/dt)/a = d(delta)/dt / (2 delta)

with c_k = 1 for a displacement history with a Mindlin stiffness (k_t = k_t0 a changes under a
fixed xi: -dk_t/dt xi = F_el (da/dt)/a), else 0.

Two spheres: the line of centres turns
--------------------------------------
Two spheres are free bodies in the plane: while they slide past each other the line of centres
turns, by ~ v_t T / (R1 + R2) over the contact (5e-3 rad for alumina at 45 deg, R = 2.5 mm,
V = 3.9 m/s), and every quantity above is of the contact frame that turns with it: n = (cos phi,
sin phi) = (r2 - r1)/|r2 - r1|, t = z x n = (-sin phi, cos phi), phi = 0 at touching (the centres
on the x axis there, engines/oblique_run.py), delta = R1 + R2 - |r2 - r1|, d(delta)/dt =
(v1 - v2).n. Body 1 gets -F_n n + F_t t, body 2 the opposite; the torques are the arms' as above.
The state carries v_yi := v_i.t, the components of the bodies' velocities along the turning
tangent, and phi; the normal components follow from the centre of mass, which moves at V_cm =
m1 (v_n, v_t)/(m1 + m2) (body 2 at rest at the start): v_i.n = V_cm.n +- (M*/m_i) d(delta)/dt.
With v_c = v_y1 - v_y2 = (v1 - v2).t and r = R1 + R2 - delta::

    d(phi)/dt = -v_c / r,      d^2(delta)/dt^2 = -F_n/M* - v_c^2 / r      (centripetal term)
    dv_yi/dt = (+-F_t/m_i) - d(phi)/dt (v_i.n)   =>   dv_c/dt = F_t/M* + v_c d(delta)/dt / r

The slip v_s = alpha v_c + L_1 w_1 + L_2 w_2 (alpha = (R1 + R2)/(R1 + R2 - delta) with
`TangentialForm.anti_ratcheting`, YADE's, else 1) and the history are of the turning frame: the history is a
scalar along t, which both engines' rotations of it keep (LAMMPS projects the stored vector onto
the new tangent plane and rescales it to its former magnitude; YADE rotates its shear force with
the contact: in the plane, both keep the component along t), so its rate is the one above.
The results are the lab frame's, as an engine's dump gives them (records/oblique_metrics.py):
eps = -(v1 - v2).x / v_n, v_t' and v_t2' the bodies' y velocities, v_s' = (v_y1 - v_y2)_lab
+ R1 w1 + R2 w2, F_max the largest x component of the contact force on body 2 (F_n cos phi +
F_t sin phi), Ft_max the largest |y component| of that on body 1 (|F_t cos phi - F_n sin phi|,
not 0 without friction). T_F0 stays the zero of the normal force F_n itself (an engine's F0,
read on the x component, differs from it by F_t sin phi at that instant). A plane does not move and
its normal does not turn: the equations above with 1/m_2 = 0 and phi = 0 (exact).

Sliding, and the conditions of the transitions
----------------------------------------------
Let X be the quantity the cap limits: X = F_el - eta_t v_s (cap ``total``) or X = F_el (cap
``elastic``), and C = mu F_c the cap. The discrete algorithm advances the history as if sticking,
then projects it back onto |X| <= C. Its limit dt -> 0 is a sweeping process:

- stick -> slip when |X| reaches C: the event C^2 - X^2 = 0, crossed downwards;
- while sliding, X = s C with s = sign(X) fixed (the history is algebraic: F_el = s C + eta_t v_s
  under the total cap, F_el = s C under the elastic cap), and the force is F_t = s C (total) or
  F_t = s C - eta_t v_s (elastic; without the damping for ``stick_only``);
- the slide goes on while the free (sticking) evolution of X would carry it out of the cap,
  s dX_free/dt > dC/dt: each step's projection is then active. It turns to sticking where
  g = s dX_free/dt - dC/dt crosses zero downwards: from there, the free evolution stays inside.

The free rate, with the history where the slide holds it:

- elastic cap: dX_free/dt = dF_el/dt above, with F_el = s C;
- total cap: dX_free/dt = dF_el/dt - (d eta_t/dt) v_s - eta_t dv_s/dt, with F_el = s C + eta_t v_s,
  d eta_t/dt = eta_t d(delta)/dt/(2 delta), and dv_s/dt from F_t = s C (the force of the slide:
  X is continuous at the transition, so is F_t).

The cap's rate: dC/dt = mu (3/2) k_n delta^{1/2} d(delta)/dt (``elastic`` F_c), or, with
dF_n/dt = (3/2) k_n delta^{1/2} d(delta)/dt + eta sqrt(R*) delta^{-1/2} (d(delta)/dt)^2
+ 2 eta sqrt(R*) delta^{1/2} d^2(delta)/dt^2, mu dF_n/dt (``total_clipped``, 0 where F_n <= 0) or
mu sign(F_n) dF_n/dt (``total_abs``). Both event functions are multiplied by delta^{1/2} (> 0),
which removes the delta^{-1/2} of the rates at touching and leaves the sign, hence the event.

At touching X and C are both zero; the first phase is that of the limit t -> 0 of |X|/C along
the sticking motion (delta = v_n t, H from v_s t): for a Mindlin displacement history without
damping it is (6 G*/E*) |v_s|/v_n, and the contact slides from the start iff that exceeds mu.
It is evaluated at t = 1e-12 delta_e/v_n, where the corrections are ~1e-12.

Where the cap vanishes
----------------------
At the normal force's zero (F0) C has a kink (|F_n|, max(F_n, 0)), so a transition may fall
exactly there; F0 is then recorded at the same point. If C stays zero from F0 to the end (a clipped
law with a cap on the total force, or the ``total_clipped`` cap), the contact slides to the end with
F_t = 0 (total cap) or the damping alone (elastic cap), whatever the direction, and no transition is
left (LAMMPS: every trial exceeds a zero cap). Near delta = 0 both X and C vanish: transitions in the
last 1e-12 delta_e of the overlap are not followed (their impulse is < 1e-18 F_e t_e). A phase that
wants to leave at the point it was entered (both margins start at zero with zero slope, so round-off
can fire them) is kept for 1e-10 of the contact without its exit event; where it keeps wanting to, or
where F_t jumps at a transition (damping ``stick_only`` under the elastic cap), the model has no
continuous limit there (the discrete algorithm chatters; the limit would slide along the cap with a
force neither phase gives, a Filippov solution) and `solve_oblique` refuses it by name.

The normal force's zero
-----------------------
With the cap on |F_n| of the unclipped law (``total_abs``, not ``clipped``, eta > 0), F_n passes
zero at T_F0 on the way out and stays negative to the end (the attractive tail): C = mu |F_n|
falls to 0 there and grows again. |X| <= C makes X = 0 at T_F0 whatever the phase (a slide holds
X = s C -> 0; a stick meets the cap at the latest there), and dC/dt jumps from -mu |dF_n/dt| to
+mu |dF_n/dt|. A slide's margin g = s dX_free/dt - dC/dt therefore jumps by -2 mu |dF_n/dt| at the
zero: where it lands below zero the slide ends at the zero itself, but g has jumped, not crossed,
and the downward-crossing event cannot see it (it lands on either side by round-off; before this
was handled the force and rescaled histories slid on to the end, the displacement history stuck:
alumina at 10 deg, K = 0.1, mu = 0.092, omega_after 1e-4 off the discrete limit). So the phase
after the zero is decided there, as at touching, from X and C both starting at 0: over the first
steps after it the discrete trial is X + dX_free dt from X = 0, and C = mu |dF_n/dt| (t - T_F0),
so the projection stays inactive, the contact STICKS, iff

    |dX_free/dt| <= mu |dF_n/dt|     (at T_F0; dF_n/dt < 0 is continuous there),

and else it SLIDES with s = sign(dX_free/dt). dX_free/dt is the free rate above with the history
where the slide holds it at C = 0: F_t = s C = 0, F_el = 0 (elastic cap) or eta_t v_s (total cap),
so it does not depend on s; without a dashpot the terms (c_k + r) F_el (da/dt)/a of the
displacement history and of the rescaling vanish with F_el there, and dX_free/dt = -k_t v_s.
Sticking, the history is set to hold X = 0. A transition located within F0_TOUCH of the zero is the zero too. With
``total_clipped`` or a clipped law C stays 0 after the zero (no transition is left), with an
``elastic`` F_c it has no kink there: neither needs the decision.

How it is integrated
--------------------
delta^{1/2} is not smooth at either end of the contact, so, as in `reference.collision_ode`, the
integration variable changes: s = sqrt(t) from touching to t = delta_e/(4 v_n) (delta ~ v_n s^2
is smooth in s), t through the maximum compression down to delta = delta_max/2, then
u = sqrt(delta) to u = 0 (dt/du = 2u/(d delta/dt), d(delta)/dt < 0 there). Each piece is scipy's
DOP853 at rtol 1e-12 on variables scaled to O(1) (delta_e, v, ...). The stick/slip transitions,
the maximum compression, the normal force's zero (where max(F_n, 0) and |F_n| have a kink) and the
hand-over points are terminal events located on the dense output (Brent to 4 ulp), and the
integration restarts there: no step straddles a kink. A slide's margin, scaled by delta^{1/2}, is 0
at u = 0 itself, so a crossing within the last step before the end is read on the dense output at
u = U_END (`_stick_hidden_by_the_end`: a linear spring whose slip has reversed under the slide must
stick there). The maxima of F_n and |F_t| are found on the dense output: every local maximum of the
samples of every piece is refined (bounded Brent), and the largest is taken.
tests/test_oblique_reference.py checks it against an independent integration (DOP853 in t alone,
events from a finite-difference probe of the free evolution), against the discrete LAMMPS-like
algorithm as dt -> 0, and against the closed forms; for two spheres against an integration of the
same planar motion in lab-frame Cartesian coordinates with a vector history that turns with the
contact, and the conservation laws.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from .tangential_forms import TangentialForm, lever_base, lever_shares

RTOL = 1e-12
ATOL = 1e-14
#: Where the first piece (in sqrt(t)) ends [delta_e / v_n], unless the maximum compression comes first.
T_HANDOVER = 0.25
#: Where the piece in t hands over to the piece in sqrt(delta): delta = this share of delta_max.
DELTA_HANDOVER = 0.5
#: The time [delta_e / v_n] at which the first phase (stick or slip) is decided.
T_START = 1e-12
#: |F_n| [F_e = k_n delta_e^{3/2}] within which a transition is taken for the force zero (a kink of C).
F0_TOUCH = 1e-9
#: The span [of the piece's variable, ~1 a contact] a phase that wants to leave at once is kept.
GRACE = 1e-10
#: Graces in a row beyond which the stick/slip chatter is refused.
MAX_CHATTER = 20
#: sqrt(delta/delta_e) below which the transitions are not followed (see _integrate).
U_END = 1e-6
#: More transitions than this in one collision means a chattering model (or a bug): refused.
MAX_PIECES = 400
#: Samples per piece on which the maxima of F_n and |F_t| are bracketed before Brent refines them.
SAMPLES = 24


@dataclass(frozen=True)
class ObliqueResult:
    r"""One oblique collision (`solve_oblique`), SI units.

    Attributes
    ----------
    T : float
        Contact time [s] under the law's criterion: F0 (the normal force returns to zero) when
        clipped, x0 (delta returns to zero) when not.
    T_x0, T_F0 : float
        Time [s] at which delta, and the unclipped normal force, return to zero (T_F0 = T_x0
        without normal damping).
    eps : float
        Normal restitution -v_n'/v_n [-] (v_n' the normal relative velocity at separation; two
        spheres: -(v_x1' - v_x2')/v_n, the lab x component).
    delta_max : float
        Maximum overlap [m].
    F_max : float
        Maximum normal force [N] (two spheres: of the contact force's lab x component on body 2).
    vt_after, omega_after : float
        Body 1's centre velocity along +y [m/s] (lab) and spin about +z [rad/s] after the contact.
    vt2_after, omega2_after : float
        The same for body 2 (0 for a plane), in the frame where body 2 was at rest before the
        contact: vt_after - vt2_after is the relative v_y1' - v_y2' an engine records.
    e_t : float
        Tangential restitution of the contact point v_s'/v_s [-] (positive when the slip keeps its
        direction; nan without initial slip). At separation every arm is R. Two spheres: v_s' =
        (v_y1' - v_y2') + R1 w1' + R2 w2' with the lab y velocities.
    rebound_angle : float
        atan2(v_s', v_n') [degrees], v_n' = eps v_n the normal separation speed.
    Ft_max : float
        Maximum |F_t| over the contact [N] (two spheres: of the lab y component of the contact
        force on body 1, normal force included, so not 0 without friction).
    phases : tuple of (str, float)
        ("stick" | "slip", start time [s]) of each phase, in order.
    history_after : float
        The history left at delta = 0: xi [m] or F_h [N] (nan where a Mindlin displacement history
        slides at the end: k_t = 0 there, and xi = -F_el/k_t has no value).
    turn_after : float
        The angle [rad] the line of centres turned through over the contact, counter-clockwise
        (0 for a plane).
    """

    T: float
    T_x0: float
    T_F0: float
    eps: float
    delta_max: float
    F_max: float
    vt_after: float
    omega_after: float
    vt2_after: float
    omega2_after: float
    e_t: float
    rebound_angle: float
    Ft_max: float
    phases: tuple
    history_after: float
    turn_after: float = 0.0


class _Model:
    """The contact's constants and its right-hand side in physical variables.

    The physical state is y = (delta, d delta/dt, v_y1, w_1, v_y2, w_2, H), and for two spheres
    phi, the angle of the line of centres, with v_yi the components along the turning tangent
    (module docstring, "Two spheres"); the mode is (sliding, s). Every method is a pure function of (y, mode)."""

    def __init__(self, p: dict):
        self.__dict__.update(p)
        self.k_n = 4.0 / 3.0 * self.E_star * math.sqrt(self.R_star)
        self.c_eta = 2.0 * self.eta * math.sqrt(self.R_star)  # eta_n = c_eta delta^{1/2}
        f = self.form
        self.c_k = 1.0 if (f.history == "displacement" and f.stiffness == "mindlin") else 0.0
        # each sphere's share of the overlap in its arms (equal but for the modulus-weighted arm)
        (self.sh1s, self.sh2s), (self.sh1t, self.sh2t) = (lever_shares(c, self.young_1, self.young_2)
                                                          for c in (f.lever_slip, f.lever_torque))
        # the arms are L = b R - s delta: b = 0 where the spins never enter the slip, or the force applies
        # no torque (lever "none", ESyS's HertzMindlin); b = 1 otherwise (1.0 R is R bitwise)
        self.b_s, self.b_t = lever_base(f.lever_slip), lever_base(f.lever_torque)
        # the slip the model itself sees at touching (its history's source): the contact point's
        # v_s0 unless the spins do not enter it; e_t stays the contact point's v_s'/v_s0
        self.v_slip0 = self.v_s0 if self.b_s else self.v_t
        # a plane does not move: its inverse mass and inertia are zero, and so are its arms' terms
        # after the normal force's zero the cap stays 0 to the end: clipped, or clipped in the cap
        # (the unclipped force stays negative once it has crossed zero on the way out)
        self.capless_after_f0 = f.cap_normal != "elastic" and (self.clipped or f.cap_normal == "total_clipped")
        # F_t jumps at a transition when the damping switches off with the slide (YADE's form): a
        # phase that wants to leave at once is then a true chatter, not round-off
        self.force_jumps = (f.cap == "elastic" and f.damping == "stick_only" and self.x_t * self.eta > 0.0)
        # a cap on |F_n| of the unclipped law: C is 0 at the normal force's zero and grows after it
        self.reopens_after_f0 = (f.cap_normal == "total_abs" and not self.clipped and 0.0 < self.mu < math.inf)
        self.im1, self.iI1 = 1.0 / self.m1, 1.0 / self.I1
        self.im2 = 0.0 if self.plane else 1.0 / self.m2
        self.iI2 = 0.0 if self.plane else 1.0 / self.I2
        if not self.plane:
            # two spheres: the line of centres turns (module docstring, "Two spheres"); the centre of
            # mass moves at V_cm (body 2 at rest at the start) and each body's normal velocity is
            # V_cm.n + (M*/m_i) (+-d(delta)/dt)
            self.R12 = self.R1 + self.R2
            self.vcm = (self.m1 * self.v_n / (self.m1 + self.m2), self.m1 * self.v_t / (self.m1 + self.m2))
            self.share1, self.share2 = self.M_star / self.m1, self.M_star / self.m2

    def local(self, y, sliding: bool, s: float) -> dict:
        """Every force and rate at state y in mode (sliding, s)."""
        d, dd, vy1, w1, vy2, w2, H = y[:7]
        f = self.form
        d = max(d, 0.0)
        rd = math.sqrt(d)
        a = math.sqrt(self.R_star) * rd
        F_el_n = self.k_n * d * rd
        eta_n = self.c_eta * rd
        F_raw = F_el_n + eta_n * dd
        F_n = max(F_raw, 0.0) if self.clipped else F_raw
        ddd = -F_n / self.M_star
        turn = 0.0  # d(phi)/dt, the line of centres' rate of turn [rad/s]
        if not self.plane:  # |r2 - r1| = R1 + R2 - delta, the centripetal term of the relative motion
            v_c = vy1 - vy2
            r = self.R12 - d
            turn = -v_c / r
            ddd -= v_c * v_c / r
        if f.cap_normal == "total_abs":
            F_c = abs(F_n)
        elif f.cap_normal == "total_clipped":
            F_c = max(F_n, 0.0)
        else:
            F_c = F_el_n
        cap = math.inf if self.mu == math.inf else self.mu * F_c  # mu = inf: no cap, not inf * 0
        k_t = self.k_t0 * a if f.stiffness == "mindlin" else self.k_t0
        L1s, L1t = self.b_s * self.R1 - self.sh1s * d, self.b_t * self.R1 - self.sh1t * d
        L2s, L2t = self.b_s * self.R2 - self.sh2s * d, self.b_t * self.R2 - self.sh2t * d
        if self.plane:
            L2s = L2t = 0.0
        alpha = 1.0  # YADE's anti-ratcheting factor on the translational slip (two spheres)
        if f.anti_ratcheting and not self.plane:
            alpha = self.R12 / (self.R12 - d)
            v_s = alpha * (vy1 - vy2) + L1s * w1 + L2s * w2
        else:
            v_s = (vy1 + L1s * w1) - (vy2 - L2s * w2)
        eta_stick = 0.0 if f.damping == "none" else self.x_t * eta_n
        eta_slide = 0.0 if f.damping == "stick_only" else eta_stick
        if not sliding:
            F_el = -k_t * H if f.history == "displacement" else H
            F_t = F_el - eta_stick * v_s
            X = F_t if f.cap == "total" else F_el
        elif f.cap == "total":
            F_t = s * cap
            F_el = F_t + eta_stick * v_s
            X = F_t
        else:
            F_el = s * cap
            F_t = F_el - eta_slide * v_s
            X = F_el
        return dict(d=d, rd=rd, dd=dd, ddd=ddd, a=a, F_el_n=F_el_n, F_raw=F_raw, F_n=F_n, F_c=F_c, cap=cap,
                    k_t=k_t, L1s=L1s, L1t=L1t, L2s=L2s, L2t=L2t, w1=w1, w2=w2, v_s=v_s, eta_stick=eta_stick,
                    F_el=F_el, F_t=F_t, X=X, turn=turn, alpha=alpha)

    def rates(self, y, sliding: bool, s: float, q: dict | None = None) -> np.ndarray:
        """dy/dt."""
        q = q or self.local(y, sliding, s)
        F_t = q["F_t"]
        dH = 0.0
        if not sliding:  # while sliding the history is algebraic (set at the transitions)
            dH = q["v_s"] if self.form.history == "displacement" else -q["k_t"] * q["v_s"]
            if self.form.rescale and q["dd"] < 0.0 and q["d"] > 0.0:
                dH += y[6] * q["dd"] / (2.0 * q["d"])
        if self.plane:
            return np.array([q["dd"], q["ddd"],
                             F_t * self.im1, q["L1t"] * F_t * self.iI1,
                             -F_t * self.im2, q["L2t"] * F_t * self.iI2, dH])
        # the frame turns: d(v_i.t)/dt = a_i.t - turn (v_i.n), v_i.n = V_cm.n +- (M*/m_i) d(delta)/dt
        turn, dd = q["turn"], q["dd"]
        c, s_ = math.cos(y[7]), math.sin(y[7])
        v_cm_n = self.vcm[0] * c + self.vcm[1] * s_
        return np.array([dd, q["ddd"],
                         F_t * self.im1 - turn * (v_cm_n + self.share1 * dd), q["L1t"] * F_t * self.iI1,
                         -F_t * self.im2 - turn * (v_cm_n - self.share2 * dd), q["L2t"] * F_t * self.iI2, dH,
                         turn])

    def lab_forces(self, y, q: dict) -> tuple[float, float]:
        """(x component of the contact force on body 2, |y component of that on body 1|) [N]: what
        an engine's dump records (records/oblique_metrics.py); the plane's are F_n and |F_t|."""
        if self.plane:
            return q["F_n"], abs(q["F_t"])
        c, s_ = math.cos(y[7]), math.sin(y[7])
        # on body 1: -F_n n + F_t t, n = (cos phi, sin phi), t = (-sin phi, cos phi); body 2 the opposite
        return q["F_n"] * c + q["F_t"] * s_, abs(-q["F_n"] * s_ + q["F_t"] * c)

    def cap_rate_scaled(self, q: dict) -> float:
        """delta^{1/2} dC/dt, C = mu F_c [N/s m^{1/2}]."""
        rd, dd = q["rd"], q["dd"]
        if self.form.cap_normal == "elastic":
            return self.mu * 1.5 * self.k_n * rd * rd * dd
        if self.clipped and q["F_raw"] <= 0.0:
            return 0.0
        dF = 1.5 * self.k_n * rd * rd * dd + 0.5 * self.c_eta * dd * dd + self.c_eta * rd * rd * q["ddd"]
        if self.form.cap_normal == "total_clipped":
            return self.mu * dF if q["F_n"] > 0.0 else 0.0
        return self.mu * math.copysign(1.0, q["F_n"]) * dF

    def slip_margin(self, y, s: float) -> float:
        """delta^{1/2} (s dX_free/dt - dC/dt) while sliding: > 0 keeps the slide (module docstring)."""
        q = self.local(y, True, s)
        return s * self.free_rate_scaled(y, q) - self.cap_rate_scaled(q)

    def phase_at_f0(self, y) -> tuple[bool, float]:
        """(sliding, s) from the normal force's zero on, for a cap on |F_n| of the unclipped law.

        C = mu |F_n| is 0 there and grows again (the attractive tail), X is 0 too (X = s C while
        sliding; |X| <= C while sticking), so, as at touching, the phase is that of the limit of
        |X|/C along the free evolution: it slides on s = sign(dX_free/dt) iff |dX_free/dt| exceeds
        the cap's rate after the zero, mu |dF_n/dt| (module docstring, "The normal force's zero")."""
        q = self.local(y, True, 1.0)  # F_t = s C = 0 here: dX_free/dt does not depend on s
        dX = self.free_rate_scaled(y, q)
        dC = abs(self.cap_rate_scaled(q))  # mu |dF_n/dt| delta^{1/2}, whatever the sign of F_n at the zero
        if abs(dX) > dC:
            return True, math.copysign(1.0, dX)
        return False, 0.0

    def free_rate_scaled(self, y, q: dict) -> float:
        """delta^{1/2} dX_free/dt while sliding [N/s m^{1/2}] (q = `local` in the slide's mode): the
        rate of X under the sticking evolution from the slide's history (module docstring)."""
        rd, dd = q["rd"], q["dd"]
        r = 1.0 if (self.form.rescale and dd < 0.0) else 0.0
        # delta^{1/2} (da/dt)/a = dd / (2 delta^{1/2}); at delta = 0 the history is 0 with the cap
        half_rate = dd / (2.0 * rd) if rd > 0.0 else 0.0
        dX = -q["k_t"] * q["v_s"] * rd + (self.c_k + r) * q["F_el"] * half_rate
        if self.form.cap == "total":
            F_t = q["F_t"]
            if self.plane:
                dv_s = (F_t * (self.im1 + q["L1s"] * q["L1t"] * self.iI1 + self.im2 + q["L2s"] * q["L2t"] * self.iI2)
                        - self.sh1s * dd * q["w1"])
            else:  # alpha (v_y1 - v_y2), the frame turning: d(v_y1 - v_y2)/dt = F_t/M* - turn d(delta)/dt
                alpha, v_c = q["alpha"], y[2] - y[4]
                d_alpha = (alpha * alpha / self.R12 * dd) if self.form.anti_ratcheting else 0.0
                dv_s = (alpha * (F_t * (self.im1 + self.im2) - q["turn"] * dd) + d_alpha * v_c
                        + F_t * (q["L1s"] * q["L1t"] * self.iI1 + q["L2s"] * q["L2t"] * self.iI2)
                        - dd * (self.sh1s * q["w1"] + self.sh2s * q["w2"]))
            dX -= q["eta_stick"] * (half_rate * q["v_s"] + rd * dv_s)
        return dX

    def stick_margin(self, y) -> float:
        """C^2 - X^2 while sticking: < 0 beyond the cap [N^2]."""
        q = self.local(y, False, 0.0)
        return q["cap"] ** 2 - q["X"] ** 2

    def history_at(self, y, sliding: bool, s: float) -> float:
        """The history that holds the state's elastic force (set when a slide ends)."""
        q = self.local(y, sliding, s)
        if self.form.history == "force":
            return q["F_el"]
        return -q["F_el"] / q["k_t"] if q["k_t"] > 0.0 else y[6]

    def first_phase(self) -> tuple[bool, float]:
        """(sliding, s) at touching: the limit t -> 0 of |X|/C along the sticking motion."""
        t0 = T_START * self.t_e
        v_s0 = self.v_slip0
        if v_s0 == 0.0:
            return False, 0.0
        if self.form.history == "displacement":
            H0 = v_s0 * t0
        elif self.form.stiffness == "mindlin":
            H0 = -self.k_t0 * math.sqrt(self.R_star * self.v_n) * v_s0 * (2.0 / 3.0) * t0 ** 1.5
        else:
            H0 = -self.k_t0 * v_s0 * t0
        y0 = np.array([self.v_n * t0, self.v_n, self.v_t, self.w1, 0.0, 0.0, H0] + ([] if self.plane else [0.0]))
        q = self.local(y0, False, 0.0)
        if q["X"] ** 2 > q["cap"] ** 2 or self.mu == 0.0:
            return True, math.copysign(1.0, q["X"])
        return False, 0.0


def solve_oblique(*, geometry: str, R1: float, m1: float, R2: float, m2: float, E_star: float, G_star: float,
                  R_star: float, M_star: float, eta: float, clipped: bool, mu: float, form: TangentialForm,
                  v_n: float, v_t: float, w1: float = 0.0, k_t0: float | None = None, x_t: float = 0.0,
                  I1: float | None = None, I2: float | None = None, young_1: float | None = None,
                  young_2: float | None = None) -> ObliqueResult:
    r"""One oblique collision of sphere 1 with a sphere or a plane (body 2, at rest), solved with the
    model's own equations (module docstring: conventions, transitions, method).

    Parameters
    ----------
    geometry : str
        ``"sphere-sphere"`` or ``"sphere-plane"``.
    R1, m1 : float
        Body 1's radius [m] and mass [kg].
    R2, m2 : float
        Body 2's radius [m] and mass [kg] (``math.inf`` for a plane; ignored there).
    E_star, G_star : float
        Effective Young's and shear moduli [Pa].
    R_star, M_star : float
        Effective radius [m] and normal effective mass [kg].
    eta : float
        Effective viscosity [Pa s] of the dissipative term 2 eta a d(delta)/dt (0: elastic).
    clipped : bool
        The normal force clipped at zero (F0 physics), else the attractive tail is kept.
    mu : float
        Friction coefficient [-] (``math.inf``: no cap, the contact sticks throughout).
    form : TangentialForm
        The tangential model.
    v_n : float
        Normal approach velocity of body 1 [m/s], > 0.
    v_t : float
        Body 1's centre velocity along +y at touching [m/s].
    w1 : float, optional
        Body 1's spin about +z at touching [rad/s].
    k_t0 : float, optional
        The tangential stiffness constant: [Pa] for Mindlin (default 8 G*), [N/m] for linear
        (required then).
    x_t : float, optional
        eta_t / eta_n [-] for the damped forms.
    I1, I2 : float, optional
        Moments of inertia [kg m^2]; default (2/5) m R^2 (solid spheres).
    young_1, young_2 : float, optional
        The bodies' Young's moduli [Pa], for the modulus-weighted lever arm only
        (`reference.tangential_forms.lever_shares`).

    Returns
    -------
    ObliqueResult
        The collision's characteristics; phases lists each stick/slip phase with its start.
    """
    if geometry not in ("sphere-sphere", "sphere-plane"):
        raise ValueError(f"geometry must be 'sphere-sphere' or 'sphere-plane', got {geometry!r}")
    if not v_n > 0.0:
        raise ValueError(f"v_n must be > 0 (body 1 approaches), got {v_n}")
    plane = geometry == "sphere-plane"
    if k_t0 is None:
        if form.stiffness != "mindlin":
            raise ValueError("k_t0 [N/m] is required for a linear tangential stiffness")
        k_t0 = 8.0 * G_star
    I1 = 0.4 * m1 * R1 * R1 if I1 is None else I1
    I2 = (math.inf if plane else 0.4 * m2 * R2 * R2) if I2 is None else I2
    delta_e = (15.0 * M_star * v_n ** 2 / (16.0 * E_star * math.sqrt(R_star))) ** 0.4
    t_e = delta_e / v_n
    model = _Model(dict(plane=plane, R1=R1, m1=m1, R2=(0.0 if plane else R2), m2=m2, I1=I1, I2=I2,
                        E_star=E_star, G_star=G_star, R_star=R_star, M_star=M_star, eta=eta, clipped=clipped,
                        mu=mu, form=form, k_t0=k_t0, x_t=x_t, v_n=v_n, v_t=v_t, w1=w1, t_e=t_e,
                        v_s0=v_t + R1 * w1, young_1=young_1, young_2=young_2))
    V = math.hypot(v_n, v_t + R1 * w1)
    F_e = model.k_n * delta_e ** 1.5
    H_scale = V * t_e if form.history == "displacement" else F_e
    scale = [delta_e, v_n, V, V / R1, V, V / (R1 if plane else R2), H_scale]
    if not plane:  # the line of centres' angle [rad]: it turns by ~ V t_e / (R1 + R2)
        scale.append(V * t_e / (R1 + R2))
    scale = np.array(scale)
    return _integrate(model, scale, t_e, delta_e)


# --- the pieces: three independent variables, one physical state --------------------------------

def _to_phys(kind, w, Y, scale, t_e, delta_e):
    """(t, y) from the piece's variable w and scaled state Y."""
    if kind == "s":
        return t_e * w * w, Y * scale
    if kind == "t":
        return t_e * w, Y * scale
    y = Y * scale
    t = Y[0] * t_e
    y[0] = delta_e * w * w
    return t, y


def _from_phys(kind, t, y, scale, t_e, delta_e):
    """(w, Y) of the piece from (t, y)."""
    Y = y / scale
    if kind == "s":
        return math.sqrt(t / t_e), Y
    if kind == "t":
        return t / t_e, Y
    Y[0] = t / t_e
    return math.sqrt(max(y[0], 0.0) / delta_e), Y


def _integrate(model: _Model, scale, t_e, delta_e) -> ObliqueResult:
    sliding, s = model.first_phase()
    phases = [("slip" if sliding else "stick", 0.0)]
    kind, t = "s", 0.0
    y = np.array([0.0, model.v_n, model.v_t, model.w1, 0.0, 0.0, 0.0] + ([] if model.plane else [0.0]))
    delta_max = math.nan
    T_F0 = math.nan
    fn_crossed = model.eta == 0.0  # the force zero is an event only with a dissipative term
    capless = grace = switched = False
    chatter = 0
    F_e = model.k_n * delta_e ** 1.5
    pieces = []  # (kind, sol, sliding, s, w0, w1) for the maxima

    for _ in range(MAX_PIECES):
        w0, Y0 = _from_phys(kind, t, y, scale, t_e, delta_e)
        mode = (sliding, s)

        def phys(w, Y, kind=kind):
            return _to_phys(kind, w, Y, scale, t_e, delta_e)

        def rhs(w, Y, kind=kind, mode=mode):
            tt, yy = phys(w, Y)
            dy = model.rates(yy, *mode)
            if kind == "s":
                return 2.0 * w * t_e * dy / scale
            if kind == "t":
                return t_e * dy / scale
            dt_du = 2.0 * w * delta_e / yy[1]
            out = dy * dt_du / scale
            out[0] = dt_du / t_e
            return out

        events, names = [], []

        def add(name, fun, direction=-1.0):
            def ev(w, Y):
                return fun(*phys(w, Y))
            ev.terminal, ev.direction = True, direction
            events.append(ev)
            names.append(name)

        if capless or grace:
            pass
        elif sliding:
            add("stick", lambda tt, yy, s=s: model.slip_margin(yy, s))
        else:
            add("slip", lambda tt, yy: model.stick_margin(yy))
        if not fn_crossed:
            add("F0", lambda tt, yy: model.local(yy, *mode)["F_raw"])
        if kind in ("s", "t") and math.isnan(delta_max):
            add("max", lambda tt, yy: yy[1])
        if kind == "t" and not math.isnan(delta_max):
            add("handover", lambda tt, yy: yy[0] - DELTA_HANDOVER * delta_max)
        w_end = {"s": math.sqrt(T_HANDOVER), "t": 1e3, "u": 0.0}[kind]
        if grace:
            w_end = w0 + math.copysign(GRACE, w_end - w0)
        sol = solve_ivp(rhs, (w0, w_end), Y0, method="DOP853", rtol=RTOL, atol=ATOL, events=events,
                        dense_output=True)
        if sol.status == -1:
            raise RuntimeError(f"solve_oblique: the integration failed ({sol.message})")
        fired = [(sol.t_events[i][0], names[i], sol.y_events[i][0]) for i in range(len(events))
                 if len(sol.t_events[i])]
        pieces.append((kind, sol.sol, sliding, s, w0, sol.t[-1]))
        # Every margin vanishes with delta, and may fire at u = 0 itself, or chatter just before it
        # (X and C both -> 0): transitions within the last U_END^2 delta_e of the overlap are not
        # followed; the forces there are < ~U_END F_e over ~U_END^2 t_e, an impulse < 1e-18 F_e t_e.
        fired = [e for e in fired if not (kind == "u" and e[0] <= U_END)]
        if not fired and kind == "u" and sliding and not (capless or grace):
            fired = _stick_hidden_by_the_end(model, sol.sol, s, phys, w0)
        if not fired:
            t, y = phys(sol.t[-1], sol.y[:, -1])
            if grace:
                grace, switched = False, False
                continue
            if kind == "s":
                kind = "t"
                continue
            if kind == "t":
                raise RuntimeError("solve_oblique: the overlap did not return")
            break  # u = 0: delta is back to zero
        w_ev, name, Y_ev = min(fired, key=lambda e: abs(e[0] - w0))
        if name in ("slip", "stick") and switched and abs(w_ev - w0) <= 1e-12 * max(1.0, abs(w0)):
            # The phase just entered wants to leave at once: at a transition both C^2 - X^2 and the
            # slide's margin start at zero with zero slope, so round-off can fire them. The phase
            # is kept for GRACE without its exit event; a true chatter (no continuous limit: a
            # Filippov slide on the cap, e.g. a damping that switches off with the slide) repeats,
            # and is refused (at once where F_t jumps at a transition: no round-off zero there).
            chatter += 1
            if chatter > MAX_CHATTER or model.force_jumps:
                raise RuntimeError(f"solve_oblique: stick/slip chatter at t = {t:.12g} s: the model has no "
                                   "continuous limit there (the contact would slide along the cap with a "
                                   "force neither phase gives)")
            grace = True
            continue
        switched = name in ("slip", "stick")
        if not switched:
            chatter = 0
        t, y = phys(w_ev, Y_ev)
        at_f0 = name == "F0"
        if name in ("slip", "stick") and not fn_crossed and abs(model.local(y, sliding, s)["F_raw"]) <= F0_TOUCH * F_e:
            # a transition at the normal force's zero (the kink of C there, |F_n| or max(F_n, 0), can
            # make one): F0's own event, a few ulp later, would now be lost, so F0 is this point too
            at_f0 = True
            if model.capless_after_f0:
                name = "F0"
        if at_f0:
            fn_crossed, T_F0 = True, t
        if at_f0 and model.reopens_after_f0:
            # C = mu |F_n| is 0 here and grows again: the phase after is decided afresh, as at
            # touching (module docstring, "The normal force's zero"); whatever fired here, a slide's
            # exit event could not (its margin jumps to < 0 at the zero, it does not cross it)
            new_sliding, new_s = model.phase_at_f0(y)
            if new_sliding != sliding:
                if not new_sliding:
                    y = y.copy()
                    y[6] = model.history_at(y, True, s)
                phases.append(("slip" if new_sliding else "stick", t))
            switched = (new_sliding, new_s) != (sliding, s)
            sliding, s = new_sliding, new_s
        elif name == "F0":
            if model.capless_after_f0:
                # C = 0 from here to the end: the contact slides, with F_t = 0 (total cap) or the
                # damping alone (elastic cap) whatever the direction, and no transition is left
                if not sliding:
                    phases.append(("slip", t))
                sliding, s, capless = True, (s or 1.0), True
        elif name == "slip":
            q = model.local(y, False, 0.0)
            sliding, s = True, math.copysign(1.0, q["X"])
            phases.append(("slip", t))
        elif name == "stick":
            y = y.copy()
            y[6] = model.history_at(y, True, s)
            sliding, s = False, 0.0
            phases.append(("stick", t))
        elif name == "max":
            delta_max, kind = y[0], "t"
        elif name == "handover":
            kind = "u"
    else:
        raise RuntimeError(f"solve_oblique: more than {MAX_PIECES} pieces (a chattering stick/slip?)")

    T_x0 = t
    if math.isnan(T_F0):
        T_F0 = T_x0
    if sliding:  # the history of a slide is where the cap holds it (undefined for xi when k_t = 0)
        y = y.copy()
        y[6] = model.history_at(y, True, s) if model.local(y, True, s)["k_t"] > 0 else math.nan
    vy1, w1, vy2, w2 = y[2:6]
    if model.plane:
        vn_after = -y[1]
    else:  # the lab frame: n = (cos phi, sin phi), t = (-sin phi, cos phi)
        c, s_ = math.cos(y[7]), math.sin(y[7])
        v_cm_n = model.vcm[0] * c + model.vcm[1] * s_
        vn1, vn2 = v_cm_n + model.share1 * y[1], v_cm_n - model.share2 * y[1]
        vn_after = -((vn1 - vn2) * c - (vy1 - vy2) * s_)  # -(v1 - v2).x
        vy1, vy2 = vn1 * s_ + vy1 * c, vn2 * s_ + vy2 * c
    eps = vn_after / model.v_n
    R2 = 0.0 if model.plane else model.R2
    v_s_after = (vy1 + model.R1 * w1) - (vy2 - R2 * w2)
    e_t = v_s_after / model.v_s0 if model.v_s0 != 0.0 else math.nan
    F_max, Ft_max = _maxima(model, pieces, scale, t_e, delta_e)
    phases = tuple((name, float(t)) for name, t in phases)
    return ObliqueResult(T=float(T_F0 if model.clipped else T_x0), T_x0=float(T_x0), T_F0=float(T_F0),
                         eps=float(eps), delta_max=float(delta_max), F_max=float(F_max), vt_after=float(vy1),
                         omega_after=float(w1), vt2_after=float(vy2), omega2_after=float(w2), e_t=float(e_t),
                         rebound_angle=math.degrees(math.atan2(v_s_after, eps * model.v_n)), Ft_max=float(Ft_max),
                         phases=phases, history_after=float(y[6]),
                         turn_after=0.0 if model.plane else float(y[7]))


def _stick_hidden_by_the_end(model, sol, s, phys, w0) -> list:
    r"""A slide's end that the last piece's event could not see: [(u, "stick", Y)] or [].

    The slide's margin is scaled by delta^{1/2} (`_Model.slip_margin`), so it is exactly 0 at
    u = 0, the end of the overlap. Where it crosses zero downwards within the last solver step
    before u = 0 (+ at the step's start, - inside it, 0 at its end), the event function is >= 0 at
    both ends of that step and the crossing is hidden; the only zero seen is u = 0 itself, which
    `_integrate` discards (U_END). A linear spring (k_t constant) under a cap C = mu F_n that falls
    as delta^{1/2} d(delta)/dt meets this whenever the slip has reversed under the slide: the
    margin is delta^{1/2} (k_t |v_s| s' - |dC/dt|) with s' = -s sign(v_s), and |dC/dt| -> 0 with
    delta while k_t |v_s| does not, so the contact must stick before the end (Chung & Ooi test 6 at
    5.49 rad/s: the margin turns negative at delta ~ 1e-2 delta_e). The margin is therefore read on
    the dense output at u = U_END, where delta^{1/2} > 0 leaves its sign: if it is negative there,
    the first sign change on a grid of SAMPLES points from the piece's start is refined by Brent
    (4 ulp, as solve_ivp's events) and returned as the slide's exit.

    Parameters
    ----------
    model : _Model
        The collision.
    sol : callable
        The piece's dense output, Y(u) [scaled state].
    s : float
        The slide's sign (+1 or -1).
    phys : callable
        (u, Y) -> (t [s], y), the piece's map to the physical state.
    w0 : float
        The piece's start u = sqrt(delta/delta_e) [-] (> U_END).

    Returns
    -------
    list
        [(u, "stick", Y(u))] where the slide ends, else [].
    """
    def margin(w):
        return model.slip_margin(phys(w, sol(w))[1], s)

    if not margin(U_END) < 0.0:
        return []
    grid = np.linspace(w0, U_END, SAMPLES)
    values = [margin(w) for w in grid]
    i = next(k for k, v in enumerate(values) if v < 0.0)
    if i == 0:
        return [(w0, "stick", sol(w0))]
    eps4 = 4.0 * np.finfo(float).eps
    w = brentq(margin, grid[i], grid[i - 1], xtol=eps4, rtol=eps4)
    return [(w, "stick", sol(w))]


def _maxima(model, pieces, scale, t_e, delta_e) -> tuple[float, float]:
    """max F_n and max |F_t| [N] over the pieces' dense outputs (two spheres: of the lab frame's
    components, `_Model.lab_forces`): every local maximum of SAMPLES points a piece is refined by
    bounded Brent within its neighbours, and the largest refined value is taken. Refining only the
    best sample picked the lower of two near-equal peaks in different pieces (a linear spring's
    tangential oscillation, Chung & Ooi test 8 at 0.175 rad/s: the samples' 506.96 N of the
    second peak against 506.59 N of the first, whose refined top, 507.116 N, is the maximum; the
    second's is 507.077 N, 7.7e-5 lower)."""

    def value(piece, w, which):
        kind, sol, sliding, s, _, _ = piece
        _, y = _to_phys(kind, w, sol(w), scale, t_e, delta_e)
        q = model.local(y, sliding, s)
        return model.lab_forces(y, q)[0 if which == "n" else 1]

    def refined(piece, grid, vals, j, which):
        top = vals[j]
        lo, hi = grid[max(j - 1, 0)], grid[min(j + 1, len(grid) - 1)]
        if lo != hi:
            lo, hi = min(lo, hi), max(lo, hi)
            res = minimize_scalar(lambda w: -value(piece, w, which), bounds=(lo, hi), method="bounded",
                                  options={"xatol": 1e-13 * max(abs(lo), abs(hi), 1e-300)})
            top = max(top, -res.fun)
        return top

    best = []
    for which in ("n", "t"):
        top = -math.inf
        for piece in pieces:
            grid = np.linspace(piece[4], piece[5], SAMPLES)
            vals = [value(piece, w, which) for w in grid]
            n = len(vals)
            # every sample not below its neighbours: the best one alone can be the lower peak
            for j in range(n):
                if vals[j] >= vals[max(j - 1, 0)] and vals[j] >= vals[min(j + 1, n - 1)]:
                    top = max(top, refined(piece, grid, vals, j, which))
        best.append(top)
    return best[0], best[1]


def rigid_body_sliding(v_n: float, eps_n: float, mu: float, R: float, m: float, I: float, *, v_s: float = 1.0,
                       R2: float = math.inf, m2: float = math.inf, I2: float = math.inf) -> dict:
    r"""The changes of velocity of a contact that slides throughout (closed form, rigid bodies).

    The normal impulse is J_n = (1 + eps_n) M* v_n [N s] with M* = m m2/(m + m2) (M* = m on a
    plane), the tangential one J_t = -mu J_n sign(v_s) (against the slip), applied at arm R:
    body 1 gains dv = J_t/m, dw = R J_t/I; body 2 dv_2 = -J_t/m_2, dw_2 = R_2 J_t/I_2. For a solid
    sphere (I = (2/5) m R^2) on a plane: |dv| = mu (1 + eps_n) v_n, |dw| = (5/2) mu (1 + eps_n) v_n/R.

    Parameters
    ----------
    v_n : float
        Normal approach velocity [m/s].
    eps_n : float
        Normal restitution [-].
    mu : float
        Friction coefficient [-].
    R, m, I : float
        Body 1's radius (the arm) [m], mass [kg] and moment of inertia [kg m^2].
    v_s : float, optional
        The slip velocity [m/s]; only its sign is used.
    R2, m2, I2 : float, optional
        Body 2's radius [m], mass [kg] and moment of inertia [kg m^2] (``math.inf``: a plane).

    Returns
    -------
    dict of str to float
        ``dv1``, ``dw1``, ``dv2``, ``dw2`` [m/s, rad/s], the impulses ``J_n``, ``J_t`` [N s], and
        ``dv_s`` [m/s], the change of the slip velocity (arms R and R2).
    """
    M = m if math.isinf(m2) else m * m2 / (m + m2)
    J_n = (1.0 + eps_n) * M * v_n
    J_t = -math.copysign(mu * J_n, v_s)
    dv1, dw1 = J_t / m, R * J_t / I
    dv2 = 0.0 if math.isinf(m2) else -J_t / m2
    dw2 = 0.0 if math.isinf(I2) else R2 * J_t / I2
    dv_s = dv1 + R * dw1 - dv2 + (0.0 if math.isinf(R2) else R2 * dw2)
    return dict(dv1=dv1, dw1=dw1, dv2=dv2, dw2=dw2, J_n=J_n, J_t=J_t, dv_s=dv_s)
