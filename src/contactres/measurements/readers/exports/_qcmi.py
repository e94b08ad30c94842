"""Reader plug-in for MicroVacuum QCM-I exports (tab- or comma-separated text).

Layout, per channel X = A-D: ``Channel X QCM Time [sec]``, ``Channel X Fundamental Frequency
[Hz]``, ``Channel X Fundamental Dissipation [ ]``, ``Channel X 3. Overtone [Hz]``,
``Channel X 3. Dissipation  [ ]``, ... up to the 13th overtone, among many other columns
(Boffs, Fi, Flow, FWHM, Gmax, Goffs, Q, Residual, Sauerbrey Mass, Temp, and "Variation" columns
of each). **Confirmed** by a sample export, github.com/b-pardi/pyQCM, offset_data/
"06092023_bare gold in air in 25C_STA.txt" (106 columns, tab-separated, the flow and temperature
columns repeated per overtone), and by pyQCM-BraTaDio's column map (format_file.py,
``format_QCMi``), and comma-separated by pyQCM's sample_generations/qcmi-bsa-after/
QSM-I-BSA_1mgpml.csv (879 rows, channel A, n = 1-13, read as it is): the frequency columns
hold the resonance frequencies f_n (4961272 Hz for the fundamental there), the dissipation
columns D as a plain number ("[ ]"; 1.31e-5 there, equal to FWHM/f of the same row).

What the header tells: time in seconds, D as a plain number (``dissipation_scale`` 1). Whether
the frequency columns hold f_n or shifts is told from the values; with f_n a ``baseline`` is
asked for (the file's "Variation" columns are f_n minus its first row in the sample:
``baseline="first"`` reproduces them). ``channel`` is asked for when the file holds several.
Rows out of time order: ``baseline="first"`` takes the point of the earliest time. A header
naming a time, frequency or dissipation column twice is an error (the flow and temperature
columns, repeated per overtone, are not read); an overtone with a frequency column and no
dissipation column, or the reverse, is left out with a warning.
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

NAME = "qcmi"
SUFFIXES = (".txt", ".tsv", ".csv")
SOURCE = (
    "github.com/b-pardi/pyQCM: offset_data/06092023_bare gold in air in 25C_STA.txt (sample "
    "export) and format_file.py (format_QCMi)"
)
CONVENTIONS = MappingProxyType(
    {
        "time": "Channel X QCM Time [sec]: seconds",
        "frequency": "Channel X Fundamental Frequency [Hz], Channel X N. Overtone [Hz]: f_n "
        "(or shifts, told from the values)",
        "dissipation": "Channel X ... Dissipation [ ]: D as a plain number",
        "overtones": "Fundamental = 1, N. = N",
        "channels": "X = A-D (asked: channel, when the file holds several)",
    }
)

_TIME = re.compile(r"^Channel ([A-Z]) QCM Time \[sec\]$")
_F = re.compile(r"^Channel ([A-Z]) (?:Fundamental Frequency|(\d+)\. Overtone) \[Hz\]$")
_D = re.compile(r"^Channel ([A-Z]) (?:Fundamental|(\d+)\.) Dissipation \[ ?\]$")


def _columns(names: list[str]):
    times: dict[str, str] = {}  # sensor -> time column
    freqs: dict[tuple[str, int], str] = {}  # (sensor, overtone) -> column
    diss: dict[tuple[str, int], str] = {}
    for name in names:
        if m := _TIME.match(name):
            times.setdefault(m.group(1), name)
        elif m := _F.match(name):
            freqs.setdefault((m.group(1), int(m.group(2) or 1)), name)
        elif m := _D.match(name):
            diss.setdefault((m.group(1), int(m.group(2) or 1)), name)
    pairs = sorted(key for key in freqs.keys() & diss.keys() if key[0] in times)
    return times, freqs, diss, pairs


def detect(path: Path, head: str) -> bool:
    """True for a header with a QCM-I time column and a frequency/dissipation pair."""
    return bool(_columns(header_names(head))[3])


def _layout(path: Path, names: list[str], channel) -> Layout:
    times, freqs, diss, pairs = _columns(names)
    if not pairs:
        raise ContactresInputError(f"{path}: no QCM-I columns (Channel A QCM Time [sec], ...)")
    check_duplicates(path, NAME, names, (_TIME, _F, _D))
    x = pick_channel(path, NAME, (key[0] for key in pairs), channel)
    traces = tuple((n, freqs[(xx, n)], diss[(xx, n)]) for xx, n in pairs if xx == x)
    for n, fcol, _ in traces:
        if n % 2 == 0:
            raise ContactresInputError(
                f"{path}, column {fcol!r}: overtone {n} is not odd (QCM-I export)"
            )
    text = "QCM-I text export: Channel X QCM Time [sec], ... Frequency/Overtone [Hz], Dissipation"
    left = unpaired(
        {n: c for (xx, n), c in freqs.items() if xx == x},
        {n: c for (xx, n), c in diss.items() if xx == x},
    )
    return Layout(
        text, times[x], traces, channel=x, time_unit="s", dissipation_scale=1.0, left_out=left
    )


def load(path, **conventions) -> ExportTable:
    """Read a QCM-I text export (see the module docstring for the conventions)."""
    path = Path(path)
    check_keys(path, NAME, conventions)
    raw = read_rows(path)
    layout = _layout(path, list(raw.columns), conventions.get("channel"))
    return convert(path, NAME, raw, layout, conventions)


READER = ExportReader(NAME, SUFFIXES, detect, load, conventions=CONVENTIONS, source=SOURCE)
