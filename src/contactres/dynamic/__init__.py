"""Dynamic (frequency-dependent) contact stiffness of a sphere on an anisotropic half-space.

Paper 1: the displacement models R0, R1, SA, WA, TP (Eqs. 24-28), the whole-contact average WA2D
and the exact rigid flat punch, as DCSF = K_da/K_sa (Eq. 29). :func:`prepare` builds the kernel
table of a material once; pass it as ``prepared=`` to evaluate many curves of that material.
:func:`checked_dcsf_models` checks each value against a refined evaluation at run time (and
refines where it misses rtol), with an estimated error per value.

The tangential counterpart (a rigid disk translating tangentially; relaxed contact): the static
stiffness tensor (:func:`tangential_stiffness_static`), the exact dynamic one
(:func:`tangential_contact_stiffness`, :func:`tangential_dcsf`, table :func:`prepare_tangential`)
and two bodies in series (:func:`two_body_contact_stiffness`, the QCM contact of paper 2).

On a layered or viscoelastic substrate: the time-harmonic normal and tangential stiffness of
the rigid flat punch (:func:`layered_punch_stiffness`) and its DCSF (:func:`layered_dcsf`).

The public names are loaded on first use (PEP 562 module ``__getattr__``): the model names
(``MODELS``, ``ALL_MODELS``, ``WAVENUMBERS``) come without scipy, for the command line's options.
The modules that implement them are private (``_normal_stiffness``, ``_exact``, ``_table``, ...,
scipy's rule): import from ``contactres.dynamic``.
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the module that defines it.
_EXPORTS = MappingProxyType(
    {
        "ALL_MODELS": "._models",
        "MODELS": "._models",
        "WAVENUMBERS": "._models",
        "CheckedDCSF": "._convergence",
        "checked_dcsf_models": "._convergence",
        "KernelTable": "._table",
        "MAX_ISOTROPIC_POISSON": "._table",
        "MAX_STIFFNESS_CONTRAST": "._table",
        "prepare": "._table",
        "contact_displacement": "._normal_stiffness",
        "contact_pressure": "._normal_stiffness",
        "dcsf": "._dcsf",
        "dcsf_models": "._dcsf",
        "dynamic_contact_stiffness": "._dcsf",
        "flat_punch_stiffness": "._layered_punch",
        "layered_dcsf": "._layered_punch",
        "layered_punch_stiffness": "._layered_punch",
        "normalised_wavenumber": "._normal_stiffness",
        "shear_wavenumber_ratio": "._normal_stiffness",
        "wave_modulus": "._normal_stiffness",
        "KSA_MAX": "._tangential_table",
        "TangentialTable": "._tangential_table",
        "prepare_tangential": "._tangential_table",
        "tangential_contact_stiffness": "._tangential_stiffness",
        "tangential_dcsf": "._tangential_stiffness",
        "tangential_stiffness_static": "._tangential_static",
        "two_body_contact_stiffness": "._tangential_stiffness",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._convergence import (
        CheckedDCSF as CheckedDCSF,
        checked_dcsf_models as checked_dcsf_models,
    )
    from ._dcsf import (
        dcsf as dcsf,
        dcsf_models as dcsf_models,
        dynamic_contact_stiffness as dynamic_contact_stiffness,
    )
    from ._layered_punch import (
        flat_punch_stiffness as flat_punch_stiffness,
        layered_dcsf as layered_dcsf,
        layered_punch_stiffness as layered_punch_stiffness,
    )
    from ._models import (
        ALL_MODELS as ALL_MODELS,
        MODELS as MODELS,
        WAVENUMBERS as WAVENUMBERS,
    )
    from ._normal_stiffness import (
        contact_displacement as contact_displacement,
        contact_pressure as contact_pressure,
        normalised_wavenumber as normalised_wavenumber,
        shear_wavenumber_ratio as shear_wavenumber_ratio,
        wave_modulus as wave_modulus,
    )
    from ._table import (
        KernelTable as KernelTable,
        MAX_ISOTROPIC_POISSON as MAX_ISOTROPIC_POISSON,
        MAX_STIFFNESS_CONTRAST as MAX_STIFFNESS_CONTRAST,
        prepare as prepare,
    )
    from ._tangential_static import (
        tangential_stiffness_static as tangential_stiffness_static,
    )
    from ._tangential_stiffness import (
        tangential_contact_stiffness as tangential_contact_stiffness,
        tangential_dcsf as tangential_dcsf,
        two_body_contact_stiffness as two_body_contact_stiffness,
    )
    from ._tangential_table import (
        KSA_MAX as KSA_MAX,
        TangentialTable as TangentialTable,
        prepare_tangential as prepare_tangential,
    )

    # isort: on


__getattr__, __dir__ = attach(__name__, _EXPORTS)
