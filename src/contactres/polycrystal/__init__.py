"""Polycrystals: per-pixel contact properties of an orientation map (EBSD).

:mod:`.orientations` holds the orientations: Bunge Euler angles, quaternions and (hkl)[uvw] as
surface-frame matrices (the convention of :func:`contactres.materials.rotation_to_surface`), the
crystal symmetry groups (cubic, hexagonal) and the reduction to a fundamental zone;
:mod:`.moduli` the indentation modulus of many orientations in one vectorised evaluation.
"""

from .moduli import indentation_moduli
from .orientations import (
    LATTICES,
    euler_from_surface_matrices,
    quaternions_from_surface_matrices,
    random_orientations,
    reduce_to_fundamental_zone,
    surface_matrices_from_euler,
    surface_matrices_from_quaternions,
    surface_matrix_from_miller,
    symmetry_operators,
)

__all__ = [
    "LATTICES",
    "euler_from_surface_matrices",
    "indentation_moduli",
    "quaternions_from_surface_matrices",
    "random_orientations",
    "reduce_to_fundamental_zone",
    "surface_matrices_from_euler",
    "surface_matrices_from_quaternions",
    "surface_matrix_from_miller",
    "symmetry_operators",
]
