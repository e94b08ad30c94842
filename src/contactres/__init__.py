"""contactres: contact mechanics at resonance.

Forward models (Hertz/JKR/DMT, anisotropic half-spaces, dynamic contact stiffness, partial-slip
tangential loops, QCM frequency shifts) and the analysis of QCM amplitude sweeps. SI units
throughout (m, N, Pa, Hz, kg).
"""

from importlib.metadata import PackageNotFoundError, version

from .analysis import AnalysisSettings, analyze
from .crystals import crystal_names, crystal_table
from .dynamic import (
    contact_displacement,
    contact_pressure,
    dcsf,
    dcsf_models,
    dynamic_contact_stiffness,
)
from .halfspace import dynamic_kernel, isotropic_dynamic_kernel, shear_reference, static_kernel
from .materials import Material
from .measurements.sweeps import SweepWarning, read_sweeps
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
from .report import Results
from .resonators.qcm import (
    QCM,
    cattaneo_mindlin_expansion,
    friction_from_slopes,
    loop_stiffness,
    savkoor_expansion,
    shifts_from_loop,
    shifts_from_stiffness,
    stiffness_from_shifts,
)
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
    "QCM",
    "AnalysisSettings",
    "AnisotropicContact",
    "CattaneoMindlinLoop",
    "Contact",
    "DashpotLoop",
    "MasingLoop",
    "Material",
    "PlateauLoop",
    "Results",
    "SavkoorLoop",
    "SweepWarning",
    "VoigtLoop",
    "__version__",
    "analyze",
    "cattaneo_mindlin_expansion",
    "contact_displacement",
    "contact_integrals",
    "contact_pressure",
    "crystal_names",
    "crystal_table",
    "dcsf",
    "dcsf_models",
    "dmt",
    "dynamic_contact_stiffness",
    "dynamic_kernel",
    "effective_modulus",
    "effective_shear_modulus",
    "friction_from_slopes",
    "hertz",
    "indentation_modulus",
    "isotropic_dynamic_kernel",
    "jkr",
    "jkr_contact_radius",
    "jkr_from_depth",
    "jkr_pull_off_force",
    "loop_stiffness",
    "mindlin_deresiewicz_energy",
    "mindlin_stiffness",
    "read_sweeps",
    "savkoor_expansion",
    "shear_modulus",
    "shear_reference",
    "shifts_from_loop",
    "shifts_from_stiffness",
    "sphere_contact",
    "static_kernel",
    "stiffness_from_shifts",
    "tabor_parameter",
    "which_adhesion_model",
    "with_dashpot",
]
