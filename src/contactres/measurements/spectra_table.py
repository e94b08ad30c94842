"""Admittance spectra of a QCM: reading and validating into a :class:`SpectraTable`.

Paper 2's shifts "were acquired with impedance analysis": every amplitude step is an admittance
spectrum Y(f) = G + iB of the quartz around one overtone. Two inputs are read:

* a **tidy table** (CSV, as the sweep table: comma, semicolon or tab separated), one row per
  frequency point, columns :data:`SPECTRA_TABLE` (``spectrum``, ``frequency_Hz``, ``G_S``,
  optional ``B_S``, and per spectrum the drive voltage, overtone, whether it is a no-contact
  reference, and the sweep labels; optionally the constants of the sweep table,
  :data:`CONSTANT_COLUMNS`, passed on to it);
* a **folder** of one file per spectrum as network analysers write them, with an ``index.csv``
  naming each file (column ``file``) and carrying the same per-spectrum labels. A file is a
  Touchstone one-port file (``.s1p``, ``.y1p``, ``.z1p``: its option line ``# Hz S RI R 50``
  says the frequency unit, the parameter (S11, Y or Z), the format (RI real/imaginary, MA
  magnitude/angle in degrees, DB dB/angle) and the reference impedance), or a delimited file
  with a header whose names say what the two columns hold (:data:`SPECTRUM_LAYOUTS`; the
  ``layout`` argument when they do not). S11 becomes Y = (1 − S)/(Z0 (1 + S)) with the reference
  impedance Z0 (Touchstone: its R; otherwise ``reference_impedance``, 50 Ω by default).

Conventions: frequencies in Hz, G and B in S (siemens); the drive voltage is the amplitude
(peak) voltage across the crystal, V (``voltage="rms"`` converts an rms value by √2). Every
error names the file, the line, the column and the value.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from .messages import at_cell, column_names, shown_value, where_rows
from .readers import delimited
from .schema import Column, TableSchema

__all__ = [
    "CONSTANT_COLUMNS",
    "SPECTRA_TABLE",
    "SPECTRUM_LAYOUTS",
    "SpectraTable",
    "read_spectra",
    "validate_spectra",
]

SPECTRA_TABLE = TableSchema(
    "spectra table",
    "one row per frequency point of an admittance spectrum (CSV, as the sweep table)",
    (
        Column("spectrum", "text", "id of one spectrum (one amplitude step)", required=True),
        Column("frequency_Hz", "Hz", "frequency of the point", required=True, rule="> 0"),
        Column(
            "G_S", "S", "conductance Re Y (a NaN leaves its spectrum out, flagged)", required=True
        ),
        Column("B_S", "S", "susceptance Im Y (empty or absent: G alone is fitted)"),
        Column(
            "reference",
            "-",
            "true for a no-contact reference spectrum (true/false, 1/0, yes/no)",
            level="sweep",
            default="false",
        ),
        Column("overtone", "-", "overtone order n", level="sweep", rule="odd integer >= 1"),
        Column(
            "drive_voltage_V",
            "V",
            "amplitude (peak) of the drive voltage across the crystal",
            level="sweep",
            rule="> 0",
        ),
        Column("time_s", "s", "time of the spectrum (any origin)", level="sweep", rule="finite"),
        Column(
            "sweep", "text", "amplitude ramp of the spectrum (empty: a reference)", level="sweep"
        ),
        Column("ramp", "-", "ramp number of the sweep", level="sweep", rule="integer >= 1"),
        Column("experiment", "text", "experiment of the sweep", level="sweep", default="1"),
        Column("normal_force_N", "N", "normal force per contact", level="sweep", rule="> 0"),
        Column("configuration", "text", "configuration", level="sweep", default="default"),
        Column("medium", "text", "medium", level="sweep", default="unspecified"),
    ),
)

#: Header names of the two data columns of a delimited spectrum file -> layout name.
SPECTRUM_LAYOUTS = {
    "G/B": (("G_S", "B_S"), "conductance and susceptance, S"),
    "Y-RI": (("Y_re_S", "Y_im_S"), "real and imaginary part of Y, S"),
    "S11-RI": (("S11_re", "S11_im"), "real and imaginary part of S11"),
    "Y-MA": (("Y_mag_S", "Y_phase_deg"), "|Y| in S and its phase in degrees"),
}
_TRUE = {"true", "1", "yes", "y", "t"}
_FALSE = {"false", "0", "no", "n", "f", ""}
#: Constants of the sweep table a spectra table may carry as columns (passed on to the sweeps).
CONSTANT_COLUMNS = ("fundamental_Hz", "area_m2", "n_contacts", "sphere_radius_m", "poisson")
_LABELS = (*(c.name for c in SPECTRA_TABLE.columns if c.level == "sweep"), *CONSTANT_COLUMNS)
_NUMERIC_LABELS = (
    "overtone", "drive_voltage_V", "time_s", "ramp", "normal_force_N", *CONSTANT_COLUMNS
)  # fmt: skip


@dataclass(frozen=True)
class SpectraTable:
    """A validated set of admittance spectra.

    Attributes
    ----------
    points : one row per frequency point: ``spectrum``, ``frequency_Hz``, ``G_S``, ``B_S``
        (NaN where only G was recorded), ``line`` (where it was read), sorted by spectrum and
        frequency
    spectra : one row per spectrum, in the order of first appearance: ``spectrum``, the labels
        of :data:`SPECTRA_TABLE` (``reference`` as bool, numbers as float, NaN where absent),
        ``n_points`` and ``line`` (first line of the spectrum)
    source : the file or folder read
    """

    points: pd.DataFrame
    spectra: pd.DataFrame
    source: str


def _number(raw: pd.DataFrame, col: str, source: str, decimal: str = ".") -> np.ndarray:
    """Parse ``col`` as numbers; empty cells are NaN; anything else not a number is an error."""
    s = raw[col].astype(str).str.strip()
    if decimal == ",":
        s = s.str.replace(",", ".", regex=False)
    values = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float)
    bad = np.isnan(values) & (s != "").to_numpy() & ~s.str.lower().isin(["nan"]).to_numpy()
    if bad.any():
        raise ContactresInputError(f"{at_cell(raw, source, bad, col)} is not a number")
    return values


def _flag(raw: pd.DataFrame, col: str, source: str) -> np.ndarray:
    s = raw[col].astype(str).str.strip().str.lower()
    bad = ~s.isin(_TRUE | _FALSE).to_numpy()
    if bad.any():
        raise ContactresInputError(
            f"{at_cell(raw, source, bad, col)} is not true/false (or 1/0, yes/no)"
        )
    return s.isin(_TRUE).to_numpy()


def validate_spectra(raw: pd.DataFrame, source: str = "<table>") -> SpectraTable:
    """Validate a raw tidy table (string cells and a ``line`` column, as the readers give it).

    Checks: the required columns; numbers where numbers belong; frequencies > 0 and distinct
    within a spectrum (a NaN G or B is left to the fit, which flags that spectrum); the
    per-spectrum labels single-valued
    within a spectrum; overtone an odd integer, ramp an integer >= 1, drive voltage and force
    > 0. Raises ValueError naming the file, line, column and value of the first problem.
    """
    raw = raw.copy()
    if "line" not in raw.columns:
        raw["line"] = np.arange(2, len(raw) + 2)
    missing = [c for c in SPECTRA_TABLE.required if c not in raw.columns]
    if missing:
        raise ContactresInputError(
            f"{source}: missing column(s) {missing}; the columns found are "
            f"{column_names(c for c in raw.columns if c != 'line')} (a spectra table needs "
            "spectrum, frequency_Hz, G_S)"
        )
    if len(raw) == 0:
        raise ContactresInputError(f"{source}: no data rows")
    decimal = raw.attrs.get("decimal", ".")
    sid = raw["spectrum"].astype(str).str.strip()
    empty = (sid == "").to_numpy()
    if empty.any():
        raise ContactresInputError(
            f"{at_cell(raw, source, empty, 'spectrum')} is empty; every row needs one"
        )
    pts = pd.DataFrame({"spectrum": sid.to_numpy(), "line": raw["line"].to_numpy()})
    for col in ("frequency_Hz", "G_S", "B_S"):
        if col in raw.columns:
            pts[col] = _number(raw, col, source, decimal)
        else:
            pts[col] = np.nan
    # A NaN or empty G/B is left to the fit, which flags that spectrum (bad-values) and leaves
    # it out with one line: one bad spectrum does not cost the others.
    bad = ~np.isfinite(pts["frequency_Hz"].to_numpy())
    if bad.any():
        raise ContactresInputError(
            f"{at_cell(raw, source, bad, 'frequency_Hz')}: must be a finite number"
        )
    bad = ~(pts["frequency_Hz"].to_numpy() > 0)
    if bad.any():
        raise ContactresInputError(f"{at_cell(raw, source, bad, 'frequency_Hz')}: must be > 0 Hz")
    dup = pts.duplicated(["spectrum", "frequency_Hz"]).to_numpy()
    if dup.any():
        raise ContactresInputError(
            f"{where_rows(raw, source, dup, 'frequency_Hz')}: frequency "
            f"{shown_value(raw['frequency_Hz'].iloc[int(np.flatnonzero(dup)[0])])} appears "
            "twice in spectrum "
            f"{shown_value(pts['spectrum'].iloc[int(np.flatnonzero(dup)[0])])}"
        )
    labels = _spectrum_labels(raw, pts, source, decimal)
    order = {s: i for i, s in enumerate(labels["spectrum"])}
    pts["_order"] = pts["spectrum"].map(order)
    pts = pts.sort_values(["_order", "frequency_Hz"], kind="stable").drop(columns="_order")
    return SpectraTable(pts.reset_index(drop=True), labels, source)


def _spectrum_labels(
    raw: pd.DataFrame, pts: pd.DataFrame, source: str, decimal: str
) -> pd.DataFrame:
    """One row per spectrum: the labels, checked single-valued and against their rules."""
    cols = {}
    for col in _LABELS:
        if col not in raw.columns:
            continue
        if col == "reference":
            cols[col] = _flag(raw, col, source)
        elif col in _NUMERIC_LABELS:
            cols[col] = _number(raw, col, source, decimal)
        else:
            cols[col] = raw[col].astype(str).str.strip().to_numpy()
    table = pd.DataFrame({"spectrum": pts["spectrum"], "line": pts["line"], **cols})
    for col in cols:
        per = table.groupby("spectrum", sort=False)[col].nunique(dropna=False)
        if (per > 1).any():
            sid = per.index[int(np.flatnonzero(per.to_numpy() > 1)[0])]
            mask = (table["spectrum"] == sid).to_numpy()
            raise ContactresInputError(
                f"{where_rows(raw, source, mask, col)}: spectrum {shown_value(sid)} has "
                f"several values of {col!r}; it takes one value per spectrum"
            )
    first = table.drop_duplicates("spectrum", keep="first").reset_index(drop=True)
    first["n_points"] = pts.groupby("spectrum", sort=False).size().reindex(first["spectrum"]).values
    for col, default in (("reference", False), ("experiment", "1")):
        if col not in first.columns:
            first[col] = default
    for col in ("configuration", "medium"):
        if col not in first.columns:
            first[col] = SPECTRA_TABLE.column(col).default
    for col in _NUMERIC_LABELS:
        if col not in first.columns:
            first[col] = np.nan
    _check_label_rules(first, raw, table, source)
    return first


def _check_label_rules(first: pd.DataFrame, raw, table, source: str) -> None:
    def fail(mask_first: np.ndarray, col: str, rule: str) -> None:
        sid = first["spectrum"].to_numpy()[mask_first][0]
        mask = (table["spectrum"] == sid).to_numpy()
        raise ContactresInputError(f"{at_cell(raw, source, mask, col)}: {rule}")

    n = first["overtone"].to_numpy(float)
    bad = np.isfinite(n) & ((n < 1) | (n % 2 != 1))
    if bad.any():
        fail(bad, "overtone", "the overtone must be an odd integer >= 1")
    for col in ("drive_voltage_V", "normal_force_N"):
        v = first[col].to_numpy(float)
        bad = np.isfinite(v) & ~(v > 0)
        if bad.any():
            fail(bad, col, "must be > 0")
    r = first["ramp"].to_numpy(float)
    bad = np.isfinite(r) & ((r < 1) | (r % 1 != 0))
    if bad.any():
        fail(bad, "ramp", "the ramp must be an integer >= 1")


# ----------------------------------------------------------------------------- the readers
_OPTION_LINE = re.compile(r"^\s*#(.*)$")
_UNITS = {"hz": 1.0, "khz": 1e3, "mhz": 1e6, "ghz": 1e9}


def _touchstone(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(frequency Hz, G S, B S, line numbers) of a one-port Touchstone file."""
    unit, param, fmt, z0 = 1e9, "S", "MA", 50.0  # the Touchstone defaults
    freq, a, b, lines = [], [], [], []
    for number, text in enumerate(path.read_text(errors="replace").splitlines(), start=1):
        text = text.split("!", 1)[0].strip()
        if not text:
            continue
        if text.startswith("["):
            raise ContactresInputError(
                f"{path}, line {number}: Touchstone 2 keyword {shown_value(text)}: save the "
                "spectrum as a Touchstone 1 file (.s1p) or as CSV"
            )
        option = _OPTION_LINE.match(text)
        if option:
            words = option.group(1).lower().split()
            for i, w in enumerate(words):
                if w in _UNITS:
                    unit = _UNITS[w]
                elif w in ("s", "y", "z"):
                    param = w.upper()
                elif w in ("ri", "ma", "db"):
                    fmt = w.upper()
                elif w == "r" and i + 1 < len(words):
                    z0 = float(words[i + 1])
            continue
        fields = text.split()
        try:
            values = [float(x) for x in fields]
        except ValueError:
            raise ContactresInputError(
                f"{path}, line {number}: {shown_value(text)} is not three numbers "
                "(frequency and the two parts of the one-port parameter)"
            ) from None
        if len(values) != 3:
            raise ContactresInputError(
                f"{path}, line {number}: {len(values)} numbers, a one-port Touchstone line has 3"
            )
        freq.append(values[0] * unit)
        a.append(values[1])
        b.append(values[2])
        lines.append(number)
    first, second = np.array(a), np.array(b)
    if fmt == "RI":
        x = first + 1j * second
    else:
        mag = 10 ** (first / 20) if fmt == "DB" else first
        x = mag * np.exp(1j * np.radians(second))
    # Touchstone 1: Y and Z are normalised to R (y = Y R, z = Z/R), S is dimensionless.
    if param == "S":
        y = (1 - x) / (z0 * (1 + x))
    elif param == "Z":
        y = 1 / (x * z0)
    else:
        y = x / z0
    return np.array(freq), y.real, y.imag, np.array(lines)


