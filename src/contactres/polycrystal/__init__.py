"""Polycrystals: per-pixel contact properties of an orientation map (EBSD).

The orientations (private module ``_orientations``): Bunge Euler angles, quaternions and
(hkl)[uvw] as surface-frame matrices (the convention of
:func:`contactres.materials.rotation_to_surface`), the crystal symmetry groups (cubic,
hexagonal) and the reduction to a fundamental zone; the indentation modulus of many orientations
in one vectorised evaluation (:func:`indentation_moduli`) and its table over the standard
triangle (:func:`prepare_normal_table`).

The map container (:class:`OrientationMap`), the chunked per-pixel evaluation
(:func:`evaluate_map`: numpy, or dask on a cluster: the optional extra ``maps``) and Zarr IO
(``_maps``); .ang/.ctf/.h5oina exports (:func:`read_ebsd`, ``_ebsd``, ``_h5oina``, the phases
they name: ``_ebsd_phases``); seeded Voronoi polycrystals (:func:`synthetic_polycrystal`);
grains, the predicted contact-stiffness map (bare, and under films: :func:`coated_moduli`) and
the inverse fits of the elastic constants to a measured map (:func:`fit_map`).

The public names are loaded on first use (PEP 562 module ``__getattr__``); the modules that
implement them are private (scipy's rule): import from ``contactres.polycrystal``.
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the (private) module that defines it.
_EXPORTS = MappingProxyType(
    {
        "EBSD_READERS": "._ebsd",
        "read_ang": "._ebsd",
        "read_ctf": "._ebsd",
        "read_ebsd": "._ebsd",
        "write_ang": "._ebsd",
        "write_ctf": "._ebsd",
        "CUBIC_LATTICES": "._ebsd_phases",
        "EbsdPhase": "._ebsd_phases",
        "ebsd_phase": "._ebsd_phases",
        "read_h5oina": "._h5oina",
        "folded_normals": "._grains",
        "grain_orientations": "._grains",
        "segment_grains": "._grains",
        "GrainOrientations": "._grains",
        "fit_cubic_constants": "._inverse",
        "fit_map": "._inverse",
        "grain_means": "._inverse",
        "CubicInverseResult": "._inverse",
        "fit_hexagonal_constants": "._inverse_hexagonal",
        "HexagonalInverseResult": "._inverse_hexagonal",
        "ipf_colors": "._ipf",
        "ipf_triangle": "._ipf",
        "IPFTriangle": "._ipf",
        "TriangleModuli": "._ipf",
        "triangle_moduli": "._ipf",
        "MAP_CONVENTIONS": "._maps",
        "check_map_output": "._maps",
        "evaluate_map": "._maps",
        "map_from_dataset": "._maps",
        "map_to_dataset": "._maps",
        "read_map": "._maps",
        "write_map": "._maps",
        "ExactModulus": "._maps",
        "OrientationMap": "._maps",
        "MIN_CI": "._indexing",
        "IndexedPixels": "._indexing",
        "indexed_pixels": "._indexing",
        "indentation_moduli": "._moduli",
        "prepare_normal_table": "._normal_table",
        "reduce_normals": "._normal_table",
        "surface_matrices_from_normals": "._normal_table",
        "NormalTable": "._normal_table",
        "LATTICES": "._orientations",
        "euler_from_surface_matrices": "._orientations",
        "quaternions_from_surface_matrices": "._orientations",
        "random_orientations": "._orientations",
        "reduce_to_fundamental_zone": "._orientations",
        "surface_matrices_from_euler": "._orientations",
        "surface_matrices_from_quaternions": "._orientations",
        "surface_matrix_from_miller": "._orientations",
        "symmetry_operators": "._orientations",
        "CoatedModuli": "._coated",
        "coated_moduli": "._coated",
        "hill_poisson_ratio": "._coated",
        "contact_stiffness_map": "._predicted",
        "dynamic_factor_map": "._predicted",
        "map_wavenumbers": "._predicted",
        "ContactMap": "._predicted",
        "synthetic_polycrystal": "._synthetic",
        "SyntheticPolycrystal": "._synthetic",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._ebsd import (
        EBSD_READERS as EBSD_READERS,
        read_ang as read_ang,
        read_ctf as read_ctf,
        read_ebsd as read_ebsd,
        write_ang as write_ang,
        write_ctf as write_ctf,
    )
    from ._ebsd_phases import (
        CUBIC_LATTICES as CUBIC_LATTICES,
        EbsdPhase as EbsdPhase,
        ebsd_phase as ebsd_phase,
    )
    from ._h5oina import read_h5oina as read_h5oina
    from ._grains import (
        GrainOrientations as GrainOrientations,
        folded_normals as folded_normals,
        grain_orientations as grain_orientations,
        segment_grains as segment_grains,
    )
    from ._inverse import (
        CubicInverseResult as CubicInverseResult,
        fit_cubic_constants as fit_cubic_constants,
        fit_map as fit_map,
        grain_means as grain_means,
    )
    from ._inverse_hexagonal import (
        HexagonalInverseResult as HexagonalInverseResult,
        fit_hexagonal_constants as fit_hexagonal_constants,
    )
    from ._ipf import (
        IPFTriangle as IPFTriangle,
        ipf_colors as ipf_colors,
        ipf_triangle as ipf_triangle,
        TriangleModuli as TriangleModuli,
        triangle_moduli as triangle_moduli,
    )
    from ._maps import (
        ExactModulus as ExactModulus,
        MAP_CONVENTIONS as MAP_CONVENTIONS,
        OrientationMap as OrientationMap,
        check_map_output as check_map_output,
        evaluate_map as evaluate_map,
        map_from_dataset as map_from_dataset,
        map_to_dataset as map_to_dataset,
        read_map as read_map,
        write_map as write_map,
    )
    from ._indexing import (
        MIN_CI as MIN_CI,
        IndexedPixels as IndexedPixels,
        indexed_pixels as indexed_pixels,
    )
    from ._moduli import (
        indentation_moduli as indentation_moduli,
    )
    from ._normal_table import (
        NormalTable as NormalTable,
        prepare_normal_table as prepare_normal_table,
        reduce_normals as reduce_normals,
        surface_matrices_from_normals as surface_matrices_from_normals,
    )
    from ._orientations import (
        LATTICES as LATTICES,
        euler_from_surface_matrices as euler_from_surface_matrices,
        quaternions_from_surface_matrices as quaternions_from_surface_matrices,
        random_orientations as random_orientations,
        reduce_to_fundamental_zone as reduce_to_fundamental_zone,
        surface_matrices_from_euler as surface_matrices_from_euler,
        surface_matrices_from_quaternions as surface_matrices_from_quaternions,
        surface_matrix_from_miller as surface_matrix_from_miller,
        symmetry_operators as symmetry_operators,
    )
    from ._coated import (
        CoatedModuli as CoatedModuli,
        coated_moduli as coated_moduli,
        hill_poisson_ratio as hill_poisson_ratio,
    )
    from ._predicted import (
        ContactMap as ContactMap,
        contact_stiffness_map as contact_stiffness_map,
        dynamic_factor_map as dynamic_factor_map,
        map_wavenumbers as map_wavenumbers,
    )
    from ._synthetic import (
        SyntheticPolycrystal as SyntheticPolycrystal,
        synthetic_polycrystal as synthetic_polycrystal,
    )

    # isort: on

__getattr__, __dir__ = attach(__name__, _EXPORTS)
