"""Job ``afm_invert``: the contact resonances of a CR-AFM table -> contact stiffness k*, tip
position, damping and modulus, one row per point or map pixel.

Inputs: the path of the resonance table (CSV or a numpy archive, ``.npz``; columns
:data:`contactres.measurements.schema.AFM_TABLE`). Settings: the normalisation of the
frequencies, the tolerance between modes, and the sample for paper 1's dynamic correction of
the Hertz rows. The inversion is :func:`contactres.invert_afm_table` (Euler-Bernoulli lever,
U. Rabe et al., Rev. Sci. Instrum. 67, 3281 (1996)).

On a coated sample (``coating``: one built-in film ``"MATERIAL:THICKNESS"``, parsed by
:func:`contactres.jobs.contact.parse_coating`, on ``substrate``) every Hertz row's k* (with
tip_radius_m, load_N and M_tip_Pa) is also turned into the film's modulus by
:func:`contactres.analysis.film_modulus_from_contact_stiffness` (exact layered contact):
columns coating, M_film_Pa, film_contact_radius_m, film_weight and film_verdict; the film
material's static constants (a viscoelastic film's storage constants at 1 Hz, as ``contact``)
give its anisotropy and Poisson's ratio, its modulus is the unknown. The coating, the search
range and the thresholds are recorded in the result (``coating``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError, ContactresWarning
from ..measurements.schema import AFM_INVERT_RESULTS
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import pandas as pd

    from ..materials import Material
    from ..measurements import ArrayTable

__all__ = ["Result", "Settings", "add_film_columns", "coated_film", "film_names", "run"]


@dataclass(frozen=True)
class Settings:
    """How to invert a CR-AFM table.

    Parameters
    ----------
    normalisation : str
        "global" (β_n from f1_free_Hz only) or "modewise" (each mode's own free frequency).
    mode_tolerance : float
        Relative disagreement of κ between modes, dimensionless, beyond which a row is flagged.
    sample : Material or None
        The sample in the frame of its face, for paper 1's dynamic correction of the Hertz rows
        (with its density); None: no correction.
    loss : float
        Material loss Q⁻¹ of the sample for the correction, dimensionless (0: lossless).
    coating : tuple
        One film on the sample, ``("MATERIAL:THICKNESS",)`` (thickness in m, e.g.
        ``"pmma:250e-9"``; :func:`contactres.jobs.contact.parse_coating`): adds the film's
        modulus. Empty: a homogeneous sample.
    substrate : Material or None
        The substrate under the coating, in the frame of its face (needed with ``coating``).
    film_range : (float, float) or None
        Search range of the film's indentation modulus, Pa (None: the film material's own
        modulus divided and multiplied by 10).
    min_film_weight : float
        Film weight below which the film is too thin to be resolved, dimensionless.
    arrays : bool
        The table of the result as an :class:`~contactres.measurements.ArrayTable` (numpy
        columns) rather than a :class:`pandas.DataFrame`: a numpy archive is then read,
        inverted and handed back without pandas (issue 31: its import was a third of the time
        of a 512² map written to ``.npz``). The numbers are the same.
    """

    normalisation: str = "global"
    mode_tolerance: float = 0.05
    sample: Material | None = None
    loss: float = 0.0
    coating: tuple = ()
    substrate: Material | None = None
    film_range: tuple[float, float] | None = None
    min_film_weight: float = 0.1
    arrays: bool = False


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: the input's columns (``input_columns``, copied) then the computed ones
    (:data:`contactres.measurements.schema.AFM_INVERT_RESULTS`, which lists the computed
    ones only; an :class:`~contactres.measurements.ArrayTable` with ``Settings.arrays``).
    ``coating``: with a coating, its label, the substrate, the film's thickness
    (m), its material's modulus, the search range (Pa), the thresholds and the estimated
    interpolation error (:func:`add_film_columns`), and ``notes``, the film inversion's
    warnings one line each (a contact beyond Hertz's a/R limit); None without. ``warnings``: the
    :class:`~contactres.errors.ContactresWarning` s of the inversion, one line each (a tip
    radius above 1 mm: check its unit)."""

    SCHEMAS = MappingProxyType({"table": AFM_INVERT_RESULTS})

    table: pd.DataFrame | ArrayTable
    input_columns: tuple[str, ...]
    coating: dict | None = None
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(inputs: str | os.PathLike, settings: Settings, progress: Progress | None = None) -> Result:
    """Invert every row of the CR-AFM table ``inputs`` (see the module docstring)."""
    from ..analysis import invert_afm_table
    from ..measurements import read_resonance_table
    from ..measurements.schema import AFM_TABLE

    s = settings
    if s.coating and s.sample is not None:
        raise ContactresInputError(
            "the dynamic correction (--crystal) of a coated sample (--coating) is not "
            "available: give the substrate with --substrate and drop --crystal"
        )
    film = coated_film(s.coating, s.substrate)  # checked before the table is read
    say(progress, f"reading {Path(inputs).name}")
    checked = read_resonance_table(inputs, AFM_TABLE, arrays=s.arrays)
    say(progress, f"inverting {len(checked)} rows")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ContactresWarning)  # the user's notes, returned below
        table = invert_afm_table(
            checked,
            str(Path(inputs)),
            normalisation=s.normalisation,
            sample=s.sample,
            loss=s.loss,
            mode_tolerance=s.mode_tolerance,
            appended=() if film is None else film_names(),
        )
    notes = []
    for w in caught:
        if not issubclass(w.category, ContactresWarning):  # anything else goes on as it came
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        elif (text := " ".join(str(w.message).split())) not in notes:
            notes.append(text)
    coating = None
    if film is not None:
        say(progress, "film modulus on the coated substrate")
        coating = add_film_columns(
            table,
            table["k_star_N_per_m"],
            checked["tip_radius_m"],  # the checked table has every column (NaN: not given)
            checked["load_N"],
            checked["M_tip_Pa"],
            film,
            s,
            str(Path(inputs)),
        )
    return Result(
        table=table,
        input_columns=tuple(checked.columns),
        coating=coating,
        warnings=tuple(notes),
    )


