"""Hertz's small-contact limit, a ≪ R, checked where the Python API answers for a contact.

Hertz's theory, and the anisotropic and layered contacts built on it, take the sphere as a
paraboloid on a half-space in small strain (K. L. Johnson, *Contact Mechanics*, Cambridge
University Press (1985), §4.2: a/R ≲ 0.1). The command line flags a contact wider than that
(``contact``: a/R > 0.1 "Hertz approximate", values kept; a/R > 0.5 "beyond Hertz, no value",
the row left empty); :func:`checked` does the same for :func:`contactres.hertz` and
:func:`contactres.sphere_contact`: a :class:`contactres.errors.ContactresWarning` naming a/R,
and NaN for the values of a contact beyond a/R = 0.5 (issue 30: R = 20 nm and F = 1 N gave
a/R = 24 and p0 = 2 TPa without a word). The rule's numbers are
:data:`contactres.units.HERTZ_APPROXIMATE_RATIO` and :data:`~contactres.units.HERTZ_MAX_RATIO`.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ..errors import ContactresWarning
from ..units import HERTZ_APPROXIMATE_RATIO, HERTZ_MAX_RATIO

__all__ = ["checked"]

# The fields of a contact that answer for one (radius, force): left empty beyond Hertz. The
# force is the caller's; an anisotropic contact's moduli, orientation and ellipticity belong
# to the material, not to the contact's size.
_PER_CONTACT = (
    "contact_radius", "semi_major", "semi_minor", "depth", "mean_pressure", "peak_pressure",
    "stiffness",
)  # fmt: skip


def checked(contact, radius, function: str):
    """``contact`` (a frozen dataclass of :mod:`contactres.normal`) as the API returns it:
    warned about where a/R > 0.1, its values NaN where a/R > 0.5.

    Parameters
    ----------
    contact : Contact, AnisotropicContact or LayeredContact
        The computed contact; ``contact_radius`` a (m), per element of the broadcast inputs.
    radius : float or array
        The sphere radius R, m, as given (broadcasts against ``contact_radius``).
    function : str
        The function's name, for the message (``"hertz"``).

    Returns
    -------
    The same type: ``contact`` itself where every a/R <= 0.1; otherwise after one
    :class:`~contactres.errors.ContactresWarning`, with ``contact_radius``, the semi-axes, the
    depth, the pressures and the stiffness (and a layered contact's M(a)) NaN where
    a/R > 0.5.
    """
    a = np.asarray(contact.contact_radius, dtype=float)
    ratio = a / np.asarray(radius, dtype=float)
    over = ratio > HERTZ_APPROXIMATE_RATIO
    if not over.any():
        return contact
    worst = float(np.max(ratio[over]))
    beyond = ratio > HERTZ_MAX_RATIO
    where = "" if ratio.ndim == 0 else f" ({int(over.sum())} of {ratio.size} contacts)"
    if not beyond.any():
        warnings.warn(
            f"{function}: a/R = {worst:.3g} > {HERTZ_APPROXIMATE_RATIO:g}{where}: Hertz "
            "approximate (the theory takes the sphere as a paraboloid, for a ≪ R); values kept",
            ContactresWarning,
            stacklevel=3,
        )
        return contact
    warnings.warn(
        f"{function}: a/R = {worst:.3g} > {HERTZ_MAX_RATIO:g}"
        f"{'' if ratio.ndim == 0 else f' ({int(beyond.sum())} of {ratio.size} contacts)'}: "
        "beyond Hertz, no value (NaN); check the sphere radius (m) and the force (N)",
        ContactresWarning,
        stacklevel=3,
    )
    names = [*_PER_CONTACT, *(["indentation_modulus"] if "layered" in contact.model else [])]
    emptied = {}
    for name in names:
        if not hasattr(contact, name):
            continue
        value = np.asarray(getattr(contact, name), dtype=float)
        out = np.where(beyond, np.nan, value)
        emptied[name] = float(out) if out.ndim == 0 else out
    return dataclasses.replace(contact, **emptied)