def _delimited_spectrum(path: Path, layout: str | None, z0: float):
    """(frequency Hz, G S, B S (NaN where absent), line numbers) of a delimited file."""
    raw = delimited.load(path)
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
    f = _number(raw, "frequency_Hz", source, decimal)
    first = _number(raw, names[0], source, decimal)
    if names[1] in raw.columns:
        second = _number(raw, names[1], source, decimal)
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
        s = first + 1j * second
        y = (1 - s) / (z0 * (1 + s))
    else:
        y = first * np.exp(1j * np.radians(second))
    return f, y.real, y.imag, raw["line"].to_numpy()


def _read_folder(folder: Path, layout, z0: float) -> pd.DataFrame:
    index_path = folder / "index.csv"
    if not index_path.exists():
        raise ContactresInputError(
            f"{folder}: a folder of spectra needs an index.csv naming each file (column 'file') "
            "with its labels (drive_voltage_V, overtone, reference, sweep, ...)"
        )
    index = delimited.load(index_path)
    if "file" not in index.columns:
        raise ContactresInputError(
            f"{index_path}: no column 'file' (the spectrum file of each row)"
        )
    parts = []
    for _, row in index.iterrows():  # one row per file: the loop is over files, not points
        name = str(row["file"]).strip()
        path = folder / name
        if not name or not path.is_file():
            raise ContactresInputError(
                f"{index_path}, line {row['line']}, column 'file': no such file "
                f"{shown_value(name)} in {folder}"
            )
        if path.suffix.lower() in (".s1p", ".y1p", ".z1p"):
            f, g, b, lines = _touchstone(path)
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
            }
        )
        comma = index.attrs.get("decimal", ".") == ","
        for col in _LABELS:
            if col in index.columns:
                cell = str(row[col])
                # The index's decimal comma: its numbers are joined to files read with a point.
                part[col] = cell.replace(",", ".") if comma and col in _NUMERIC_LABELS else cell
        parts.append(part)
    if not parts:
        raise ContactresInputError(f"{index_path}: no rows (one per spectrum file)")
    return pd.concat(parts, ignore_index=True)


