"""Which pixels of an orientation map hold a trusted orientation (indexed, of the chosen phase).

An EBSD export lists every pixel of its grid, indexed or not: a TSL/OIM .ang marks the pixels
whose solution was not confirmed with the confidence index CI = −1 and rates the others by CI
(0 to 1); an Oxford/HKL .ctf gives the phase 0 to pixels it did not index and rates the others
by the mean angular deviation MAD (degrees). The Euler angles of a pixel that is not indexed are
a placeholder (often 0, 0, 0), so a modulus computed from them is the modulus of a made-up
orientation: such pixels are left out of every prediction and fit, and counted.

Rules (the defaults are the ones users of these instruments apply; both are options):

- .ang: CI >= ``min_confidence`` (default :data:`MIN_CI` = 0.1; Field, Ultramicroscopy 67, 1
  (1997): above CI 0.1 about 95 % of the pixels are indexed right);
- .ctf: phase != 0, and MAD <= ``max_mad`` when it is given (degrees; no default);
- a map of several phases (ids other than the not-indexed 0 of a .ctf) needs ``phase``, the one
  whose constants are used: the others are left out; a map of one phase uses it.

A synthetic map, or a map store without such a confidence, keeps every pixel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._summary import Summarised
from ..errors import ContactresInputError
from ._maps import OrientationMap

__all__ = ["MIN_CI", "IndexedPixels", "indexed_pixels"]

#: Default lowest confidence index of a usable .ang pixel (see the module docstring).
MIN_CI = 0.1


# repr=False: the summary (Summarised, _facts) replaces the numpy repr of the mask.
@dataclass(frozen=True, repr=False)
class IndexedPixels(Summarised):
    """The pixels of a map that are used, and why the others are not.

    Attributes
    ----------
    mask : ndarray of bool, shape (H, W)
        True where the pixel is used.
    low_confidence : int
        Pixels left out by the confidence rule (CI below the threshold, or MAD above it).
    not_indexed : int
        Pixels left out as not indexed (phase 0 of a .ctf, CI = −1 of an .ang).
    other_phase : int
        Pixels of another phase than ``phase``.
    phase : int or None
        The phase used (None: every phase, the map has one).
    rule : str
        The rule in words, for reports (e.g. "CI >= 0.1").
    """

    mask: np.ndarray
    low_confidence: int
    not_indexed: int
    other_phase: int
    phase: int | None
    rule: str

    @property
    def left_out(self) -> int:
        """Pixels not used, all reasons together."""
        return int(self.mask.size - np.count_nonzero(self.mask))

    def _facts(self) -> list[tuple[str, str]]:
        """The map's size, the pixels used and :meth:`summary`."""
        used = int(np.count_nonzero(self.mask))
        return [("pixels", f"{used} of {self.mask.size} used"), ("", self.summary())]

    def summary(self) -> str:
        """One line: how many pixels are used and why the others are not."""
        total = self.mask.size
        if self.left_out == 0:
            return f"all {total} pixels used ({self.rule})"
        parts = [
            f"{n} {what}"
            for n, what in (
                (self.not_indexed, "not indexed"),
                (self.low_confidence, f"below the confidence rule ({self.rule})"),
                (self.other_phase, f"of another phase than {self.phase}"),
            )
            if n
        ]
        return f"{self.left_out} of {total} pixels left out: {', '.join(parts)}"


def indexed_pixels(
    omap: OrientationMap,
    *,
    min_confidence: float | None = None,
    max_mad: float | None = None,
    phase: int | None = None,
) -> IndexedPixels:
    """The pixels of ``omap`` with a trusted orientation of one phase (module docstring).

    Parameters
    ----------
    omap : OrientationMap
        The map (``confidence_name`` says what ``confidence`` is: "CI", "MAD (degrees)", ...).
    min_confidence : float, optional
        Lowest CI of a used .ang pixel (default :data:`MIN_CI`); ignored for other maps.
    max_mad : float, optional
        Largest MAD (degrees) of a used .ctf pixel (default: no limit); ignored for other maps.
    phase : int, optional
        The phase id whose pixels are used; needed when the map holds several.

    Returns
    -------
    IndexedPixels

    Raises
    ------
    ContactresInputError
        A threshold that is not a finite number; a ``phase`` the map does not hold; a map of
        several phases without ``phase``; a map with no usable pixel.
    """
    conf = np.asarray(omap.confidence, dtype=float)
    ids = np.asarray(omap.phase)
    kind = omap.confidence_name
    not_indexed = np.zeros(conf.shape, dtype=bool)
    low = np.zeros(conf.shape, dtype=bool)
    if kind == "CI":
        ci = MIN_CI if min_confidence is None else _finite("min_confidence (CI)", min_confidence)
        not_indexed = conf < 0  # CI = −1: the solution was not confirmed
        low = ~not_indexed & ~(conf >= ci)
        rule = f"CI >= {ci:g}"
    elif kind.startswith("MAD"):
        not_indexed = ids == 0
        if max_mad is not None:
            limit = _finite("max_mad (degrees)", max_mad)
            low = ~not_indexed & ~(conf <= limit)
            rule = f"phase != 0, MAD <= {limit:g}°"
        else:
            rule = "phase != 0"
    else:
        rule = "every pixel (no confidence in this map)"
    held = np.unique(ids[~not_indexed])
    other = np.zeros(conf.shape, dtype=bool)
    if phase is not None:
        if int(phase) not in held:
            raise ContactresInputError(
                f"{omap.source or 'the map'}: no indexed pixel of phase {phase}; its phases are "
                f"{', '.join(str(int(p)) for p in held) or 'none'}"
            )
        other = ~not_indexed & (ids != int(phase))
    elif held.size > 1:
        raise ContactresInputError(
            f"{omap.source or 'the map'} holds phases {', '.join(str(int(p)) for p in held)}: "
            "choose the one whose constants are given (phase, --phase on the command line)"
        )
    mask = ~(not_indexed | low | other)
    if not mask.any():
        raise ContactresInputError(
            f"{omap.source or 'the map'}: no pixel is usable ({rule}); check the confidence "
            "threshold and the phase"
        )
    return IndexedPixels(
        mask=mask,
        low_confidence=int(np.count_nonzero(low)),
        not_indexed=int(np.count_nonzero(not_indexed)),
        other_phase=int(np.count_nonzero(other)),
        phase=None if phase is None else int(phase),
        rule=rule,
    )


def _finite(name: str, value) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise ContactresInputError(f"{name} must be a finite number, got {value!r}")
    return v
