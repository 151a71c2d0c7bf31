r"""The engines' discrete map of an oblique collision of a sphere on a plane, replayed at a given dt.

`reference.engine_map` is the head-on collision's map; this is the same map with the tangential
half of any `reference.TangentialForm` added, in SI units, as LAMMPS's ``fix nve/sphere`` and
granular pair style order it (velocity Verlet, the forces from the positions and the half-step
velocities). One step, dt [s], state (delta, v_n, v_y, w, H) with the velocities at the half step:

    half kick     v_n -= F_n/m dt/2;  v_y += F_t/m dt/2;  w += L_t F_t/I dt/2   (last step's forces)
    drift         delta += v_n dt
    forces        a = sqrt(R* delta); F_n = k_n delta^{3/2} + 2 eta a v_n (clipped: max(F_n, 0));
                  v_s = v_y + L_s w; the history H (xi or F_h) rescaled by a/a_prev where a fell
                  (``rescale``), advanced as if sticking (xi += v_s dt, F_h -= k_t v_s dt), and
                  capped and reset (`reference.tangential_forms.cap_force`, written inline here)
    half kick     with the new forces

where delta > 0; elsewhere no force acts and the history is 0 (an engine drops a contact's history
when it ends). L_s, L_t are the arms of `TangentialForm.lever_slip` and ``lever_torque`` at the
overlap of the force evaluation. The normal half is `reference.engine_map`'s map exactly: the two
half kicks make one kick by dt F_n(delta_n, v_{n-1/2}) between half-step velocities.

The contact starts ``start_phase`` of a step after sample ``gap_steps``: body 1 starts at overlap
-(gap_steps + start_phase) v_n dt and moves freely until it touches, at (gap_steps + start_phase)
dt. The contact time is read on the map's own trajectory: between samples an engine moves the
centre at the half-step velocity, so the overlap is linear there, and T_x0 is where that line
crosses zero after the contact, less the touching time. T_F0 is where the unclipped normal force,
linear between the samples it is evaluated at, first falls to zero (T_x0 where it does not before
the overlap returns). After separation no force acts, so the velocities left are final: eps =
-v_n'/v_n, v_t' = v_y', omega' = w', e_t = v_s'/v_s with every arm R (delta = 0), and the rebound
angle atan2(v_s', eps v_n) [deg], as `reference.solve_oblique` defines them.

Only the sphere on a plane: two spheres are free bodies whose line of centres turns while they
slide (`reference.oblique_collision`, "Two spheres"), which a map with a fixed normal would not
follow; their map is not written yet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from .tangential_forms import TangentialForm, lever_base, lever_share

#: The codes of `TangentialForm.cap_normal` and `TangentialForm.damping` in the compiled loop.
_CAP_NORMAL = {"total_abs": 0, "total_clipped": 1, "elastic": 2}
_DAMPING = {"none": 0, "normal_xt": 1, "stick_only": 2}


@dataclass(frozen=True)
class ObliqueMapResult:
    """One oblique collision of the discrete map (`oblique_map`), SI units.

    Attributes
    ----------
    T : float
        Contact time [s] under the law's criterion: T_F0 when clipped, T_x0 when not.
    T_x0, T_F0 : float
        When the overlap, and the unclipped normal force, return to zero, from touching [s].
    eps : float
        Normal restitution -v_n'/v_n [-].
    vt_after : float
        Body 1's centre velocity along +y after the contact [m/s].
    omega_after : float
        Body 1's spin about +z after the contact [rad/s].
    e_t : float
        Tangential restitution of the contact point v_s'/v_s [-] (nan without initial slip).
    rebound_angle : float
        atan2(v_s', eps v_n) [deg].
    steps : int
        The steps the map took [-], from the start to the overlap's return.
    """

    T: float
    T_x0: float
    T_F0: float
    eps: float
    vt_after: float
    omega_after: float
    e_t: float
    rebound_angle: float
    steps: int


@numba.njit(cache=True)
def _advance(p, flags, start, max_steps):
    """The map's steps from overlap `start` [m] to the overlap's return (see the module docstring).

    p: m, I, R, k_n, c_eta (2 eta sqrt(R*)), sqrt(R*), k_t0, x_t, mu, dt, v_n, v_t, w1, share_slip,
    share_torque, base_slip, base_torque (the arms b R - s delta, `reference.tangential_forms.lever`);
    flags: clipped, force history, mindlin stiffness, rescale, total cap, cap_normal code, damping code.
    Returns (steps, t_exit, t_F0, v_n', v_y', w') with t from the start [s]
    (t_F0 < 0: the unclipped force did not fall to zero while in contact); steps = -1 where the
    overlap did not return within `max_steps`."""
    m, I, R, kn, c_eta, sqrt_rs, kt0, x_t, mu, dt, vn, vy, w, sh_s, sh_t = (
        p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14])
    R_s, R_t = p[15] * R, p[16] * R  # b R: R, or 0 where the arm is "none"
    clipped, hist_force, mindlin, rescale, cap_total, cap_normal, damping = (
        flags[0], flags[1], flags[2], flags[3], flags[4], flags[5], flags[6])
    d = start
    v = vn  # the normal rate d(delta)/dt, at the half step
    H = 0.0
    a_prev = 0.0
    Fn = 0.0
    Ft = 0.0
    arm_t = R_t
    touched = False
    f_prev = 0.0
    t_f0 = -1.0
    for n in range(1, max_steps + 1):
        # first half kick, with the forces (and torque arm) of the last evaluation
        v -= Fn / m * dt * 0.5
        vy += Ft / m * dt * 0.5
        w += arm_t * Ft / I * dt * 0.5
        d_old = d
        d += v * dt
        if d <= 0.0:
            Fn = 0.0
            Ft = 0.0
            H = 0.0
            a_prev = 0.0
            if touched:  # the overlap is back: linear between the samples (the drift)
                t_exit = (n - 1 + d_old / (d_old - d)) * dt
                return n, t_exit, t_f0, v, vy, w
            continue
        touched = True
        rd = math.sqrt(d)
        a = sqrt_rs * rd
        Fe = kn * d * rd
        F_raw = Fe + c_eta * rd * v
        if t_f0 < 0.0 and f_prev > 0.0 and F_raw <= 0.0:
            t_f0 = (n - 1 + f_prev / (f_prev - F_raw)) * dt
        f_prev = F_raw
        Fn = max(F_raw, 0.0) if clipped else F_raw
        if cap_normal == 0:
            Fc = abs(Fn)
        elif cap_normal == 1:
            Fc = max(Fn, 0.0)
        else:
            Fc = Fe
        kt = kt0 * a if mindlin else kt0
        vs = vy + (R_s - sh_s * d) * w
        if rescale and a < a_prev:
            H *= a / a_prev
        a_prev = a
        if hist_force:
            H -= kt * vs * dt
        else:
            H += vs * dt
        eta_t = 0.0 if damping == 0 else x_t * c_eta * rd
        # cap_force: the trial force, Coulomb's cap, the history reset to match
        F_el = H if hist_force else -kt * H
        cap = mu * Fc
        if cap_total:
            trial = F_el - eta_t * vs
            if abs(trial) <= cap:
                Ft = trial
            else:
                Ft = math.copysign(cap, trial)
                H = (Ft + eta_t * vs) if hist_force else -(Ft + eta_t * vs) / kt
        elif abs(F_el) <= cap:
            Ft = F_el - eta_t * vs
        else:
            F_el = math.copysign(cap, F_el)
            Ft = F_el - (0.0 if damping == 2 else eta_t) * vs
            H = F_el if hist_force else -F_el / kt
        arm_t = R_t - sh_t * d
        # second half kick
        v -= Fn / m * dt * 0.5
        vy += Ft / m * dt * 0.5
        w += arm_t * Ft / I * dt * 0.5
    return -1, 0.0, -1.0, v, vy, w


def oblique_map(*, geometry: str = "sphere-plane", R1: float, m1: float, E_star: float, G_star: float,
                R_star: float, eta: float, clipped: bool, mu: float, form: TangentialForm, v_n: float, v_t: float,
                dt: float, start_phase: float = 0.5, gap_steps: int = 3, w1: float = 0.0, k_t0: float | None = None,
                x_t: float = 0.0, I1: float | None = None, max_steps: int = 2_000_000) -> ObliqueMapResult:
    r"""One oblique collision of a sphere on a plane as the engines' discrete map gives it at step dt.

    The arguments are `reference.solve_oblique`'s (its ``R2``, ``m2``, ``M_star`` and ``I2`` are
    those of the plane: M* = m1) and the step grid's (module docstring).

    Parameters
    ----------
    geometry : str
        ``"sphere-plane"`` (two spheres are refused: their line of centres turns, module docstring).
    R1, m1 : float
        The sphere's radius [m] and mass [kg].
    E_star, G_star : float
        Effective Young's and shear moduli [Pa].
    R_star : float
        Effective radius [m] (R1 on a plane).
    eta : float
        Effective viscosity [Pa s] of the dissipative term 2 eta a d(delta)/dt (0: elastic).
    clipped : bool
        The normal force clipped at zero (criterion F0), else the attractive tail is kept.
    mu : float
        Friction coefficient [-].
    form : TangentialForm
        The tangential model.
    v_n : float
        Normal approach velocity [m/s], > 0.
    v_t : float
        The sphere's centre velocity along +y at touching [m/s].
    dt : float
        The time step [s].
    start_phase : float
        The contact starts this fraction of a step after sample `gap_steps` [-], in [0, 1).
    gap_steps : int
        Free steps before the contact [-].
    w1 : float, optional
        The sphere's spin about +z at touching [rad/s].
    k_t0 : float, optional
        The tangential stiffness constant: [Pa] for Mindlin (default 8 G*), [N/m] for linear.
    x_t : float, optional
        eta_t / eta_n [-] for the damped forms.
    I1 : float, optional
        The sphere's moment of inertia [kg m^2]; default (2/5) m1 R1^2.
    max_steps : int
        The most steps taken [-]; RuntimeError where the overlap has not returned by then.

    Returns
    -------
    ObliqueMapResult
        T, T_x0, T_F0 [s], eps [-], vt_after [m/s], omega_after [rad/s], e_t [-], rebound_angle
        [deg] and the steps taken.

    Raises
    ------
    ValueError
        For two spheres, a step or a velocity that is not positive, a phase outside [0, 1), or a
        linear stiffness without k_t0.
    RuntimeError
        Where the overlap does not return within `max_steps`.
    """
    if geometry != "sphere-plane":
        raise ValueError(f"oblique_map answers for a sphere on a plane only, got {geometry!r}: two spheres' line of "
                         "centres turns while they slide, which a map with a fixed normal does not follow "
                         "(not written yet)")
    if not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"dt must be positive and finite, got {dt}")
    if not v_n > 0:
        raise ValueError(f"v_n must be > 0 (the sphere approaches), got {v_n}")
    if not 0.0 <= start_phase < 1.0:
        raise ValueError(f"start_phase must lie in [0, 1), got {start_phase}")
    if k_t0 is None:
        if form.stiffness != "mindlin":
            raise ValueError("k_t0 [N/m] is required for a linear tangential stiffness")
        k_t0 = 8.0 * G_star
    I1 = 0.4 * m1 * R1 * R1 if I1 is None else I1
    k_n = 4.0 / 3.0 * E_star * math.sqrt(R_star)
    p = np.array([m1, I1, R1, k_n, 2.0 * eta * math.sqrt(R_star), math.sqrt(R_star), k_t0, x_t, mu, dt, v_n, v_t,
                  w1, lever_share(form.lever_slip), lever_share(form.lever_torque), lever_base(form.lever_slip),
                  lever_base(form.lever_torque)], dtype=np.float64)
    flags = np.array([clipped, form.history == "force", form.stiffness == "mindlin", form.rescale,
                      form.cap == "total", _CAP_NORMAL[form.cap_normal], _DAMPING[form.damping]], dtype=np.int64)
    touch = (gap_steps + start_phase) * dt
    steps, t_exit, t_f0, vn_after, vy, w = _advance(p, flags, -touch * v_n, int(max_steps))
    if steps < 0:
        raise RuntimeError(f"oblique_map: the overlap did not return within {max_steps} steps of {dt:.3g} s")
    T_x0 = t_exit - touch
    T_F0 = t_f0 - touch if t_f0 >= 0 else T_x0
    eps = -vn_after / v_n
    v_s0 = v_t + R1 * w1
    v_s = vy + R1 * w
    return ObliqueMapResult(T=float(T_F0 if clipped else T_x0), T_x0=float(T_x0), T_F0=float(T_F0), eps=float(eps),
                            vt_after=float(vy), omega_after=float(w),
                            e_t=float(v_s / v_s0) if v_s0 != 0.0 else math.nan,
                            rebound_angle=math.degrees(math.atan2(v_s, eps * v_n)), steps=int(steps))
