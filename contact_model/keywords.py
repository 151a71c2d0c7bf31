r"""The Hertz normal-damping keywords the engines offer, as data: what each computes, in the Hertz
units of `reference`, and what it promises.

Every keyword here adds to the Hertz force (4/3) E* sqrt(R*) delta^{3/2} a damping force; in
x = delta/delta_e, tau = t V/delta_e (delta_e = (15 M* V^2 / (16 E* sqrt(R*)))^{2/5}) each is one of

- ``quarter``: x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0, b a function of what the user wrote (e, or a
  damping ratio) and nothing else: the restitution is the same at every velocity
  (`reference.quarter_power_damping` solves it in closed form);
- ``half``: x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0 (Kuwabara-Kono / Brilliantov), K growing as
  V^{1/5}: the study's viscoelastic law (`reference.collision_ode`);
- ``velocity``: x'' + c x' + (5/4) x^{3/2} = 0, c falling as V^{-1/5} at a fixed coefficient
  (LAMMPS ``damping velocity`` and ``mass_velocity``; `reference.linear_damping`): the user
  gives eta_n, not a restitution, and the study tells it the eta_n that restitutes e at the run's
  velocity (x0);

with the total force clipped at zero where the code clips it. `KEYWORDS` holds each keyword's
form, its map from the user's input to the coefficient exactly as the code computes it (read from
each release's source, cited in `source`; docs/keywords.md), whether it clips, the releases that
have it, and a departure of the code from its documentation that is known upstream.

Its promise: a restitution keyword told e should restitute e. `promised_restitution` gives what its
own equation restitutes, exactly, under the criterion its force allows (x0 when the tail is kept,
F0 when clipped), so that ``eps_own - e`` is the error of the keyword's map, which an engine that
computes the keyword right reproduces (the engines' side is gated against the same equation).

Out of scope (not Hertz in the normal direction): LIGGGHTS ``model hooke`` (and ``hooke/stiffness``,
``hooke/hysteresis``), LAMMPS ``hooke`` and ``dmt``/``jkr`` (adhesive), Kratos's ``DEM_D_Linear_*``
laws and ``DEM_D_Hertz_viscous_Coulomb2D`` (a linear spring given the Hertz map), ESyS's linear
walls; plastic laws (LIGGGHTS ``thornton_ning``, ``edinburgh``; Kratos ``DEM_D_Conical_damage``
after damage starts) damp by hysteresis, not by a dashpot.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Callable

#: Thornton et al. (2013), Table 2: the coefficients h_1 ... h_10 of alpha(e) = sum h_i e^i, whose
#: beta(e) = sqrt(1 / (1 - (1 + e)^2 exp(alpha)) - 1) YADE (`en`, 2023.02a) and Kratos
#: (GammaForHertzThornton, 9.3 ... 10.4) both code.
THORNTON_H = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757,
              -1489.915)


def log_beta(e: float, pi: float = math.pi) -> float:
    """|beta| = -ln e / sqrt(ln^2 e + pi^2): the damping ratio of a linear spring-dashpot that restitutes e.

    As LIGGGHTS, LAMMPS coeff_restitution and ESyS HertzMindlinVisco (which writes pi as 3.1415926)
    compute it.

    Parameters
    ----------
    e : float
        The restitution coefficient, 0 < e <= 1 [-].
    pi : float
        The value of pi the code writes [-].

    Returns
    -------
    float
        The damping ratio |beta| [-].
    """
    lg = math.log(e)
    return -lg / math.sqrt(lg * lg + pi * pi)


def thornton_beta(e: float) -> float:
    """Thornton et al. (2013)'s (B6): beta = sqrt(1 / (1 - (1 + e)^2 exp(alpha(e))) - 1).

    The fit YADE and Kratos use for a clipped Hertz contact (0 at e = 1).

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        The damping ratio beta [-].

    References
    ----------
    Thornton, C. et al. (2013), eq. (B6) and Table 2 (the coefficients h_1 ... h_10 of alpha(e)).
    """
    if e >= 1.0:
        return 0.0
    alpha = 0.0
    for h in reversed(THORNTON_H):  # Horner, as both codes write it
        alpha = e * (h + alpha)
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(alpha)) - 1.0)


def kratos_gamma(e: float) -> float:
    """Kratos's GammaForHertzThornton (sphere_strategy.py:617-637 @ 10.4.0).

    `thornton_beta` with e raised to 0.001 below it and gamma = 0 above 0.999.

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        The damping ratio gamma [-].

    References
    ----------
    Thornton, C. et al. (2013), eq. (B6) and Table 2 (the coefficients h_1 ... h_10 of alpha(e)).
    """
    if e > 0.999:
        return 0.0
    return thornton_beta(max(e, 0.001))


def lammps_tsuji_alpha(e: float) -> float:
    """LAMMPS's `damping tsuji` alpha(e) (Marshall 2009's fit of Tsuji et al. 1992).

    1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5 + 4.8218 e^6.

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        alpha(e) [-].

    References
    ----------
    Tsuji, Y., Tanaka, T. & Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
    cohesionless particles in a horizontal pipe. Powder Technol. 71, 239-250.
    Marshall (2009), the polynomial fit of alpha(e) of Tsuji et al. (as the code cites it).
    """
    return (1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4 - 18.022 * e**5
            + 4.8218 * e**6)


#: YADE's [3/6] Pade approximant of Mueller & Poeschel (2011)'s eps(v*), as YADE 2024.02a and later
#: code it (pkg/dem/HertzMindlin.cpp:26-27 @2025.2.0): (numerator, denominator) coefficients of
#: v*^0, v*^1, ... The `en` + `vn` route solves eps(v*) = en for v* and sets beta = v*^2 vn^(-1/5).
YADE_PADE = ((1.0, 1.07232, 0.574198, 0.141552), (1.0, 1.07232, 1.72765, 1.37842, 1.19449, 0.467273, 0.235585))


def yade_pade_restitution(v: float) -> float:
    """eps(v*) of YADE's Pade approximant (`YADE_PADE`).

    Parameters
    ----------
    v : float
        The scaled velocity v* >= 0 [-].

    Returns
    -------
    float
        The restitution coefficient [-].

    References
    ----------
    Mueller, P. & Poeschel, T. (2011). Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution. Phys. Rev. E 84, 021302.
    """
    num, den = (sum(c * v**i for i, c in enumerate(cs)) for cs in YADE_PADE)
    return num / den


@functools.lru_cache(maxsize=256)
def yade_vstar(e: float) -> float:
    """The v* >= 0 at which YADE's Pade gives e; 0 at e = 1.

    YADE's getVstar solves the same equation by Newton from 0.5 to machine precision
    (HertzMindlin.cpp:88-114 @2025.2.0).

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        The scaled velocity v* [-].

    References
    ----------
    Mueller, P. & Poeschel, T. (2011). Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution. Phys. Rev. E 84, 021302.
    """
    from scipy.optimize import brentq

    if e >= 1.0:
        return 0.0
    hi = 1.0
    while yade_pade_restitution(hi) > e:  # eps(v*) falls from 1 to 0
        hi *= 2.0
    return brentq(lambda v: yade_pade_restitution(v) - e, 0.0, hi, xtol=1e-16, rtol=8.9e-16, maxiter=500)


def yade_en_vn_K(e: float, velocity_ratio: float = 1.0) -> float:
    """K of YADE's `en` + `vn` route.

    Its force is Brilliantov's, F_d = (3/2) A k_no delta^{1/2} d(delta)/dt with
    A = (2/3) beta (k_no/m)^(-2/5) (HertzMindlin.cpp:469-470), beta = v*(e)^2 vn^(-1/5); in the
    study's units K = (5/4)^{3/5} beta V^{1/5} = (5/4)^{3/5} v*(e)^2 (V/vn)^{1/5}.

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].
    velocity_ratio : float
        V/vn, the impact velocity over the velocity vn the user gives (1 when vn is the impact
        velocity) [-].

    Returns
    -------
    float
        The dissipation parameter K [-].

    References
    ----------
    Brilliantov, N. V., Spahn, F., Hertzsch, J.-M. & Poeschel, T. (1996). Model for collisions in
    granular gases. Phys. Rev. E 53, 5382.
    Mueller, P. & Poeschel, T. (2011). Collision of viscoelastic spheres: compact expressions for the
    coefficient of normal restitution. Phys. Rev. E 84, 021302.
    """
    return 1.25**0.6 * yade_vstar(e) ** 2 * velocity_ratio**0.2


#: sqrt(15/2): b per unit of a coefficient c in c_n = 2 c sqrt(M* k_t), k_t = 2 E* sqrt(R* delta)
#: (the tangent stiffness; YADE and Kratos).
ROOT_15_2 = math.sqrt(7.5)


@dataclass(frozen=True)
class Keyword:
    """One damping keyword of one code.

    Attributes
    ----------
    name : str
        The registry's key, '<code>:<keyword>'.
    code : str
        The engine code (engines.codes) that offers it.
    written : str
        How a user writes it in the code's input.
    form : str
        'quarter', 'half' or 'velocity' (see the module's docstring).
    clipped : bool
        Whether the code clips the total normal force at zero (by default).
    told : str
        What the user gives: 'e' (a restitution coefficient), 'beta' (a damping ratio), 'alpha'
        (OpenFOAM's dashpot coefficient) or 'eta'.
    coefficient : callable or None
        For the 'quarter' form: told value -> b, exactly as the code computes it.
    releases : str
        The releases of the study's builds that have it.
    source : str
        Where the code computes it (file:line@release).
    known_defect : str
        A departure known upstream (with the issue or PR and the releases it affects); ''.
    """

    name: str
    code: str
    written: str
    form: str
    clipped: bool
    told: str
    coefficient: Callable[[float], float] | None
    releases: str
    source: str
    known_defect: str = ""
    accepts: tuple[float, float] = (0.0, 1.0)
    #: What the code is given for a requested restitution e, when it is told something else
    #: (YADE's betan: Thornton's beta of e, what its own `en` would compute); None: e itself.
    from_restitution: Callable[[float], float] | None = None
    #: The first release of the code that has it, (year, month, day); None: every release.
    since: tuple[int, int, int] | None = None

    @property
    def damping_form(self):
        """Its `contact_model.damping_forms.DampingForm` (equation, solver, ladder powers).

        Returns
        -------
        DampingForm
        """
        from contact_model.damping_forms import DAMPING_FORMS

        return DAMPING_FORMS[self.form]

    def told_for(self, e: float) -> float:
        """The value the code is told for a requested restitution `e` (`from_restitution`).

        Parameters
        ----------
        e : float
            The requested restitution coefficient, 0 < e <= 1 [-].

        Returns
        -------
        float
            e itself, or what the code is told in its place (e.g. YADE betan's beta) [-].
        """
        return e if self.from_restitution is None else self.from_restitution(e)

    def refuses(self, told: float) -> str:
        """Why the code refuses the told value ('' when it takes it).

        Parameters
        ----------
        told : float
            The value the code is told: a restitution coefficient e, a damping ratio beta, or the
            dimensionless dashpot coefficient c of a 'velocity' keyword [-].

        Returns
        -------
        str
            '' when low < told <= high (`accepts`), else the code's refusal in words.
        """
        low, high = self.accepts
        if low < told <= high:
            return ""
        return f"{self.code} refuses it: {self.told} must lie in ({low:g}, {high:g}]"

    @property
    def criterion(self) -> str:
        """The end of contact its force allows: F0 when it clips, x0 when the tail is kept.

        Returns
        -------
        str
            'F0' or 'x0'.
        """
        return "F0" if self.clipped else "x0"

    def b(self, told: float) -> float:
        """The coefficient of its equation for the told value.

        b of x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 (form 'quarter'), K of
        x'' + K x^{1/2} x' + (5/4) x^{3/2} = 0 (form 'half'), c of x'' + c x' + (5/4) x^{3/2} = 0
        (form 'velocity', told the dimensionless c itself: its code's eta_n is c M* V / delta_e or
        c V / delta_e).

        Parameters
        ----------
        told : float
            The value the code is told: a restitution coefficient e, a damping ratio beta, or the
            dimensionless dashpot coefficient c of a 'velocity' keyword [-].

        Returns
        -------
        float
            The coefficient b, K or c [-].

        Raises
        ------
        ValueError
            When the keyword has no map to the coefficient of its equation.
        """
        if self.coefficient is None:
            raise ValueError(f"{self.name} has no map to the coefficient of its equation")
        return self.coefficient(told)


def _identity(c: float) -> float:
    return c


def openfoam_alpha(e: float) -> float:
    """OpenFOAM's alpha whose own equation restitutes e (x0, the tail kept): alpha = sqrt(5) |beta(e)|.

    OpenFOAM takes alpha, not a restitution: eta_N = alpha sqrt(M* k_N) delta^{1/4}
    (PairSpringSliderDashpot.C:205-212, WallSpringSliderDashpot.C:91-99 @v1912) is b = sqrt(5/4) alpha
    in x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0, whose x0 restitution is exp(-pi zeta / sqrt(1 - zeta^2))
    with zeta = 2 b / 5 (`reference.quarter_power_damping.damping_for_restitution_quarter_power`):
    b = (5/2) |beta(e)|, alpha = b / sqrt(5/4) = sqrt(5) |beta(e)|, |beta| = -ln e / sqrt(ln^2 e + pi^2).

    Parameters
    ----------
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        alpha [-] (0 at e = 1).
    """
    if not 0.0 < e <= 1.0:
        raise ValueError(f"a restitution coefficient must lie in (0, 1], got {e!r}")
    return math.sqrt(5.0) * abs(log_beta(e))  # abs: no -0.0 at e = 1


@functools.lru_cache(maxsize=256)
def _dashpot_for_restitution(e: float) -> float:
    """The linear dashpot's c that restitutes e under x0 (`reference.linear_damping`): what the
    study tells `damping velocity` and `mass_velocity`, as eta_n at each run's velocity."""
    from reference.linear_damping import damping_for_restitution_linear

    return damping_for_restitution_linear(e, "x0")


_TSUJI_DEFECT = ("LAMMPS applies Tsuji's alpha(e), fitted with the particle's mass, to the reduced mass M* "
                 "and so damps sqrt(2) too little (b = sqrt(5/4) alpha instead of sqrt(5/2) alpha): "
                 "every LAMMPS release up to 4 Jul 2026 carries it (all the study ran: 29 Sep 2021, 23 Jun 2022, "
                 "2 Aug 2023, 29 Aug 2024, 4 Feb 2025 and 22 Jul 2025); the LAMMPS manual dates its fix "
                 "(`damp *= MY_SQRT2`, lammps/lammps PR #5113) to the next release, 2 Sep 2026 ('changed in "
                 "2 Sep 2026'), which is not on PyPI: no release the study can install fixes it")

KEYWORDS: dict[str, Keyword] = {k.name: k for k in (
    Keyword("liggghts:hertz-coefficientRestitution", "liggghts",
            "pair_style gran model hertz + fix property/global coefficientRestitution", "quarter", False, "e",
            lambda e: 2.5 * log_beta(e), "3.8.0",
            "src/normal_model_hertz.h:231-255, src/global_properties.cpp:539 @3.8.0 (limitForce off by default: "
            "src/settings.h:237; 0.05 < e <= 1 required: src/global_properties.cpp:488-489)", accepts=(0.05, 1.0)),
    Keyword("lammps:tsuji", "lammps", "pair_style granular hertz/material E e nu damping tsuji", "quarter", False,
            "e", lambda e: math.sqrt(1.25) * lammps_tsuji_alpha(e), "29 Sep 2021 ... 22 Jul 2025",
            "src/GRANULAR/pair_granular.cpp:369-370, 986-992 @stable_29Sep2021_update2; "
            "src/GRANULAR/gran_sub_mod_damping.cpp (GranSubModDampingTsuji) @stable_22Jul2025",
            known_defect=_TSUJI_DEFECT),
    Keyword("lammps:coeff_restitution", "lammps", "pair_style granular hertz/material E e nu damping coeff_restitution",
            "quarter", False, "e", lambda e: 2.5 * log_beta(e), "29 Aug 2024 ... (not in 29 Sep 2021)",
            "src/GRANULAR/gran_sub_mod_damping.cpp:161-185 @stable_29Aug2024 (PR #4068)", since=(2024, 8, 29)),
    Keyword("lammps:velocity", "lammps", "pair_style granular hertz/material E eta_n nu damping velocity", "velocity",
            False, "eta", _identity, "29 Sep 2021 ... 22 Jul 2025",
            "src/GRANULAR/pair_granular.cpp:363-364, 373-374 @stable_29Sep2021_update2 (damp_normal = 1: F_d = -eta_n "
            "d(delta)/dt); gran_sub_mod_damping.cpp:46, 79 @stable_29Aug2024", accepts=(0.0, math.inf),
            from_restitution=_dashpot_for_restitution),
    Keyword("lammps:mass_velocity", "lammps", "pair_style granular hertz/material E eta_n nu damping mass_velocity",
            "velocity", False, "eta", _identity, "29 Sep 2021 ... 22 Jul 2025",
            "src/GRANULAR/pair_granular.cpp:365-366 @stable_29Sep2021_update2 (damp_normal = meff: F_d = -eta_n M* "
            "d(delta)/dt); gran_sub_mod_damping.cpp:96 @stable_29Aug2024", accepts=(0.0, math.inf),
            from_restitution=_dashpot_for_restitution),
    Keyword("yade:en", "yade", "Ip2_FrictMat_FrictMat_MindlinPhys(en=e)", "quarter", True, "e",
            lambda e: ROOT_15_2 * thornton_beta(e), "2023.02a",
            "pkg/dem/HertzMindlin.cpp:76-104 (Thornton 2013 (B6)), :352-356 (c_n = 2 beta_n sqrt(m k_n)), "
            ":389-402 (the clip) @2023.02a"),
    Keyword("yade:betan", "yade", "Ip2_FrictMat_FrictMat_MindlinPhys(betan=beta)", "quarter", True, "beta",
            lambda beta: ROOT_15_2 * beta, "2023.02a",
            "pkg/dem/HertzMindlin.cpp:106-109, :352-356, :389-402 @2023.02a", accepts=(0.0, 1e300),
            from_restitution=thornton_beta),
    Keyword("yade:en-vn", "yade", "Ip2_FrictMat_FrictMat_MindlinPhys(en=e, vn=V)", "half", True, "e",
            yade_en_vn_K, "2024.02a ... (not in 2023.02a)",
            "pkg/dem/HertzMindlin.cpp:26-27 (the Pade), :88-114 (getVstar), :180-183 (beta = v*^2 vn^-0.2), "
            ":469-471 (A = (2/3) beta (kno/mbar)^-0.4, c_n = A k_n), :507-513 (the clip) @2025.2.0; told vn = the "
            "impact velocity", since=(2024, 2, 1)),
    Keyword("kratos:hertz-COEFFICIENT_OF_RESTITUTION", "kratos",
            "DEM_D_Hertz_viscous_Coulomb with COEFFICIENT_OF_RESTITUTION", "quarter", True, "e",
            lambda e: ROOT_15_2 * kratos_gamma(e), "9.3 ... 10.4",
            "DEMApplication/sphere_strategy.py:617-637 (GammaForHertzThornton) @10.4.0; "
            "DEM_D_Hertz_viscous_Coulomb_CL.cpp CalculateViscoDampingForce (2 gamma sqrt(M* kn)) and the clip "
            "in CalculateForces (checked in the 10.4.0 library)"),
    Keyword("esys:HertzMindlinVisco", "esys", "HertzMindlinViscoPrms(E, nu, mu, COR)", "quarter", False, "e",
            lambda e: 2.5 * log_beta(e, pi=3.1415926), "2.3.5",
            "Model/HertzMindlinViscoInteraction.cpp:135-147 @2.3.5 (Antypov 2011, eq. 6; pi written 3.1415926; "
            "the force is not clipped)"),
    Keyword("openfoam:alpha", "openfoam", "pairSpringSliderDashpot / wallSpringSliderDashpot with alpha", "quarter",
            False, "alpha", lambda alpha: math.sqrt(1.25) * alpha, "v1912",
            "src/lagrangian/intermediate/submodels/Kinematic/CollisionModel/PairCollision/PairModel/"
            "PairSpringSliderDashpot/PairSpringSliderDashpot.C:205-212, WallModel/WallSpringSliderDashpot/"
            "WallSpringSliderDashpot.C:91-99 @v1912 (eta_N = alpha sqrt(M* k_N) delta^(1/4), no clip); told "
            "alpha(e) = sqrt(5) |beta(e)|, the alpha whose own equation restitutes e (openfoam_alpha)",
            accepts=(-math.inf, math.inf), from_restitution=openfoam_alpha),
    # A code the study runs no engine of (engines.codes.KIT_CODES): the conformance kit exports its plans for
    # a user to run in their own build; the study never plans it (no build of config `builds:` can name it).
    Keyword("chrono:smc_hertz", "chrono",
            "ChSystemSMC with SetContactForceModel(Hertz) and UseMaterialProperties(true) (the defaults), "
            "ChContactMaterialSMC::SetRestitution(e)", "quarter", True, "e", lambda e: 2.5 * log_beta(e),
            "not run by the study (the conformance kit exports it)",
            "src/chrono/physics/ChContactSMC.cpp:94-104 (S_n = 2 E* sqrt(R* delta), k_n = (2/3) S_n, "
            "beta = ln e / sqrt(ln^2 e + pi^2), g_n = -2 sqrt(5/6) beta sqrt(S_n m*)), "
            ":170 (F_n = k_n delta - g_n v_n), "
            ":175-178 (the clip), src/chrono/physics/ChSystemSMC.cpp:35-36 (the defaults) @7689fbc0 (18 Aug 2026); "
            "e and E* are stored as float (ChContactMaterialSMC.h:108), a relative 6e-8 off the double the plan "
            "gives"),
)}


def promised_restitution(keyword: str, e: float) -> float:
    """What `keyword`'s own equation restitutes when asked for `e` (told `Keyword.told_for(e)`).

    Exactly, under the criterion its force allows (`Keyword.criterion`); its promise error is this
    minus e.

    Parameters
    ----------
    keyword : str
        The keyword's registry name, '<code>:<keyword>' (`KEYWORDS`).
    e : float
        The requested restitution coefficient, 0 < e <= 1 [-].

    Returns
    -------
    float
        The restitution coefficient its equation delivers [-].
    """
    k = KEYWORDS[keyword]
    return k.damping_form.restitution(k.b(k.told_for(e)), k.criterion)


#: The month names of the engines' version banners.
MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def release_date(banner: str) -> tuple[int, int, int] | None:
    """(year, month, day) of a version banner that dates its release.

    'LAMMPS (29 Sep 2021 - Update 2)' is (2021, 9, 29); 'Yade version: 2025.2.0' is (2025, 2, 1).

    Parameters
    ----------
    banner : str
        The engine's version banner.

    Returns
    -------
    tuple of int or None
        (year, month, day), None when the banner names no date.
    """
    import re

    m = re.search(r"\b(\d{1,2}) (" + "|".join(MONTHS) + r")[a-z]* (\d{4})\b", banner)
    if m:
        return (int(m.group(3)), MONTHS.index(m.group(2)) + 1, int(m.group(1)))
    yade = re.search(r"Yade version: (\d{4})\.(\d{1,2})", banner)  # YADE numbers releases year.month
    return (int(yade.group(1)), int(yade.group(2)), 1) if yade else None


def missing_in(keyword: str, banner: str) -> str | None:
    """Why the build whose version banner is `banner` lacks `keyword`.

    Its release predates the keyword's `since`.

    Parameters
    ----------
    keyword : str
        The keyword's registry name, '<code>:<keyword>' (`KEYWORDS`).
    banner : str
        The build's version banner.

    Returns
    -------
    str or None
        The reason in words; None when the build has it or its release is not dated.
    """
    k = KEYWORDS[keyword]
    date = release_date(banner)
    if k.since is None or date is None or date >= k.since:
        return None
    y, m, d = k.since
    return f"{k.written.split(' + ')[-1]} came in the release of {d} {MONTHS[m - 1]} {y}; this build is {banner}"


def keyword_reference(keyword: str, told: float, K: float = 0.0, direct: bool = False) -> dict:
    """The reference row of a run of `keyword` asked for restitution `told`.

    Its code is given `Keyword.told_for(told)` (`direct`: `told` itself, the code's own input, e.g.
    yade:betan's beta given by the user); `reference.quarter_power_damping`'s characteristics
    of its own equation, in the fields of a `reference.CollisionTable` row, with the run's
    viscoelastic K (its name and plots place it by it), the keyword's b, and tau_return: where the
    overlap of a clipped run returns to zero in free flight after the force vanished
    (x^{5/4} = (4b/5) eps_F0 there), the length its engine run must cover.

    Parameters
    ----------
    keyword : str
        The keyword's registry name, '<code>:<keyword>' (`KEYWORDS`).
    told : float
        The requested restitution coefficient (or the dimensionless c of a 'velocity' keyword) [-].
    K : float
        The run's viscoelastic dissipation parameter [-].
    direct : bool
        Whether `told` is what the code is told in its own input (`Keyword.told`), not a restitution.

    Returns
    -------
    dict
        The row, in the reference's units (lengths of delta_e, times of delta_e/V; eps, b and K
        [-]).
    """
    return {**_own_row(keyword, float(told), direct), "K": float(K)}


@functools.lru_cache(maxsize=256)
def _own_row(keyword: str, told: float, direct: bool = False) -> dict:
    """`keyword_reference` without K, once per (keyword, told): a plan asks for it at every
    velocity, and a dashpot's c is a root-find of ~50 solves."""
    from reference.quarter_power_damping import solve_quarter_power

    k = KEYWORDS[keyword]
    coefficient = k.b(told if direct else k.told_for(told))
    if k.form == "velocity":  # the tail kept: the run ends with the overlap's return (x0)
        from reference.linear_damping import solve_linear_damping

        row = solve_linear_damping(coefficient)
        return {**row, "b": row["c"], "tau_return": row["tau_0"]}
    if k.form == "half":  # Brilliantov's law at its K; clipped, it lets go at x = (4/5) K eps_F0
        from reference import solve_collision

        K = coefficient
        row = {**solve_collision(K), "b": K}
        return {**row, "tau_return": row["tau_f"] + 0.8 * K if k.clipped else row["tau_0"]}
    row = solve_quarter_power(coefficient)
    x_f = (0.8 * row["b"] * row["eps_F0"]) ** 0.8
    return {**row, "tau_return": row["tau_f"] + (x_f / row["eps_F0"] if row["eps_F0"] > 0 else 0.0)}


def restitution_keywords() -> list[str]:
    """The keywords told a restitution coefficient (their promise: eps = e).

    Returns
    -------
    list of str
        Their registry names.
    """
    return [name for name, k in KEYWORDS.items() if k.told == "e"]
