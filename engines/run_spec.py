"""What one engine run is: a contact pair, an impact velocity, a time step and a contact law.

Everything an engine needs is derived here, from `contact_model`, so that the decks and drivers
only translate numbers into their engine's syntax.

Contact laws:

- ``viscoelastic``: the model under test, F = (4/3) E* sqrt(R*) delta^{3/2} + 2 eta sqrt(R*)
  delta^{1/2} d(delta)/dt, with the attractive tail kept (the x0 trajectory), so that one run
  gives both criteria.
- ``viscoelastic_clipped``: the same force clipped at zero (the bodies separate where the force
  vanishes: F0 physics). Represents criterion F0 only.
- ``elastic``: the same contact with eta = 0, Hertz alone (K = 0: T, A and eps = 1 are known
  exactly). Every code can express it, so it is the one law of the model every engine runs (and
  is gated in), including those that cannot express the viscoelastic force (`engines.codes`,
  ``unavailable``). The
  trajectory has no tail, so x0 and F0 coincide; it stands for x0.
- ``default``: what a user gets out of the box, the code's restitution keyword
  (`engines.codes` ``keyword``: LIGGGHTS ``model hertz``, YADE Hertz-Mindlin with ``en``, LAMMPS
  ``damping tsuji``, ...), told a restitution (`engines.plan`: the viscoelastic reference eps at K =
  default_law_match_K, or the case's own); gated like the others, against its own equation (its reference row
  is `contact_model.keywords.keyword_reference`), under the criterion its force allows.
- a keyword law (``betan``, ``coeff_restitution``, ``velocity``, ``mass_velocity``, ``en_vn``:
  `contact_model.laws`): another keyword of one code, run and gated as ``default`` is, against its
  own equation (`RunSpec.keyword`).

Every law is gated, each against its own equation; what a keyword restitutes against what it was
told (its promise) is reported, not gated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from contact_model import LAW_CRITERIA, LAWS, ContactPair
from contact_model.keywords import KEYWORDS
from contact_model.laws import LAW_REGISTRY
from reference import HERTZ_TAU, solve_collision

from .codes import CODES, KIT_CODES, keyword_of
from .ladder import START_PHASE, aligned_time_step

# The laws and criteria (LAWS, GATED_LAWS, LAW_CRITERIA) are the model's: contact_model.laws.
ENGINES = tuple(CODES)
#: The criterion each engine's default law stands for (engines.codes: whether it keeps the tail).
DEFAULT_LAW_CRITERION = {name: c.default_criterion for name, c in CODES.items()}

#: Steps of free flight before contact (plus START_PHASE: contact starts half a step after a
#: sample) and after separation.
GAP_STEPS = 20
TAIL_STEPS = 30
#: Unit round-off of an IEEE double: a stored number is off by at most this, relatively.
UNIT_ROUNDOFF = 2.0**-53


@dataclass(frozen=True)
class RunSpec:
    """One engine run. SI units. `name` is unique within a case and safe as a file name."""

    case: str
    engine: str
    law: str
    pair: ContactPair
    velocity: float
    time_step_factor: float = 1000.0  # dt ~ T_e / factor (aligned: `time_step`)
    matched_restitution: float | None = None  # for a keyword law: the restitution e it is told
    label: str = ""  # appended to the name, for runs that differ in something else
    #: The reference solution at this run's K (a `reference.CollisionTable` row), solved once
    #: for the whole case by the plan and handed on; None: solved here when needed.
    reference: dict | None = field(default=None, compare=False, repr=False)
    #: The engine build (config `builds:`) that runs it; its id leads the run's name, so two
    #: builds of one code never collide. Empty: the code's name (a build named as its code).
    build: str = ""
    #: Where contact starts on the step grid (a fraction of a step after a sample): the ladders'
    #: START_PHASE; the advisor's checks (tests/test_engine_timestep.py) run others.
    start_phase: float = START_PHASE
    #: False: dt is exactly T_e / time_step_factor, not moved to align the contact's end (a
    #: production step, as a user runs it).
    aligned: bool = True
    #: For a keyword told its own input directly (`Keyword.told`: yade:betan's beta, the conformance
    #: kit's --beta), in place of a restitution the study asks for: that value, given to the code as it
    #: stands. No restitution is asked (`matched_restitution` None), so the run has no promise.
    told_input: float | None = None

    def __post_init__(self):
        if not self.build:
            object.__setattr__(self, "build", self.engine)
        if self.engine not in ENGINES and self.engine not in KIT_CODES:  # KIT_CODES: the kit's plans alone
            raise ValueError(f"unknown engine {self.engine!r}; known: {ENGINES}")
        if self.law not in LAWS:
            raise ValueError(f"unknown contact law {self.law!r}; known: {LAWS}")
        if not (self.velocity > 0 and math.isfinite(self.velocity)):
            raise ValueError(f"impact velocity must be positive, got {self.velocity}")
        if self.law == "elastic" and self.pair.eta != 0:
            object.__setattr__(self, "pair", replace(self.pair, eta=0.0))  # Hertz alone
        if self.keyword is not None and self.matched_restitution is None and self.told_input is None:
            raise ValueError(f"law {self.law!r} (a keyword) needs the restitution coefficient it is told")
        if self.told_input is not None and self.matched_restitution is not None:
            raise ValueError(f"law {self.law!r}: told either a restitution or its own input, not both")

    @property
    def keyword(self) -> str | None:
        """The engine keyword this run runs (`engines.codes.keyword_of`), None for the model's laws."""
        return keyword_of(self.law, self.engine)

    @property
    def scales(self) -> dict:
        return self.pair.scales(self.velocity)

    @property
    def K(self) -> float:
        return self.pair.dissipation_parameter(self.velocity)

    @property
    def time_step(self) -> float:
        """dt [s]: T_e / time_step_factor, moved so that a whole number of steps spans the
        contact up to the law's aligned end (`aligned_end`, `engines.ladder.aligned_time_step`):
        with the start at START_PHASE, the end then falls at the same phase at every time step
        of a ladder. Unaligned (exactly T_e / factor) where the reference is not solved (K > 10)."""
        T_e = self.scales["T_e"]
        tau = self._reference_time(self.aligned_end) if self.aligned else None
        if tau is None:
            return T_e / self.time_step_factor
        return aligned_time_step(tau / HERTZ_TAU * T_e, T_e, self.time_step_factor)

    @property
    def aligned_end(self) -> str | None:
        """The end of contact its time step is aligned to (`engines.ladder.aligned_time_step`): the point
        where its force is not smooth, so that it falls at the same phase of the step grid at every rung
        of a ladder (`contact_model.laws.Law.aligned_end`: the tail's x0 end, the clipped force's kink at
        F0, Hertz's x0 end); for an engine's keyword, the end its force allows (F0 where it clips, x0
        where it keeps the tail)."""
        if self.keyword is not None:
            return KEYWORDS[self.keyword].criterion
        return LAW_REGISTRY[self.law].aligned_end

    def _reference_row(self) -> dict | None:
        """The reference solution at this run's K (None for K > 10, outside the solver's range)."""
        if self.keyword is not None or (self.reference is not None and self.K <= 10.0):
            return self.reference  # an engine keyword's row is its own equation's, at any K
        if self.K > 10.0:
            return None
        return solve_collision(self.K) if self.K > 0 else None

    def _reference_time(self, end: str | None) -> float | None:
        """The reference (dimensionless) time of contact end `end` ('x0', 'F0', or 'F0 return':
        where a clipped run's overlap returns to zero in free flight), None when unknown."""
        if end is None:
            return None
        if self.K == 0:
            return HERTZ_TAU  # Hertz alone: x0 and F0 coincide
        r = self._reference_row()
        if r is None:
            return None
        if end == "x0":
            return r["tau_0"]
        if end == "F0":
            return r["tau_f"]
        if "tau_return" in r:  # an engine keyword's row (contact_model.keywords.keyword_reference)
            return r["tau_return"]
        # After F0 a clipped run flies freely at eps_F0 from x_f, where (5/4) x_f + K x' = 0,
        # i.e. x_f = (4/5) K eps_F0: it touches zero (4/5) K later.
        return r["tau_f"] + 0.8 * self.K

    @property
    def represents(self) -> tuple[str, ...]:
        """The end-of-collision criteria this run's trajectory stands for."""
        if self.keyword is not None:
            return (KEYWORDS[self.keyword].criterion,)
        return LAW_CRITERIA[self.law]

    @property
    def name(self) -> str:
        return self._name(f"-dt{self.time_step_factor:g}")

    @property
    def ladder(self) -> str:
        """The name of the ladder this run is a rung of: its name without the time step (the
        runs that differ in their time step alone are extrapolated together)."""
        return self._name("")

    def _name(self, time_step: str) -> str:
        name = f"{self.build}-{self.law}-{self.pair.geometry}-K{self.K:.6g}-V{self.velocity:.6e}{time_step}"
        if self.start_phase != START_PHASE or not self.aligned:
            name += f"-phase{self.start_phase:.4f}" + ("" if self.aligned else "-unaligned")
        if self.matched_restitution is not None:
            name += f"-e{self.matched_restitution:.6f}"
        if self.told_input is not None:  # e.g. -beta0.100000: what the code was told, by its own name
            name += f"-{KEYWORDS[self.keyword].told}{self.told_input:.6f}"
        return f"{name}-{self.label}" if self.label else name

    def initial_gap(self) -> float:
        """Distance between the surfaces at t = 0 [m]: GAP_STEPS + START_PHASE steps of
        approach, so that contact starts half a step after sample GAP_STEPS."""
        return (GAP_STEPS + self.start_phase) * self.velocity * self.time_step

    def steps(self) -> int:
        """Steps to run: the approach, the contact (the reference duration until the overlap
        returns to zero, with a margin for the engines' own errors and for the default laws),
        and some free flight. A clipped run flies freely after F0 and is over sooner than the
        tail's x0 end (at K = 5: 5.9 against 14.7 in units of delta_e / V)."""
        clipped = self.law == "viscoelastic_clipped" or (self.keyword is not None and self.aligned_end == "F0")
        tau = self._reference_time("F0 return" if clipped else "x0")
        if tau is None:  # K > 10: the solver's largest K, a lower bound of the contact's length
            tau = solve_collision(10.0)["tau_0"]
        contact_steps = 1.25 * tau / HERTZ_TAU * self.scales["T_e"] / self.time_step
        return int(GAP_STEPS + math.ceil(contact_steps) + TAIL_STEPS)

    def roundoff_floor(self) -> float:
        """The relative error [-] double-precision positions may leave in T, A and eps:

            sqrt(steps) u X / delta_max,

        X the magnitude of the stored centres (|x1| + |x2|; the sphere's centre starts at
        -(R1 + gap)), u = 2^-53. Every position update x += v dt is rounded by up to u |x|; the
        overlap, a difference of positions, carries those errors, which add up over the steps as
        a random walk. Measured (tests/test_ladder.py, on the engines' map with positions stored
        at their magnitude): the rms error of T, A and eps lies between u X / delta_max and this
        bound; for steel on a plane at 1e-12 m/s, LIGGGHTS, YADE and LAMMPS missed T by 7e-3
        against 6.7e-3 predicted."""
        state = self.initial_state()
        X = abs(state["x1"]) + abs(state.get("x2", 0.0))
        r = self._reference_row()
        x_max = r["x_max"] if r is not None and (self.K > 0 or self.keyword is not None) else 1.0
        return math.sqrt(self.steps()) * UNIT_ROUNDOFF * X / (x_max * self.scales["delta_e"])

    def initial_velocities(self) -> tuple[float, float]:
        """Velocities of body 1 and 2 along the line of centres (body 1 moves +x towards
        body 2). The centre of mass is at rest for two spheres; a plane does not move."""
        if self.pair.body_2.is_plane:
            return self.velocity, 0.0
        m1, m2 = self.pair.body_1.mass, self.pair.body_2.mass
        return self.velocity * m2 / (m1 + m2), -self.velocity * m1 / (m1 + m2)

    def initial_state(self) -> dict[str, float]:
        """The numbers every engine needs to set the run up (SI): radius, density, velocity and
        x-position of body 1 (a sphere moving +x, touching body 2 at x = 0 after the gap) and
        of body 2 (absent for the plane x = 0), time step and number of steps."""
        p = self.pair
        R1, gap = p.body_1.radius, self.initial_gap()
        v1, v2 = self.initial_velocities()
        state = {"R1": R1, "rho1": p.body_1.density, "v1": v1, "dt": self.time_step, "steps": self.steps()}
        if p.body_2.is_plane:
            state["x1"] = -(R1 + gap)
        else:
            R2 = p.body_2.radius
            state.update({"x1": -(R1 + gap / 2), "R2": R2, "rho2": p.body_2.density, "v2": v2, "x2": R2 + gap / 2})
        return state

    def metadata(self) -> dict:
        """The case parameters recorded in every dump header."""
        p = self.pair
        s = self.scales
        meta = {
            "case": self.case, "build": self.build, "engine": self.engine, "law": self.law, "geometry": p.geometry,
            "represents": list(self.represents),
            "impact_velocity": self.velocity, "K": self.K, "time_step": self.time_step,
            "time_step_factor": self.time_step_factor,
            "effective_modulus": p.E, "effective_radius": p.R, "effective_mass": p.M,
            "viscosity": p.eta, "radius_1": p.body_1.radius, "density_1": p.body_1.density,
            "radius_2": None if p.body_2.is_plane else p.body_2.radius,
            "density_2": None if p.body_2.is_plane else p.body_2.density,
            "delta_e": s["delta_e"], "T_e": s["T_e"], "A_e": s["A_e"],
            "ladder": self.ladder, "aligned_end": self.aligned_end, "start_phase": self.start_phase,
            "roundoff_floor": self.roundoff_floor(),
        }
        if self.matched_restitution is not None:
            meta["matched_restitution"] = self.matched_restitution
        if self.told_input is not None:
            meta["told_input"] = self.told_input
        return meta
