"""Reader plug-in for Biolin Scientific QSense exports (QSoft, Dfind or QTools, saved as text).

Two layouts are recognised from the header (sensor k = 1-4, overtone n):

A. ``Time_k``, ``F_k:n``, ``D_k:n`` (with ``Meas. Temp. Time``, ``Tact``): semicolon- or
   tab-separated text, often with a decimal comma. **Confirmed** by a file exported this way,
   github.com/safyre8/QCM-D_data_processing, data/S1_20230523_d-h-hex-50nm_1-ps_4-pip_slb.txt
   (``Time_1;F_1:5;D_1:5;...;Meas. Temp. Time;Tact``; its values start at 0: shifts), and by
   the column map of pyQCM-BraTaDio (github.com/b-pardi/pyQCM, format_file.py,
   ``format_Qsense``), which takes F as Δf/n and D in units of 1e-6 ("qsense records just
   change in frequency", its README). The header states none of these units, so this reader
   asks for ``time_unit``, ``df_divided_by_n`` and ``dissipation_scale`` (and ``fundamental``,
   for ΔΓ = ΔD n f_F / 2).
B. ``Time_k [s]``, ``fn_k [Hz]``, ``Dn_k [ppm]`` (e.g. ``f3_1 [Hz]``; a QSoft export to a
   spreadsheet saved as text). **Confirmed** by an export of four sensors, n = 1-13,
   github.com/safyre8/QCM-D_data_processing, data/20230703_hex_50nM.txt (``;``-separated,
   decimal point, 3694 rows of resonance frequencies f_n and absolute D in ppm; read with
   ``channel=1, baseline="first"``), and by third-party scripts that read QSoft exports (a
   public code search for "Time_1 [s]" and "D3_1 [ppm]"). Time in s and D in ppm come from
   the header; whether the f columns hold f_n or shifts is told from the values
   (:data:`~._base.ABSOLUTE_FREQUENCY_HZ`); shifts ask for ``df_divided_by_n``, resonance
   frequencies for a ``baseline``.
C. ``Time``, ``fundamental_freq``, ``3rd_freq``, ..., ``fundamental_dis``, ``3rd_dis``, ...
   (and ``Temp_Time``, ``Temp``): a QSense export as pyQCM-BraTaDio rewrites it
   (github.com/b-pardi/pyQCM, src/format_file.py: its ``freqs`` and ``disps`` names, written
   with ``to_csv(index=False)``, comma separated, as ``raw_data/Formatted-<name>.csv``). The
   units are those of the export it was made from and are not in the header: pyQCM renames
   QSense's columns and leaves Δf/n and D in ppm as they were, unless calibration offsets were
   given, when it writes n x F plus the offset (resonance frequencies f_n) and D x 1e-6. So
   this reader asks for ``time_unit`` and ``dissipation_scale``; whether the frequency columns
   hold f_n or shifts is told from the values (shifts then ask for ``df_divided_by_n``, f_n for
   a ``baseline``). pyQCM writes its table with the same names from the other instruments'
   exports (QCM-I, openQCM, AWSensors): those tables are read here too, with the same
   questions. One sensor; ``channel`` does not apply.

Every layout: a header that names a time, frequency or dissipation column twice is an error
(the columns cannot be told apart); an overtone with a frequency column and no dissipation
column, or the reverse, is left out with a warning (:class:`~._base.ExportWarning`).

QSoft's own .qsd files and Excel workbooks are binary and not read: export the sheet as text.
QSoft shows Δf/n (github.com/jmfriedt/read_qsense_qtools, README): say so with
``df_divided_by_n=True`` if the export kept that normalisation.
"""

from __future__ import annotations

import re
from pathlib import Path
from types import MappingProxyType

from ....errors import ContactresInputError
from ._base import (
    ExportReader,
    ExportTable,
    Layout,
    check_duplicates,
    check_keys,
    header_names,
    pick_channel,
    read_rows,
    unpaired,
)
from ._tidy import convert

__all__ = ["CONVENTIONS", "NAME", "READER", "SUFFIXES", "detect", "load"]

NAME = "qsense"
SUFFIXES = (".txt", ".csv", ".tsv")
SOURCE = (
    "github.com/safyre8/QCM-D_data_processing (sample export, layout A); "
    "github.com/b-pardi/pyQCM format_file.py (column map); scripts reading QSoft exports "
    "(layout B, names only); github.com/b-pardi/pyQCM src/format_file.py (layout C, the table "
    "pyQCM writes)"
)
CONVENTIONS = MappingProxyType(
    {
        "time": "Time_k, Time (pyQCM): unit not stated (asked: time_unit); Time_k [s]: seconds",
        "frequency": "F_k:n: shifts, Δf or Δf/n not stated (asked: df_divided_by_n); "
        "fn_k [Hz], Nth_freq (pyQCM): f_n or shifts, told from the values",
        "dissipation": "D_k:n, Nth_dis (pyQCM): D, unit not stated (asked: dissipation_scale, "
        "1e-6 for ppm); Dn_k [ppm]: D in 1e-6",
        "overtones": "as named in the columns (n of F_k:n, fn_k, Nth_freq; fundamental = 1)",
        "channels": "sensors k = 1-4 (asked: channel, when the file holds several); pyQCM: one",
    }
)

