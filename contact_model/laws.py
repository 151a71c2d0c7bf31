r"""The contact laws the study runs, as data: one `Law` per entry of `LAW_REGISTRY`.

Every law adds to the Hertz force (4/3) E* sqrt(R*) delta^{3/2} a damping force. In the reference
solver's units (x = delta/delta_e, tau = t V/delta_e) its head-on collision is

    x'' + c x^p x' + (5/4) x^{3/2} = 0,      x(0) = 0,  x'(0) = 1,

with the total force clipped at zero where the law clips it. The damping power p says which law
family it is (`Law.damping`):

- ``half`` (p = 1/2, c = K): Kuwabara-Kono / Brilliantov, the viscoelastic model under test
  (`reference.collision_ode`); K grows as V^{1/5}, so the restitution falls with velocity;
- ``quarter`` (p = 1/4, c = b): Tsuji's form, what the engines' restitution keywords compute, b a
  function of the restitution told (`contact_model.keywords`; closed form:
  `reference.quarter_power_damping`); the restitution is the same at every velocity;
- ``velocity`` (p = 0, c): a linear dashpot (LAMMPS ``damping velocity`` and ``mass_velocity``;
  `reference.linear_damping`); at a fixed coefficient c falls as V^{-1/5}, so the restitution
  rises with velocity;
- ``none``: Hertz alone (c = 0; T, A and eps = 1 in closed form);
- ``keyword``: whatever a code's out-of-the-box keyword computes (law ``default``: the keyword of
  each code, `engines.codes` ``keyword``).

The laws:

- ``viscoelastic``: the model, F = -(k delta^{3/2} + A k delta^{1/2} d(delta)/dt), the attractive tail
  kept (one trajectory, both criteria);
- ``viscoelastic_clipped``: the same force clipped at zero (F0);
- ``elastic``: Hertz alone (the one law every code can express);
- ``default``: each code's own restitution keyword, told a restitution, gated against its own
  equation; its promise (what it restitutes against what it was told) reported beside it;
- ``betan``, ``coeff_restitution``, ``velocity``, ``mass_velocity``: a keyword that is not its
  code's default, run as a law of its own (`Law.keyword`), gated the same way; the two linear
  dashpots are told the eta_n that restitutes the same e at the run's velocity.

A criterion is where a collision ends (reference.series): `x0` when the overlap returns to zero,
`F0` when the force does. The geometries are `contact_pair.GEOMETRIES`.

Adding a law: one `Law` entry here (and, for a keyword, its `contact_model.keywords` entry with
its map and source), its engine words in the decks of the codes that express it, and the
solution of its equation in `reference`; `tests/test_adding_a_law.py` walks the recipe.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact_model.damping_forms import DAMPING_FORMS, DampingForm
from reference.series import CRITERIA

#: The damping forms' powers p of x^p x' (`contact_model.damping_forms`); 'keyword': each code's own.
DAMPING_POWER = {**{name: form.power for name, form in DAMPING_FORMS.items()}, "keyword": None}


@dataclass(frozen=True)
class Law:
    """One contact law of the study.

    Attributes
    ----------
    name : str
        How config `laws:`, the case reports and the results name it.
    title : str
        What it is, in a sentence of the report.
    damping : str
        Its damping form: a key of `DAMPING_POWER` ('half', 'quarter', 'none', or 'keyword' for
        each code's own keyword).
    clipped : bool or None
        Whether the total force is clipped at zero; None: as its keyword's code does.
    criteria : tuple of str
        The end-of-collision criteria one of its runs stands for; () as its keyword's clip says
        (F0 where it clips, x0 where it keeps the tail).
    aligned_end : str or None
        Where the contact's force is not smooth, the end its time steps are aligned to
        (`engines.ladder.aligned_time_step`); None: its criterion.
    model : bool
        Whether it is the viscoelastic model under test: told the case's viscosity, compared
        with the paper's series, replayed on the engines' map, its ladder refined by sqrt(K).
    keyword : str or None
        For a keyword run as a law of its own: its `contact_model.keywords.KEYWORDS` key (the
        codes that lack it cannot run the law). None for the model's laws and for ``default``.
    told : str
        What a run is told: 'eta' (the case's viscosity), 'none', or 'e' (a restitution: the
        case's own, else the viscoelastic reference eps at config `default_law_match_K`).
    left_out : str
        Why the default study (config/config.yaml `laws:`) does not run it; '' when it does.
    """

    name: str
    title: str
    damping: str
    clipped: bool | None
    criteria: tuple[str, ...]
    aligned_end: str | None
    model: bool
    keyword: str | None = None
    told: str = "eta"
    #: Why config/config.yaml's `laws:` (the default study) leaves it out; '' when it lists it.
    left_out: str = ""

    @property
    def form(self) -> DampingForm | None:
        """Its damping form (`contact_model.damping_forms`): what its equation, reference solver and
        ladder powers are; None for ``default``, whose form is each code's keyword's.

        Returns
        -------
        DampingForm or None
        """
        return None if self.damping == "keyword" else DAMPING_FORMS[self.damping]

    @property
    def is_keyword(self) -> bool:
        """Whether it runs an engine's keyword (``default`` or a named one), told a restitution.

        Returns
        -------
        bool
        """
        return self.told == "e"


LAW_REGISTRY: dict[str, Law] = {law.name: law for law in (
    Law("viscoelastic", "Hertz + Brilliantov's dissipative force, the attractive tail kept", "half", False,
        ("x0", "F0"), "x0", True),
    Law("viscoelastic_clipped", "Hertz + Brilliantov's dissipative force, clipped at zero", "half", True,
        ("F0",), "F0", True),
    Law("elastic", "Hertz alone", "none", False, ("x0",), "x0", True, told="none"),
    Law("default", "each code's own restitution keyword, against its own equation", "keyword", None, (), None,
        False, told="e"),
    Law("betan", "YADE's Hertz-Mindlin told betan (Thornton's beta of the restitution), against its own equation",
        "quarter", True, ("F0",), "F0", False, keyword="yade:betan", told="e"),
    Law("en_vn", "YADE's Hertz-Mindlin told en and vn (Mueller & Poeschel's Pade route to Brilliantov's law, "
        "YADE 2024.02a and later), against its own equation", "half", True, ("F0",), "F0", False,
        keyword="yade:en-vn", told="e",
        left_out="it runs in one build (yade-2025) at YADE's per-step cost, about 40 s more of the study; run it "
                 "with --config 'laws=[en_vn]' (docs/keywords.md)"),
    Law("coeff_restitution", "LAMMPS's hertz/material with damping coeff_restitution, against its own equation",
        "quarter", False, ("x0",), "x0", False, keyword="lammps:coeff_restitution", told="e"),
    Law("velocity", "LAMMPS's hertz/material with damping velocity (F_d = -eta_n d(delta)/dt), against its own "
        "equation", "velocity", False, ("x0",), "x0", False, keyword="lammps:velocity", told="e"),
    Law("mass_velocity", "LAMMPS's hertz/material with damping mass_velocity (F_d = -eta_n M* d(delta)/dt), against "
        "its own equation", "velocity", False, ("x0",), "x0", False, keyword="lammps:mass_velocity", told="e"),
)}

LAWS = tuple(LAW_REGISTRY)
#: The laws of the viscoelastic model under test (the paper's series and the engines' map are theirs).
MODEL_LAWS = tuple(name for name, law in LAW_REGISTRY.items() if law.model)
#: The laws the study gates against tolerances: all of them (a keyword against its own equation).
GATED_LAWS = LAWS
#: The laws that run an engine's keyword told a restitution.
KEYWORD_LAWS = tuple(name for name, law in LAW_REGISTRY.items() if law.is_keyword)
#: The end-of-collision criteria a run of each law of fixed clip stands for (`engines.RunSpec.represents`).
LAW_CRITERIA = {name: law.criteria for name, law in LAW_REGISTRY.items() if law.criteria}


def law(name: str) -> Law:
    """The registry's entry `name`.

    Parameters
    ----------
    name : str
        The law's name ('viscoelastic', 'viscoelastic_clipped', 'elastic', 'default', ...).

    Returns
    -------
    Law
        The registered law.

    Raises
    ------
    ValueError
        Naming the known laws, for an unknown name.
    """
    try:
        return LAW_REGISTRY[name]
    except KeyError:
        raise ValueError(f"unknown contact law {name!r}; known: {', '.join(LAWS)}") from None


__all__ = ["CRITERIA", "GATED_LAWS", "KEYWORD_LAWS", "LAWS", "LAW_CRITERIA", "LAW_REGISTRY", "Law", "MODEL_LAWS",
           "law"]