def coated_film(coating, substrate) -> tuple | None:
    """(film material with static constants, thickness in m, coating label, substrate) of a
    one-film ``coating`` on ``substrate``, or None without a coating (checked: one line for a
    bad coating, a missing substrate or more than one film)."""
    if not coating:
        if substrate is not None:
            raise ContactresInputError(
                "the substrate (--substrate) is the solid under a coating: give --coating too"
            )
        return None
    from ..layered import thickness_text  # a homogeneous sample needs none
    from ..materials import require_material
    from .contact import parse_coating

    # Static constants, as contact's: a viscoelastic film's storage constants at 1 Hz.
    layers = parse_coating(coating, static=True)
    if len(layers) != 1:
        raise ContactresInputError(
            f"the film's modulus is found for one film (--coating), got {len(layers)} layers"
        )
    if substrate is None:
        raise ContactresInputError(
            "a coating (--coating) needs the substrate under it (--substrate, e.g. fused-silica)"
        )
    substrate = require_material(substrate)
    ((material, h),) = layers
    label = f"{getattr(material, 'name', None) or 'film'} {thickness_text(h)}"  # as contact's
    return material, h, label, substrate


def film_names() -> tuple[str, ...]:
    """The columns :func:`add_film_columns` appends, in its order: ``coating``, then the film
    columns (:data:`contactres.analysis.FILM_COLUMNS`). The inversions refuse a given column of
    these names with their own (``appended``), so that one line names every clash."""
    from ..analysis import FILM_COLUMNS  # imported here: a run without a coating needs none

    return ("coating", *FILM_COLUMNS)


def add_film_columns(
    table, k_star, tip_radius, load, tip_modulus, film, s, source: str = "table"
) -> dict:
    """Append the film columns to ``table`` (in place; k* (N/m), tip radius (m), load (N), tip
    modulus (Pa, NaN: rigid) per row or one value) and return the ``coating`` record; ``film``
    from :func:`coated_film`, ``s`` the settings (film_range, min_film_weight). The film
    inversion's ContactresWarnings (Hertz's a/R limit) are the record's ``notes``, one line
    each, for the command to print. A given column of ``table`` named as a film column is
    refused in one line naming ``source`` (its values would be replaced). The jobs have the
    inversion refuse these with its own names (``appended=`` :func:`film_names`), in one line,
    before any inversion runs; this check is for a caller of this function alone."""
    from .._column_names import refuse_computed_names
    from ..analysis import film_columns

    material, h, label, substrate = film
    n = len(table)
    arrays = (
        np.broadcast_to(np.asarray(x, dtype=float), (n,))
        for x in (k_star, tip_radius, load, tip_modulus)
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ContactresWarning)  # the user's notes, in the record
        cols, res = film_columns(
            *arrays,
            substrate=substrate,
            film=material,
            thickness=h,
            film_range=s.film_range,
            min_film_weight=s.min_film_weight,
        )
    notes: list[str] = []
    for w in caught:
        if not issubclass(w.category, ContactresWarning):  # anything else goes on as it came
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        elif (text := " ".join(str(w.message).split())) not in notes:
            notes.append(text)
    refuse_computed_names(table, film_names(), source)
    table["coating"] = label
    for name, values in cols.items():
        table[name] = values
    return {
        "label": label,
        "substrate": getattr(substrate, "name", None) or "substrate",
        "thickness_m": h,
        "film_material_modulus_Pa": None if res is None else res.reference_modulus,
        "film_range_Pa": None if res is None else list(res.film_range),
        "min_film_weight": s.min_film_weight,
        "interpolation_error": None if res is None else res.interpolation_error,
        "notes": tuple(notes),
    }
