"""The public API stays put, and users' type checkers see it.

In the manner of scipy's ``scipy/_lib/tests/test_public_api.py``, the public names are pinned here
as literal lists: adding or removing a public name is a deliberate edit of this file, not a side
effect of an edit elsewhere.

* ``contactres.__all__`` exactly (the names the API reference, docs/api.md, lists;
  tests/report/test_docs_site.py keeps that reference complete).
* The subpackages ``contactres`` loads on attribute access.
* For each public subpackage (or module) with names of its own, every name of its ``__all__``:
  each is public and listed at its public path in the API reference, docs/api.md
  (tests/report/test_docs_site.py). A helper that is not meant for users has a leading
  underscore and is in no ``__all__``.
* The modules of ``contactres.jobs``, one per workflow, and the names of each: ``Settings``,
  ``Result`` and ``run`` are the public API of every job (docs/developer/adding.md).
* scipy's rule (its ``test_all_modules_are_expected``): the public surface of a subpackage is its
  ``__init__``, the modules that implement it are private (``contactres/dynamic/_exact.py``).
  Every module without a leading underscore is a package or one of the public modules pinned in
  ``PUBLIC_MODULES`` (or, until a later step, ``NOT_YET_PRIVATE``); and ``dir()`` of a
  subpackage that loads its names lazily is exactly its pinned names (and public submodules).

Type checking: the package ships ``py.typed`` (PEP 561), and the lazily loaded names of
``contactres`` and its lazy subpackages (PEP 562 ``__getattr__``) are also imported under
``if TYPE_CHECKING:``, which never runs; the imports must name exactly the lazy ones, and mypy,
run on a user's file, must reveal the real signatures, not ``Any``.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import pkgutil
import sys
import types
from pathlib import Path

import pytest

import contactres

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

PACKAGE_DIR = Path(contactres.__file__).parent
PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"

# contactres.__all__, exactly.
TOP_LEVEL = [
    "AIR",
    "AnalysisSettings",
    "AnisotropicContact",
    "Cantilever",
    "CattaneoMindlinLoop",
    "ConstantLoss",
    "Contact",
    "ContactResonanceResult",
    "DashpotLoop",
    "FilmModulusResult",
    "Flag",
    "LayeredContact",
    "LayeredMaterial",
    "MasingLoop",
    "Material",
    "Medium",
    "ModulusResult",
    "ModulusTable",
    "Particle",
    "ParticleFit",
    "PlateauLoop",
    "PowerLaw",
    "Prony",
    "QCM",
    "RUMOscillator",
    "Results",
    "SavkoorLoop",
    "SweepTable",
    "SweepWarning",
    "ViscoelasticMaterial",
    "VoigtLoop",
    "WATER",
    "__version__",
    "analyze",
    "at_cut_quartz",
    "cattaneo_mindlin_expansion",
    "contact_displacement",
    "contact_ellipse",
    "contact_frequencies",
    "contact_integrals",
    "contact_pressure",
    "coupled_resonance",
    "crystal_names",
    "crystal_table",
    "dart_reconstruct",
    "dcsf",
    "dcsf_models",
    "dmt",
    "dynamic_contact_stiffness",
    "dynamic_kernel",
    "effective_modulus",
    "effective_shear_modulus",
    "example_afm_map",
    "example_path",
    "film_modulus_from_contact_stiffness",
    "fit_particles",
    "flat_punch_stiffness",
    "friction_from_slopes",
    "hertz",
    "indentation_modulus",
    "indentation_modulus_at",
    "invert_afm_table",
    "invert_contact_resonance",
    "invert_cr_map",
    "invert_rum_table",
    "isotropic_dynamic_kernel",
    "jkr",
    "jkr_contact_radius",
    "jkr_from_depth",
    "jkr_pull_off_force",
    "kanazawa_gordon",
    "loop_stiffness",
    "medium_named",
    "mindlin_deresiewicz_energy",
    "mindlin_stiffness",
    "modulus_from_contact_stiffness",
    "particle_model_validity",
    "particle_shifts",
    "particle_stiffness",
    "penetration_depth",
    "pmma",
    "read_ibw",
    "read_resonance_table",
    "read_sweeps",
    "savkoor_expansion",
    "shear_modulus",
    "shear_reference",
    "shifts_from_loop",
    "shifts_from_stiffness",
    "sphere_contact",
    "static_kernel",
    "stiffness_from_shifts",
    "surface_green",
    "tabor_parameter",
    "tangential_contact_stiffness",
    "tangential_dcsf",
    "tangential_stiffness_static",
    "two_body_contact_stiffness",
    "validate_sweeps",
    "which_adhesion_model",
    "with_dashpot",
    "write_report",
]

# The subpackages and modules `contactres.X` loads on first access (the CLI is left out on
# purpose). jobs defines no names of its own and imports none of its modules: its public names
# are its modules (JOBS, below).
SUBPACKAGES = [
    "analysis",
    "apps",
    "crystals",
    "dynamic",
    "examples",
    "fileio",
    "fitting",
    "halfspace",
    "jobs",
    "layered",
    "materials",
    "measurements",
    "normal",
    "numerics",
    "polycrystal",
    "report",
    "resonators",
    "tangential",
    "units",
    "validation",
    "viscoelastic",
]

# The workflows of contactres.jobs, one module each (`from contactres.jobs import dcsf`), and the
# two modules beside them: the contract every job keeps and the computations of the map jobs.
JOBS = [
    "afm_invert",
    "afm_map",
    "contact",
    "crystals",
    "dcsf",
    "demo",
    "examples",
    "maps_fit",
    "maps_predict",
    "maps_synthetic",
    "paper1",
    "paper2",
    "qcm_loop",
    "qcm_particles",
    "qcm_spectra",
    "qcm_stiffness",
    "qcm_sweeps",
    "rum_invert",
]
JOB_HELPERS = ["contract", "maps", "readers"]
# The public API of every job (docs/developer/adding.md: always the same three names).
JOB_API = ["Result", "Settings", "run"]

# Documented names of each subpackage's __all__ (normal has no __all__: the names it re-exports).
PUBLIC = {
    "examples": ["EXAMPLES", "Example", "copy_examples", "example_path"],
    "analysis": [
        "AnalysisSettings",
        "CR_MAP_FLAGS",
        "CR_MAP_UNITS",
        "DART_FLAGS",
        "DESCRIPTIONS",
        "DartReconstruction",
        "FIGURE_POINTS",
        "FILM_COLUMNS",
        "FILM_VERDICTS",
        "FLAG_DESCRIPTIONS",
        "FilmModulusResult",
        "Flag",
        "LIMIT_CHI2",
        "ModulusModel",
        "ModulusResult",
        "PAGE_POINTS",
        "PARTICLE_FLAGS",
        "ParticleFit",
        "REGISTRY",
        "RELATIVE_ERROR_LIMIT",
        "Results",
        "analyze",
        "dart_flag_names",
        "dart_reconstruct",
        "dart_reconstruction",
        "figure_examples",
        "film_columns",
        "film_modulus_from_contact_stiffness",
        "fit_jkr_mindlin",
        "fit_particles",
        "has",
        "invert_afm_table",
        "invert_cr_map",
        "invert_rum_table",
        "material_by_name",
        "modulus_from_contact_stiffness",
        "radiation_for",
        "radiation_loss",
        "radiation_summary",
        "render",
        "sweep_rows",
    ],
    "crystals": [
        "CrystalRecord",
        "crystal_names",
        "crystal_record",
        "crystal_table",
    ],
    "dynamic": [
        "ALL_MODELS",
        "CheckedDCSF",
        "KSA_MAX",
        "KernelTable",
        "MAX_ISOTROPIC_POISSON",
        "MAX_STIFFNESS_CONTRAST",
        "MODELS",
        "TangentialTable",
        "WAVENUMBERS",
        "checked_dcsf_models",
        "contact_displacement",
        "contact_pressure",
        "dcsf",
        "dcsf_models",
        "dynamic_contact_stiffness",
        "flat_punch_stiffness",
        "layered_dcsf",
        "layered_punch_stiffness",
        "normalised_wavenumber",
        "prepare",
        "prepare_tangential",
        "shear_wavenumber_ratio",
        "tangential_contact_stiffness",
        "tangential_dcsf",
        "tangential_stiffness_static",
        "two_body_contact_stiffness",
        "wave_modulus",
    ],
    "halfspace": [
        "dynamic_kernel",
        "has_mirror_plane",
        "inv3",
        "isotropic_dynamic_kernel",
        "mm",
        "scaled_tensor",
        "shear_reference",
        "stacked_normal_compliance",
        "static_kernel",
        "surface_compliance",
        "surface_compliance_pair",
        "transpose",
    ],
    "layered": [
        "MAX_THICKNESS_M",
        "FrequencyDependentMaterial",
        "LayeredMaterial",
        "checked_thickness",
        "compliance_factors",
        "impedance_recursion",
        "isotropic_moduli",
        "layer_waves",
        "material_at",
        "stack_compliance",
        "substrate_impedance",
        "surface_green",
        "thickness_text",
        "two_root_expm",
    ],
    "materials": [
        "AT_CUT_ANGLE",
        "Material",
        "at_cut_quartz",
        "require_material",
        "rotate_tensor",
        "rotation_to_surface",
        "tensor_to_voigt",
        "voigt_to_tensor",
    ],
    "measurements": [
        "ArrayTable",
        "CONSTANTS",
        "D26_AT",
        "EXAMPLE_SEED",
        "ExampleLever",
        "FLAGS",
        "IgorWave",
        "NAMED_SURFACES",
        "ResonanceMaps",
        "SHO_FIELDS",
        "PARTICLE_EXAMPLE_SEED",
        "ParticleStudy",
        "SweepGroup",
        "SweepStudy",
        "SweepTable",
        "SweepWarning",
        "at_cell",
        "check_frequency_map",
        "dart_frequency_Hz",
        "example_afm_map",
        "example_study",
        "fit_resonances",
        "is_spectra_input",
        "parse_note",
        "read_be_sho",
        "read_ibw",
        "read_resonance_grid",
        "read_resonance_table",
        "read_spectra_sweeps",
        "read_sweeps",
        "spectra_from_sweeps",
        "synthetic_particle_study",
        "synthetic_spectra",
        "synthetic_sweeps",
        "validate_sweeps",
        "validation_study",
        "where_rows",
    ],
    "normal": [
        "AnisotropicContact",
        "Contact",
        "ContactEllipse",
        "ContactIntegrals",
        "LayeredContact",
        "THETA_RTOL",
        "contact_ellipse",
        "contact_integrals",
        "contrast_poisson",
        "dmt",
        "effective_modulus",
        "effective_shear_modulus",
        "hertz",
        "indentation_modulus",
        "indentation_modulus_at",
        "isotropic_constants",
        "jkr",
        "jkr_contact_radius",
        "jkr_from_depth",
        "jkr_pull_off_force",
        "shear_modulus",
        "sphere_contact",
        "sphere_contact_at",
        "static_punch_stiffness",
        "stiffness_contrast",
        "tabor_parameter",
        "which_adhesion_model",
    ],
    "polycrystal": [
        "CUBIC_LATTICES",
        "CoatedModuli",
        "ContactMap",
        "CubicInverseResult",
        "EBSD_READERS",
        "EbsdPhase",
        "ExactModulus",
        "GrainOrientations",
        "HexagonalInverseResult",
        "IPFTriangle",
        "IndexedPixels",
        "LATTICES",
        "MAP_CONVENTIONS",
        "MIN_CI",
        "NormalTable",
        "OrientationMap",
        "SyntheticPolycrystal",
        "TriangleModuli",
        "check_map_output",
        "coated_moduli",
        "contact_stiffness_map",
        "dynamic_factor_map",
        "ebsd_phase",
        "euler_from_surface_matrices",
        "evaluate_map",
        "fit_cubic_constants",
        "fit_hexagonal_constants",
        "fit_map",
        "folded_normals",
        "grain_means",
        "grain_orientations",
        "hill_poisson_ratio",
        "indentation_moduli",
        "indexed_pixels",
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
        "read_h5oina",
        "read_map",
        "reduce_normals",
        "reduce_to_fundamental_zone",
        "segment_grains",
        "surface_matrices_from_euler",
        "surface_matrices_from_normals",
        "surface_matrices_from_quaternions",
        "surface_matrix_from_miller",
        "symmetry_operators",
        "synthetic_polycrystal",
        "triangle_moduli",
        "write_ang",
        "write_ctf",
        "write_map",
    ],
    "apps": [
        "check_demo_output",
        "write_demo",
    ],
    "resonators": [
        "AIR",
        "Cantilever",
        "ContactResonanceResult",
        "DEFAULT_NODES",
        "FREE_ROOTS",
        "FREE_TOLERANCE",
        "MODE_TOLERANCE",
        "Medium",
        "Particle",
        "QCM",
        "RUMOscillator",
        "VALIDITY_RADIUS_RATIO",
        "WATER",
        "cattaneo_mindlin_expansion",
        "contact_frequencies",
        "coupled_resonance",
        "flag_names",
        "friction_from_slopes",
        "invert_contact_resonance",
        "kanazawa_gordon",
        "loop_stiffness",
        "masing_stiffness",
        "medium_named",
        "mu_from_slopes",
        "particle_compliance",
        "particle_model_validity",
        "particle_shifts",
        "particle_stiffness",
        "penetration_depth",
        "savkoor_expansion",
        "shifts_from_loop",
        "shifts_from_stiffness",
        "sphere_drag",
        "stiffness_from_shifts",
    ],
    "report": [
        "FORMATS",
        "friction_table",
        "html_report",
        "loads_table",
        "modulus_map_figure",
        "prediction_figure",
        "radiation_lines",
        "report_names",
        "report_set",
        "summary",
        "sweeps_table",
        "table1_text",
        "withheld_lines",
        "write_html",
        "write_report",
    ],
    "viscoelastic": [
        "ConstantLoss",
        "Law",
        "ModulusTable",
        "PMMA_DENSITY",
        "PMMA_LONGITUDINAL_SPEED",
        "PMMA_SHEAR_SPEED",
        "PMMA_STATIC_E",
        "PMMA_STATIC_FREQUENCY",
        "PMMA_STATIC_POISSON",
        "PMMA_ULTRASONIC_FREQUENCY",
        "PowerLaw",
        "Prony",
        "STATIC_FREQUENCY_HZ",
        "ViscoelasticMaterial",
        "material_at",
        "pmma",
        "static_solid",
    ],
    "tangential": [
        "CattaneoMindlinLoop",
        "DashpotLoop",
        "HysteresisLoop",
        "MasingLoop",
        "PlateauLoop",
        "SavkoorLoop",
        "VoigtLoop",
        "kappa_jkr_mindlin",
        "mindlin_deresiewicz_energy",
        "mindlin_stiffness",
        "with_dashpot",
    ],
    "fileio": [
        "CSV_FLOAT_FORMAT",
        "MANIFEST",
        "OutputError",
        "ResultSet",
        "check_output",
        "check_output_file",
        "ensure_dir",
        "neutralised",
        "replace_folder",
        "save_figure",
        "write_bytes",
        "write_csv",
        "write_npz",
        "write_text",
    ],
    "fitting": [
        "FitResult",
        "LMOptions",
        "LeastSquaresResult",
        "Model",
        "ModelRegistry",
        "Parameter",
        "fit",
        "levenberg_marquardt",
        "solve_stacked",
    ],
    "jobs.maps": [
        "METHODS",
        "TipLoad",
        "check_tip_load",
        "fit_measured_map",
        "fit_record",
        "open_map",
        "predict_map",
        "read_value_grid",
        "synthetic_map",
    ],
    "numerics": [
        "IllinoisBracket",
        "column_run_starts",
        "factorize_at_runs",
        "factorize_runs",
        "gauss_legendre",
        "gauss_legendre_unit",
        "illinois_step",
        "lobatto_weights",
        "object_pointers",
        "repeat_runs",
        "run_starts",
    ],
    "units": [
        "ABSOLUTE_FREQUENCY_FRACTION",
        "HERTZ_APPROXIMATE_RATIO",
        "HERTZ_MAX_RATIO",
        "JUNCTION_SIGMAS",
        "LINEAR_ONSET_X",
        "MAX_AMPLITUDE_M",
        "MAX_MU",
        "MIN_AMPLITUDE_M",
        "MIN_SWEEP_POINTS",
        "POISSON_OPEN_RANGE",
        "Plausible",
        "QUANTITIES",
        "SMALL_LOAD_LIMIT",
        "check_magnitude",
        "format_number",
        "unit_slip",
    ],
    "validation": [
        "amplitude",
        "nonnegative",
        "positive",
    ],
    **{f"jobs.{job}": JOB_API for job in JOBS},
    "jobs.afm_invert": [
        *JOB_API,
        "add_film_columns",
        "coated_film",
        "film_names",
    ],
    "jobs.afm_map": [
        *JOB_API,
        "DART_LAYERS",
        "MapInput",
        "PHASE_SIGNS",
        "read_input",
        "series",
    ],
    "jobs.contact": [
        *JOB_API,
        "HERTZ_APPROXIMATE_RATIO",
        "HERTZ_MAX_RATIO",
        "MAX_COATING_LAYERS",
        "STATIC_FREQUENCY_HZ",
        "coating_materials",
        "parse_coating",
    ],
    "jobs.demo": [
        *JOB_API,
        "COATED_CONTACT",
        "CRYSTAL_DCSF_MODEL",
        "CR_MAP",
        "STEPS",
    ],
    "jobs.maps_predict": [
        *JOB_API,
        "TRIANGLE_GRID",
        "check_phase_name",
    ],
    "jobs.paper1": [
        *JOB_API,
        "DISPLACEMENT_KLA",
        "KLA",
        "LOSS",
        "PAPER_MODELS",
        "POISSONS",
        "STEMS",
        "ZENERS",
        "crystal_curves",
        "cubic",
        "displacement",
        "fig3_curves",
        "ranking_table",
        "wa_with_exact",
    ],
    "jobs.paper2": [
        *JOB_API,
        "Paper2Example",
        "loops_table",
        "shifts_table",
    ],
    "jobs.qcm_loop": [
        *JOB_API,
        "MODELS",
    ],
    "jobs.qcm_particles": [
        *JOB_API,
        "COLUMN_UNITS",
        "CONVENTIONS",
        "EQUATION",
        "ROCKING",
    ],
    "jobs.qcm_stiffness": [
        *JOB_API,
        "COLUMN_UNITS",
        "EQUATION",
        "stiffness_table",
    ],
    "jobs.qcm_sweeps": [
        *JOB_API,
        "Reading",
        "coating_layers",
        "loads_table",
        "radiation_table",
        "read",
        "stages",
        "summary",
        "sweeps_table",
        "warning_lines",
    ],
    "jobs.contract": [
        "JobResult",
        "Progress",
        "json_value",
        "say",
    ],
    "jobs.readers": [
        "ALL_READERS",
        "GRID_READER",
        "read_afm_map_file",
        "read_ebsd_file",
        "read_grid_file",
        "read_value_grid",
    ],
}

# scipy's rule: a subpackage's public surface is its ``__init__``; the modules that implement it
# are private (``contactres/dynamic/_exact.py``). The modules below have no leading underscore
# and are public on purpose: the top-level single modules, one module per workflow of
# contactres.jobs (and the three beside them), and the modules the docs present as modules.
PUBLIC_MODULES = [
    "contactres.apps.afm_map",  # the command line and the demo write a CR map's folder with it
    "contactres.apps.paper1",  # the gallery calls its figure functions
    "contactres.apps.paper2",
    "contactres.crystals",
    "contactres.errors",
    "contactres.examples",
    "contactres.fileio",
    "contactres.fitting",
    *(f"contactres.jobs.{m}" for m in (*JOBS, *JOB_HELPERS)),
    "contactres.materials",
    "contactres.numerics",
    "contactres.report.dictionary",  # the data dictionary page (docs/dictionary.md)
    "contactres.report.figures",  # the gallery's figures; key_below for every figure
    "contactres.tangential",
    "contactres.typed_units",  # values typed with their unit, to SI (pint)
    "contactres.units",
    "contactres.validation",
    "contactres.viscoelastic",
]

# Implementation modules that do not have their leading underscore yet (a later step, after
# the work under way in these subpackages): this list only shrinks.
NOT_YET_PRIVATE: list[str] = []

# Subpackages whose ``__init__`` loads its public names on first use through
# ``contactres._lazy.attach`` (dir() is then exactly the public names and public submodules).
LAZY_PACKAGES = [
    "analysis",
    "apps",
    "dynamic",
    "measurements",
    "normal",
    "polycrystal",
    "report",
    "resonators",
]


def own_names(module: types.ModuleType) -> set[str]:
    """``__all__``, else the public attributes that are not modules (a re-exporting package)."""
    if hasattr(module, "__all__"):
        return set(module.__all__)
    return {
        name
        for name, value in vars(module).items()
        if not name.startswith("_") and not isinstance(value, types.ModuleType)
    }


# --- the names ---------------------------------------------------------------------------------


def test_top_level_names_are_pinned():
    assert sorted(contactres.__all__) == TOP_LEVEL


def test_subpackages_are_pinned():
    assert sorted(contactres._SUBMODULES) == SUBPACKAGES


@pytest.mark.parametrize("name", [*SUBPACKAGES, *(f"jobs.{m}" for m in (*JOBS, *JOB_HELPERS))])
def test_subpackage_names_are_pinned(name):
    module = importlib.import_module(f"contactres.{name}")
    public = set(PUBLIC.get(name, []))
    assert own_names(module) == public
    missing = sorted(n for n in public if not hasattr(module, n))
    assert not missing, f"contactres.{name}: pinned public names that do not resolve: {missing}"


# The reader registry, a public subpackage of contactres.measurements (docs/api.md).
READERS = [
    "BUILT_IN",
    "BUILT_IN_READERS",
    "CONSTANT_COLUMNS",
    "KINDS",
    "LABELS",
    "NUMERIC_LABELS",
    "RESONANCE_READERS",
    "Reader",
    "Readers",
    "SPECTRUM_LAYOUTS",
    "SweepReader",
    "TWO_PORT_PARAMETERS",
    "cells_as_numbers",
    "line_ranges",
    "pick_reader",
]


def test_the_reader_registrys_names_are_pinned():
    module = importlib.import_module("contactres.measurements.readers")
    assert sorted(module.__all__) == READERS
    missing = [n for n in READERS if not hasattr(module, n)]
    assert not missing, f"contactres.measurements.readers: names that do not resolve: {missing}"


def test_job_modules_are_pinned():
    import contactres.jobs as jobs

    found = {info.name for info in pkgutil.iter_modules(jobs.__path__)}
    assert sorted(found) == sorted([*JOBS, *JOB_HELPERS])


@pytest.mark.parametrize("name", JOBS)
def test_every_job_keeps_the_contract(name):
    """Settings and Result frozen dataclasses, Result a JobResult, run(inputs, settings,
    progress, ...): what docs/developer/adding.md promises of every job."""
    from contactres.jobs.contract import JobResult

    job = importlib.import_module(f"contactres.jobs.{name}")
    for cls in (job.Settings, job.Result):
        assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen, cls
    assert issubclass(job.Result, JobResult)
    assert list(inspect.signature(job.run).parameters)[:3] == ["inputs", "settings", "progress"]


def _library_modules() -> dict[str, bool]:
    """Every module of the installed package (name -> is a package), the command line left out:
    ``contactres.cli`` is run, not imported (tests/test_layout.py keeps the library off it)."""
    return {
        info.name: info.ispkg
        for info in pkgutil.walk_packages(contactres.__path__, "contactres.")
        if not info.name.startswith("contactres.cli")
    }


def _defined_names(path: str) -> set[str]:
    """The names a module defines at its top level (functions, classes, assignments)."""
    tree = ast.parse(Path(path).read_text(encoding="utf-8"))
    names: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names - {"TYPE_CHECKING"}


def test_a_public_modules_names_are_its_all_or_private():
    """In a public module (and a subpackage's ``__init__``) every name it defines is in its
    ``__all__`` (pinned above, documented in docs/api.md) or has a leading underscore: no
    public-looking helper outside the documented surface."""
    loose = []
    for name in ["contactres", *_library_modules()]:
        if any(part.startswith("_") for part in name.split(".")):
            continue
        module = importlib.import_module(name)
        exported = set(getattr(module, "__all__", ()))
        if module.__file__ is None:  # pragma: no cover - a namespace package
            continue
        extra = sorted(n for n in _defined_names(module.__file__) - exported if n[0] != "_")
        loose += [f"{name}.{n}" for n in extra]
    assert loose == []


def test_every_module_without_an_underscore_is_a_package_or_listed_public():
    """scipy's test_all_modules_are_expected: a new module is private unless listed here."""
    found = _library_modules()
    public = sorted(
        name
        for name, is_package in found.items()
        if not is_package and not any(part.startswith("_") for part in name.split("."))
    )
    assert public == sorted([*PUBLIC_MODULES, *NOT_YET_PRIVATE])


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_dir_of_a_lazy_subpackage_is_its_public_names(name):
    """``dir()`` shows what a user may call: the pinned names, and public submodules only."""
    module = importlib.import_module(f"contactres.{name}")
    names = [n for n in dir(module) if not isinstance(getattr(module, n), types.ModuleType)]
    pinned = PUBLIC.get(name, [])
    assert names == sorted(module.__all__) == sorted(pinned)
    assert not [n for n in dir(module) if n.startswith("_")]


def test_pinned_lists_have_no_duplicates():
    for name, names in PUBLIC.items():
        assert len(set(names)) == len(names), name
    assert len(set(TOP_LEVEL)) == len(TOP_LEVEL)


# --- what type checkers see --------------------------------------------------------------------


def type_checking_imports(path: Path) -> dict[str, str]:
    """Name -> relative module of every ``from .x import name as name`` under TYPE_CHECKING.

    ``from . import sub as sub`` gives ``sub -> "."``; ``typing`` imports are left out.
    """
    found: dict[str, str] = {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if not (isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING"):
            continue
        for stmt in node.body:
            if isinstance(stmt, ast.ImportFrom) and stmt.level:
                module = "." * stmt.level + (stmt.module or "")
                for alias in stmt.names:
                    # `name as name`: an explicit re-export for mypy --strict and pyright
                    assert alias.asname == alias.name, f"{path.name}: import {alias.name} as itself"
                    found[alias.name] = module
    return found


def test_py_typed_ships_with_the_package():
    assert (PACKAGE_DIR / "py.typed").is_file()
    package_data = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["tool"]["setuptools"]
    assert "py.typed" in package_data["package-data"]["contactres"]


def test_type_checkers_see_every_lazy_name_of_contactres():
    seen = type_checking_imports(PACKAGE_DIR / "__init__.py")
    expected = {
        **contactres._EXPORTS,
        **dict.fromkeys(contactres._SUBMODULES, "."),
        "__version__": "._version",
    }
    assert seen == expected


@pytest.mark.parametrize("name", LAZY_PACKAGES)
def test_type_checkers_see_every_lazy_name_of_a_subpackage(name):
    package = importlib.import_module(f"contactres.{name}")
    seen = type_checking_imports(PACKAGE_DIR / name / "__init__.py")
    assert seen == dict(package._EXPORTS)


USER_FILE = """
import contactres
from contactres import Material, hertz

reveal_type(contactres.hertz)
reveal_type(hertz)
reveal_type(Material)
reveal_type(contactres.dynamic.prepare)
reveal_type(contactres.polycrystal.fit_map)
reveal_type(contactres.__version__)
"""


# A user's configuration that leaves the third-party libraries out of the check (their names
# become ``Any``): mypy then reads contactres and the standard library only, ~3 s of CPU instead
# of ~13 s for the stubs of scipy, pandas and numpy (1800 modules instead of 290). The names of
# contactres are resolved exactly as without it (the lazy ``__getattr__`` still gives ``Any``).
USER_CONFIG = """
[mypy]
follow_imports_for_stubs = True

[mypy-numpy.*,scipy.*,pandas.*,matplotlib.*,dask.*,distributed.*,xarray.*,zarr.*,click.*]
follow_imports = skip
"""


def test_mypy_sees_the_real_objects_in_a_users_file(tmp_path, monkeypatch):
    """A user's mypy reveals signatures, not ``Any`` (the lazy ``__getattr__`` returns ``Any``).

    mypy finds contactres where this process imports it from (its sys.path), and reads the
    annotations only because of ``py.typed``: without it every name would be ``Any``.
    """
    mypy_api = pytest.importorskip("mypy.api", reason="mypy is not installed (the dev extra)")
    (tmp_path / "user.py").write_text(USER_FILE, encoding="utf-8")
    (tmp_path / "mypy.ini").write_text(USER_CONFIG, encoding="utf-8")
    monkeypatch.chdir(tmp_path)  # not the project's configuration: a user's own
    stdout, stderr, status = mypy_api.run(
        ["--cache-dir", str(tmp_path / "cache"), "--no-error-summary", "user.py"]
    )
    revealed = [
        line.split('Revealed type is "', 1)[1].removesuffix('"')
        for line in stdout.splitlines()
        if "Revealed type is" in line
    ]
    assert len(revealed) == USER_FILE.count("reveal_type"), stdout + stderr
    assert not any(r.startswith("Any") for r in revealed), stdout
    hertz_attr, hertz_imported, material, prepare, fit_map, version = revealed
    assert hertz_attr == hertz_imported
    assert hertz_attr.startswith("def (") and "contactres.normal._isotropic.Contact" in hertz_attr
    assert material.startswith("def (") and material.endswith("-> contactres.materials.Material")
    assert "-> contactres.dynamic._table.KernelTable" in prepare
    assert fit_map.startswith("def (")
    assert version.startswith("builtins.str") or version.startswith("str")
    # reveal_type is a note: the check passes (an error would break a user's type check)
    assert status == 0, stdout + stderr