# Layout A: (k) ; (k, n) ; (k, n). Layout B: (k) ; (n, k) ; (n, k). Layout C (pyQCM's
# table): () ; (n) ; (n), with n written "fundamental" (1) or as an ordinal (3rd, 5th, ...).
_A = (re.compile(r"^Time_(\d+)$"), re.compile(r"^F_(\d+):(\d+)$"), re.compile(r"^D_(\d+):(\d+)$"))
_B = (
    re.compile(r"^Time_(\d+) \[s\]$", re.IGNORECASE),
    re.compile(r"^f(\d+)_(\d+) \[Hz\]$", re.IGNORECASE),
    re.compile(r"^D(\d+)_(\d+) \[ppm\]$", re.IGNORECASE),
)
_ORDINAL = r"(?:fundamental|(\d+)(?:st|nd|rd|th))"
_C = (
    re.compile(r"^()Time$"),
    re.compile(rf"^{_ORDINAL}_freq$", re.IGNORECASE),
    re.compile(rf"^{_ORDINAL}_dis$", re.IGNORECASE),
)
_LAYOUTS = (("A", _A, "kn"), ("B", _B, "nk"), ("C", _C, "n"))


def _key(m: re.Match, order: str) -> tuple[str, int]:
    """(sensor, overtone) of a frequency or dissipation column: the groups in ``order``
    ("kn", "nk", or "n": one sensor, "" , and "fundamental" for n = 1)."""
    if order == "n":
        return "", int(m.group(1) or 1)
    k, n = (m.group(1), m.group(2)) if order == "kn" else (m.group(2), m.group(1))
    return k, int(n)


def _columns(names: list[str], patterns, order: str):
    """Time columns by sensor and (f, D) columns by (sensor, overtone)."""
    times: dict[str, str] = {}  # sensor -> time column
    freqs: dict[tuple[str, int], str] = {}  # (sensor, overtone) -> column
    diss: dict[tuple[str, int], str] = {}
    for name in names:
        if m := patterns[0].match(name):
            times.setdefault(m.group(1), name)
        elif m := patterns[1].match(name):
            freqs.setdefault(_key(m, order), name)
        elif m := patterns[2].match(name):
            diss.setdefault(_key(m, order), name)
    return times, freqs, diss


def _layout_of(names: list[str]):
    """(tag, patterns, times, freqs, diss) of the layout the names follow, or None."""
    for tag, patterns, order in _LAYOUTS:
        times, freqs, diss = _columns(names, patterns, order)
        if times and any(key[0] in times for key in freqs.keys() & diss.keys()):
            return tag, patterns, times, freqs, diss
    return None


def detect(path: Path, head: str) -> bool:
    """True for a header with a QSense time column and F/D columns of the same sensor (or
    pyQCM's Time, fundamental_freq/_dis, 3rd_freq/_dis, ...)."""
    return _layout_of(header_names(head)) is not None


def _layout(path: Path, names: list[str], channel) -> Layout:
    found = _layout_of(names)
    if found is None:
        raise ContactresInputError(
            f"{path}: no QSense columns (Time_k with F_k:n and D_k:n, fn_k [Hz], or pyQCM's "
            "Time, 3rd_freq, 3rd_dis)"
        )
    tag, patterns, times, freqs, diss = found
    check_duplicates(path, NAME, names, patterns)
    pairs = sorted(key for key in freqs.keys() & diss.keys() if key[0] in times)
    k = pick_channel(path, NAME, (key[0] for key in pairs), channel) if tag != "C" else ""
    if tag == "C" and channel is not None:
        raise ContactresInputError(
            f"{path}: channel (--channel) does not apply: pyQCM's table holds one sensor"
        )
    traces = tuple((n, freqs[(k, n)], diss[(k, n)]) for kk, n in pairs if kk == k)
    for n, fcol, _ in traces:
        if n < 1 or n % 2 == 0:
            raise ContactresInputError(
                f"{path}, column {fcol!r}: overtone {n} is not odd (QSense export)"
            )
    left = unpaired(
        {n: c for (kk, n), c in freqs.items() if kk == k},
        {n: c for (kk, n), c in diss.items() if kk == k},
    )
    if tag == "A":
        text = "QSense text export: Time_k, F_k:n, D_k:n (units not in the header)"
        return Layout(text, times[k], traces, channel=k, left_out=left)
    if tag == "C":
        text = (
            "pyQCM-BraTaDio table: Time, fundamental_freq, 3rd_freq, ..., fundamental_dis, "
            "3rd_dis, ... (units not in the header)"
        )
        return Layout(text, times[k], traces, left_out=left)
    text = "QSense text export: Time_k [s], fn_k [Hz], Dn_k [ppm]"
    return Layout(
        text, times[k], traces, channel=k, time_unit="s", dissipation_scale=1e-6, left_out=left
    )


def load(path, **conventions) -> ExportTable:
    """Read a QSense text export (see the module docstring for the conventions asked for)."""
    path = Path(path)
    check_keys(path, NAME, conventions)
    raw = read_rows(path)
    layout = _layout(path, list(raw.columns), conventions.get("channel"))
    return convert(path, NAME, raw, layout, conventions)


READER = ExportReader(NAME, SUFFIXES, detect, load, conventions=CONVENTIONS, source=SOURCE)
