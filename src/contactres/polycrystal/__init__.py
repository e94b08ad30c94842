"""Polycrystals: per-pixel contact properties of an orientation map (EBSD).

:mod:`.orientations` holds the orientations: Bunge Euler angles, quaternions and (hkl)[uvw] as
surface-frame matrices (the convention of :func:`contactres.materials.rotation_to_surface`), the
crystal symmetry groups (cubic, hexagonal) and the reduction to a fundamental zone;
:mod:`.moduli` the indentation modulus of many orientations in one vectorised evaluation.

:mod:`.maps` holds the map container, the chunked per-pixel evaluation (numpy, or dask on a
cluster: the optional extra ``maps``) and Zarr IO; :mod:`.ebsd` reads .ang/.ctf exports;
:mod:`.synthetic` builds seeded Voronoi polycrystals.
"""

from .ebsd import read_ang, read_ctf, read_ebsd, write_ang, write_ctf
from .grains import GrainOrientations, folded_normals, grain_orientations, segment_grains
from .inverse import CubicInverseResult, fit_cubic_constants, fit_map, grain_means
from .inverse_hexagonal import HexagonalInverseResult, fit_hexagonal_constants
from .ipf import IPFTriangle, ipf_colors, ipf_triangle
from .maps import (
    MAP_CONVENTIONS,
    ExactModulus,
    OrientationMap,
    evaluate_map,
    map_from_dataset,
    map_to_dataset,
    read_map,
    write_map,
)
from .moduli import indentation_moduli
from .normal_table import NormalTable, prepare_normal_table, reduce_normals
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
from .predicted import contact_stiffness_map, dynamic_factor_map, map_wavenumbers
from .synthetic import SyntheticPolycrystal, synthetic_polycrystal

__all__ = [
    "LATTICES",
    "MAP_CONVENTIONS",
    "CubicInverseResult",
    "ExactModulus",
    "GrainOrientations",
    "HexagonalInverseResult",
    "IPFTriangle",
    "NormalTable",
    "OrientationMap",
    "SyntheticPolycrystal",
    "contact_stiffness_map",
    "dynamic_factor_map",
    "euler_from_surface_matrices",
    "evaluate_map",
    "fit_cubic_constants",
    "fit_hexagonal_constants",
    "fit_map",
    "folded_normals",
    "grain_means",
    "grain_orientations",
    "indentation_moduli",
    "ipf_colors",
    "ipf_triangle",
    "map_from_dataset",
    "map_to_dataset",
    "map_wavenumbers",
    "prepare_normal_table",
    "quaternions_from_surface_matrices",
    "random_orientations",
    "read_ang",
    "read_ctf",
    "read_ebsd",
    "read_map",
    "reduce_normals",
    "reduce_to_fundamental_zone",
    "segment_grains",
    "surface_matrices_from_euler",
    "surface_matrices_from_quaternions",
    "surface_matrix_from_miller",
    "symmetry_operators",
    "synthetic_polycrystal",
    "write_ang",
    "write_ctf",
    "write_map",
]
