"""Dynamic (frequency-dependent) contact stiffness of a sphere on an anisotropic half-space."""

from .normal_stiffness import (
    ALL_MODELS,
    MODELS,
    WAVENUMBERS,
    contact_displacement,
    contact_pressure,
    dcsf,
    dcsf_models,
    dynamic_contact_stiffness,
    shear_wavenumber_ratio,
)

__all__ = [
    "ALL_MODELS",
    "MODELS",
    "WAVENUMBERS",
    "contact_displacement",
    "contact_pressure",
    "dcsf",
    "dcsf_models",
    "dynamic_contact_stiffness",
    "shear_wavenumber_ratio",
]
