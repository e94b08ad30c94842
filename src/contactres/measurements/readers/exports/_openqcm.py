"""Reader plug-in for openQCM data logs (CSV written by the openQCM Python software).

Two layouts, both **confirmed** in the openQCM sources (github.com/openQCM):

* single overtone (openQCM Q-1; openQCM Next in single mode): ``Date, Time, Relative_time,
  Temperature, Resonance_Frequency, Dissipation`` (openQCM_Q-1, openQCM/common/fileStorage.py
  and the sample log docs/2026-04-24_10-25-14_F0.csv: 10011102.85 Hz, D = 3.05e-4);
* multiscan (openQCM Next): ``Date, Time, Relative_time, Temperature, Frequency_0,
  Dissipation_0, ..., Frequency_4, Dissipation_4`` (openqcm-next, software/openQCM/common/
  fileStorage.py, ``CSVsave_Multi``); index i is overtone 2i + 1 (openqcm-next
  docs/impedance-analysis/datalog-quantities-2026-09-10.md; pyQCM-BraTaDio, format_file.py).

What the file tells: ``Relative_time`` in seconds, the frequencies are f_n (resonance
frequencies; the overtones of the multiscan log from the column index). What it does not tell,
and is therefore asked for:

* ``dissipation_scale``: the Q-1 software logs D = 1/Q = (-3 dB width)/f as a plain number (1;
  openQCM_Q-1, openQCM/processors/Serial.py); openQCM Next's impedance-analysis software logs
  D = 2Γ/f in ppm (1e-6). openQCM Next's ``main`` software logs in its Dissipation columns the
  full width at 0.3 dB below the peak divided by 1e6, which is not D and has no fixed relation
  to Γ (datalog-quantities-2026-09-10.md): such a log cannot be converted, and the file does
  not say which software wrote it;
* ``overtone`` of a single-overtone log (the file name's ``_F0`` is not documented);
* ``baseline`` (the log holds resonance frequencies, not shifts).

The multiscan writer skips a zero frequency or dissipation without leaving an empty cell, which
shifts the later cells of that row: such rows cannot be told from the file.
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
    missing,
    read_rows,
    unpaired,
)
from ._tidy import convert

__all__ = ["CONVENTIONS", "NAME", "READER", "SUFFIXES", "detect", "load"]

NAME = "openqcm"
SUFFIXES = (".csv",)
SOURCE = (
    "github.com/openQCM/openQCM_Q-1 (fileStorage.py, Serial.py, docs sample log); "
    "github.com/openQCM/openqcm-next (fileStorage.py CSVsave_Multi, datalog-quantities doc)"
)
CONVENTIONS = MappingProxyType(
    {
        "time": "Relative_time: seconds",
        "frequency": "Resonance_Frequency or Frequency_i: resonance frequency f_n (Hz)",
        "dissipation": "Dissipation(_i): D, scale depends on the software (asked: "
        "dissipation_scale, 1 for the Q-1, 1e-6 for openQCM Next impedance analysis)",
        "overtones": "Frequency_i: n = 2i + 1; Resonance_Frequency: not stated (asked: overtone)",
        "channels": "one",
    }
)

_HEAD = ["Date", "Time", "Relative_time", "Temperature"]
_F = re.compile(r"^Frequency_(\d+)$")
_D = re.compile(r"^Dissipation_(\d+)$")
_SINGLE = (re.compile(r"^Relative_time$"), re.compile(r"^Resonance_Frequency$"),
           re.compile(r"^Dissipation$"))  # fmt: skip


def detect(path: Path, head: str) -> bool:
    """True for a header starting Date, Time, Relative_time, Temperature with f and D columns."""
    names = header_names(head)
    single = "Resonance_Frequency" in names and "Dissipation" in names
    multi = any((m := _F.match(n)) and f"Dissipation_{m.group(1)}" in names for n in names)
    return names[:4] == _HEAD and (single or multi)


def _layout(path: Path, names: list[str], overtone) -> Layout:
    if names[:4] != _HEAD:
        raise ContactresInputError(f"{path}: not an openQCM log (header {', '.join(_HEAD)}, ...)")
    check_duplicates(path, NAME, names, (_F, _D, *_SINGLE))
    multi = [
        (2 * int(m.group(1)) + 1, name, f"Dissipation_{m.group(1)}")
        for name in names
        if (m := _F.match(name)) and f"Dissipation_{m.group(1)}" in names
    ]
    if multi:
        text = "openQCM Next multiscan log: Relative_time, Frequency_i, Dissipation_i (n = 2i+1)"
        left = unpaired(
            {2 * int(m.group(1)) + 1: c for c in names if (m := _F.match(c))},
            {2 * int(m.group(1)) + 1: c for c in names if (m := _D.match(c))},
        )
        return Layout(
            text,
            "Relative_time",
            tuple(sorted(multi)),
            time_unit="s",
            frequency="absolute",
            left_out=left,
        )
    if "Resonance_Frequency" not in names or "Dissipation" not in names:
        raise ContactresInputError(f"{path}: no openQCM frequency and dissipation columns")
    if overtone is None:
        why = "a single-overtone log does not say its overtone"
        raise missing(path, NAME, [("overtone", why)])
    n = int(overtone)
    if n < 1 or n % 2 == 0:
        raise ContactresInputError(
            f"{path}: overtone {overtone!r} (--overtone) must be an odd integer >= 1"
        )
    text = "openQCM single-overtone log: Relative_time, Resonance_Frequency, Dissipation"
    trace = ((n, "Resonance_Frequency", "Dissipation"),)
    return Layout(
        text, "Relative_time", trace, time_unit="s", frequency="absolute", overtone_in_file=False
    )


def load(path, **conventions) -> ExportTable:
    """Read an openQCM log (see the module docstring for the conventions asked for)."""
    path = Path(path)
    check_keys(path, NAME, conventions)
    if conventions.get("channel") is not None:
        raise ContactresInputError(
            f"{path}: channel (--channel) does not apply: an openQCM log has one channel"
        )
    raw = read_rows(path)
    layout = _layout(path, list(raw.columns), conventions.get("overtone"))
    return convert(path, NAME, raw, layout, conventions)


READER = ExportReader(NAME, SUFFIXES, detect, load, conventions=CONVENTIONS, source=SOURCE)
