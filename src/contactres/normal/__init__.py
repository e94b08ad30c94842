"""Normal contact: isotropic Hertz/JKR/DMT (``_isotropic``), anisotropic Hertz (``_anisotropic``)
and the axisymmetric contact on a coated (layered) substrate (``_axisymmetric``: the solver on a
wave-number-dependent compliance; ``_layered``: the punch, sphere and M(a) on a
:class:`~contactres.LayeredMaterial`). These modules are private (scipy's rule): import from
``contactres.normal``. The anisotropic Hertz contact is an ellipse (:func:`contact_ellipse`).

The public functions of these modules are re-exported here and from :mod:`contactres`
(:func:`sphere_contact` is the one of ``_layered``, which hands a homogeneous material to the
anisotropic Hertz contact of ``_anisotropic``). Beside them, the pieces of the anisotropic
contact that the polycrystal moduli and the dynamic tables build on: the stiffness contrast of a
solid (:func:`stiffness_contrast`, :func:`contrast_poisson`), the isotropic constants of a
stiffness (:func:`isotropic_constants`) and the default accuracy of the θ integrals
(``THETA_RTOL``). They are loaded on first use (PEP 562 module ``__getattr__``): a caller of the
isotropic formulas (the tangential loops, the QCM analysis) does not import the anisotropic
half-space behind ``_anisotropic``.
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the module that defines it.
_EXPORTS = MappingProxyType(
    {
        "AnisotropicContact": "._anisotropic",
        "ContactEllipse": "._anisotropic",
        "ContactIntegrals": "._anisotropic",
        "contact_ellipse": "._anisotropic",
        "contact_integrals": "._anisotropic",
        "indentation_modulus": "._anisotropic",
        "THETA_RTOL": "._anisotropic",
        "contrast_poisson": "._anisotropic",
        "isotropic_constants": "._anisotropic",
        "stiffness_contrast": "._anisotropic",
        "LayeredContact": "._layered",
        "static_punch_stiffness": "._layered",
        "indentation_modulus_at": "._layered",
        "sphere_contact": "._layered",
        "sphere_contact_at": "._layered",
        "Contact": "._isotropic",
        "dmt": "._isotropic",
        "effective_modulus": "._isotropic",
        "effective_shear_modulus": "._isotropic",
        "hertz": "._isotropic",
        "jkr": "._isotropic",
        "jkr_contact_radius": "._isotropic",
        "jkr_from_depth": "._isotropic",
        "jkr_pull_off_force": "._isotropic",
        "shear_modulus": "._isotropic",
        "tabor_parameter": "._isotropic",
        "which_adhesion_model": "._isotropic",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._anisotropic import (
        AnisotropicContact as AnisotropicContact,
        ContactEllipse as ContactEllipse,
        ContactIntegrals as ContactIntegrals,
        THETA_RTOL as THETA_RTOL,
        contact_ellipse as contact_ellipse,
        contact_integrals as contact_integrals,
        contrast_poisson as contrast_poisson,
        indentation_modulus as indentation_modulus,
        isotropic_constants as isotropic_constants,
        stiffness_contrast as stiffness_contrast,
    )
    from ._isotropic import (
        Contact as Contact,
        dmt as dmt,
        effective_modulus as effective_modulus,
        effective_shear_modulus as effective_shear_modulus,
        hertz as hertz,
        jkr as jkr,
        jkr_contact_radius as jkr_contact_radius,
        jkr_from_depth as jkr_from_depth,
        jkr_pull_off_force as jkr_pull_off_force,
        shear_modulus as shear_modulus,
        tabor_parameter as tabor_parameter,
        which_adhesion_model as which_adhesion_model,
    )
    from ._layered import (
        LayeredContact as LayeredContact,
        static_punch_stiffness as static_punch_stiffness,
        indentation_modulus_at as indentation_modulus_at,
        sphere_contact as sphere_contact,
        sphere_contact_at as sphere_contact_at,
    )

    # isort: on


__getattr__, __dir__ = attach(__name__, _EXPORTS)