def read_spectra(
    path,
    *,
    layout: str | None = None,
    reference_impedance: float = 50.0,
    voltage: str = "amplitude",
) -> SpectraTable:
    """Read admittance spectra from a tidy table or a folder of spectrum files.

    Parameters
    ----------
    path : str or path-like
        A tidy spectra table (CSV) or a folder with ``index.csv`` and one file per spectrum
        (module docstring). Never modified.
    layout : str, optional
        What the two data columns of the folder's delimited files hold, a key of
        :data:`SPECTRUM_LAYOUTS`, when their header does not say it.
    reference_impedance : float
        Z0 in Ω for S11 in delimited files (Touchstone files give their own), default 50.
    voltage : str
        "amplitude" (default): ``drive_voltage_V`` is the peak voltage; "rms": it is the rms
        value (multiplied by √2 here).

    Returns
    -------
    SpectraTable
    """
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{p}: no such file or folder")
    z0 = float(reference_impedance)
    if not (math.isfinite(z0) and z0 > 0):
        raise ContactresInputError(
            f"reference impedance must be > 0 Ω, got {reference_impedance!r}"
        )
    if voltage not in ("amplitude", "rms"):
        raise ContactresInputError(f"voltage must be 'amplitude' or 'rms', got {voltage!r}")
    raw = _read_folder(p, layout, z0) if p.is_dir() else delimited.load(p)
    table = validate_spectra(raw, str(p))
    if voltage == "rms":
        spectra = table.spectra.assign(drive_voltage_V=table.spectra["drive_voltage_V"] * 2**0.5)
        table = SpectraTable(table.points, spectra, table.source)
    return table
