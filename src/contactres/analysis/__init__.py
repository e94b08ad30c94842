"""Analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion.

:func:`analyze` runs the steps (settings :class:`AnalysisSettings`, results :class:`Results`);
its private modules hold one step each: padded arrays and closed-form fits (``_amplitude``),
the exact loops (``_loops``), the fitted models, one module each, with their registry and
batched fitters (``_models``, :data:`REGISTRY`), the model choice (``_classify``), friction
(``_friction``), drift (``_drift``), statistics per load (``_loads``), the JKR + Mindlin fit
(``_jkr``, :func:`fit_jkr_mindlin`), the radiation loss of the contacts (``_radiation``,
:func:`radiation_for`, :func:`radiation_loss`), the flags (``_flags``, :class:`Flag`), the
points and fitted curves the report draws (``_curves``), the loads Fig. 4 draws (``_examples``,
:func:`figure_examples`) and the results (``_results``). Beside
them, the inversion of contact resonances to a modulus (:func:`modulus_from_contact_stiffness`,
:func:`invert_afm_table`, :func:`invert_rum_table`) and to the modulus of a film on a known
substrate (``_film_inversion``, :func:`film_modulus_from_contact_stiffness`). And the fit of
attached particles' contact stiffness and coverage to QCM-D shifts (``_particles``,
:func:`fit_particles`).

The public names are loaded on first use (PEP 562 module ``__getattr__``).

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein J.
Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the (private) module that defines it.
_EXPORTS = MappingProxyType(
    {
        "FIGURE_POINTS": "._curves",
        "CR_MAP_FLAGS": "._cr_map",
        "CR_MAP_UNITS": "._cr_map",
        "ModulusModel": "._cr_map",
        "invert_cr_map": "._cr_map",
        "DART_FLAGS": "._dart",
        "DartReconstruction": "._dart",
        "dart_flag_names": "._dart",
        "dart_reconstruct": "._dart",
        "dart_reconstruction": "._dart",
        "figure_examples": "._examples",
        "PAGE_POINTS": "._curves",
        "sweep_rows": "._curves",
        "DESCRIPTIONS": "._flags",
        "has": "._flags",
        "render": "._flags",
        "Flag": "._flags",
        "FLAG_DESCRIPTIONS": "._inversion",
        "modulus_from_contact_stiffness": "._inversion",
        "ModulusResult": "._inversion",
        "FILM_COLUMNS": "._film_inversion",
        "FILM_VERDICTS": "._film_inversion",
        "FilmModulusResult": "._film_inversion",
        "film_columns": "._film_inversion",
        "film_modulus_from_contact_stiffness": "._film_inversion",
        "fit_jkr_mindlin": "._jkr",
        "REGISTRY": "._models",
        "analyze": "._pipeline",
        "AnalysisSettings": "._settings",
        "material_by_name": "._radiation",
        "radiation_for": "._radiation",
        "radiation_loss": "._radiation",
        "radiation_summary": "._radiation",
        "LIMIT_CHI2": "._particles",
        "PARTICLE_FLAGS": "._particles",
        "ParticleFit": "._particles",
        "RELATIVE_ERROR_LIMIT": "._particles",
        "fit_particles": "._particles",
        "invert_afm_table": "._resonance_tables",
        "invert_rum_table": "._resonance_tables",
        "Results": "._results",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._curves import (
        FIGURE_POINTS as FIGURE_POINTS,
        PAGE_POINTS as PAGE_POINTS,
        sweep_rows as sweep_rows,
    )
    from ._cr_map import (
        CR_MAP_FLAGS as CR_MAP_FLAGS,
        CR_MAP_UNITS as CR_MAP_UNITS,
        ModulusModel as ModulusModel,
        invert_cr_map as invert_cr_map,
    )
    from ._dart import (
        DART_FLAGS as DART_FLAGS,
        DartReconstruction as DartReconstruction,
        dart_flag_names as dart_flag_names,
        dart_reconstruct as dart_reconstruct,
        dart_reconstruction as dart_reconstruction,
    )
    from ._examples import (
        figure_examples as figure_examples,
    )
    from ._flags import (
        DESCRIPTIONS as DESCRIPTIONS,
        Flag as Flag,
        has as has,
        render as render,
    )
    from ._film_inversion import (
        FILM_COLUMNS as FILM_COLUMNS,
        FILM_VERDICTS as FILM_VERDICTS,
        FilmModulusResult as FilmModulusResult,
        film_columns as film_columns,
        film_modulus_from_contact_stiffness as film_modulus_from_contact_stiffness,
    )
    from ._inversion import (
        FLAG_DESCRIPTIONS as FLAG_DESCRIPTIONS,
        ModulusResult as ModulusResult,
        modulus_from_contact_stiffness as modulus_from_contact_stiffness,
    )
    from ._jkr import (
        fit_jkr_mindlin as fit_jkr_mindlin,
    )
    from ._models import (
        REGISTRY as REGISTRY,
    )
    from ._particles import (
        LIMIT_CHI2 as LIMIT_CHI2,
        PARTICLE_FLAGS as PARTICLE_FLAGS,
        ParticleFit as ParticleFit,
        RELATIVE_ERROR_LIMIT as RELATIVE_ERROR_LIMIT,
        fit_particles as fit_particles,
    )
    from ._pipeline import (
        analyze as analyze,
    )
    from ._radiation import (
        material_by_name as material_by_name,
        radiation_for as radiation_for,
        radiation_loss as radiation_loss,
        radiation_summary as radiation_summary,
    )
    from ._resonance_tables import (
        invert_afm_table as invert_afm_table,
        invert_rum_table as invert_rum_table,
    )
    from ._settings import (
        AnalysisSettings as AnalysisSettings,
    )
    from ._results import (
        Results as Results,
    )

    # isort: on

__getattr__, __dir__ = attach(__name__, _EXPORTS)
