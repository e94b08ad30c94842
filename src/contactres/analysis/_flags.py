"""The flags the sweep analysis sets: a closed, documented set, held as a bit mask per sweep.

Inside the analysis a sweep's flags are one integer (a :class:`Flag` bit mask), combined with
vectorised ``|``; they become the ';'-separated text of ``sweeps.csv`` only when written
(:func:`render`), always in the order of :class:`Flag`.
"""

from __future__ import annotations

import enum

import numpy as np

from ..units import JUNCTION_SIGMAS, LINEAR_ONSET_X, MAX_MU, MIN_SWEEP_POINTS, SMALL_LOAD_LIMIT
from ._loops import X_MAX
from ._plateau import PLATEAU_D_C_BOUND

__all__ = ["DESCRIPTIONS", "Flag", "has", "negative_stiffness", "render"]


class Flag(enum.IntFlag):
    """Why a sweep is set aside, or what to keep in mind when reading its numbers."""

    FIRST_RAMP = enum.auto()
    FEW_POINTS = enum.auto()
    JUNCTION_GROWTH = enum.auto()
    SMALL_LOAD = enum.auto()
    PLATEAU_SLOPE = enum.auto()
    GROSS_SLIDING = enum.auto()
    DRIFT = enum.auto()
    RAMP_ORDER = enum.auto()
    FLAT_AMPLITUDE = enum.auto()
    BEYOND_ONSET = enum.auto()
    DRIFT_REMOVED = enum.auto()
    MU_OUT_OF_RANGE = enum.auto()
    PLATEAU_AT_BOUND = enum.auto()
    NEGATIVE_STIFFNESS = enum.auto()

    @property
    def text(self) -> str:
        """The flag as written in ``sweeps.csv`` (``first-ramp``, ...)."""
        return str(self.name).lower().replace("_", "-")


#: What each flag means, in the words of the README.
DESCRIPTIONS: dict[Flag, str] = {
    Flag.FIRST_RAMP: "ramp 1 of a load, set aside as running-in (unless --keep-first-ramp)",
    Flag.FEW_POINTS: f"fewer than {MIN_SWEEP_POINTS} points: not used",
    Flag.JUNCTION_GROWTH: (
        f"Δf rises with u0 by more than {JUNCTION_SIGMAS:g} standard errors (the junction "
        "grows): no μ from the Δf slope"
    ),
    Flag.SMALL_LOAD: (
        f"Δf0 above {SMALL_LOAD_LIMIT:g} of the resonance frequency in magnitude: paper 2's Eq. 1 "
        "may fail"
    ),
    Flag.PLATEAU_SLOPE: (
        "a plateau sweep: the shifts leave the plateau with no linear term, so no μ from the "
        "slopes (μ from the exact plateau loop instead)"
    ),
    Flag.GROSS_SLIDING: (
        f"the exact loop fits best beyond κu0/(μF_N) = {X_MAX:g} (gross sliding): μ not resolved"
    ),
    Flag.DRIFT: (
        "the used ramps of this load of this experiment are offset from each other beyond the "
        "noise (F test): the baseline moved"
    ),
    Flag.RAMP_ORDER: (
        "the ramp labels of this load disagree with the times (time_s) or the amplitudes, or "
        "repeat a number or skip one (see the messages); the first sweep measured (by time; "
        "by name among repeated labels) is taken as the running-in ramp"
    ),
    Flag.FLAT_AMPLITUDE: (
        "all amplitudes of the sweep are equal: no slope, so no μ from it (its Δf0 and ΔΓ0 are "
        "the mean shifts at that amplitude)"
    ),
    Flag.BEYOND_ONSET: (
        f"a Cattaneo-Mindlin sweep reaching κu0/(μF_N) > {LINEAR_ONSET_X:g} (exact-loop fit): "
        "beyond the linear onset, so μ from the slopes (paper 2, Eq. 12) reads low (by > 10 % "
        "from the ΔΓ slope); use mu_fit"
    ),
    Flag.MU_OUT_OF_RANGE: (
        f"μ above {MAX_MU:g} by more than twice its error (from a slope or the exact loop): not a "
        "friction coefficient but a wrong input (check normal_force_N, per contact, and "
        "area_m2); withheld"
    ),
    Flag.DRIFT_REMOVED: (
        "this load drifted; a drift linear in time (column time_s) was removed from its points "
        "and it passed the drift test again (--remove-drift; the rates are in summary.json)"
    ),
    Flag.PLATEAU_AT_BOUND: (
        "a plateau sweep whose own exact plateau-loop fit puts the critical displacement on its "
        f"bound 0 (below {PLATEAU_D_C_BOUND:g} of its largest amplitude): the sweep does not "
        "resolve its plateau (plateau_amplitude_m and its error empty; its block's other sweeps "
        "made it a plateau: check this sweep's smallest amplitudes); its errors of Δf0, ΔΓ0 "
        "and mu_fit are those of that fit with the critical displacement held at 0 "
        "(Cattaneo-Mindlin)"
    ),
    Flag.NEGATIVE_STIFFNESS: (
        "Δf0 below 0 by more than twice its error, or below 0 at all where it has no error (a "
        "sweep of one point: its sign alone): a negative contact stiffness κ = Δf0/P, not a "
        "result but a shift of the wrong sign (a contact raises the frequency, Δf0 = Pκ > 0; "
        "check the sign of df_Hz); the exact loops, which need Δf0 > 0, are fitted (with a "
        "negative Δf0) but have no criterion (BIC inf), so that they are never chosen"
    ),
}


def has(mask, flag: Flag) -> np.ndarray:
    """Boolean array: which entries of the bit-mask array ``mask`` carry ``flag``."""
    return (np.asarray(mask, dtype=np.int64) & int(flag)) != 0


def negative_stiffness(df0, err) -> np.ndarray:
    """Where Δf0 (Hz) lies below 0 by more than twice its error ``err`` (Hz; a missing error
    counts as 0), so that κ = Δf0/P < 0 (P > 0; paper 2, Eq. 1) beyond the noise. A Δf0 within
    two errors of 0 is a small stiffness, not a sign error. Arrays; returns a boolean array."""
    df0 = np.asarray(df0, dtype=float)
    err = np.nan_to_num(np.asarray(err, dtype=float), nan=0.0)
    return df0 + 2.0 * err < 0.0


def render(mask) -> np.ndarray:
    """The ';'-separated text of each bit mask in ``mask`` (object array of str)."""
    mask = np.asarray(mask, dtype=np.int64)
    out = np.full(mask.shape, "", dtype=object)
    for flag in Flag:
        on = has(mask, flag)
        out[on] = np.where(out[on] == "", flag.text, out[on] + ";" + flag.text)
    return out
