"""The Tsuji-type damping of the engines' default laws: velocity-independent restitution, and
LIGGGHTS's mapping from its input e, which is exact under criterion x0."""

import math

import pytest

from contact_model.constant_restitution import (LIGGGHTS_B_PER_BETA, damping_for_restitution,
                                                restitution_of_damping)


def test_no_damping_is_elastic():
    assert restitution_of_damping(0.0) == pytest.approx(1.0, abs=1e-11)


@pytest.mark.parametrize("e", [0.6, 0.8, 0.95])
def test_liggghts_hertz_restitution_is_its_input_under_x0(e):
    beta = -math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi**2)
    b = LIGGGHTS_B_PER_BETA * beta
    assert restitution_of_damping(b, "x0") == pytest.approx(e, abs=1e-9)
    # Clipping the attractive tail makes the bodies leave faster.
    assert restitution_of_damping(b, "F0") > e + 1e-4


def test_inverse():
    for eps in (0.5, 0.9):
        assert restitution_of_damping(damping_for_restitution(eps, "F0"), "F0") == pytest.approx(eps, abs=1e-10)
    with pytest.raises(ValueError):
        damping_for_restitution(0.1)
