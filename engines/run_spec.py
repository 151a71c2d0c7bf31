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
  exactly). Every code can express it, so it is the one law gated in every engine, including
  those that cannot express the viscoelastic force (`engines.codes`, ``unavailable``). The
  trajectory has no tail, so x0 and F0 coincide; it stands for x0.
- ``default``: what a user gets out of the box (LIGGGHTS ``model hertz``, YADE Hertz-Mindlin with
  its restitution-coefficient damping, LAMMPS ``damping tsuji``), its restitution set to the
  viscoelastic reference eps at one velocity (`engines.plan`, ``default_law_match_K``), under the
  criterion that engine's default stands for (`DEFAULT_LAW_CRITERION`). Compared with the
  viscoelastic reference, not expected to agree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from contact_model import ContactPair
from reference import HERTZ_TAU, solve_collision

from .codes import CODES

LAWS = ("viscoelastic", "viscoelastic_clipped", "elastic", "default")
#: The laws the study validates against tolerances (the model under test); 'default' is compared only.
GATED_LAWS = ("viscoelastic", "viscoelastic_clipped", "elastic")
#: The end-of-collision criteria a run of each gated law stands for (`RunSpec.represents`; the
#: default law's depends on the engine: `DEFAULT_LAW_CRITERION`).
LAW_CRITERIA = {"viscoelastic": ("x0", "F0"),  # the tail is kept: one trajectory, both ends
                "viscoelastic_clipped": ("F0",),
                "elastic": ("x0",)}  # no tail: x0 and F0 coincide
ENGINES = tuple(CODES)
#: The criterion each engine's default law stands for (engines.codes: whether it keeps the tail).
DEFAULT_LAW_CRITERION = {name: c.default_criterion for name, c in CODES.items()}

#: Steps of free flight before contact and after separation.
GAP_STEPS = 20
TAIL_STEPS = 30


@dataclass(frozen=True)
class RunSpec:
    """One engine run. SI units. `name` is unique within a case and safe as a file name."""

    case: str
    engine: str
    law: str
    pair: ContactPair
    velocity: float
    time_step_factor: float = 1000.0  # dt = T_e / factor
    matched_restitution: float | None = None  # for law 'default': the eps it is tuned to
    label: str = ""  # appended to the name, for runs that differ in something else
    #: The reference solution at this run's K (a `reference.CollisionTable` row), solved once
    #: for the whole case by the plan and handed on; None: solved here when needed.
    reference: dict | None = field(default=None, compare=False, repr=False)
    #: The engine build (config `builds:`) that runs it; its id leads the run's name, so two
    #: builds of one code never collide. Empty: the code's name (a build named as its code).
    build: str = ""

    def __post_init__(self):
        if not self.build:
            object.__setattr__(self, "build", self.engine)
        if self.engine not in ENGINES:
            raise ValueError(f"unknown engine {self.engine!r}; known: {ENGINES}")
        if self.law not in LAWS:
            raise ValueError(f"unknown contact law {self.law!r}; known: {LAWS}")
        if not (self.velocity > 0 and math.isfinite(self.velocity)):
            raise ValueError(f"impact velocity must be positive, got {self.velocity}")
        if self.law == "elastic" and self.pair.eta != 0:
            object.__setattr__(self, "pair", replace(self.pair, eta=0.0))  # Hertz alone
        if self.law == "default" and self.matched_restitution is None:
            raise ValueError("law 'default' needs the restitution coefficient it is matched to")

    @property
    def scales(self) -> dict:
        return self.pair.scales(self.velocity)

    @property
    def K(self) -> float:
        return self.pair.dissipation_parameter(self.velocity)

    @property
    def time_step(self) -> float:
        return self.scales["T_e"] / self.time_step_factor

    @property
    def represents(self) -> tuple[str, ...]:
        """The end-of-collision criteria this run's trajectory stands for."""
        if self.law in LAW_CRITERIA:
            return LAW_CRITERIA[self.law]
        return (DEFAULT_LAW_CRITERION[self.engine],)

    @property
    def name(self) -> str:
        name = (f"{self.build}-{self.law}-{self.pair.geometry}-K{self.K:.6g}-V{self.velocity:.6e}"
                f"-dt{self.time_step_factor:g}")
        if self.matched_restitution is not None:
            name += f"-e{self.matched_restitution:.6f}"
        return f"{name}-{self.label}" if self.label else name

    def initial_gap(self) -> float:
        """Distance between the surfaces at t = 0 [m]: GAP_STEPS steps of approach."""
        return GAP_STEPS * self.velocity * self.time_step

    def steps(self) -> int:
        """Steps to run: the approach, the contact (the reference x0 duration, with a margin
        for the engines' own errors and for the default laws), and some free flight."""
        K = min(self.K, 10.0)
        if self.reference is not None and K == self.K:
            tau_0 = self.reference["tau_0"]
        else:
            tau_0 = solve_collision(K)["tau_0"] if K > 0 else HERTZ_TAU
        contact_steps = 1.25 * tau_0 / HERTZ_TAU * self.time_step_factor
        return int(GAP_STEPS + math.ceil(contact_steps) + TAIL_STEPS)

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
        }
        if self.matched_restitution is not None:
            meta["matched_restitution"] = self.matched_restitution
        return meta
