"""The damping forms (contact_model/damping_forms.py) carry their behaviour, and the recipe of adding
one holds: `form_recipe_problems` checks each place a form must reach (its registry entry, its
equation's text, its reference solver, its ladder powers *measured on the engines' map*, the docs),
so that a form that misses one fails naming it. A dummy form (x^{3/4} x') gets through it; the same
form claiming another form's powers, or without a solver, fails at that place."""

import functools
import math
from pathlib import Path

import numpy as np
import pytest

from contact_model import damping_forms
from contact_model.damping_forms import DAMPING_FORMS, DampingForm, damping_form
from engines.ladder import START_PHASE, aligned_time_step
from records.collision_metrics import collision_metrics
from reference import HERTZ_TAU, solve_collision
from reference.engine_map import replay
from test_ladder import orders

ROOT = Path(__file__).resolve().parents[1]
DOCS = "\n".join(p.read_text() for p in (ROOT / "docs").glob("*.md"))
#: Eight halvings of dt from T_e/250, as tests/test_ladder.py measures the viscoelastic law's powers.
FACTORS = 250 * 2.0 ** np.arange(8)
#: How close the measured orders come to the form's powers over these rungs: the first within 0.06
#: (the next power's share at T_e/32000: 1.049 for the x^{1/4} form), the second within 0.02.
FIRST, SECOND = 0.06, 0.02


@functools.lru_cache(maxsize=None)
def measured_powers(power: float | None, coefficient: float = 0.5) -> tuple[float, float]:
    """The first two powers of h in the error of the engines' map (`reference.engine_map.replay`) with the
    damping c x^power x' (None: Hertz alone), from eight aligned halvings of dt: eps_x0's (delta_max's for
    Hertz alone, whose eps is 1 to round-off), the first from successive differences, the second after the
    first is eliminated at its measured value rounded to a quarter."""
    c = 0.0 if power is None else coefficient
    end = solve_collision(c)["tau_0"] if power in (None, 0.5) else _end(power, c)
    hs, values = [], []
    for factor in FACTORS:
        h = aligned_time_step(end, HERTZ_TAU, factor)
        d = replay(c, h, int(20 + 1.25 * end / h + 30), start_phase=START_PHASE,
                   power=0.5 if power is None else power)
        m = collision_metrics(*d.T, impact_velocity=1.0)
        hs.append(h)
        values.append(m.delta_max if power is None else m.eps_x0)
    h, y = np.array(hs) / HERTZ_TAU, np.array(values)
    first = float(orders(h, y, [])[-1])
    second = float(orders(h, y, [round(first * 4) / 4])[-1])
    return first, second


def _end(power: float, c: float) -> float:
    """The x0 end of x'' + c x^p x' + (5/4) x^{3/2} = 0 [-] for any p (scipy, to 1e-10: only the rungs'
    alignment needs it)."""
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        x = max(y[0], 0.0)
        return [y[1], -(1.25 * x**1.5 + c * x**power * y[1])]

    def back(t, y):
        return y[0]

    back.terminal, back.direction = True, -1
    sol = solve_ivp(rhs, (1e-12, 20.0), [1e-12, 1.0], events=back, rtol=1e-11, atol=1e-13)
    return float(sol.t_events[0][0])


def form_recipe_problems(form: DampingForm, docs: str = DOCS) -> list[str]:
    """Every place `form` misses, one sentence each naming the place; empty when it follows the recipe
    of contact_model/damping_forms.py (`docs`: the text of docs/*.md)."""
    problems = []

    def check(place, condition, what):
        if not condition:
            problems.append(f"{place}: {what}")

    check("contact_model/damping_forms.py", DAMPING_FORMS.get(form.name) is form,
          f"{form.name!r} is not registered (@register)")
    check("contact_model/damping_forms.py", form.eps_of_velocity in ("falls", "constant", "rises", "none"),
          f"eps_of_velocity {form.eps_of_velocity!r}")
    equation = form.equation()
    check("contact_model/damping_forms.py", equation.endswith("(5/4) x^(3/2) = 0")
          and (form.power is None or form.symbol in equation), f"its equation reads {equation!r}")
    try:
        row = form.solve(0.0 if form.power is None else 0.5)
        ok = all(math.isfinite(row[k]) for k in ("x_max", "tau_0", "tau_f", "eps_x0", "eps_F0"))
        ok = ok and (form.power is None or 0 < row["eps_x0"] < 1)
    except (KeyError, ValueError, TypeError, NotImplementedError):
        ok = False
    check("reference/", ok, f"no reference solution of {equation}")
    claimed = form.ladder_powers(0.0 if form.power is None else 1.0)[:2]
    measured = measured_powers(form.power)
    check("contact_model/damping_forms.py",
          len(form.ladder_powers()) >= 3 and abs(measured[0] - claimed[0]) <= FIRST
          and abs(measured[1] - claimed[1]) <= SECOND,
          f"ladder powers {claimed} but the engines' map measures ({measured[0]:.3f}, {measured[1]:.3f})")
    check("docs/keywords.md", f"`{form.name}`" in docs, f"no doc names the form `{form.name}`")
    return problems


