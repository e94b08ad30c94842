"""Reader recipes of admittance spectra: a tidy table, or a folder of one file per spectrum.

The folder holds an ``index.csv`` naming each file (column ``file``) with its labels, and one
file per spectrum as network analysers write them: a Touchstone one-port file (``.s1p``,
``.y1p``, ``.z1p``: its option line ``# Hz S RI R 50`` says the frequency unit, the parameter
(S11, Y or Z), the format (RI real/imaginary, MA magnitude/angle in degrees, DB dB/angle) and
the reference impedance; one option line, before the data; a word Touchstone does not define
is an error, never a default), a Touchstone two-port file of S parameters (``.s2p``, the
parameter read chosen by the ``two_port`` argument: :data:`TWO_PORT_PARAMETERS`), or a
delimited file whose header names say what its two columns hold (:data:`SPECTRUM_LAYOUTS`;
the ``layout`` argument when they do not). The index names
files of its own folder only (a path leading out of it is refused). S11 becomes
Y = (1 − S)/(Z0 (1 + S)) with the reference impedance Z0 (Touchstone: its R; otherwise
``reference_impedance``, 50 Ω by default).

Both recipes (:data:`SPECTRA_READERS`, kind ``spectra``) give the rows of a tidy spectra table
as string cells with a ``line`` column, which
:func:`contactres.measurements._spectra_table.validate_spectra` checks.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import ContactresInputError
from .._messages import column_names, shown_value
from ..schema import NUMBER_TEXT, SPECTRA_TABLE, check_cells
from . import _delimited
from ._recipe import Reader

if TYPE_CHECKING:  # annotations: pandas is imported where a table is read (a numpy archive's
    import pandas as pd  # reader shares this package and needs none, issue 31)

__all__ = [
    "CONSTANT_COLUMNS",
    "LABELS",
    "NUMERIC_LABELS",
    "SPECTRA_READERS",
    "SPECTRUM_LAYOUTS",
    "TWO_PORT_PARAMETERS",
    "cells_as_numbers",
    "load_folder",
    "load_table",
]

#: Header names of the two data columns of a delimited spectrum file -> layout name.
SPECTRUM_LAYOUTS = {
    "G/B": (("G_S", "B_S"), "conductance and susceptance, S"),
    "Y-RI": (("Y_re_S", "Y_im_S"), "real and imaginary part of Y, S"),
    "S11-RI": (("S11_re", "S11_im"), "real and imaginary part of S11"),
    "Y-MA": (("Y_mag_S", "Y_phase_deg"), "|Y| in S and its phase in degrees"),
}
#: Constants of the sweep table a spectra table may carry as columns (passed on to the sweeps).
CONSTANT_COLUMNS = ("fundamental_Hz", "area_m2", "n_contacts", "sphere_radius_m", "poisson")
#: The per-spectrum labels a row may carry (an index.csv passes them on to its files).
LABELS = (*(c.name for c in SPECTRA_TABLE.columns if c.level == "sweep"), *CONSTANT_COLUMNS)
#: The labels that are numbers.
NUMERIC_LABELS = (
    "overtone", "drive_voltage_V", "time_s", "ramp", "normal_force_N", *CONSTANT_COLUMNS
)  # fmt: skip


def cells_as_numbers(raw: pd.DataFrame, col: str, source: str, decimal: str = ".") -> np.ndarray:
    """The cells of ``col`` as numbers (decimal comma where ``decimal`` is ","); blank or NaN
    cells are NaN; any other cell that is not a number is a one-line error (:data:`~contactres
    .measurements.schema.NUMBER_TEXT`)."""
    import pandas as pd

    s = raw[col].astype(str).str.strip()
    if decimal == ",":
        s = s.str.replace(",", ".", regex=False)
    check_cells(raw, source, col, (NUMBER_TEXT,), s.to_numpy())
    return pd.to_numeric(s, errors="coerce").to_numpy(dtype=float)


_OPTION_LINE = re.compile(r"^\s*#(.*)$")
#: The S parameter of a two-port file (``.s2p``) read as the crystal's response, and how it
#: becomes the crystal's admittance Y with the reference impedance Z0: in reflection (the
#: crystal on port 1 or port 2, the other port not connected to it) the one-port relation
#: Y = (1 − S)/(Z0 (1 + S)); in transmission through the crystal in series between the two
#: ports, S21 = 2Z0/(2Z0 + Z), so Y = S21/(2 Z0 (1 − S21)) (D. M. Pozar, *Microwave
#: Engineering*, 4th ed., Wiley (2012), Table 4.2: a series impedance).
TWO_PORT_PARAMETERS = {
    "S11": "reflection at port 1: the crystal on port 1",
    "S22": "reflection at port 2: the crystal on port 2",
    "S21": "transmission: the crystal in series between port 1 and port 2",
}
# Position of each S parameter's pair of numbers on a two-port data line (Touchstone 1: the
# frequency, then S11, S21, S12, S22).
_TWO_PORT_COLUMNS = {"S11": 1, "S21": 3, "S12": 5, "S22": 7}

#: The words of a Touchstone 1 option line, ``# <frequency unit> <parameter> <format> R <n>``
#: (Touchstone File Format Specification 2.0, section "Option Line", which also defines
#: version 1.x files): frequency units, parameters (H and G are two-port hybrid parameters, no
#: one-port admittance: refused), formats.
_UNITS = {"hz": 1.0, "khz": 1e3, "mhz": 1e6, "ghz": 1e9}
_PARAMETERS = ("s", "y", "z", "h", "g")
_FORMATS = ("ri", "ma", "db")
_OPTION_SYNTAX = (
    "# <frequency unit: Hz, kHz, MHz or GHz> <parameter: S, Y or Z> <format: RI, MA or DB> "
    "R <reference impedance, Ω>"
)


def _options(path: Path, number: int, text: str) -> tuple[float, str, str, float]:
    """(Hz per frequency unit, parameter, format, R) of a Touchstone option line; a word the
    specification does not define, one given twice or an R that is no positive number is a
    one-line error naming the file and the line. Words left out take the specification's
    defaults (GHz, S, MA, R 50)."""
    where = f"{path}, line {number}: option line {shown_value(text)}"
    found: dict[str, str] = {}
    z0 = None
    words = text.lstrip()[1:].split()
    i = 0
    while i < len(words):
        w = words[i].lower()
        key = (
            "unit" if w in _UNITS else "parameter" if w in _PARAMETERS else
            "format" if w in _FORMATS else "r" if w == "r" else None
        )  # fmt: skip
        if key is None:
            raise ContactresInputError(
                f"{where}: unknown word {shown_value(words[i])}; Touchstone 1 has {_OPTION_SYNTAX}"
            )
        if key in found:
            raise ContactresInputError(f"{where}: the {key} is given twice; {_OPTION_SYNTAX}")
        found[key] = w
        if key == "r":
            value = words[i + 1] if i + 1 < len(words) else ""
            try:
                z0 = float(value)
            except ValueError:
                z0 = math.nan
            if not (math.isfinite(z0) and z0 > 0):
                raise ContactresInputError(
                    f"{where}: R {shown_value(value)} is no reference impedance (a number > 0, Ω)"
                )
            i += 1
        i += 1
    if found.get("parameter") in ("h", "g"):
        raise ContactresInputError(
            f"{where}: {found['parameter'].upper()} parameters are two-port hybrid "
            "parameters, not a one-port's; save the spectrum as S, Y or Z"
        )
    return (
        _UNITS[found.get("unit", "ghz")],
        found.get("parameter", "s").upper(),
        found.get("format", "ma").upper(),
        50.0 if z0 is None else z0,
    )


def _touchstone(
    path: Path, two_port: str | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(frequency Hz, G S, B S, line numbers) of a Touchstone 1 file: one-port, or two-port
    (``.s2p``) with the S parameter ``two_port`` (:data:`TWO_PORT_PARAMETERS`). Its one option
    line must come before the data: without it the unit and format would be the
    specification's defaults (GHz, MA), which a file of Hz read silently (issue 27); a second
    option line is an error (the specification allows one). A two-port file's noise
    parameters (lines of 5 numbers after the network data) are not read."""
    ports = 2 if path.suffix.lower() == ".s2p" else 1
    if ports == 2 and two_port is None:
        raise ContactresInputError(
            f"{path}: a two-port Touchstone file: give the crystal's S parameter with "
            f"--two-port (two_port=), one of {', '.join(TWO_PORT_PARAMETERS)}"
        )  # what each one means is in --help: the line stays short
    width = 9 if ports == 2 else 3
    column = 1 if ports == 1 else _TWO_PORT_COLUMNS[str(two_port)]
    options = None
    freq: list[float] = []
    a: list[float] = []
    b: list[float] = []
    lines: list[int] = []
    for number, text in enumerate(path.read_text(errors="replace").splitlines(), start=1):
        text = text.split("!", 1)[0].strip()
        if not text:
            continue
        if text.startswith("["):
            raise ContactresInputError(
                f"{path}, line {number}: Touchstone 2 keyword {shown_value(text)}: save the "
                "spectrum as a Touchstone 1 file (.s1p) or as CSV"
            )
        if _OPTION_LINE.match(text):
            if options is not None:
                raise ContactresInputError(
                    f"{path}, line {number}: a second option line {shown_value(text)} (the "
                    f"first is line {options[0]}); a Touchstone file has one"
                )
            options = (number, *_options(path, number, text))
            continue
        if options is None:
            raise ContactresInputError(
                f"{path}, line {number}: data before the option line; a Touchstone file "
                f"starts with one ({_OPTION_SYNTAX}): without it the frequency unit and "
                "format are not known"
            )
        fields = text.split()
        try:
            values = [float(x) for x in fields]
        except ValueError:
            raise ContactresInputError(
                f"{path}, line {number}: {shown_value(text)} is not {width} numbers "
                f"(frequency and the two parts of each of the {ports}-port file's parameters)"
            ) from None
        if ports == 2 and len(values) == 5 and freq:
            break  # the noise parameters of a two-port file: not the network's data
        if len(values) != width:
            raise ContactresInputError(
                f"{path}, line {number}: {len(values)} numbers, a {ports}-port Touchstone line "
                f"has {width}"
            )
        freq.append(values[0] * options[1])
        a.append(values[column])
        b.append(values[column + 1])
        lines.append(number)
    if options is None:
        raise ContactresInputError(
            f"{path}: no option line and no data; a Touchstone file has {_OPTION_SYNTAX} "
            "and one line per frequency"
        )
    _, _, param, fmt, z0 = options
    if ports == 2 and param != "S":
        raise ContactresInputError(
            f"{path}, line {options[0]}: a two-port file of {param} parameters; contactres reads "
            "two-port files of S parameters (save them as S, or the crystal alone as a one-port)"
        )
    first, second = np.array(a), np.array(b)
    if fmt == "RI":
        x = first + 1j * second
    else:
        mag = 10 ** (first / 20) if fmt == "DB" else first
        x = mag * np.exp(1j * np.radians(second))
    if two_port == "S21":
        with np.errstate(divide="ignore", invalid="ignore"):
            y = x / (2.0 * z0 * (1.0 - x))  # a series element between the ports
        return np.array(freq), y.real, y.imag, np.array(lines)
    return np.array(freq), *_admittance(param, x, z0), np.array(lines)


