"""The contact laws the study runs and the end-of-collision criteria it reads them with.

A law is a force model an engine is told to run:

- `viscoelastic`: F = -(k delta^{3/2} + A k delta^{1/2} d(delta)/dt), the Hertz elastic force plus
  the Kuwabara-Kono / Brilliantov dissipative force, with the attractive tail kept (negative F
  allowed near the end of contact);
- `viscoelastic_clipped`: the same force clipped at zero (F = max(F, 0));
- `elastic`: Hertz alone (A = 0);
- `default`: the engine's own restitution keyword (`engines.codes` ``keyword``, the registry of
  `contact_model.keywords`), told a restitution coefficient: gated against its own equation,
  x'' + b x^{1/4} x' + (5/4) x^{3/2} = 0 with the b its code computes from the e it is told
  (`reference.quarter_power_damping`); what it restitutes against what it was told is its promise,
  reported beside it.

The first three are the viscoelastic model under test (`MODEL_LAWS`: the paper's series and the
engines' discrete map describe them); all four are gated (`GATED_LAWS`).

A criterion is where a collision ends (reference.series): `x0` when the overlap returns to zero,
`F0` when the force does. The geometries are `contact_pair.GEOMETRIES`.
"""

from reference.series import CRITERIA

LAWS = ("viscoelastic", "viscoelastic_clipped", "elastic", "default")
#: The laws of the viscoelastic model under test (the paper's series and the engines' map are theirs).
MODEL_LAWS = ("viscoelastic", "viscoelastic_clipped", "elastic")
#: The laws the study validates against tolerances: the model's, and each engine's keyword against its own equation.
GATED_LAWS = (*MODEL_LAWS, "default")
#: The end-of-collision criteria a run of each model law stands for (`engines.RunSpec.represents`;
#: the default law's depends on the engine's keyword: `engines.run_spec.DEFAULT_LAW_CRITERION`).
LAW_CRITERIA = {"viscoelastic": ("x0", "F0"),  # the tail is kept: one trajectory, both ends
                "viscoelastic_clipped": ("F0",),
                "elastic": ("x0",)}  # no tail: x0 and F0 coincide

__all__ = ["CRITERIA", "GATED_LAWS", "LAWS", "LAW_CRITERIA", "MODEL_LAWS"]
