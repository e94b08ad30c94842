"""Reader plug-in for AWSensors QCM-D exports (AWS software, saved as text).

Layout: ``Time_(s)``, ``Delta_F/n_n=3_(Hz)``, ``Delta_D_n=3_()``, ... one pair per overtone.
**Confirmed only through a third party**: these are the column names pyQCM-BraTaDio maps
(github.com/b-pardi/pyQCM, format_file.py, ``format_AWSensors``: overtones 3-11, Δf/n, D
multiplied by 1e-6 there). No sample file was found, so the layout of the rest of the file (a
preamble, the separator) is not confirmed: this reader takes a header line followed by data
rows, comma, semicolon or tab separated.

What the header tells: time in seconds, shifts ("Delta"), divided by n where the name says
``F/n`` (a name ``Delta_F_n=3_(Hz)`` is read as Δf itself; that variant is not confirmed). The
unit of D is written in the last parentheses: ``(ppm)`` or ``(1e-6)`` mean 1e-6; empty, ``()``
(as in the confirmed names), is the unit of a dimensionless number, so D is read as a plain
number (scale 1) without asking. A D column in ppm under ``()`` is caught: a plain ΔD of
:data:`~._tidy.MAX_PLAIN_D_SHIFT` or more is no contact's (one line asking for
``dissipation_scale=1e-6``), and a ``dissipation_scale`` given replaces the ``()`` reading
(pyQCM-BraTaDio multiplies these D values by 1e-6 when it adds calibration offsets, so some
exports may hold ppm). ``fundamental`` is asked for (ΔΓ = ΔD n f_F/2).

A header naming a column twice is an error; an overtone with a Delta_F column and no Delta_D
column, or the reverse, is left out with a warning (:class:`~._base.ExportWarning`).
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
    read_rows,
    unpaired,
)
from ._tidy import convert

__all__ = ["CONVENTIONS", "NAME", "READER", "SUFFIXES", "detect", "load"]

NAME = "awsensors"
SUFFIXES = (".csv", ".txt", ".tsv")
SOURCE = "github.com/b-pardi/pyQCM format_file.py (format_AWSensors column map); no sample file"
CONVENTIONS = MappingProxyType(
    {
        "time": "Time_(s): seconds",
        "frequency": "Delta_F/n_n=N_(Hz): shifts divided by n (Delta_F_n=N_(Hz): Δf)",
        "dissipation": "Delta_D_n=N_(): shift of D, dimensionless (a dissipation_scale given "
        "replaces it); (ppm) or (1e-6): D in 1e-6",
        "overtones": "as named (n=N)",
        "channels": "one",
    }
)

_TIME = "Time_(s)"
_F = re.compile(r"^Delta_F(/n)?_n=(\d+)_\(Hz\)$")
_D = re.compile(r"^Delta_D_n=(\d+)_\(([^)]*)\)$")
# "" is the unit of a dimensionless number (1); see the module docstring.
_SCALES = MappingProxyType({"": 1.0, "ppm": 1e-6, "1e-6": 1e-6})


def _columns(names: list[str]):
    freqs: dict[int, tuple[str, bool]] = {}  # overtone -> (column, divided by n)
    diss: dict[int, tuple[str, str]] = {}  # overtone -> (column, unit)
    for name in names:
        if m := _F.match(name):
            freqs.setdefault(int(m.group(2)), (name, m.group(1) is not None))
        elif m := _D.match(name):
            diss.setdefault(int(m.group(1)), (name, m.group(2).strip().lower()))
    return freqs, diss


def detect(path: Path, head: str) -> bool:
    """True for a header with ``Time_(s)`` and a Delta_F/Delta_D pair of one overtone."""
    names = header_names(head)
    freqs, diss = _columns(names)
    return _TIME in names and bool(freqs.keys() & diss.keys())


def _layout(path: Path, names: list[str]) -> Layout:
    check_duplicates(path, NAME, names, (re.compile(re.escape(_TIME) + "$"), _F, _D))
    freqs, diss = _columns(names)
    overtones = sorted(freqs.keys() & diss.keys())
    if _TIME not in names or not overtones:
        raise ContactresInputError(
            f"{path}: no AWSensors columns (Time_(s), Delta_F/n_n=3_(Hz), ...)"
        )
    for n in overtones:
        if n < 1 or n % 2 == 0:
            raise ContactresInputError(f"{path}, column {freqs[n][0]!r}: overtone {n} is not odd")
    divided = {freqs[n][1] for n in overtones}
    if len(divided) > 1:
        raise ContactresInputError(f"{path}: the Delta_F columns mix F/n and F (AWSensors export)")
    units = {diss[n][1] for n in overtones}
    unknown = units - set(_SCALES)
    if len(units) > 1 or unknown:
        raise ContactresInputError(
            f"{path}: the Delta_D columns have the unit(s) {', '.join(map(repr, sorted(units)))}"
            f"; one of {', '.join(repr(u) for u in _SCALES)} is understood (AWSensors export)"
        )
    traces = tuple((n, freqs[n][0], diss[n][0]) for n in overtones)
    text = "AWSensors text export: Time_(s), Delta_F/n_n=N_(Hz), Delta_D_n=N_()"
    unit = units.pop()
    # "()" is a dimensionless D read as it is unless a scale is given; "(ppm)" states the unit.
    return Layout(
        text,
        _TIME,
        traces,
        time_unit="s",
        frequency="shift",
        divided_by_n=divided.pop(),
        dissipation_scale=None if unit == "" else _SCALES[unit],
        left_out=unpaired(
            {n: c for n, (c, _) in freqs.items()}, {n: c for n, (c, _) in diss.items()}
        ),
        dissipation_scale_default=_SCALES[unit] if unit == "" else None,
    )


def load(path, **conventions) -> ExportTable:
    """Read an AWSensors text export (see the module docstring for the conventions)."""
    path = Path(path)
    check_keys(path, NAME, conventions)
    if conventions.get("channel") is not None:
        raise ContactresInputError(
            f"{path}: channel (--channel) does not apply: the AWSensors export has one channel"
        )
    raw = read_rows(path)
    return convert(path, NAME, raw, _layout(path, list(raw.columns)), conventions)


READER = ExportReader(NAME, SUFFIXES, detect, load, conventions=CONVENTIONS, source=SOURCE)
