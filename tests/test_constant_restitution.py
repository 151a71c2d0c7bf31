"""The Tsuji-type damping of the engines' default laws: velocity-independent restitution,
LIGGGHTS's mapping from its input e, which is exact under criterion x0, and LAMMPS's, which
misses a factor sqrt(2) (the real LAMMPS: tests/test_engine_lammps.py)."""

import math

import pytest

from contact_model.constant_restitution import damping_for_restitution, restitution_of_damping
from contact_model.keywords import KEYWORDS


def test_no_damping_is_elastic():
    assert restitution_of_damping(0.0) == pytest.approx(1.0, abs=1e-11)


@pytest.mark.parametrize("e", [0.6, 0.8, 0.95])
def test_liggghts_hertz_restitution_is_its_input_under_x0(e):
    b = KEYWORDS["liggghts:hertz-coefficientRestitution"].b(e)  # 2.5 |ln e| / sqrt(ln^2 e + pi^2)
    assert restitution_of_damping(b, "x0") == pytest.approx(e, abs=1e-9)
    # Clipping the attractive tail makes the bodies leave faster.
    assert restitution_of_damping(b, "F0") > e + 1e-4


def test_inverse():
    for eps in (0.5, 0.9):
        assert restitution_of_damping(damping_for_restitution(eps, "F0"), "F0") == pytest.approx(eps, abs=1e-10)
    with pytest.raises(ValueError):
        damping_for_restitution(0.1)


def test_the_x0_restitution_is_the_linear_oscillators_in_closed_form():
    """x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 restitutes exp(-pi z / sqrt(1 - z^2)), z = 2b/5, under
    x0 (as LIGGGHTS's exact mapping above implies: beta = z)."""
    for b in (0.005, 0.056, 0.2, 0.5, 1.0):
        z = 2 * b / 5
        assert restitution_of_damping(b, "x0") == pytest.approx(math.exp(-math.pi * z / math.sqrt(1 - z * z)),
                                                                abs=1e-10)


@pytest.mark.parametrize("e, without, with_sqrt2", [(0.5, 0.616076, 0.499916), (0.904886, 0.931997, 0.905179),
                                                    (0.95, 0.965151, 0.951071)])
def test_lammps_tsuji_restitutes_more_than_told_for_want_of_sqrt2(e, without, with_sqrt2):
    """LAMMPS's alpha(e) is Tsuji's fit for the particle mass (2 M* for equal spheres) applied to M*:
    told e it restitutes `without` (x0); with the sqrt(2) of LAMMPS's development branch it
    restitutes e to within the polynomial fit's own error (<= 1.1e-3, 3e-4 at the study's e)."""
    b = KEYWORDS["lammps:tsuji"].b(e)  # sqrt(5/4) alpha(e)
    assert restitution_of_damping(b, "x0") == pytest.approx(without, abs=2e-6)
    assert restitution_of_damping(math.sqrt(2) * b, "x0") == pytest.approx(with_sqrt2, abs=2e-6)
    assert abs(with_sqrt2 - e) < 1.2e-3 < without - e
