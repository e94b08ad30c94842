"""Normal contact: isotropic Hertz/JKR/DMT (``isotropic``) and anisotropic Hertz (``anisotropic``).

The public functions of both modules are re-exported here and from :mod:`contactres`.
"""

from .anisotropic import (  # noqa: F401
    AnisotropicContact,
    ContactIntegrals,
    contact_integrals,
    indentation_modulus,
    sphere_contact,
)
from .isotropic import (  # noqa: F401
    Contact,
    dmt,
    effective_modulus,
    effective_shear_modulus,
    hertz,
    jkr,
    jkr_contact_radius,
    jkr_from_depth,
    jkr_pull_off_force,
    shear_modulus,
    tabor_parameter,
    which_adhesion_model,
)
