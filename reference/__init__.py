"""The yardstick: a high-accuracy solution of the dimensionless viscoelastic Hertz collision
(the paper's eq. 2) and the series in K, the paper's and the project's own; and the tangential half,
one oblique collision with friction and rotation in a model's own equations (`solve_oblique`)."""

from .closed_forms import FIRST_ORDER, FIRST_ORDER_INTEGRAL, HERTZ_TAU, K_PREFACTOR
from .collision_ode import CollisionTable, collision_trajectory, solve_collision, solve_collisions
from .oblique_collision import ObliqueResult, rigid_body_sliding, solve_oblique
from .series import compare_with_paper, hertz_ratios, paper_series_value, taylor_coefficients
from .tangential_forms import TangentialForm

__all__ = [
    "FIRST_ORDER", "FIRST_ORDER_INTEGRAL", "HERTZ_TAU", "K_PREFACTOR",
    "CollisionTable", "collision_trajectory", "solve_collision", "solve_collisions",
    "compare_with_paper", "hertz_ratios", "paper_series_value", "taylor_coefficients",
    "ObliqueResult", "TangentialForm", "rigid_body_sliding", "solve_oblique",
]
