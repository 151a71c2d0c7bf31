"""Compile and cache every numba kernel of the reference once (`make venv`): the solver's
single and batch kernels and the engines' discrete map. Each is `cache=True`, so that a fresh
clone pays the compilation (~15 s) here, not once in every first job or test process.

    python -m reference.warm_up
"""

from . import solve_collision, solve_collisions
from .engine_map import replay


def warm_up() -> None:
    """Call each kernel once, with and without dissipation, clipped and not.

    Returns
    -------
    None
    """
    solve_collision(0.1)
    solve_collisions([0.0, 0.1, 1.0])
    for clipped in (False, True):
        replay(0.1, 0.01, 400, clipped=clipped)


if __name__ == "__main__":
    warm_up()
