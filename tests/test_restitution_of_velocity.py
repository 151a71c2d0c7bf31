"""analysis.restitution_of_velocity: each damping form fitted to eps(V) recovers the coefficient
of measurements made by its own law, and only a form with the measured trend is said to follow."""

import numpy as np
import pytest

from analysis.restitution_of_velocity import fit_forms, form_restitution

V = np.array([0.5, 1.0, 1.64, 2.04, 2.83, 3.51, 4.43, 5.47, 6.01])


def test_measurements_of_the_viscoelastic_law_are_followed_by_it_alone():
    eps = form_restitution("half", "F0", 0.17, V)
    fits = fit_forms(V, eps).set_index(["form", "criterion"])
    assert fits.loc[("half", "F0"), "value"] == pytest.approx(0.17, rel=1e-6)
    assert fits.loc[("half", "F0"), "rms_residual"] < 1e-8 and fits.loc[("half", "F0"), "R2"] > 1 - 1e-10
    assert fits.loc[("half", "F0"), "follows"] and fits.loc[("half", "x0"), "follows"]  # the two ends differ little
    assert not fits.loc[("quarter", "any"), "follows"] and fits.loc[("quarter", "any"), "R2"] == pytest.approx(0.0)
    assert fits.loc[("quarter", "any"), "value"] == pytest.approx(eps.mean(), rel=1e-15)
    assert not fits.loc[("velocity", "x0"), "follows"] and fits.loc[("velocity", "x0"), "R2"] < 0  # wrong trend


def test_a_restitution_that_rises_with_velocity_is_a_dashpots():
    eps = form_restitution("velocity", "x0", 0.2, V)
    assert np.all(np.diff(eps) > 0)  # c ~ V^(-1/5): less damping the faster
    fits = fit_forms(V, eps).set_index(["form", "criterion"])
    assert fits.loc[("velocity", "x0"), "value"] == pytest.approx(0.2, rel=1e-6)
    assert fits.loc[("velocity", "x0"), "follows"]
    assert not fits.loc[("half", "F0"), "follows"] and not fits.loc[("half", "x0"), "follows"]
