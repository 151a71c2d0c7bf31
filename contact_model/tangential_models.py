"""The engines' tangential (friction) models as a registry: contact_model/tangential_models.yaml.

Each entry (``<code>:<model>``) says, per geometry, which of the reference's forms the model runs
(`reference.TangentialForm`: history form, stiffness, rescale, cap, damping, lever arms), in which
releases it is present, where each release's source says so, and its known defects. The study
runs a model in a build when its code has an oblique driver (`engines.codes.Code.oblique_driver`)
and the entry is in scope; its reference is `form_of`.

Adding a model: an entry in the YAML (its fields from the source, cited), its words in the
code's oblique driver, and, where its physics is not yet a `reference.TangentialForm`, that form;
tests/test_tangential_models.py walks every entry.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import yaml

from reference import TangentialForm

REGISTRY_PATH = Path(__file__).with_name("tangential_models.yaml")
#: The YAML's geometry keys and the study's geometries they stand for.
GEOMETRY_KEYS = {"pair": ("sphere-sphere",), "wall": ("sphere-plane",), "both": ("sphere-sphere", "sphere-plane")}
#: The fields of a geometry block that make the reference's form (`reference.TangentialForm`).
FORM_FIELDS = ("history", "stiffness", "rescale", "cap", "cap_normal", "damping", "lever_slip", "lever_torque")
#: Fields of the form a block may leave out, and the value they then take.
OPTIONAL_FORM_FIELDS = {"anti_ratcheting": False}
#: How each release key of the YAML's `releases:` is named in its engine's version line.
RELEASE_IN_BANNER = {
    "lammps-2021": "29 Sep 2021", "lammps-2022.6.23": "23 Jun 2022", "lammps-2023.8.2": "2 Aug 2023",
    "lammps-2024.8.29": "29 Aug 2024", "lammps-4Feb2025": "4 Feb 2025", "lammps-2025.7.22": "22 Jul 2025",
    "yade-2023.02a": "2023.02a", "yade-2025.2.0": "2025.2.0", "liggghts-3.8.0": "3.8.0", "esys-2.3.5": "2.3",
    "kratos-10.4": "10.4",
}


class NoReference(ValueError):
    """A model whose equations are not (yet) a `reference.TangentialForm`: it cannot be gated."""


@dataclass(frozen=True)
class TangentialModel:
    """One engine tangential model (an entry of tangential_models.yaml).

    Attributes
    ----------
    name : str
        ``<code>:<model>`` (e.g. ``lammps:mindlin``).
    code : str
        The engine code (`engines.codes`).
    words : str
        What a deck writes, as a template.
    blocks : dict
        {geometry: {field: value}}: the YAML's geometry blocks, per study geometry, with values
        given per geometry ({pair: .., wall: ..}) resolved.
    releases : dict
        {release: 'present' | 'absent...' | what differs}, and ``first``.
    sources : dict
        {release: [file:line citations]}.
    known_defects : tuple of dict
        Each with description, releases, size, verdict and reference.
    out_of_scope : str
        Why the study does not run it ('' where it does).
    """

    name: str
    code: str
    words: str
    blocks: dict
    releases: dict = field(default_factory=dict)
    sources: dict = field(default_factory=dict)
    known_defects: tuple = ()
    out_of_scope: str = ""

    @property
    def geometries(self) -> tuple[str, ...]:
        """The study geometries the model has a block for."""
        return tuple(g for g in ("sphere-plane", "sphere-sphere") if g in self.blocks)

    def absent_in(self, banner: str) -> str:
        """Why the release whose version line is `banner` lacks the model ('' where it has it).

        Parameters
        ----------
        banner : str
            The build's version line (`engines.builds.check_build`).
        """
        for release, state in self.releases.items():
            mark = RELEASE_IN_BANNER.get(release)
            if mark and mark in (banner or "") and str(state).lower().startswith("absent"):
                return f"{self.name} is absent in {release}: {state}"
        return ""


def _resolve(value, key: str):
    """A field's value for the YAML geometry key `key` ('pair' or 'wall'), where the value is
    given per geometry ({pair: .., wall: ..})."""
    if isinstance(value, dict) and set(value) <= {"pair", "wall"}:
        return value.get(key)
    return value


def _blocks(entry: dict, name: str) -> dict:
    out = {}
    for key, block in (entry.get("geometry") or {}).items():
        if key not in GEOMETRY_KEYS:
            raise ValueError(f"{REGISTRY_PATH}: {name}.geometry.{key}: must be one of {list(GEOMETRY_KEYS)}")
        for geometry in GEOMETRY_KEYS[key]:
            yaml_key = "pair" if geometry == "sphere-sphere" else "wall"
            out[geometry] = {f: _resolve(v, yaml_key) for f, v in block.items()}
    return out


@lru_cache(maxsize=None)
def load_registry(path: str = str(REGISTRY_PATH)) -> dict[str, TangentialModel]:
    """Every entry of the registry file, checked: {name: TangentialModel}.

    Parameters
    ----------
    path : str
        The YAML file (default: contact_model/tangential_models.yaml).

    Raises
    ------
    ValueError
        Naming the file and the entry, for an entry without code or geometry blocks.
    """
    data = yaml.safe_load(Path(path).read_text())
    models = {}
    for name, entry in data.items():
        if not isinstance(entry, dict) or "code" not in entry or not re.fullmatch(r"[a-z]+:[a-z_/]+", name):
            raise ValueError(f"{path}: entry {name!r} must be '<code>:<model>' with a `code:` and `geometry:`")
        if not name.startswith(entry["code"] + ":"):
            raise ValueError(f"{path}: entry {name!r} has code {entry['code']!r}: its name must start with it")
        blocks = _blocks(entry, name)
        if not blocks:
            raise ValueError(f"{path}: entry {name!r} has no geometry block (pair, wall or both)")
        models[name] = TangentialModel(name, entry["code"], str(entry.get("words", "")), blocks,
                                       dict(entry.get("releases") or {}), dict(entry.get("sources") or {}),
                                       tuple(entry.get("known_defects") or ()), str(entry.get("out_of_scope", "")))
    return models


TANGENTIAL_MODELS = load_registry()


def form_of(name: str, geometry: str) -> TangentialForm:
    """The reference's form of model `name` in `geometry`.

    Parameters
    ----------
    name : str
        A registry key (``lammps:mindlin``).
    geometry : str
        'sphere-sphere' or 'sphere-plane'.

    Raises
    ------
    KeyError
        For a name that is not in the registry, or a geometry it has no block for.
    NoReference
        Where its fields leave the reference's vocabulary (e.g. ESyS's 'no torque').
    """
    if name not in TANGENTIAL_MODELS:
        raise KeyError(f"unknown tangential model {name!r}; known: {', '.join(TANGENTIAL_MODELS)}")
    model = TANGENTIAL_MODELS[name]
    if geometry not in model.blocks:
        raise KeyError(f"{name} has no {geometry} contact (contact_model/tangential_models.yaml)")
    block = model.blocks[geometry]
    try:
        return TangentialForm(**{f: block[f] for f in FORM_FIELDS},
                              **{f: block.get(f, default) for f, default in OPTIONAL_FORM_FIELDS.items()})
    except (KeyError, ValueError, TypeError) as err:
        raise NoReference(f"{name} ({geometry}) is not a form of the reference yet: {err}") from None


#: The rules of a registry block's optional ``k_t0_rule`` (Mindlin's k_t0 [Pa] the reference takes).
K_T0_RULES = ("8G*", "16G/3 of E*")


def stiffness_constant(name: str, pair) -> float | None:
    r"""The Mindlin constant k_t0 [Pa] of model `name` in `pair`'s contact, as its own equations have it,
    or None for Mindlin's 8 G* (the reference's default; also for a linear stiffness, whose k_t [N/m]
    the deck gives).

    ``k_t0_rule: "16G/3 of E*"`` (ESyS's HertzMindlin, whose deck writes E = E*):

    .. math:: k_{t0} = \frac{16}{3} \frac{E^*}{2 (1 + \nu)}

    with nu the bodies' one Poisson's ratio (ESyS's interaction takes one).

    Parameters
    ----------
    name : str
        A registry key.
    pair : contact_model.ContactPair
        The contact (its E* [Pa] and bodies' Poisson's ratios).

    Raises
    ------
    ValueError
        Naming the registry file and field: an unknown rule, or bodies of two Poisson's ratios for a
        rule that takes one.
    """
    block = TANGENTIAL_MODELS[name].blocks[pair.geometry]
    rule = block.get("k_t0_rule", "8G*")
    if rule not in K_T0_RULES:
        raise ValueError(f"{REGISTRY_PATH}: {name}.k_t0_rule must be one of {K_T0_RULES}, got {rule!r}")
    if rule == "8G*":
        return None
    nus = {b.poisson for b in (pair.body_1, pair.body_2)}
    if len(nus) != 1 or None in nus:
        raise ValueError(f"{REGISTRY_PATH}: {name}.k_t0_rule {rule!r} takes one Poisson's ratio; the bodies have "
                         f"{pair.body_1.poisson!r} and {pair.body_2.poisson!r}")
    (nu,) = nus
    return 16.0 / 3.0 * pair.E / (2.0 * (1.0 + nu))


def models_for(code: str, banner: str) -> tuple[list[TangentialModel], dict[str, str]]:
    """The in-scope models of `code` that the release named by `banner` has, and {name: why} of
    those it lacks.

    Parameters
    ----------
    code : str
        The engine code.
    banner : str
        The build's version line.
    """
    have, missing = [], {}
    for model in TANGENTIAL_MODELS.values():
        if model.code != code or model.out_of_scope:
            continue
        why = model.absent_in(banner)
        if why:
            missing[model.name] = why
        else:
            have.append(model)
    return have, missing
