"""A second, independent solution of the collision ODE, at high precision with mpmath.

It shares no code with `reference.collision_ode` and differs from it in every numerical choice:
mpmath's Taylor-series integrator (`mpmath.odefun`) at 30 significant digits instead of
DOP853 in double precision; time tau as the independent variable over the middle of the
contact (x > x_s) instead of the velocity; a different switch point x_s; and events (maximum
compression, force zero) located with `mpmath.findroot` on the tau-solution instead of being
phase end points or Chandrupatla roots. Only the two ends, where x^{1/2} is singular, use the
same idea (u = sqrt(x) as independent variable), written here afresh.
"""

import mpmath as mp


def solve_high_precision(K, x_switch="0.02", dps=30):
    """Return x_max, tau_max, tau_f, eps_F0, tau_0, eps_x0 as mpf for one K (>0, F0 in the middle phase)."""
    with mp.workdps(dps):
        K = mp.mpf(K)
        xs = mp.mpf(x_switch)
        us = mp.sqrt(xs)

        # Approach: u = sqrt(x) from 0 to u_s; y = (v, tau).
        def near_contact(u, y):
            v = y[0]
            return [-2 * K * u**2 - mp.mpf(5) / 2 * u**4 / v, 2 * u / v]

        v1, t1 = mp.odefun(near_contact, 0, [mp.mpf(1), mp.mpf(0)])(us)

        # Middle: tau from t1; y = (x, v).
        def middle(t, y):
            x, v = y
            return [v, -mp.sqrt(x) * (K * v + mp.mpf(5) / 4 * x)]

        mid = mp.odefun(middle, t1, [xs, v1])
        tau_max = mp.findroot(lambda t: mid(t)[1], t1 + mp.mpf("1.3"))
        x_max = mid(tau_max)[0]
        # First zero of the force after the maximum: scan forward, then refine.
        t, dt = tau_max, mp.mpf("0.05")
        while (lambda y: mp.mpf(5) / 4 * y[0] + K * y[1])(mid(t + dt)) > 0:
            t += dt
        tau_f = mp.findroot(lambda s: mp.mpf(5) / 4 * mid(s)[0] + K * mid(s)[1], (t, t + dt),
                            solver="anderson")
        eps_F0 = -mid(tau_f)[1]
        # Return to x_s: Newton steps that never overshoot into x < 0 (where sqrt(x) is complex).
        t2 = tau_f
        for _ in range(200):
            x, v = mid(t2)
            step = (x - xs) / -v
            t2 += step if abs(step) < (x - xs / 2) / -v else (x - xs / 2) / -v
            if abs(step) < mp.mpf(10) ** (-dps + 3):
                break
        v2 = mid(t2)[1]

        # Separation: w = u_s - u from 0 to u_s (odefun integrates forward); y = (v, tau).
        def separation(w, y):
            u, v = us - w, y[0]
            return [2 * K * u**2 + mp.mpf(5) / 2 * u**4 / v, -2 * u / v]

        v_end, tau_0 = mp.odefun(separation, 0, [v2, t2])(us)
        return dict(x_max=x_max, tau_max=tau_max, tau_f=tau_f, eps_F0=eps_F0,
                    tau_0=tau_0, eps_x0=-v_end)
