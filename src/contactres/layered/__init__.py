"""Layered substrates: bonded layers on an elastic half-space, and their surface response.

The modules that implement it are private (scipy's rule: import from ``contactres.layered``),
bottom up:

- ``_stack``: :class:`LayeredMaterial`, the stack (top layer first) of materials and
  thicknesses on a substrate, with frequency-dependent materials evaluated by ``at(f)``; the
  one thickness rule of contactres (:data:`MAX_THICKNESS_M`, :func:`checked_thickness`) and
  a thickness in words (:func:`thickness_text`).
- ``_expm``: the exponential of stacks of 3x3 matrices (scaling and squaring).
- ``_recursion``: the surface compliance of the stack by a stable impedance recursion over
  the half-space solutions of every layer (:func:`stack_compliance`, dimensionless; its two
  halves :func:`layer_waves` with :func:`substrate_impedance` and :func:`impedance_recursion`
  (or :func:`compliance_factors`, its compliance as a quotient), for callers that reuse the
  waves of a slowness at many wavenumbers) and the
  surface Green's function in SI units (:func:`surface_green`, m/Pa).

Bottom and interface conditions: welded interfaces (u and σ_i3 continuous), a substrate that
carries only decaying (lossless: outgoing) waves, the traction applied on the top surface.
Accuracy: see ``_recursion`` (and :func:`surface_green`).
"""

from __future__ import annotations

from ._expm import two_root_expm
from ._recursion import (
    compliance_factors,
    impedance_recursion,
    isotropic_moduli,
    layer_waves,
    stack_compliance,
    substrate_impedance,
    surface_green,
)
from ._stack import (
    MAX_THICKNESS_M,
    FrequencyDependentMaterial,
    LayeredMaterial,
    checked_thickness,
    material_at,
    thickness_text,
)

__all__ = [
    "MAX_THICKNESS_M",
    "FrequencyDependentMaterial",
    "LayeredMaterial",
    "checked_thickness",
    "compliance_factors",
    "impedance_recursion",
    "isotropic_moduli",
    "layer_waves",
    "material_at",
    "stack_compliance",
    "substrate_impedance",
    "surface_green",
    "thickness_text",
    "two_root_expm",
]
