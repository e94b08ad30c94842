"""contactres: contact mechanics at resonance.

Forward models (Hertz/JKR/DMT, anisotropic half-spaces, dynamic contact stiffness, partial-slip
tangential loops, QCM frequency shifts) and the analysis of QCM amplitude sweeps. SI units
throughout (m, N, Pa, Hz, kg).
"""

from importlib.metadata import PackageNotFoundError, version

from .analysis import AnalysisSettings, analyze
from .crystals import crystal_names, crystal_table
from .halfspace import dynamic_kernel, isotropic_dynamic_kernel, shear_reference, static_kernel
from .materials import Material
from .normal.anisotropic import (
    AnisotropicContact,
    contact_integrals,
    indentation_modulus,
    sphere_contact,
)
from .normal.isotropic import (
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
from .qcm import (
    QCM,
    cattaneo_mindlin_expansion,
    friction_from_slopes,
    loop_stiffness,
    savkoor_expansion,
    shifts_from_loop,
    shifts_from_stiffness,
    stiffness_from_shifts,
)
from .report import Results
from .sweeps import SweepWarning, read_sweeps
from .tangential import (
    CattaneoMindlinLoop,
    DashpotLoop,
    MasingLoop,
    PlateauLoop,
    SavkoorLoop,
    VoigtLoop,
    mindlin_deresiewicz_energy,
    mindlin_stiffness,
    with_dashpot,
)

try:
    __version__ = version("contactres")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "AnalysisSettings",
    "Results",
    "SweepWarning",
    "analyze",
    "read_sweeps",
    "CattaneoMindlinLoop",
    "Contact",
    "DashpotLoop",
    "MasingLoop",
    "PlateauLoop",
    "QCM",
    "SavkoorLoop",
    "VoigtLoop",
    "cattaneo_mindlin_expansion",
    "dmt",
    "effective_modulus",
    "effective_shear_modulus",
    "friction_from_slopes",
    "hertz",
    "jkr",
    "jkr_contact_radius",
    "jkr_from_depth",
    "jkr_pull_off_force",
    "loop_stiffness",
    "mindlin_deresiewicz_energy",
    "mindlin_stiffness",
    "savkoor_expansion",
    "shear_modulus",
    "shifts_from_loop",
    "shifts_from_stiffness",
    "stiffness_from_shifts",
    "tabor_parameter",
    "which_adhesion_model",
    "with_dashpot",
    "AnisotropicContact",
    "Material",
    "contact_integrals",
    "dynamic_kernel",
    "indentation_modulus",
    "isotropic_dynamic_kernel",
    "shear_reference",
    "sphere_contact",
    "static_kernel",
    "__version__",
    "crystal_names",
    "crystal_table",
]
