"""contactres: contact mechanics at resonance.

Forward models (Hertz/JKR/DMT, anisotropic half-spaces, dynamic contact stiffness, partial-slip
tangential loops, QCM frequency shifts) and the analysis of QCM amplitude sweeps. SI units
throughout (m, N, Pa, Hz, kg).

The public names are loaded on first use (PEP 562 module ``__getattr__``), so that
``import contactres`` and the command line's ``--help`` do not pay for scipy, pandas and
matplotlib. ``from contactres import X``, ``contactres.X`` and ``dir(contactres)`` work as with
eager imports; subpackages (``contactres.dynamic``, ``contactres.analysis``, ...) are imported
when first accessed as attributes.
"""

from __future__ import annotations

import importlib

# `typing` costs ~20 ms to import and only type checkers need `Any`: a module-level
# TYPE_CHECKING = False is read as True by mypy and pyright, without importing typing here.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

# Public name -> the module (relative to this package) it is re-exported from. To add a public
# name, add one line here: ``__all__`` and ``dir()`` follow from this dict.
_EXPORTS: dict[str, str] = {
    # materials and the half-space
    "Material": ".materials",
    "crystal_names": ".crystals",
    "crystal_table": ".crystals",
    "example_path": ".examples",
    "at_cut_quartz": ".materials",
    "dynamic_kernel": ".halfspace",
    "isotropic_dynamic_kernel": ".halfspace",
    "shear_reference": ".halfspace",
    "static_kernel": ".halfspace",
    "LayeredMaterial": ".layered",
    "surface_green": ".layered",
    # viscoelastic materials
    "ConstantLoss": ".viscoelastic",
    "ModulusTable": ".viscoelastic",
    "PowerLaw": ".viscoelastic",
    "Prony": ".viscoelastic",
    "ViscoelasticMaterial": ".viscoelastic",
    "pmma": ".viscoelastic",
    # static normal contact
    "Contact": ".normal",
    "dmt": ".normal",
    "effective_modulus": ".normal",
    "effective_shear_modulus": ".normal",
    "hertz": ".normal",
    "jkr": ".normal",
    "jkr_contact_radius": ".normal",
    "jkr_from_depth": ".normal",
    "jkr_pull_off_force": ".normal",
    "shear_modulus": ".normal",
    "tabor_parameter": ".normal",
    "which_adhesion_model": ".normal",
    "AnisotropicContact": ".normal",
    "contact_ellipse": ".normal",
    "contact_integrals": ".normal",
    "indentation_modulus": ".normal",
    "LayeredContact": ".normal",
    "flat_punch_stiffness": ".dynamic",
    "indentation_modulus_at": ".normal",
    "sphere_contact": ".normal",
    # dynamic contact stiffness
    "contact_displacement": ".dynamic",
    "contact_pressure": ".dynamic",
    "dcsf": ".dynamic",
    "dcsf_models": ".dynamic",
    "dynamic_contact_stiffness": ".dynamic",
    "tangential_contact_stiffness": ".dynamic",
    "tangential_dcsf": ".dynamic",
    "tangential_stiffness_static": ".dynamic",
    "two_body_contact_stiffness": ".dynamic",
    # tangential loops
    "CattaneoMindlinLoop": ".tangential",
    "DashpotLoop": ".tangential",
    "MasingLoop": ".tangential",
    "PlateauLoop": ".tangential",
    "SavkoorLoop": ".tangential",
    "VoigtLoop": ".tangential",
    "mindlin_deresiewicz_energy": ".tangential",
    "mindlin_stiffness": ".tangential",
    "with_dashpot": ".tangential",
    # resonators
    "QCM": ".resonators",
    "cattaneo_mindlin_expansion": ".resonators",
    "friction_from_slopes": ".resonators",
    "loop_stiffness": ".resonators",
    "savkoor_expansion": ".resonators",
    "shifts_from_loop": ".resonators",
    "shifts_from_stiffness": ".resonators",
    "stiffness_from_shifts": ".resonators",
    "Cantilever": ".resonators",
    "contact_frequencies": ".resonators",
    "ContactResonanceResult": ".resonators",
    "invert_contact_resonance": ".resonators",
    "RUMOscillator": ".resonators",
    "AIR": ".resonators",
    "Medium": ".resonators",
    "Particle": ".resonators",
    "WATER": ".resonators",
    "coupled_resonance": ".resonators",
    "kanazawa_gordon": ".resonators",
    "medium_named": ".resonators",
    "particle_model_validity": ".resonators",
    "particle_shifts": ".resonators",
    "particle_stiffness": ".resonators",
    "penetration_depth": ".resonators",
    # measurements and analysis
    "SweepTable": ".measurements",
    "SweepWarning": ".measurements",
    "read_sweeps": ".measurements",
    "validate_sweeps": ".measurements",
    "AnalysisSettings": ".analysis",
    "Flag": ".analysis",
    "analyze": ".analysis",
    "ParticleFit": ".analysis",
    "fit_particles": ".analysis",
    "Results": ".analysis",
    "ModulusResult": ".analysis",
    "modulus_from_contact_stiffness": ".analysis",
    "FilmModulusResult": ".analysis",
    "film_modulus_from_contact_stiffness": ".analysis",
    "invert_afm_table": ".analysis",
    "invert_rum_table": ".analysis",
    "read_resonance_table": ".measurements",
    "example_afm_map": ".measurements",
    "write_report": ".report",
}