def _admittance(param: str, x: np.ndarray, z0: float) -> tuple[np.ndarray, np.ndarray]:
    """(G, B) in S of a one-port parameter. Touchstone 1 normalises Y and Z to R (y = Y R,
    z = Z/R); S is dimensionless. S = -1 (a short) or Z = 0 has no finite Y: NaN or inf here,
    which the resonance fit flags (bad-values) and leaves out with one line, with no numpy
    warning on the console."""
    with np.errstate(divide="ignore", invalid="ignore"):
        if param == "S":
            y = (1 - x) / (z0 * (1 + x))
        elif param == "Z":
            y = 1 / (x * z0)
        else:
            y = x / z0
    return y.real, y.imag


def _delimited_spectrum(path: Path, layout: str | None, z0: float):
    """(frequency Hz, G S, B S (NaN where absent), line numbers) of a delimited file."""
    raw = _delimited.load(path)
    if "frequency_Hz" not in raw.columns:
        raise ContactresInputError(
            f"{path}: no column 'frequency_Hz'; the columns are "
            f"{column_names(c for c in raw.columns if c != 'line')}"
        )
    found = [k for k, (names, _) in SPECTRUM_LAYOUTS.items() if names[0] in raw.columns]
    if layout is None:
        if len(found) != 1:
            known = "; ".join(
                f"{k}: {' + '.join(n)} ({w})" for k, (n, w) in SPECTRUM_LAYOUTS.items()
            )
            raise ContactresInputError(
                f"{path}: cannot tell what the columns hold (found layouts {found or 'none'}); "
                f"name them as one of: {known}, or give the layout"
            )
        layout = found[0]
    if layout not in SPECTRUM_LAYOUTS:
        raise ContactresInputError(
            f"layout must be one of {list(SPECTRUM_LAYOUTS)}, got {layout!r}"
        )
    names = SPECTRUM_LAYOUTS[layout][0]
    source = str(path)
    decimal = raw.attrs.get("decimal", ".")
    f = cells_as_numbers(raw, "frequency_Hz", source, decimal)
    first = cells_as_numbers(raw, names[0], source, decimal)
    if names[1] in raw.columns:
        second = cells_as_numbers(raw, names[1], source, decimal)
    elif layout == "G/B":
        second = np.full(f.shape, np.nan)  # G alone: fitted alone
    else:
        raise ContactresInputError(
            f"{path}: layout {layout} needs both columns {names[0]} and {names[1]}"
        )
    if layout == "G/B":
        return f, first, second, raw["line"].to_numpy()
    if layout == "Y-RI":
        y = first + 1j * second
    elif layout == "S11-RI":
        g, b = _admittance("S", first + 1j * second, z0)
        return f, g, b, raw["line"].to_numpy()
    else:
        y = first * np.exp(1j * np.radians(second))
    return f, y.real, y.imag, raw["line"].to_numpy()


