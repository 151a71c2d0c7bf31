r"""A step-by-step replay of LAMMPS's granular contact with ``tangential linear_history`` (two
spheres, or a sphere on ``fix wall/gran ... xplane NULL 0.0``), written from the sources (not
copied), in the lab frame with a VECTOR history, for the tests to set beside an engine's record
and beside `reference.solve_oblique`.

What it does each step, in LAMMPS's order (SI units, forces [N], torques [N m]):

- ``fix nve/sphere`` initial_integrate (fix_nve_sphere.cpp): v += (dt/2) f/m, x += dt v,
  w += (dt/2) tau / (0.4 m R^2);
- the contact (lammps@22Jul2025 src/GRANULAR/granular_model.cpp, calculate_forces; the same terms
  in lammps@stable_29Sep2021_update2 src/GRANULAR/pair_granular.cpp:400-560 and
  fix_wall_gran.cpp): n = (x_i - x_j)/|x_i - x_j| (from body j to body i), delta = R_i + R_j - r,
  a = sqrt(R* delta), F_n = k_n a delta (``hertz k_n``, k_n = 4/3 E*; no damping: the elastic
  law); the slip velocity of the contact point v_s = (v_i - v_j)_t - (R_i w_i + R_j w_j) z x n
  (arms R, not R - delta/2); the history xi (a vector in the tangent plane) is projected onto the
  new tangent plane and rescaled to its former magnitude where |xi.n| k_t > 1e-10 mu |F_n|
  (gran_sub_mod_tangential.cpp, GranSubModTangentialLinearHistory::calculate_forces), then
  xi += v_s dt; F_t = -k_t xi; where |F_t| > mu |F_n|: F_t <- mu |F_n| F_t/|F_t| and
  xi = -F_t/k_t (the reset, no damping here); the force on i is F_n n + F_t, on j the opposite;
  the torques -(L_i) n x F_t on i and -(L_j) n x F_t on j with L = R - delta/2 for a pair and
  L = R at the wall;
- final_integrate: v += (dt/2) f/m, w += (dt/2) tau / (0.4 m R^2); then ``fix print`` writes
  the record (engines' decks: oblique_two_spheres.in, oblique_sphere_plane.in).

`replay` returns the deck's record columns, so that a test compares them row by row.
"""

from __future__ import annotations

import math

import numpy as np

#: LAMMPS's threshold of the history's frame update (gran_sub_mod_tangential.cpp: EPSILON).
EPSILON = 1e-10


