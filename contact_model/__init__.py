"""From a material to the contact model and on to each engine's parameters (SI units inside)."""

from .case_file import Case, CaseError, load_case, parse_case
from .contact_pair import GEOMETRIES, Body, ContactPair
from .laws import CRITERIA, GATED_LAWS, KEYWORD_LAWS, LAW_CRITERIA, LAW_REGISTRY, LAWS, MODEL_LAWS
from .effective import effective_mass, effective_modulus, effective_radius, sphere_mass

__all__ = ["Case", "CaseError", "load_case", "parse_case", "CRITERIA", "GATED_LAWS", "KEYWORD_LAWS", "LAW_REGISTRY",
           "GEOMETRIES", "LAW_CRITERIA", "MODEL_LAWS", "LAWS", "Body", "ContactPair",
           "effective_mass", "effective_modulus", "effective_radius", "sphere_mass"]
