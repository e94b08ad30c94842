"""Job ``maps_fit``: a measured contact-stiffness (or modulus) map and the orientations -> the
single-crystal elastic constants, with uncertainties and the identifiability.

Inputs: the path of the orientation map (a Zarr map store or an EBSD export). Settings: where
the measured values are (a CSV grid, read by the ``grid`` recipe of
:data:`contactres.jobs.readers.ALL_READERS`, or a variable of the store), which quantity they
are, the lattice, the tolerance that segments unlabelled grains and the tip and load (for a
stiffness map). The fit is :func:`contactres.jobs.maps.fit_measured_map` (the inverse of
:mod:`contactres.polycrystal._inverse`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    from .maps import TipLoad

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """The fit.

    Parameters
    ----------
    values_path : str or None
        A CSV grid of the measured values, the map's shape (None: the variable ``variable``
        of the map store).
    variable : str
        The store's variable of the measured values.
    quantity : str
        What the values are (:func:`contactres.jobs.maps.fit_measured_map`).
    lattice : str
        "cubic" or "hexagonal".
    tolerance_deg : float
        Grains of an unlabelled map: largest angle between neighbouring pixels' normals
        within one grain, degrees.
    tipload : TipLoad or None
        Tip radius and force of a stiffness map (None: as the quantity allows).
    tip_modulus : float or None
        The tip's indentation modulus, Pa (None: rigid or fitted, as the fit decides).
    min_confidence, max_mad, phase : float, float, int or None
        Which pixels of an EBSD map are used (:func:`contactres.polycrystal.indexed_pixels`;
        None: its defaults).
    """

    values_path: str | None = None
    variable: str = "k_star_N_per_m"
    quantity: str = "stiffness"
    lattice: str = "cubic"
    tolerance_deg: float = 2.0
    tipload: TipLoad | None = None
    tip_modulus: float | None = None
    min_confidence: float | None = None
    max_mad: float | None = None
    phase: int | None = None


@dataclass(frozen=True)
class Result(JobResult):
    """``fit``: the fit result (constants, errors, identifiability, ``summary()``); ``pixels``:
    the pixels used; ``record``: the fit as JSON text (``"json"``) and its scalars (``"flat"``),
    :func:`contactres.jobs.maps.fit_record`."""

    NOT_VALUES = ("fit", "record", "warnings")
    NAME = "fit"

    fit: object
    pixels: int
    record: dict


@one_blas_thread()
def run(inputs: str | os.PathLike, settings: Settings, progress: Progress | None = None) -> Result:
    """Fit the constants to the measured map over the orientations ``inputs``."""
    import numpy as np

    from ..polycrystal import indexed_pixels
    from .maps import fit_measured_map, fit_record, open_map
    from .readers import read_grid_file

    s = settings
    say(progress, f"reading {inputs}")
    omap, ds = open_map(inputs)
    if s.values_path is not None:
        values = read_grid_file(s.values_path)
        if values.shape != omap.shape:
            raise ContactresInputError(
                f"values file (--values) {s.values_path}: {values.shape[0]} rows x "
                f"{values.shape[1]} columns, "
                f"but MAP has {omap.shape[0]} x {omap.shape[1]} pixels (same grid needed)"
            )
    elif ds is not None and s.variable in ds:
        try:
            values = ds[s.variable].values
        except (OSError, RuntimeError, ValueError, TypeError) as exc:
            # A truncated or foreign chunk of a half-written store (codec errors).
            raise ContactresInputError(
                f"map store {str(inputs)!r}: variable {s.variable!r} cannot be read "
                f"({type(exc).__name__}: {' '.join(str(exc).split())[:200]}): a half-written or "
                "damaged store; write it again"
            ) from None
    else:
        raise ContactresInputError(
            f"{inputs}: no variable {s.variable!r}; give the measured map as values_path "
            "(--values FILE on the command line)"
        )
    pixels = indexed_pixels(omap, min_confidence=s.min_confidence, max_mad=s.max_mad, phase=s.phase)
    say(progress, pixels.summary())
    fit, _, used = fit_measured_map(
        omap,
        values,
        quantity=s.quantity,
        lattice=s.lattice,
        tipload=s.tipload,
        tip_modulus=s.tip_modulus,
        tolerance_deg=s.tolerance_deg,
        pixels=pixels,
    )
    # An indexed pixel without a measured value (NaN or an empty cell) is left out of the fit
    # too: counted and said with the indexing rule, not only seen in the number of pixels used
    # (issue 27's closing campaign: 4095 pixels in 15 grains, the one left out unnamed).
    no_value = int(np.count_nonzero(pixels.mask & ~np.isfinite(np.asarray(values, dtype=float))))
    rule = pixels.summary()
    if no_value and pixels.left_out:
        rule = f"{rule}; {no_value} more without a measured value (NaN or empty)"
    elif no_value:
        rule = (
            f"{no_value} of {pixels.mask.size} pixels left out: {no_value} without a measured "
            f"value (NaN or empty); the others pass the rule ({pixels.rule})"
        )
    record = fit_record(
        fit,
        source=str(inputs),
        pixels=used,
        pixels_left_out=pixels.left_out + no_value,
        pixel_rule=rule,
        segmented=omap.labels is None,
        tolerance_deg=s.tolerance_deg,
    )
    return Result(fit=fit, pixels=used, record=record)
