"""The yardstick: a high-accuracy solution of the dimensionless viscoelastic Hertz collision
(the paper's eq. 2) and the series in K, the paper's and the project's own; and the tangential half,
one oblique collision with friction and rotation in a model's own equations (`solve_oblique`).

The names below are imported from their modules on first use (PEP 562), not when the package is:
`contact_model` reads the closed forms (plain math) from here in every process of the study, an
engine job's too, and should not pay for SciPy's integrators and the oblique solver it never calls
(about 0.5 s of a 1 s start-up, measured with `python -X importtime -c "import contact_model"`).
"""

from importlib import import_module

#: Where each public name lives (module of this package).
_SOURCES = {
    "FIRST_ORDER": "closed_forms", "FIRST_ORDER_INTEGRAL": "closed_forms", "HERTZ_TAU": "closed_forms",
    "K_PREFACTOR": "closed_forms",
    "CollisionTable": "collision_ode", "collision_trajectory": "collision_ode", "solve_collision": "collision_ode",
    "solve_collisions": "collision_ode",
    "ObliqueResult": "oblique_collision", "rigid_body_sliding": "oblique_collision",
    "solve_oblique": "oblique_collision",
    "compare_with_paper": "series", "hertz_ratios": "series", "paper_series_value": "series",
    "taylor_coefficients": "series",
    "TangentialForm": "tangential_forms",
}

__all__ = list(_SOURCES)


def __getattr__(name):
    """The public name `name`, imported from its module (`_SOURCES`) on first use."""
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f".{_SOURCES[name]}", __name__), name)
    globals()[name] = value  # once: the next lookup is the module's own
    return value


def __dir__():
    return sorted(set(globals()) | set(_SOURCES))
