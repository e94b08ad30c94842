"""From the columns of an export to the tidy Δf, ΔΓ table, with every convention recorded.

Conversions (paper 2, Eqs. 1-2: Γ is the half width at half maximum, D = 2Γ/f):

* shifts: Δf_n = n x value when the file holds Δf_n/n; ΔΓ_n = ΔD_n x scale x n f_F / 2, first
  order in Δf/f (the error is D Δf / 2: below 1e-3 Hz for D < 1e-5 and Δf < 100 Hz);
* absolute values: Γ_n = D_n x scale x f_n / 2 row by row, then Δf = f_n - f_ref and
  ΔΓ = Γ_n - Γ_ref with the references of the baseline (the point of earliest time, or the mean
  over a window);
* a file of Γ (Hz) is taken as it is.

Checks on the way, each a one-line error naming file, line, column, value and rule: a frequency
cell on the wrong side of :data:`~._base.ABSOLUTE_FREQUENCY_HZ` (shifts and resonance
frequencies mixed), "shifts" that are resonance frequencies typed in kHz or MHz (n f_F in a QCM's
range, nearly constant), ``|D|`` x scale >= :data:`MAX_DISSIPATION` (a mis-scaled D), a negative
absolute D, absolute f_n/n that differ between overtones by more than
:data:`FUNDAMENTAL_TOLERANCE` (columns divided by n, or misnumbered), an absolute f_n cell whose
f_n/n is that far from the file's f_F (a corrupted or mistyped cell), a fundamental given that
disagrees with the file, a baseline window without points.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ....errors import ContactresInputError
from ._base import (
    ABSOLUTE_FREQUENCY_HZ,
    COLUMNS,
    CONVENTION_KEYS,
    TIME_UNITS,
    ExportTable,
    ExportWarning,
    Layout,
    fail_at,
    missing,
    numbers,
    parse_baseline,
    rows_left_out,
)

if TYPE_CHECKING:  # pandas is imported where a table is made (see .base: the help needs none)
    import pandas as pd

__all__ = [
    "FUNDAMENTAL_TOLERANCE",
    "MAX_DISSIPATION",
    "MAX_PLAIN_D_SHIFT",
    "QCM_FUNDAMENTAL_RANGE_HZ",
    "convert",
]

#: ``|D|`` x scale at or above this is no dissipation factor (a Q of 10): a mis-scaled column.
MAX_DISSIPATION = 0.1

#: A D shift read with the unit ``()`` (dimensionless, AWSensors) at or above this is D in
#: ppm: ΔD = 1e-3 is ΔΓ = 7.5 kHz on the 3rd overtone of a 5 MHz quartz, far beyond a contact
#: (tens of Hz) or water (ΔD ~ 2e-4), while a ppm column reaches it with ΔD = 0.001 ppm.
MAX_PLAIN_D_SHIFT = 1e-3

#: Relative spread of f_n/n between overtones (and against a fundamental given) tolerated.
FUNDAMENTAL_TOLERANCE = 0.05


def _agree(path: Path, reader: str, key: str, from_file, given):
    """The file's value of one convention, or the caller's; they must agree when both exist."""
    if from_file is not None and given is not None and given != from_file:
        raise ContactresInputError(
            f"{path}: {key}={given!r} ({CONVENTION_KEYS[key]}) contradicts the file, whose "
            f"header says {from_file!r} ({reader} export)"
        )
    return from_file if from_file is not None else given


def _reference(kind: str, t0: float, t1: float, t: np.ndarray, values: np.ndarray) -> float:
    """The baseline value of one series (NaN when the window holds no point). "first" is the
    point of the earliest time, not the first row: rows out of time order (a QCM-I export
    appended to, or sorted by another column) must not make a later point the reference."""
    if kind == "first":
        return float(values[int(np.argmin(t))]) if values.size else math.nan
    inside = (t >= t0) & (t <= t1)
    return float(values[inside].mean()) if inside.any() else math.nan


def _frequency_kind(raw, path: Path, traces, stated: str | None) -> str:
    """'absolute' or 'shift': from the header, else from the first value; all cells agree."""
    kind = stated
    for _, fcol, _ in traces:
        f = numbers(raw, fcol, path)
        finite = np.isfinite(f)
        if kind is None and finite.any():
            kind = "absolute" if abs(f[finite][0]) > ABSOLUTE_FREQUENCY_HZ else "shift"
        if kind is None:
            continue
        wrong = finite & ((np.abs(f) <= ABSOLUTE_FREQUENCY_HZ) == (kind == "absolute"))
        if wrong.any():
            fail_at(
                raw,
                path,
                fcol,
                wrong,
                f"is no resonance frequency (the column holds f_n > {ABSOLUTE_FREQUENCY_HZ:g} Hz)"
                if kind == "absolute"
                else f"is no shift (the column holds shifts below {ABSOLUTE_FREQUENCY_HZ:g} Hz)",
            )
    if kind is None:
        raise ContactresInputError(
            f"{path}: no frequency value in the file ({traces[0][1]!r} and others)"
        )
    if kind == "shift":
        _refuse_scaled_absolute(raw, path, traces)
    return kind


#: Fundamentals of a QCM (Hz), for telling resonance frequencies in kHz or MHz from shifts.
QCM_FUNDAMENTAL_RANGE_HZ = (1e6, 1e8)
#: Largest relative spread of a column of resonance frequencies over a measurement (a film's
#: few kHz on 15 MHz are 3e-4); a column of shifts spreads by its own size.
_ABSOLUTE_SPREAD = 1e-3


def _refuse_scaled_absolute(raw, path: Path, traces) -> None:
    """A one-line error if the "shifts" are resonance frequencies f_n typed in kHz or MHz.

    Such cells sit below :data:`~._base.ABSOLUTE_FREQUENCY_HZ` and would pass for shifts of a
    few Hz (issue 27: a QSense export in MHz gave κ of 5e4 N/m). They are told by all of: two
    or more overtones whose values divided by n (f_n/n = f_F) agree to
    :data:`FUNDAMENTAL_TOLERANCE` and, in kHz or MHz, lie in :data:`QCM_FUNDAMENTAL_RANGE_HZ`;
    positive values; each column spread by less than 1e-3 of its size (shifts start near 0).
    """
    per_n = []
    for n, fcol, _ in traces:
        f = numbers(raw, fcol, path)
        f = f[np.isfinite(f)]
        if f.size == 0 or not (f > 0).all():
            return
        mid = float(np.median(f))
        if (f.max() - f.min()) > _ABSOLUTE_SPREAD * mid:
            return
        per_n.append((n, fcol, mid))
    if len(per_n) < 2:
        return  # one overtone: nothing to compare, the values may be shifts
    f0 = float(np.median([mid / n for n, _, mid in per_n]))
    if any(abs(mid / n / f0 - 1) > FUNDAMENTAL_TOLERANCE for n, _, mid in per_n):
        return
    lo, hi = QCM_FUNDAMENTAL_RANGE_HZ
    for unit, factor in (("MHz", 1e6), ("kHz", 1e3)):
        if lo <= f0 * factor <= hi:
            n, fcol, mid = per_n[0]
            raise ContactresInputError(
                f"{path}, column {fcol!r}: {mid:.6g} looks like an absolute resonance frequency "
                f"in {unit} (n f_F = {n} x {f0:.6g} {unit}), not a shift: give the frequency "
                "columns in Hz (they are then read as f_n, with a baseline: --baseline first or "
                "window:T0:T1), or subtract the baseline to give shifts"
            )


def _choices(
    path: Path, reader: str, layout: Layout, given: dict, kind: str
) -> tuple[str, bool, float | None, tuple[str, float, float]]:
    """Time unit, Δf divided by n, D scale and baseline: the file's or the caller's. Every
    choice the file does not tell and the caller did not give is named in one error."""
    needed = []
    unit = _agree(path, reader, "time_unit", layout.time_unit, given.get("time_unit"))
    if unit is None:
        needed.append(
            ("time_unit", f"the time column {layout.time_column!r} has no unit (s, min or h)")
        )
    elif unit not in TIME_UNITS:
        raise ContactresInputError(
            f"{path}: time_unit {unit!r} is not one of {', '.join(TIME_UNITS)}"
        )
    divided = False
    if kind == "absolute" and given.get("df_divided_by_n"):
        raise ContactresInputError(
            f"{path}: df_divided_by_n=True (--df-divided-by-n) does not apply: the file holds "
            f"resonance frequencies f_n, not shifts ({reader} export)"
        )
    if kind == "shift":
        got = given.get("df_divided_by_n")
        divided = _agree(path, reader, "df_divided_by_n", layout.divided_by_n, got)
        if divided is None:
            needed.append(("df_divided_by_n", "the header does not say Δf or Δf/n"))
    scale = None
    if layout.dissipation == "D":
        scale = given.get("dissipation_scale", layout.dissipation_scale)
        if scale is None:
            scale = layout.dissipation_scale_default
        if scale is None:
            needed.append(
                ("dissipation_scale", "the header does not say the unit of D (1e-6 for ppm, or 1)")
            )
        else:
            scale = float(scale)
            if not (math.isfinite(scale) and 0 < scale <= 1):
                raise ContactresInputError(
                    f"{path}: dissipation_scale {scale!r} must lie in (0, 1]"
                )
            if layout.dissipation_scale is not None and not math.isclose(
                scale, layout.dissipation_scale, rel_tol=1e-9
            ):
                raise ContactresInputError(
                    f"{path}: dissipation_scale={scale:g} (--dissipation-scale) contradicts the "
                    f"header, whose unit of D is {layout.dissipation_scale:g} ({reader} export)"
                )
    base = given.get("baseline")
    if base is None and kind == "absolute":
        needed.append(
            (
                "baseline",
                "the file holds resonance frequencies, not shifts: which "
                "points are the reference (first, window:T0:T1)",
            )
        )
    if kind == "shift" and layout.dissipation == "D" and given.get("fundamental") is None:
        needed.append(("fundamental", "ΔΓ = ΔD n f_F / 2 needs the fundamental f_F (Hz)"))
    if needed:
        raise missing(path, reader, needed)
    baseline = parse_baseline("as-exported" if base is None else str(base))
    if baseline[0] == "as-exported" and kind == "absolute":
        raise ContactresInputError(
            f"{path}: baseline as-exported (--baseline) needs a file of shifts; this one holds "
            f"resonance frequencies: use first or window:T0:T1 ({reader} export)"
        )
    return unit, bool(divided), scale, baseline


def _series(raw, path: Path, layout: Layout, traces, t_all, kind: str, scale, implied: bool):
    """(n, column, kept rows, f, D x scale or Γ) per overtone, with the checks of D; the
    number of rows left out and a line per overtone naming them. ``implied``: the scale is
    the one the header implies (:attr:`Layout.dissipation_scale_default`), checked here."""
    series, skipped, notes = [], 0, []
    for n, fcol, dcol in traces:
        f, d = numbers(raw, fcol, path), numbers(raw, dcol, path)
        keep = np.isfinite(t_all) & np.isfinite(f) & np.isfinite(d)
        if not keep.any():
            # A real QCM-I export holds the 13th overtone's frequency but none of its bandwidths:
            # the overtone is left out by name, the others are read (issue 27: nothing dropped
            # without a word).
            notes.append(
                f"overtone {n} left out: no row holds its time, frequency ({fcol!r}) and "
                f"dissipation ({dcol!r}) together"
            )
            continue
        skipped += int((~keep).sum())
        if (note := rows_left_out(raw, n, keep)) is not None:
            notes.append(note)
        if implied and (keep & (np.abs(d) >= MAX_PLAIN_D_SHIFT)).any():
            rule = (
                f"is no D shift in the header's unit '()' (dimensionless: |ΔD| < "
                f"{MAX_PLAIN_D_SHIFT:g}); D in ppm? give dissipation_scale=1e-6 "
                "(--dissipation-scale 1e-6)"
            )
            fail_at(raw, path, dcol, keep & (np.abs(d) >= MAX_PLAIN_D_SHIFT), rule)
        if scale is not None:
            d = d * scale
            too_big = keep & (np.abs(d) >= MAX_DISSIPATION)
            if too_big.any():
                rule = (
                    f"x dissipation_scale {scale:g} is no dissipation factor "
                    f"(|D| < {MAX_DISSIPATION:g}): check the scale (1e-6 for ppm)"
                )
                fail_at(raw, path, dcol, too_big, rule)
        if kind == "absolute" and (keep & (d < 0)).any():
            fail_at(raw, path, dcol, keep & (d < 0), "is negative: an absolute D or Γ is >= 0")
        series.append((n, fcol, keep, f, d))
    if not series:
        raise ContactresInputError(f"{path}: no row with time, frequency and dissipation")
    return series, skipped, notes


def _fundamental(
    raw, path: Path, reader: str, given, kind, baseline: tuple[str, float, float], t_all, series
):
    """f_F and where it came from: given (checked against absolute f_n/n) or from the file."""
    fundamental = given.get("fundamental")
    source = "given"
    if fundamental is not None:
        fundamental = float(fundamental)
        if not (math.isfinite(fundamental) and fundamental > 0):
            raise ContactresInputError(
                f"{path}: fundamental {fundamental!r} Hz must be a positive number"
            )
    if kind != "absolute":
        return fundamental, (source if fundamental is not None else None)
    per_n = {}
    for n, fcol, keep, f, _ in series:
        ref = _reference(*baseline, t_all[keep], f[keep])
        if not math.isnan(ref):
            per_n[n] = (ref / n, fcol)
    if not per_n:
        return fundamental, (source if fundamental is not None else None)
    median = float(np.median([v for v, _ in per_n.values()]))
    for n, (v, fcol) in per_n.items():
        if abs(v / median - 1) > FUNDAMENTAL_TOLERANCE:
            raise ContactresInputError(
                f"{path}, column {fcol!r}: f_{n}/{n} = {v:.6g} Hz at the baseline differs from "
                f"the other overtones' {median:.6g} Hz by more than {FUNDAMENTAL_TOLERANCE:.0%}: "
                "the columns are not n f_F (divided by n, or misnumbered)"
            )
    # Every cell, not only the baseline's: a resonance that moved by 5 % of n f_F (250 kHz on a
    # 5 MHz quartz, thousands of times a contact's or a film's shift) is a corrupted or mistyped
    # cell, and it became a shift of that size without a word (issue 27's closing campaign: a
    # cell of 1e300 Hz gave Δf = 1e300 Hz).
    for n, fcol, keep, f, _ in series:
        off = keep & (np.abs(f / (n * median) - 1) > FUNDAMENTAL_TOLERANCE)
        if off.any():
            rule = (
                f"is no resonance frequency of overtone {n}: f_{n}/{n} is more than "
                f"{FUNDAMENTAL_TOLERANCE:.0%} from the file's f_F = {median:.6g} Hz"
            )
            fail_at(raw, path, fcol, off, rule)
    if fundamental is None:
        return median, "from the file: median of f_n/n at the baseline"
    if abs(median / fundamental - 1) > FUNDAMENTAL_TOLERANCE:
        raise ContactresInputError(
            f"{path}: fundamental={fundamental:g} Hz (--fundamental) disagrees with the file, "
            f"whose f_n/n is {median:.6g} Hz at the baseline ({reader} export)"
        )
    return fundamental, source


def _out_of_order(raw, t: np.ndarray) -> str | None:
    """The line saying that the rows are out of time order and which row is the baseline
    "first" (the earliest; a QCM-I sample export starts with a row 5 ms later than its
    second), or None when the times do not decrease."""
    finite = np.isfinite(t)
    times, lines = t[finite], np.asarray(raw.attrs["lines"])[finite]
    back = np.flatnonzero(np.diff(times) < 0)
    if back.size == 0:
        return None
    i, first = int(back[0]), int(np.argmin(times))
    return (
        f"rows out of time order (line {lines[i + 1]}, t = {times[i + 1]:g} s, after line "
        f"{lines[i]}, t = {times[i]:g} s): the baseline 'first' is the earliest point, line "
        f"{lines[first]} (t = {times[first]:g} s)"
    )


def convert(
    path: Path,
    reader: str,
    raw: pd.DataFrame,
    layout: Layout,
    conventions: Mapping[str, str | float | None],
) -> ExportTable:
    """The columns of ``layout`` in ``raw`` (from :func:`~._base.read_rows`) as an ExportTable.

    ``conventions`` are the caller's choices (keys of :data:`~._base.CONVENTION_KEYS`, None for
    not given); those the file states must agree with it, those it does not state must be given
    where they are needed (one-line ValueError naming the file and the choice otherwise).
    """
    import pandas as pd

    path = Path(path)
    given = {k: v for k, v in conventions.items() if v is not None}
    traces = layout.traces
    if "overtone" in given and layout.overtone_in_file:
        traces = tuple(tr for tr in traces if tr[0] == int(given["overtone"]))
        if not traces:
            held = ", ".join(str(tr[0]) for tr in layout.traces)
            raise ContactresInputError(
                f"{path}: overtone {given['overtone']} (--overtone) is not in the file; it holds "
                f"{held} ({reader} export)"
            )
    kind = _frequency_kind(raw, path, traces, layout.frequency)
    unit, divided, scale, baseline = _choices(path, reader, layout, given, kind)
    implied = (
        scale is not None
        and layout.dissipation_scale is None
        and "dissipation_scale" not in given
        and layout.dissipation_scale_default is not None
    )
    t_all = numbers(raw, layout.time_column, path) * TIME_UNITS[unit]
    series, skipped, notes = _series(raw, path, layout, traces, t_all, kind, scale, implied)
    # Nothing is left out without a word (issue 27): overtones without their frequency or
    # dissipation column, rows without a value, comment lines among the rows.
    kept_n = {tr[0] for tr in traces}
    notes = [why for n, why in layout.left_out if "overtone" not in given or n in kept_n] + notes
    if comments := raw.attrs.get("comment_lines", ()):
        from .._delimited import line_ranges

        notes.append(
            f"{len(comments)} comment line(s) among the rows skipped (first character '#'): "
            f"line(s) {line_ranges(comments)}"
        )
    if baseline[0] == "first" and (order := _out_of_order(raw, t_all)) is not None:
        notes.append(order)
    for note in notes:
        warnings.warn(f"{path}: {note}", ExportWarning, stacklevel=3)
    fundamental, fsource = _fundamental(raw, path, reader, given, kind, baseline, t_all, series)
    bkind, t0, t1 = baseline
    frames, refs_f, refs_g = [], {}, {}
    for n, fcol, keep, f, d in series:
        t, f, d = t_all[keep], f[keep], d[keep]
        if kind == "absolute":
            gamma = d * f / 2.0 if scale is not None else d
        else:
            f = f * n if divided else f
            gamma = d * n * fundamental / 2.0 if scale is not None else d
        if bkind != "as-exported":
            rf, rg = _reference(*baseline, t, f), _reference(*baseline, t, gamma)
            if math.isnan(rf):
                span = f"run from {t.min():g} to {t.max():g} s" if t.size else "are missing"
                raise ContactresInputError(
                    f"{path}: no point of overtone {n} ({fcol!r}) in the baseline window "
                    f"{t0:g} <= t <= {t1:g} s (--baseline; its times {span})"
                )
            refs_f[str(n)], refs_g[str(n)] = rf, rg
            f, gamma = f - rf, gamma - rg
        frames.append(pd.DataFrame({"time_s": t, "overtone": n, "df_Hz": f, "dgamma_Hz": gamma}))
    data = pd.concat(frames, ignore_index=True)
    data["overtone"] = data["overtone"].astype(int)
    record = {
        "source_file": str(path),
        "reader": reader,
        "layout": layout.description,
        "channel": layout.channel,
        "overtones": [int(s[0]) for s in series],
        "time_unit_as_read": unit,
        "frequency_as_read": "absolute f_n" if kind == "absolute" else "shift",
        "df_as_read": (
            "absolute (not divided by n)"
            if kind == "absolute"
            else ("divided by n (Δf_n/n)" if divided else "per overtone (Δf_n)")
        ),
        "dissipation_as_read": "D" if scale is not None else "Gamma (Hz)",
        "dissipation_scale": scale,
        "dissipation_scale_source": (
            None
            if scale is None
            else "given"
            if "dissipation_scale" in given
            else "implied by the header (unit '()': dimensionless)"
            if implied
            else "the header"
        ),
        "baseline": {
            "first": "the first point of each overtone",
            "window": f"the mean over {t0:g} <= t <= {t1:g} s of each overtone",
            "as-exported": "as exported (the reference the instrument software chose)",
        }[bkind],
        "reference_frequency_Hz": refs_f if kind == "absolute" else None,
        "reference_gamma_Hz": refs_g if kind == "absolute" else None,
        "shift_offsets_removed_Hz": (
            {"df": refs_f, "dgamma": refs_g} if kind == "shift" and refs_f else None
        ),
        "fundamental_Hz": fundamental,
        "fundamental_source": fsource,
        "gamma_rule": (
            "Γ read from the file (Hz)"
            if scale is None
            else (
                "Γ_n = D_n x scale x f_n / 2 per row, ΔΓ = Γ_n - Γ_ref"
                if kind == "absolute"
                else "ΔΓ_n = ΔD_n x scale x n f_F / 2 (first order in Δf/f)"
            )
        ),
        "empty_cells_skipped": skipped,
        "left_out": notes,
        "given_by_user": sorted(given),
    }
    return ExportTable(data[list(COLUMNS)], record)
