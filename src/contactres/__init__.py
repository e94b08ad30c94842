"""contactres: contact mechanics at resonance.

Forward models (Hertz/JKR/DMT, anisotropic half-spaces, dynamic contact stiffness, partial-slip
tangential loops, QCM frequency shifts) and the analysis of QCM amplitude sweeps. SI units
throughout (m, N, Pa, Hz, kg).
"""

from importlib.metadata import PackageNotFoundError, version

from .crystals import crystal_names, crystal_table
from .materials import Material

try:
    __version__ = version("contactres")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "Material",
    "__version__",
    "crystal_names",
    "crystal_table",
]