# Submodules imported on attribute access (``contactres.dynamic.prepare``). The command line
# (``cli``) is left out on purpose: the library never imports it.
_SUBMODULES: frozenset[str] = frozenset(
    {
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
    }
)

__all__ = sorted([*_EXPORTS, "__version__"])

# What type checkers see: the real objects behind every public name and subpackage, so that a
# user's mypy or pyright checks calls against their signatures instead of the ``Any`` that
# ``__getattr__`` returns. Never run (TYPE_CHECKING is False at run time): the imports stay lazy.
# tests/test_public_api.py keeps these imports and ``_EXPORTS``/``_SUBMODULES`` the same.
# ``X as X`` marks an explicit re-export (mypy --strict, pyright); isort would split every such
# name onto a line of its own, hence one block per module, sorted by hand.
if TYPE_CHECKING:
    # isort: off
    from . import (
        analysis as analysis,
        apps as apps,
        crystals as crystals,
        dynamic as dynamic,
        examples as examples,
        fileio as fileio,
        fitting as fitting,
        halfspace as halfspace,
        jobs as jobs,
        layered as layered,
        materials as materials,
        measurements as measurements,
        normal as normal,
        numerics as numerics,
        polycrystal as polycrystal,
        report as report,
        resonators as resonators,
        tangential as tangential,
        units as units,
        validation as validation,
        viscoelastic as viscoelastic,
    )
    from .analysis import (
        AnalysisSettings as AnalysisSettings,
        FilmModulusResult as FilmModulusResult,
        Flag as Flag,
        ModulusResult as ModulusResult,
        ParticleFit as ParticleFit,
        Results as Results,
        analyze as analyze,
        film_modulus_from_contact_stiffness as film_modulus_from_contact_stiffness,
        fit_particles as fit_particles,
        invert_afm_table as invert_afm_table,
        invert_rum_table as invert_rum_table,
        modulus_from_contact_stiffness as modulus_from_contact_stiffness,
    )
    from .crystals import (
        crystal_names as crystal_names,
        crystal_table as crystal_table,
    )
    from .examples import example_path as example_path
    from .dynamic import (
        contact_displacement as contact_displacement,
        flat_punch_stiffness as flat_punch_stiffness,
        contact_pressure as contact_pressure,
        dcsf as dcsf,
        dcsf_models as dcsf_models,
        dynamic_contact_stiffness as dynamic_contact_stiffness,
        tangential_contact_stiffness as tangential_contact_stiffness,
        tangential_dcsf as tangential_dcsf,
        tangential_stiffness_static as tangential_stiffness_static,
        two_body_contact_stiffness as two_body_contact_stiffness,
    )
    from .halfspace import (
        dynamic_kernel as dynamic_kernel,
        isotropic_dynamic_kernel as isotropic_dynamic_kernel,
        shear_reference as shear_reference,
        static_kernel as static_kernel,
    )
    from .layered import (
        LayeredMaterial as LayeredMaterial,
        surface_green as surface_green,
    )
    from .materials import (
        Material as Material,
        at_cut_quartz as at_cut_quartz,
    )
    from .measurements import (
        SweepTable as SweepTable,
        SweepWarning as SweepWarning,
        example_afm_map as example_afm_map,
        read_resonance_table as read_resonance_table,
        read_sweeps as read_sweeps,
        validate_sweeps as validate_sweeps,
    )
    from .normal import (
        AnisotropicContact as AnisotropicContact,
        Contact as Contact,
        LayeredContact as LayeredContact,
        contact_ellipse as contact_ellipse,
        contact_integrals as contact_integrals,
        dmt as dmt,
        effective_modulus as effective_modulus,
        effective_shear_modulus as effective_shear_modulus,
        hertz as hertz,
        indentation_modulus as indentation_modulus,
        indentation_modulus_at as indentation_modulus_at,
        jkr as jkr,
        jkr_contact_radius as jkr_contact_radius,
        jkr_from_depth as jkr_from_depth,
        jkr_pull_off_force as jkr_pull_off_force,
        shear_modulus as shear_modulus,
        sphere_contact as sphere_contact,
        tabor_parameter as tabor_parameter,
        which_adhesion_model as which_adhesion_model,
    )
    from .report import (
        write_report as write_report,
    )
    from .resonators import (
        Cantilever as Cantilever,
        ContactResonanceResult as ContactResonanceResult,
        QCM as QCM,
        RUMOscillator as RUMOscillator,
        cattaneo_mindlin_expansion as cattaneo_mindlin_expansion,
        contact_frequencies as contact_frequencies,
        friction_from_slopes as friction_from_slopes,
        invert_contact_resonance as invert_contact_resonance,
        loop_stiffness as loop_stiffness,
        savkoor_expansion as savkoor_expansion,
        shifts_from_loop as shifts_from_loop,
        shifts_from_stiffness as shifts_from_stiffness,
        stiffness_from_shifts as stiffness_from_shifts,
        AIR as AIR,
        Medium as Medium,
        Particle as Particle,
        WATER as WATER,
        coupled_resonance as coupled_resonance,
        kanazawa_gordon as kanazawa_gordon,
        medium_named as medium_named,
        particle_model_validity as particle_model_validity,
        particle_shifts as particle_shifts,
        particle_stiffness as particle_stiffness,
        penetration_depth as penetration_depth,
    )
    from .tangential import (
        CattaneoMindlinLoop as CattaneoMindlinLoop,
        DashpotLoop as DashpotLoop,
        MasingLoop as MasingLoop,
        PlateauLoop as PlateauLoop,
        SavkoorLoop as SavkoorLoop,
        VoigtLoop as VoigtLoop,
        mindlin_deresiewicz_energy as mindlin_deresiewicz_energy,
        mindlin_stiffness as mindlin_stiffness,
        with_dashpot as with_dashpot,
    )
    from .viscoelastic import (
        ConstantLoss as ConstantLoss,
        ModulusTable as ModulusTable,
        PowerLaw as PowerLaw,
        Prony as Prony,
        ViscoelasticMaterial as ViscoelasticMaterial,
        pmma as pmma,
    )
    from ._version import __version__ as __version__

    # isort: on


def __getattr__(name: str) -> Any:
    """Import the module behind a public name (or a subpackage) on first access."""
    # Nothing is stored in globals(): the import system already keeps each module once in
    # sys.modules, so a repeated access is a dict look-up plus getattr, and no state is cached here.
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    if name == "__version__":
        # importlib.metadata costs ~50 ms to import: only pay for it when the version is asked.
        return importlib.import_module("._version", __name__).__version__
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    """The public names and subpackages, as tab completion and ``dir()`` expect them."""
    return sorted({*globals(), *__all__, *_SUBMODULES})
