"""What one oblique engine run is: a head-on run (`RunSpec`) plus friction, a tangential model,
a tangential velocity and a spin.

The normal half of every tangential model of the study is the normal law alone (no model of
`contact_model/tangential_models.yaml` lets the tangential force act back on the normal one), so
an oblique run's normal motion, contact time and step grid are those of the head-on run at the
normal velocity: its time step, its steps and its initial positions come from `RunSpec`
unchanged, and its ladder is aligned the same way (`engines.ladder`).

Conventions (docs/physics.md, "Oblique impacts"): the normal n = +x points from body 1 to body
2; body 1 approaches with normal velocity v_n > 0; the tangential direction is +y; spins are
about +z (counter-clockwise positive). For two spheres the initial velocities are split in the
centre-of-mass frame, tangential as normal (`initial_velocities`); body 2 does not spin at the
start, and they start offset along y so that their centres lie on the x axis when they touch
(`initial_positions`). The contact point's slip velocity is

    v_s = (v_y1 + R1 w1) - (v_y2 - R2 w2)    [m/s]

(the plane: v_y2 = w2 = 0; R_i the arm the model uses, `reference.TangentialForm`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .run_spec import RunSpec


@dataclass(frozen=True)
class ObliqueRun:
    """One oblique collision in one engine build. SI units.

    Attributes
    ----------
    normal : RunSpec
        The head-on run at the normal velocity v_n (`normal.velocity`), with the normal law,
        the pair (its bodies carry Young's modulus and Poisson's ratio: G* needs them), the build
        and the time step.
    model : str
        The tangential model, a key of `contact_model.tangential_models` (e.g. ``lammps:mindlin``).
    friction : float
        Coulomb's mu [-].
    tangential_velocity : float
        The bodies' relative tangential velocity of centres at the start, v_y1 - v_y2 [m/s].
    spin : float
        Body 1's initial angular velocity about +z [rad/s].
    damping_ratio : float
        x_t, the tangential damping as a fraction of the normal one's coefficient (LAMMPS ``xt``),
        for models whose damping is ``normal_xt``; 0: none.
    ranks : int
        MPI processes of the engine run (the processor-boundary check: 2, the subdomain boundary
        across the contact).
    """

    normal: RunSpec
    model: str
    friction: float
    tangential_velocity: float
    spin: float = 0.0
    damping_ratio: float = 0.0
    ranks: int = 1

    def __post_init__(self):
        if not (self.friction >= 0 and math.isfinite(self.friction)):
            raise ValueError(f"friction must be a finite number >= 0, got {self.friction!r}")
        if not all(math.isfinite(x) for x in (self.tangential_velocity, self.spin, self.damping_ratio)):
            raise ValueError("tangential velocity, spin and damping ratio must be finite numbers")
        if self.ranks not in (1, 2):
            raise ValueError(f"an oblique run runs on 1 or 2 MPI ranks, got {self.ranks!r}")

    @property
    def build(self) -> str:
        return self.normal.build

    @property
    def pair(self):
        return self.normal.pair

    @property
    def law(self) -> str:
        """The normal law (`RunSpec.law`)."""
        return self.normal.law

    @property
    def angle(self) -> float:
        """The incidence from the normal [deg]: atan(v_t / v_n) of the centres' relative velocity."""
        return math.degrees(math.atan2(self.tangential_velocity, self.normal.velocity))

    @property
    def contact_angle(self) -> float:
        """The incidence of the contact point's slip from the normal [deg]: atan((v_t + R1 w1) / v_n)
        (the centres' `angle` where nothing spins; Chung & Ooi's tests 6-8 give it by spin alone)."""
        return math.degrees(math.atan2(self.tangential_velocity + self.pair.body_1.radius * self.spin,
                                       self.normal.velocity))

    @property
    def ladder(self) -> str:
        """The runs that differ in their time step alone share it (see `RunSpec.ladder`)."""
        return self._name(self.normal.ladder)

    @property
    def name(self) -> str:
        """Unique within a case and safe as a file name."""
        return self._name(self.normal.name)

    def _name(self, normal: str) -> str:
        model = self.model.replace(":", "-").replace("/", "_")
        name = f"{normal}-{model}-mu{self.friction:.6g}-vt{self.tangential_velocity:.6e}-w{self.spin:.6e}"
        if self.damping_ratio:
            name += f"-xt{self.damping_ratio:.6g}"
        return name + (f"-np{self.ranks}" if self.ranks != 1 else "")

    def at_time_step(self, time_step_factor: float) -> "ObliqueRun":
        """The same run at another rung of its ladder."""
        return replace(self, normal=replace(self.normal, time_step_factor=time_step_factor))

    def initial_velocities(self) -> dict[str, float]:
        """The tangential velocities [m/s] and spins [rad/s] of both bodies at the start:
        vy1, vy2, w1, w2. Two spheres: split in the centre-of-mass frame like the normal ones
        (`RunSpec.initial_velocities`); the plane: vy2 = 0."""
        p = self.pair
        if p.body_2.is_plane:
            return {"vy1": self.tangential_velocity, "vy2": 0.0, "w1": self.spin, "w2": 0.0}
        m1, m2 = p.body_1.mass, p.body_2.mass
        return {"vy1": self.tangential_velocity * m2 / (m1 + m2), "vy2": -self.tangential_velocity * m1 / (m1 + m2),
                "w1": self.spin, "w2": 0.0}

    def touching_time(self) -> float:
        """When the bodies touch [s]: the head-on run's gap closed at the normal velocity
        (`RunSpec.initial_gap`, GAP_STEPS + START_PHASE steps)."""
        return self.normal.initial_gap() / self.normal.velocity

    def initial_positions(self) -> dict[str, float]:
        """The bodies' y positions at t = 0 [m] (x: `RunSpec.initial_state`): two spheres start
        offset along y so that their centres are aligned on the x axis when they touch, at the
        planned time and phase of the step grid (`touching_time`). The line of centres then turns
        during the contact (by about v_t T / (R1 + R2)): the reference follows it
        (`reference.solve_oblique`, which starts at touching with the centres on x). The plane:
        y1 = 0, except on two MPI ranks, where the sphere crosses y = 0 in the middle of the
        contact (the decks split the domain there, so that the contact's history changes rank)."""
        if self.pair.body_2.is_plane:
            if self.ranks == 1:
                return {"y1": 0.0}
            middle = self.touching_time() + 0.5 * self.normal.scales["T_e"]  # T_e: Hertz's contact time
            return {"y1": -self.tangential_velocity * middle}
        v, t = self.initial_velocities(), self.touching_time()
        return {"y1": -v["vy1"] * t, "y2": -v["vy2"] * t}

    def metadata(self) -> dict:
        """The run's parameters recorded in every dump header: the head-on run's and these."""
        return {**self.normal.metadata(), "tangential_model": self.model, "friction": self.friction,
                "tangential_velocity": self.tangential_velocity, "spin": self.spin,
                "damping_ratio": self.damping_ratio, "ranks": self.ranks, "angle": self.angle,
                "oblique_ladder": self.ladder, **{f"initial_{k}": v for k, v in self.initial_velocities().items()},
                **{f"initial_{k}": v for k, v in self.initial_positions().items()}}


@dataclass(frozen=True)
class ObliqueJob:
    """An `ObliqueRun` as an engine's sweep machinery sees a run (`engines.script_engine`,
    `engines.driven_sweep`): its name, engine, case, ladder and the steps its time limit counts,
    with the knobs of the sensitivity checks (1: the model's own).

    Attributes
    ----------
    run : ObliqueRun
        The run.
    step_cost : int
        A step of the driver's oblique deck in head-on steps of the cost table
        (`engines.codes.EngineCost`), for this run's rank count: what its time limit counts.
    stiffness_factor : float
        The factor on the tangential stiffness k_t the deck writes [-].
    friction_factor : float
        The factor on the friction coefficient mu the deck writes [-].
    """

    run: ObliqueRun
    step_cost: int = 1
    stiffness_factor: float = 1.0
    friction_factor: float = 1.0

    @property
    def name(self) -> str:
        return self.run.name

    @property
    def engine(self) -> str:
        return self.run.normal.engine

    @property
    def case(self) -> str:
        return self.run.normal.case

    @property
    def ladder(self) -> str:
        return self.run.ladder

    def steps(self) -> int:
        """The run's steps in head-on steps' cost: what its time limit counts."""
        return self.step_cost * self.run.normal.steps()
