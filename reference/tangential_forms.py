r"""The tangential (friction) half of a DEM contact, as one engine writes it: `TangentialForm`,
and the pure force law of one instant.

Every code the study runs writes the tangential force of a Hertz contact as a spring on a
history variable, capped by Coulomb's law, with or without a dashpot; they differ in the details,
and each detail is one field of `TangentialForm` (a registry in `contact_model` fills them, one
form per engine and keyword). The quantities, SI throughout:

    delta    overlap [m];  a = sqrt(R* delta) the contact radius [m]
    v_s      slip velocity of the contact point, body 1 relative to body 2 [m/s]
    k_t      tangential stiffness [N/m]: k_t0 a (mindlin, k_t0 = 8 G* [Pa]) or k_t0 (linear)
    F_el     elastic tangential force [N]: -k_t xi (displacement history) or F_h (force history)
    eta_t    tangential damping coefficient [N s/m]: x_t eta_n, eta_n = 2 eta a
    F_c      the normal force that enters the cap [N]
    F_t      tangential force on body 1 [N] (body 2 gets -F_t)

One instant of the discrete algorithm (LAMMPS's granular pair style, and the others in the same
order): the history is advanced as if sticking, the trial force is formed, and if it exceeds the
Coulomb cap the force is set on the cap and the history is reset to match (`cap_force`).
`reference.oblique_collision` integrates the continuous limit of that algorithm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

HISTORIES = ("displacement", "force")
STIFFNESSES = ("mindlin", "linear")
CAPS = ("total", "elastic")
CAP_NORMALS = ("total_abs", "total_clipped", "elastic")
DAMPINGS = ("none", "normal_xt", "stick_only")
#: The arm whose share of the overlap is the other body's Young's modulus over the sum (Kratos's pair
#: contact): each sphere's share differs where the moduli do (`lever_shares`).
MODULUS_WEIGHTED = "R-delta*Ej/(Ei+Ej)"
#: The lever arms, L = b R - s delta: choice -> (b, the share of the radius it keeps; s, the share of
#: the overlap it loses) [-]. b is 1 or exactly 0, so that b R = R bitwise for the arms of R; "none"
#: (b = s = 0) is no arm: the spins do not enter the slip, or the force applies no torque (ESyS's
#: HertzMindlin), and dL/dt = -s d(delta)/dt = 0. The modulus-weighted arm's s is per sphere (None
#: here: `lever_shares`).
ARMS = {"R": (1.0, 0.0), "R-delta/2": (1.0, 0.5), "R-delta": (1.0, 1.0), "none": (0.0, 0.0),
        MODULUS_WEIGHTED: (1.0, None)}
LEVERS = tuple(ARMS)


@dataclass(frozen=True)
class TangentialForm:
    r"""One engine's tangential contact model, field by field.

    Attributes
    ----------
    history : str
        The history variable. ``"displacement"``: the tangential spring's elongation xi [m],
        d(xi)/dt = v_s while sticking, F_el = -k_t(a) xi [N] (LAMMPS mindlin, LIGGGHTS).
        ``"force"``: the elastic force itself F_h [N], dF_h/dt = -k_t(a) v_s while sticking,
        F_el = F_h (the incremental form: LAMMPS mindlin/force, YADE Mindlin, Kratos). With a
        constant k_t the two are the same; with k_t = k_t0 a they differ while a changes.
    stiffness : str
        ``"mindlin"``: k_t = k_t0 a [N/m], a = sqrt(R* delta) [m], k_t0 = 8 G* [Pa] (Mindlin's
        no-slip stiffness). ``"linear"``: k_t = k_t0 [N/m], a constant.
    rescale : bool
        True: while the contact radius decreases (da/dt < 0) the history (xi or F_h) is scaled by
        a/a_prev each step (LAMMPS ``*_rescale``, Kratos). Continuous limit: d(history)/dt gains
        the term history (da/dt)/a [history unit/s] while da/dt < 0.
    cap : str
        ``"total"``: Coulomb's cap on the trial force |F_el - eta_t v_s| <= mu F_c [N], damping
        included (LAMMPS); beyond it F_t = mu F_c trial/|trial| and the history is reset so that
        F_el = F_t + eta_t v_s. ``"elastic"``: the cap on |F_el| <= mu F_c alone; beyond it the
        history is scaled back to |F_el| = mu F_c, and the damping is added after:
        F_t = F_el - eta_t v_s (LIGGGHTS), or, with `damping` ``"stick_only"``, F_t = F_el while
        sliding (YADE).
    cap_normal : str
        The normal force F_c [N] in the cap. ``"total_abs"``: |F_n|, damping included (LAMMPS,
        not clipped); ``"total_clipped"``: max(F_n, 0); ``"elastic"``: the Hertz elastic part
        k_n delta^{3/2}, k_n = (4/3) E* sqrt(R*).
    damping : str
        ``"none"``: eta_t = 0. ``"normal_xt"``: eta_t = x_t eta_n [N s/m], eta_n = 2 eta a the
        normal law's coefficient of d(delta)/dt at this overlap (LAMMPS ``damping xt``).
        ``"stick_only"``: as ``normal_xt``, but only while sticking (under the total cap this
        is the same as ``normal_xt``: the sliding force is the cap either way).
    lever_slip : str
        The arm [m] of each sphere in the contact point's velocity, v_s = (v_1 + L_1 w_1) -
        (v_2 - L_2 w_2): ``"R"``, ``"R-delta/2"`` or ``"R-delta"`` (its radius less that much of
        the overlap [m]), ``"R-delta*Ej/(Ei+Ej)"``: L_i = R_i - delta E_j / (E_i + E_j), E_i the
        bodies' Young's moduli [Pa] (Kratos's pair contact; R - delta/2 for equal moduli), or
        ``"none"``: L = 0, the spins never enter the slip, v_s = v_1 - v_2 (ESyS's HertzMindlin,
        whose slip is the centres' relative velocity alone).
    lever_torque : str
        The arm [m] of each sphere in its torque, tau_i = L_i F_t [N m] about +z (same choices;
        ``"none"``: L = 0, the force applies no torque and the spins stay as they were, ESyS's
        HertzMindlin).
    anti_ratcheting : bool
        True: the translational part of the slip velocity is multiplied by alpha = (R1 + R2) /
        (R1 + R2 - delta), v_s = alpha (v_1 - v_2).t + L_1 w_1 + L_2 w_2 (YADE's
        ``avoidGranularRatcheting``, on by default, ScGeom::getIncidentVel; two spheres: 1 + 2.2e-3
        at the maximum overlap of alumina at 3.9 m/s). No effect on a plane.
    """

    history: str = "displacement"
    stiffness: str = "mindlin"
    rescale: bool = False
    cap: str = "total"
    cap_normal: str = "total_abs"
    damping: str = "none"
    lever_slip: str = "R"
    lever_torque: str = "R"
    anti_ratcheting: bool = False

    def __post_init__(self):
        for name, allowed in (("history", HISTORIES), ("stiffness", STIFFNESSES), ("cap", CAPS),
                              ("cap_normal", CAP_NORMALS), ("damping", DAMPINGS),
                              ("lever_slip", LEVERS), ("lever_torque", LEVERS)):
            if getattr(self, name) not in allowed:
                raise ValueError(f"TangentialForm.{name} must be one of {allowed}, got {getattr(self, name)!r}")
        for name in ("rescale", "anti_ratcheting"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"TangentialForm.{name} must be a bool, got {getattr(self, name)!r}")


def lever(choice: str, R: float, delta: float) -> float:
    """The arm of a sphere at the contact point [m]: L = b R - s delta with b = `lever_base` and
    s = `lever_share`: R, R - delta/2, R - delta, or 0 (``"none"``).

    Parameters
    ----------
    choice : str
        ``"R"``, ``"R-delta/2"``, ``"R-delta"`` or ``"none"`` (`TangentialForm.lever_slip`,
        `lever_torque`).
    R : float
        The sphere's radius [m].
    delta : float
        The overlap [m].

    Returns
    -------
    float
        The arm [m].
    """
    return lever_base(choice) * R - lever_share(choice) * delta


def lever_shares(choice: str, young_1: float | None = None, young_2: float | None = None) -> tuple[float, float]:
    """The shares (s_1, s_2) of the overlap each sphere's arm loses, L_i = R_i - s_i delta [-].

    Parameters
    ----------
    choice : str
        ``"R"``, ``"R-delta/2"``, ``"R-delta"`` (both spheres alike, `lever_share`) or
        ``"R-delta*Ej/(Ei+Ej)"``: s_1 = E_2/(E_1 + E_2), s_2 = E_1/(E_1 + E_2).
    young_1, young_2 : float, optional
        The bodies' Young's moduli [Pa]; required for the modulus-weighted arm.

    Returns
    -------
    tuple of float
        (s_1, s_2).

    Raises
    ------
    ValueError
        For the modulus-weighted arm without two finite positive moduli.
    """
    if choice != MODULUS_WEIGHTED:
        s = lever_share(choice)
        return s, s
    if not (young_1 and young_2 and young_1 > 0 and young_2 > 0 and math.isfinite(young_1 + young_2)):
        raise ValueError(f"the lever arm {choice!r} needs both bodies' finite Young's moduli, got {young_1!r}, "
                         f"{young_2!r}")
    return young_2 / (young_1 + young_2), young_1 / (young_1 + young_2)


def _arm(choice: str) -> tuple[float, float | None]:
    """(b, s) of the arm `choice` (`ARMS`), or ValueError naming the arms: the one place a choice of
    `lever_base` and `lever_share` is validated."""
    if choice not in ARMS:
        raise ValueError(f"a lever arm is one of {LEVERS}, got {choice!r}")
    return ARMS[choice]


def lever_share(choice: str) -> float:
    """The share s of the overlap an arm loses, L = b R - s delta [-] (`ARMS`).

    Parameters
    ----------
    choice : str
        ``"R"``, ``"R-delta/2"``, ``"R-delta"`` or ``"none"``.

    Returns
    -------
    float
        0, 0.5, 1 or 0.

    Raises
    ------
    ValueError
        For the modulus-weighted arm (its share is per sphere: `lever_shares`) or an unknown one.
    """
    s = _arm(choice)[1]
    if s is None:  # a share per sphere, from the moduli
        raise ValueError(f"the lever arm {choice!r} has a share per sphere: lever_shares(choice, E_1, E_2)")
    return s


def lever_base(choice: str) -> float:
    """The share b of the radius an arm keeps, L = b R - s delta [-] (`ARMS`).

    Parameters
    ----------
    choice : str
        One of `LEVERS`.

    Returns
    -------
    float
        1, or 0 for ``"none"``.

    Raises
    ------
    ValueError
        For an unknown arm.
    """
    return _arm(choice)[0]


def stiffness(form: TangentialForm, k_t0: float, a: float) -> float:
    """The tangential stiffness k_t [N/m]: k_t0 a (mindlin, k_t0 [Pa]) or k_t0 (linear, [N/m]).

    Parameters
    ----------
    form : TangentialForm
        The model.
    k_t0 : float
        8 G* [Pa] (mindlin) or the constant stiffness [N/m] (linear).
    a : float
        The contact radius sqrt(R* delta) [m].

    Returns
    -------
    float
        k_t [N/m].
    """
    return k_t0 * a if form.stiffness == "mindlin" else k_t0


def cap_normal_force(form: TangentialForm, F_n: float, F_elastic: float) -> float:
    """The normal force in the Coulomb cap, F_c [N] (`TangentialForm.cap_normal`).

    Parameters
    ----------
    form : TangentialForm
        The model.
    F_n : float
        The normal force as the law gives it, damping included [N] (positive: repulsive).
    F_elastic : float
        The Hertz elastic part k_n delta^{3/2} [N].

    Returns
    -------
    float
        |F_n|, max(F_n, 0) or F_elastic [N].
    """
    if form.cap_normal == "total_abs":
        return abs(F_n)
    if form.cap_normal == "total_clipped":
        return max(F_n, 0.0)
    return F_elastic


def damping_coefficient(form: TangentialForm, eta_n: float, x_t: float, sliding: bool) -> float:
    """The tangential damping coefficient eta_t [N s/m].

    Parameters
    ----------
    form : TangentialForm
        The model.
    eta_n : float
        The normal law's coefficient of d(delta)/dt at this overlap, 2 eta a [N s/m].
    x_t : float
        The ratio eta_t / eta_n [-].
    sliding : bool
        Whether the contact slides (``stick_only`` damps only while sticking).

    Returns
    -------
    float
        eta_t [N s/m].
    """
    if form.damping == "none" or (form.damping == "stick_only" and sliding):
        return 0.0
    return x_t * eta_n


def elastic_force(form: TangentialForm, history: float, k_t: float) -> float:
    """The elastic tangential force F_el [N] of the history: -k_t xi or F_h.

    Parameters
    ----------
    form : TangentialForm
        The model.
    history : float
        xi [m] (displacement) or F_h [N] (force).
    k_t : float
        The tangential stiffness [N/m].

    Returns
    -------
    float
        F_el [N].
    """
    return -k_t * history if form.history == "displacement" else history


def history_for_force(form: TangentialForm, F_el: float, k_t: float) -> float:
    """The history that gives the elastic force F_el: xi = -F_el/k_t [m] or F_h = F_el [N].

    Parameters
    ----------
    form : TangentialForm
        The model.
    F_el : float
        The elastic tangential force [N].
    k_t : float
        The tangential stiffness [N/m] (> 0 for a displacement history).

    Returns
    -------
    float
        xi [m] or F_h [N].
    """
    return -F_el / k_t if form.history == "displacement" else F_el


def cap_force(form: TangentialForm, history: float, k_t: float, v_s: float, eta_t: float, mu: float,
              F_c: float) -> tuple[float, float, bool]:
    """One instant of the force law: the tangential force on body 1 from the history advanced as if
    sticking, capped by Coulomb's law, and the history reset to match.

    With F_el = -k_t xi or F_h and eta_t the damping coefficient while sticking:

    - cap ``"total"``: trial = F_el - eta_t v_s; if |trial| <= mu F_c, F_t = trial; else
      F_t = mu F_c trial/|trial| and the history is reset to F_el = F_t + eta_t v_s, so that the
      next trial starts on the cap (``stick_only`` is ``normal_xt`` here: the sliding force is the
      cap either way).
    - cap ``"elastic"``: if |F_el| > mu F_c the history is scaled to F_el = mu F_c F_el/|F_el|;
      F_t = F_el - eta_t v_s, with no damping while sliding for ``stick_only``.

    Parameters
    ----------
    form : TangentialForm
        The model.
    history : float
        xi [m] or F_h [N], advanced as if the contact stuck.
    k_t : float
        The tangential stiffness [N/m].
    v_s : float
        The slip velocity of the contact point [m/s].
    eta_t : float
        The damping coefficient while sticking [N s/m] (`damping_coefficient` with sliding=False).
    mu : float
        The friction coefficient [-].
    F_c : float
        The normal force of the cap [N] (`cap_normal_force`).

    Returns
    -------
    F_t : float
        The tangential force on body 1 [N].
    history : float
        The history after the cap [m or N].
    sliding : bool
        Whether the cap acted.
    """
    F_el = elastic_force(form, history, k_t)
    cap = mu * F_c
    if form.cap == "total":
        trial = F_el - eta_t * v_s
        if abs(trial) <= cap:
            return trial, history, False
        F_t = math.copysign(cap, trial)
        return F_t, history_for_force(form, F_t + eta_t * v_s, k_t), True
    if abs(F_el) <= cap:
        return F_el - eta_t * v_s, history, False
    F_el = math.copysign(cap, F_el)
    eta_slide = 0.0 if form.damping == "stick_only" else eta_t
    return F_el - eta_slide * v_s, history_for_force(form, F_el, k_t), True