def replay(variables: dict, geometry: str, kn: float, kt: float, mu: float, steps: int | None = None) -> dict:
    r"""The record of a LAMMPS oblique deck with ``tangential linear_history``, replayed.

    Parameters
    ----------
    variables : dict
        The deck's variables (a dump's ``engine_variables``): R1, rho1, x1, y1, v1, vy1, w1, dt,
        steps, and for two spheres R2, rho2, x2, y2, v2, vy2, w2 (SI, as strings or numbers).
    geometry : str
        ``"sphere-sphere"`` or ``"sphere-plane"`` (the wall at x = 0, the sphere at x < 0).
    kn : float
        ``hertz`` k_n = 4/3 E* [Pa]: F_n = k_n sqrt(R* delta) delta [N].
    kt : float
        ``linear_history`` k_t [N/m] (constant).
    mu : float
        Friction coefficient [-].
    steps : int, optional
        Steps to run (default: the deck's).

    Returns
    -------
    dict
        Arrays per recorded step (step 0 included), the deck's columns: time [s], overlap [m],
        normal_velocity vx1 - vx2 [m/s], normal_force (x force on body 2; -fx on body 1 at the
        wall) [N], tangential_velocity vy1 - vy2 [m/s], omega_1, omega_2 [rad/s],
        tangential_force (fy on body 1) [N].
    """
    g = {k: float(v) for k, v in variables.items() if k not in ("grid", "pair", "model", "wall")}
    dt = g["dt"]
    n_steps = int(g["steps"]) if steps is None else steps
    pair = geometry == "sphere-sphere"
    R1 = g["R1"]
    m1 = g["rho1"] * 4.0 / 3.0 * math.pi * R1 ** 3
    I1 = 0.4 * m1 * R1 * R1
    x1, y1, vx1, vy1, w1 = g["x1"], g["y1"], g["v1"], g["vy1"], g["w1"]
    if pair:
        R2 = g["R2"]
        m2 = g["rho2"] * 4.0 / 3.0 * math.pi * R2 ** 3
        I2 = 0.4 * m2 * R2 * R2
        x2, y2, vx2, vy2, w2 = g["x2"], g["y2"], g["v2"], g["vy2"], g["w2"]
    else:
        R2, m2, I2 = 0.0, math.inf, math.inf
        x2 = y2 = vx2 = vy2 = w2 = 0.0
    R_star = R1 * R2 / (R1 + R2) if pair else R1
    hx = hy = 0.0  # the history vector xi [m], of body 1 against body 2
    touching = False
    f1x = f1y = t1 = t2 = 0.0
    rows = np.zeros((n_steps + 1, 8))

    def record(step, overlap):
        # the deck's columns: the force on body 2 is -f1 (two spheres), the wall's is -fx[1]
        rows[step] = (step * dt, overlap, vx1 - vx2, -f1x, vy1 - vy2, w1, w2, f1y)

    def overlap_now():
        return R1 + R2 - math.hypot(x1 - x2, y1 - y2) if pair else R1 + x1

    record(0, overlap_now())
    h = 0.5 * dt
    for step in range(1, n_steps + 1):
        vx1 += h * f1x / m1
        vy1 += h * f1y / m1
        x1 += dt * vx1
        y1 += dt * vy1
        w1 += h * t1 / I1
        if pair:
            vx2 -= h * f1x / m2
            vy2 -= h * f1y / m2
            x2 += dt * vx2
            y2 += dt * vy2
            w2 += h * t2 / I2
        f1x = f1y = t1 = t2 = 0.0
        # n from body 2 (j) to body 1 (i); the wall's point is (0, y1)
        dx, dy = (x1 - x2, y1 - y2) if pair else (x1, 0.0)
        r = math.hypot(dx, dy)
        delta = R1 + R2 - r
        if delta > 0.0:
            touching = True
            nx, ny = dx / r, dy / r
            F_n = kn * math.sqrt(R_star * delta) * delta
            vrx, vry = vx1 - vx2, vy1 - vy2
            vnn = vrx * nx + vry * ny
            wr = R1 * w1 + R2 * w2
            # v_s = v_t - (wr z) x n = v_t - wr (-n_y, n_x)
            vsx = vrx - vnn * nx + wr * ny
            vsy = vry - vnn * ny - wr * nx
            cap = mu * abs(F_n)
            rsht = hx * nx + hy * ny
            if abs(rsht) * kt > EPSILON * cap:  # the frame update: project, keep the magnitude
                mag = math.hypot(hx, hy)
                hx, hy = hx - rsht * nx, hy - rsht * ny
                prj = math.hypot(hx, hy)
                scale = mag / prj if prj > 0.0 else 0.0
                hx, hy = hx * scale, hy * scale
            hx += vsx * dt
            hy += vsy * dt
            ftx, fty = -kt * hx, -kt * hy
            mag = math.hypot(ftx, fty)
            if mag > cap:
                if math.hypot(hx, hy) != 0.0:
                    ftx, fty = ftx * cap / mag, fty * cap / mag
                    hx, hy = -ftx / kt, -fty / kt
                else:
                    ftx = fty = 0.0
            f1x, f1y = F_n * nx + ftx, F_n * ny + fty
            nxf = nx * fty - ny * ftx  # (n x F_t).z
            t1 = -(R1 - 0.5 * delta if pair else R1) * nxf
            t2 = -(R2 - 0.5 * delta) * nxf if pair else 0.0
        elif touching:
            hx = hy = 0.0  # the contact is gone, and its history with it
        vx1 += h * f1x / m1
        vy1 += h * f1y / m1
        w1 += h * t1 / I1
        if pair:
            vx2 -= h * f1x / m2
            vy2 -= h * f1y / m2
            w2 += h * t2 / I2
        record(step, delta)
    names = ("time", "overlap", "normal_velocity", "normal_force", "tangential_velocity", "omega_1", "omega_2",
             "tangential_force")
    return {name: rows[:, i] for i, name in enumerate(names)}
