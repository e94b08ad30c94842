"""Job ``rum_invert``: the contact resonance of a RUM table -> contact stiffness k*, one row per
point or map pixel.

Inputs: the path of the resonance table (CSV, columns
:data:`contactres.measurements.schema.RUM_TABLE`): f0_Hz, fc_Hz and the calibration,
K_eff_N_per_m (lumped oscillator, (f/f0)² = 1 + k*/K_eff) or mass_kg (a rod free at one end,
k* = (EA/L)(kL) tan(kL)). Settings: none for k* (the calibration columns choose the model).
The inversion is :func:`contactres.invert_rum_table`.

On a coated sample (``coating``, ``substrate`` and the sphere's ``tip_radius`` and ``force``,
as the ``afm_invert`` job's) every k* is also turned into the film's modulus by
:func:`contactres.analysis.film_modulus_from_contact_stiffness`: columns coating, M_film_Pa,
film_contact_radius_m, film_weight and film_verdict, the coating recorded in the result.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..measurements.schema import RUM_INVERT_RESULTS
from ..validation import positive
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import pandas as pd

    from ..materials import Material

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """How to invert a RUM table: k* needs nothing (the calibration columns decide); the film's
    modulus on a coated sample needs the rest.

    Parameters
    ----------
    coating, substrate, film_range, min_film_weight
        As in the ``afm_invert`` job's Settings (one film ``"MATERIAL:THICKNESS"``, the
        substrate Material, the search range in Pa, the threshold of the film weight).
    tip_radius, force : float or None
        Radius of the sphere (m) and static force (N) of the contact, with a coating.
    tip_modulus : float or None
        Indentation modulus of the sphere, Pa (None: rigid).
    """

    coating: tuple = ()
    substrate: Material | None = None
    tip_radius: float | None = None
    force: float | None = None
    tip_modulus: float | None = None
    film_range: tuple[float, float] | None = None
    min_film_weight: float = 0.1


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: the input's columns (``input_columns``, copied), then rum_model and
    k_star_N_per_m (:data:`contactres.measurements.schema.RUM_INVERT_RESULTS`, which lists the
    computed ones only); with a coating the film columns, and ``coating`` its record (as the
    ``afm_invert`` job's; None without)."""

    SCHEMAS = MappingProxyType({"table": RUM_INVERT_RESULTS})

    table: pd.DataFrame
    input_columns: tuple[str, ...]
    coating: dict | None = None


@one_blas_thread()
def run(
    inputs: str | os.PathLike, settings: Settings | None = None, progress: Progress | None = None
) -> Result:
    """k* of every row of the RUM table ``inputs`` (see the module docstring)."""
    from ..analysis import invert_rum_table
    from ..measurements import read_resonance_table
    from ..measurements.schema import RUM_TABLE
    from .afm_invert import add_film_columns, coated_film, film_names

    s = Settings() if settings is None else settings
    film = coated_film(s.coating, s.substrate)  # checked before the table is read
    if film is not None:
        if s.tip_radius is None or s.force is None:
            raise ContactresInputError(
                "the film's modulus (--coating) needs the sphere's radius and force "
                "(--tip-radius, --force)"
            )
        positive("tip radius (--tip-radius)", s.tip_radius, "m")
        positive("force (--force)", s.force, "N")
        if s.tip_modulus is not None:
            positive("tip modulus (--tip-modulus)", s.tip_modulus, "Pa")
    elif (s.tip_radius, s.force, s.tip_modulus) != (None, None, None):
        raise ContactresInputError(
            "--tip-radius, --force and --tip-modulus are for the film's modulus: give "
            "--coating and --substrate too"
        )
    say(progress, f"reading {Path(inputs).name}")
    checked = read_resonance_table(inputs, RUM_TABLE)
    say(progress, f"inverting {len(checked)} rows")
    table = invert_rum_table(
        checked, str(Path(inputs)), appended=() if film is None else film_names()
    )
    coating = None
    if film is not None:
        say(progress, "film modulus on the coated substrate")
        tip = math.nan if s.tip_modulus is None else s.tip_modulus
        coating = add_film_columns(
            table, table["k_star_N_per_m"], s.tip_radius, s.force, tip, film, s, str(Path(inputs))
        )
    return Result(table=table, input_columns=tuple(checked.columns), coating=coating)