@pytest.mark.parametrize("name", list(DAMPING_FORMS))
def test_every_form_follows_the_recipe_its_powers_measured_on_the_map(name):
    assert form_recipe_problems(DAMPING_FORMS[name]) == []


def test_the_measured_powers_are_the_expansions():
    """Measured, not asserted: x^{1/2} 1 then 3/2, x^{1/4} 1 then 5/4, a dashpot 1 then 2, Hertz 2 then 5/2."""
    for power, expected in ((0.5, (1.0, 1.5)), (0.25, (1.0, 1.25)), (0.0, (1.0, 2.0)), (None, (2.0, 2.5))):
        first, second = measured_powers(power)
        assert abs(first - expected[0]) <= FIRST and abs(second - expected[1]) <= SECOND, (power, first, second)


class ThreeQuarter(DampingForm):
    """A dummy form, c x^{3/4} x', solved by scipy (its powers are the base class's generic ones)."""

    name, power, symbol, label, eps_of_velocity = "three_quarter", 0.75, "c", "δ^¾ δ'", "falls"

    def solve(self, coefficient):
        from scipy.integrate import solve_ivp

        def rhs(t, y):
            x = max(y[0], 0.0)
            return [y[1], -(1.25 * x**1.5 + coefficient * x**0.75 * y[1])]

        def back(t, y):
            return y[0]

        back.terminal, back.direction = True, -1
        sol = solve_ivp(rhs, (1e-12, 20.0), [1e-12, 1.0], events=back, rtol=1e-11, atol=1e-13, dense_output=True)
        tau_0 = float(sol.t_events[0][0])
        t = np.linspace(1e-12, tau_0, 4001)
        eps = -float(sol.y_events[0][0][1])  # the rebound velocity where the overlap returns to zero
        return {"x_max": float(sol.sol(t)[0].max()), "tau_0": tau_0, "tau_f": tau_0, "eps_x0": eps, "eps_F0": eps}


def test_a_dummy_form_gets_through_the_recipe_and_a_missed_place_fails_naming_it(monkeypatch):
    dummy = ThreeQuarter()
    assert dummy.ladder_powers() == (1.0, 1.75, 2.0, 2.5, 2.75)  # 1 + p + k beside 1, 2 and Hertz's 5/2
    assert dummy.equation() == "x'' + c x^(3/4) x' + (5/4) x^(3/2) = 0"
    monkeypatch.setitem(damping_forms.DAMPING_FORMS, dummy.name, dummy)
    assert form_recipe_problems(dummy, DOCS + "\n| `three_quarter` | δ^{3/4} δ̇ |") == []
    assert damping_form("three_quarter") is dummy

    class WrongPowers(ThreeQuarter):  # claims the x^{1/4} form's expansion
        name = "wrong_powers"

        def ladder_powers(self, coefficient=1.0):
            return DAMPING_FORMS["quarter"].ladder_powers(coefficient)

    wrong = WrongPowers()
    monkeypatch.setitem(damping_forms.DAMPING_FORMS, wrong.name, wrong)
    problems = form_recipe_problems(wrong)
    assert [p.split(":")[0] for p in problems] == ["contact_model/damping_forms.py", "docs/keywords.md"], problems
    assert "ladder powers (1.0, 1.25) but the engines' map measures (1.0" in problems[0]

    class Unsolved(DampingForm):  # registered alone: no solver, no doc
        name, power, symbol, eps_of_velocity = "unsolved", 0.75, "c", "falls"

    unsolved = Unsolved()
    places = {p.split(":")[0] for p in form_recipe_problems(unsolved)}
    assert places == {"contact_model/damping_forms.py", "reference/", "docs/keywords.md"}
    with pytest.raises(ValueError, match="unknown damping form 'cubic'; known: half, quarter, velocity, none"):
        damping_form("cubic")
