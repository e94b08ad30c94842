"""Measured data: the schema of every table, the readers, validated tables, synthetic data.

Two public subpackages: :mod:`contactres.measurements.schema` (every input and output table,
its columns and rules) and :mod:`contactres.measurements.readers` (the reader recipes and their
registry; the instrument exports in :mod:`contactres.measurements.readers.exports`). The names
below are those of the private modules beside them: the validated sweep table
(:func:`read_sweeps`, :class:`SweepTable`), the resonance tables of CR-AFM and RUM
(:func:`read_resonance_table`; a numpy archive's held as numpy columns by
:class:`ArrayTable`), admittance spectra to sweeps (:func:`read_spectra_sweeps`,
:func:`fit_resonances`), the synthetic data (:func:`synthetic_sweeps`,
:func:`synthetic_spectra`, :func:`example_study`, :func:`example_afm_map`, the particle studies
of :func:`synthetic_particle_study`), the wording of
the messages that point at a cell of a table (:func:`at_cell`, :func:`where_rows`) and the
contact-resonance AFM instrument files: Asylum Research ``.ibw`` images (:func:`read_ibw`,
:class:`IgorWave`, :func:`parse_note`, :func:`dart_frequency_Hz`), BGlib band-excitation SHO
fits (:func:`read_be_sho`) and NetCDF/Zarr grids (:func:`read_resonance_grid`), all as
:class:`ResonanceMaps` where they give frequency and Q, and :func:`check_frequency_map`.

The public names are loaded on first use (PEP 562 module ``__getattr__``); the modules that
implement them are private (``_sweeps``, ``_shifts``, ..., scipy's rule).
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the (private) module that defines it.
_EXPORTS = MappingProxyType(
    {
        "NAMED_SURFACES": "._afm_example",
        "example_afm_map": "._afm_example",
        "ExampleLever": "._afm_example",
        "ResonanceMaps": "._afm_maps",
        "SHO_FIELDS": "._afm_maps",
        "check_frequency_map": "._afm_maps",
        "dart_frequency_Hz": "._afm_maps",
        "read_be_sho": "._afm_maps",
        "ArrayTable": "._array_table",
        "read_resonance_grid": "._afm_maps",
        "IgorWave": "._ibw",
        "parse_note": "._ibw",
        "read_ibw": "._ibw",
        "at_cell": "._messages",
        "PARTICLE_EXAMPLE_SEED": "._particle_study",
        "ParticleStudy": "._particle_study",
        "synthetic_particle_study": "._particle_study",
        "where_rows": "._messages",
        "read_resonance_table": "._resonances",
        "D26_AT": "._shifts",
        "is_spectra_input": "._shifts",
        "read_spectra_sweeps": "._shifts",
        "FLAGS": "._spectra",
        "fit_resonances": "._spectra",
        "EXAMPLE_SEED": "._studies",
        "example_study": "._studies",
        "validation_study": "._studies",
        "CONSTANTS": "._sweeps",
        "read_sweeps": "._sweeps",
        "validate_sweeps": "._sweeps",
        "SweepTable": "._sweeps",
        "SweepWarning": "._sweep_checks",
        "synthetic_sweeps": "._synthetic",
        "SweepGroup": "._synthetic",
        "SweepStudy": "._synthetic",
        "spectra_from_sweeps": "._synthetic_spectra",
        "synthetic_spectra": "._synthetic_spectra",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._afm_example import (
        ExampleLever as ExampleLever,
        NAMED_SURFACES as NAMED_SURFACES,
        example_afm_map as example_afm_map,
    )
    from ._afm_maps import (
        SHO_FIELDS as SHO_FIELDS,
        ResonanceMaps as ResonanceMaps,
        check_frequency_map as check_frequency_map,
        dart_frequency_Hz as dart_frequency_Hz,
        read_be_sho as read_be_sho,
        read_resonance_grid as read_resonance_grid,
    )
    from ._array_table import ArrayTable as ArrayTable
    from ._ibw import (
        IgorWave as IgorWave,
        parse_note as parse_note,
        read_ibw as read_ibw,
    )
    from ._messages import (
        at_cell as at_cell,
        where_rows as where_rows,
    )
    from ._particle_study import (
        PARTICLE_EXAMPLE_SEED as PARTICLE_EXAMPLE_SEED,
        ParticleStudy as ParticleStudy,
        synthetic_particle_study as synthetic_particle_study,
    )
    from ._resonances import (
        read_resonance_table as read_resonance_table,
    )
    from ._shifts import (
        D26_AT as D26_AT,
        is_spectra_input as is_spectra_input,
        read_spectra_sweeps as read_spectra_sweeps,
    )
    from ._spectra import (
        FLAGS as FLAGS,
        fit_resonances as fit_resonances,
    )
    from ._studies import (
        EXAMPLE_SEED as EXAMPLE_SEED,
        example_study as example_study,
        validation_study as validation_study,
    )
    from ._sweep_checks import SweepWarning as SweepWarning
    from ._sweeps import (
        CONSTANTS as CONSTANTS,
        SweepTable as SweepTable,
        read_sweeps as read_sweeps,
        validate_sweeps as validate_sweeps,
    )
    from ._synthetic import (
        SweepGroup as SweepGroup,
        SweepStudy as SweepStudy,
        synthetic_sweeps as synthetic_sweeps,
    )
    from ._synthetic_spectra import (
        spectra_from_sweeps as spectra_from_sweeps,
        synthetic_spectra as synthetic_spectra,
    )

    # isort: on

__getattr__, __dir__ = attach(__name__, _EXPORTS)
