"""Closed-form constants of the Hertz collision and of its first-order dissipative correction.

All are pure numbers (dimensionless). They are computed from Euler's beta function rather than
typed in, so that a test can compare them with the decimal values quoted in the paper.
"""

import math


def beta(a: float, b: float) -> float:
    """Euler's beta function B(a, b) = Gamma(a) Gamma(b) / Gamma(a + b).

    The standard library's gamma gives it to ~5e-16 here (against mpmath), and saves importing
    scipy.special.

    Parameters
    ----------
    a : float
        The first argument, a > 0 [-].
    b : float
        The second argument, b > 0 [-].

    Returns
    -------
    float
        B(a, b) [-].
    """
    return math.gamma(a) * math.gamma(b) / math.gamma(a + b)


#: Dimensionless Hertz collision time, tau_e = T_e V / delta_e = (4/5) B(2/5, 1/2) = 2.94327518432470...
#: It is the time x(tau) of the elastic ODE ``x'' + (5/4) x^{3/2} = 0`` spends at x > 0 when x'(0) = 1.
HERTZ_TAU = float(0.8 * beta(0.4, 0.5))

#: I1 = (2/5) B(3/5, 3/2) = 0.50445489...; the first-order coefficients in K are
#: eps_1 = -2 I1, A_1 = -(4/5) I1, T_1 = I1 / 5.
FIRST_ORDER_INTEGRAL = float(0.4 * beta(0.6, 1.5))

#: alpha = 2 (15/16)^{3/5} = 1.924034...: K = alpha (eta^5 V R* / (M*^2 E*^3))^{1/5}.
K_PREFACTOR = 2.0 * (15.0 / 16.0) ** 0.6

#: First-order Taylor coefficients in K (x0 criterion), from the closed form above.
FIRST_ORDER = {
    "eps": -2.0 * FIRST_ORDER_INTEGRAL,
    "A/A_e": -0.8 * FIRST_ORDER_INTEGRAL,
    "T/T_e": FIRST_ORDER_INTEGRAL / 5.0,
}
