"""Names of the displacement models and wave-number conventions of :mod:`contactres.dynamic`.

No numerics here, so that the command line can build its ``--model`` and ``--wavenumber`` choices
without importing scipy.
"""

from __future__ import annotations

__all__ = ["ALL_MODELS", "MODELS", "WAVENUMBERS"]

#: The displacement conditions (paper 1, Eqs. 24-28) plus the whole-contact weighted average.
MODELS = ("R0", "R1", "SA", "WA", "TP", "WA2D")
#: ... and the exact rigid-flat-punch solution (Galerkin, :mod:`contactres.dynamic._exact`).
ALL_MODELS = (*MODELS, "exact")
#: Normalisations of the wave number: k_l = ω√(ρ/C33) (the paper's figures), k_s = ω√(ρ/C44).
WAVENUMBERS = ("longitudinal", "shear")