def _read_folder(folder: Path, layout, z0: float, two_port: str | None) -> pd.DataFrame:
    import pandas as pd

    index_path = folder / "index.csv"
    if not index_path.exists():
        raise ContactresInputError(
            f"{folder}: a folder of spectra needs an index.csv naming each file (column 'file') "
            "with its labels (drive_voltage_V, overtone, reference, sweep, ...)"
        )
    index = _delimited.load(index_path)
    if "file" not in index.columns:
        raise ContactresInputError(
            f"{index_path}: no column 'file' (the spectrum file of each row)"
        )
    # Only the columns of LABELS are passed on: a misspelt one would be dropped unseen.
    SPECTRA_TABLE.check_names(index.columns, str(index_path), extra=(*CONSTANT_COLUMNS, "file"))
    parts = []
    home = folder.resolve()
    for _, row in index.iterrows():  # one row per file: the loop is over files, not points
        name = str(row["file"]).strip()
        path = folder / name
        # The index names files of its own folder only: a path elsewhere (absolute, "..", or a
        # link leading out) would read, and echo in an error, any file (issue 27, point 14).
        if name and not path.resolve().is_relative_to(home):
            raise ContactresInputError(
                f"{index_path}, line {row['line']}, column 'file': {shown_value(name)} is "
                f"outside the folder {folder}; the index names files in its own folder"
            )
        if not name or not path.is_file():
            raise ContactresInputError(
                f"{index_path}, line {row['line']}, column 'file': no such file "
                f"{shown_value(name)} in {folder}"
            )
        if path.suffix.lower() in (".s1p", ".y1p", ".z1p", ".s2p"):
            f, g, b, lines = _touchstone(path, two_port)
        else:
            f, g, b, lines = _delimited_spectrum(path, layout, z0)
        sid = str(row.get("spectrum", "") or "").strip() or path.stem
        part = pd.DataFrame(
            {
                "spectrum": sid,
                "frequency_Hz": [repr(float(x)) for x in f],
                "G_S": [repr(float(x)) for x in g],
                "B_S": [repr(float(x)) if np.isfinite(x) else "" for x in b],
                "line": lines,
                "file": name,  # named in the checks of the spectra's frequencies
            }
        )
        comma = index.attrs.get("decimal", ".") == ","
        for col in LABELS:
            if col in index.columns:
                cell = str(row[col])
                # The index's decimal comma: its numbers are joined to files read with a point.
                part[col] = cell.replace(",", ".") if comma and col in NUMERIC_LABELS else cell
        parts.append(part)
    if not parts:
        raise ContactresInputError(f"{index_path}: no rows (one per spectrum file)")
    return pd.concat(parts, ignore_index=True)


def load_table(path, **options) -> pd.DataFrame:
    """A tidy spectra table as string cells and ``line`` (the options concern folders only)."""
    return _delimited.load(Path(path))


def load_folder(
    path, *, layout=None, reference_impedance: float = 50.0, two_port: str | None = None
) -> pd.DataFrame:
    """The files of a folder of spectra as the rows of a tidy table (string cells, ``line``);
    ``two_port``: the S parameter of its ``.s2p`` files (:data:`TWO_PORT_PARAMETERS`)."""
    if two_port is not None and two_port not in TWO_PORT_PARAMETERS:
        raise ContactresInputError(
            f"two-port parameter must be one of {', '.join(TWO_PORT_PARAMETERS)}, got "
            f"{shown_value(two_port)}"
        )
    return _read_folder(Path(path), layout, float(reference_impedance), two_port)


#: The spectra recipes: a folder of spectrum files, else a tidy table (any other file: its
#: validator names what is missing).
SPECTRA_READERS: tuple[Reader, ...] = (
    Reader("folder", (), lambda path, head: Path(path).is_dir(), load_folder, "spectra"),
    Reader(
        "csv",
        _delimited.suffixes,
        lambda path, head: not Path(path).is_dir(),
        load_table,
        "spectra",
    ),
)
