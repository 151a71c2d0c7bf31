"""The yardstick: a high-accuracy solution of the dimensionless viscoelastic Hertz collision
(the paper's eq. 2) and the series in K, the paper's and the project's own."""

from .closed_forms import FIRST_ORDER, FIRST_ORDER_INTEGRAL, HERTZ_TAU, K_PREFACTOR
from .collision_ode import CollisionTable, collision_trajectory, solve_collision, solve_collisions
from .series import compare_with_paper, hertz_ratios, paper_series_value, taylor_coefficients

__all__ = [
    "FIRST_ORDER", "FIRST_ORDER_INTEGRAL", "HERTZ_TAU", "K_PREFACTOR",
    "CollisionTable", "collision_trajectory", "solve_collision", "solve_collisions",
    "compare_with_paper", "hertz_ratios", "paper_series_value", "taylor_coefficients",
]
