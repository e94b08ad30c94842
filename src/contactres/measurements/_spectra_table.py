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
error names the file, the line, the column and the value. The readers of both inputs are the
recipes of kind ``spectra`` of :mod:`contactres.measurements.readers`; the columns and
their rules are :data:`contactres.measurements.schema.SPECTRA_TABLE`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ._messages import at_cell, column_names, shown_value, where_rows
from .readers import (
    BUILT_IN,
    CONSTANT_COLUMNS,
    LABELS,
    NUMERIC_LABELS,
    SPECTRUM_LAYOUTS,
    cells_as_numbers,
)
from .schema import SPECTRA_TABLE, TRUE_WORDS, broken_rule

__all__ = [
    "CONSTANT_COLUMNS",
    "SPECTRA_TABLE",
    "SPECTRUM_LAYOUTS",
    "SpectraTable",
    "read_spectra",
    "validate_spectra",
]


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


def _flag(raw: pd.DataFrame, col: str, source: str) -> np.ndarray:
    """A true/false column as bools (its rule: one of :data:`~.schema.inputs.TRUE_WORDS` and
    :data:`~.schema.inputs.FALSE_WORDS`)."""
    SPECTRA_TABLE.check_cells(raw, source, col)
    return raw[col].astype(str).str.strip().str.lower().isin(TRUE_WORDS).to_numpy()


def validate_spectra(raw: pd.DataFrame, source: str = "<table>") -> SpectraTable:
    """Validate a raw tidy table (string cells and a ``line`` column, as the readers give it).

    Checks: the required columns; numbers where numbers belong; frequencies > 0 and distinct
    within a spectrum (a NaN G or B is left to the fit, which flags that spectrum); the
    per-spectrum labels single-valued
    within a spectrum; overtone an odd integer, ramp an integer >= 1, drive voltage and force
    > 0. Raises ValueError naming the file, line, column and value of the first problem.
    """
    raw = raw.copy()
    SPECTRA_TABLE.check_names(raw.columns, source, extra=(*CONSTANT_COLUMNS, "file"))
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
    SPECTRA_TABLE.check_cells(raw, source, "spectrum", sid.to_numpy())
    pts = pd.DataFrame({"spectrum": sid.to_numpy(), "line": raw["line"].to_numpy()})
    for col in ("frequency_Hz", "G_S", "B_S"):
        if col in raw.columns:
            pts[col] = cells_as_numbers(raw, col, source, decimal)
        else:
            pts[col] = np.nan
    # A NaN or empty G/B is left to the fit, which flags that spectrum (bad-values) and leaves
    # it out with one line: one bad spectrum does not cost the others.
    SPECTRA_TABLE.check_cells(raw, source, "frequency_Hz", pts["frequency_Hz"].to_numpy())
    dup = pts.duplicated(["spectrum", "frequency_Hz"]).to_numpy()
    if dup.any():
        raise ContactresInputError(
            f"{where_rows(raw, source, dup, 'frequency_Hz')}: frequency "
            f"{shown_value(raw['frequency_Hz'].iloc[int(np.flatnonzero(dup)[0])])} appears "
            "twice in spectrum "
            f"{shown_value(pts['spectrum'].iloc[int(np.flatnonzero(dup)[0])])}"
        )
    labels = _spectrum_labels(raw, pts, source, decimal)
    if "file" in raw.columns:  # a folder's spectrum files, named in later messages
        files = pd.Series(raw["file"].astype(str).to_numpy()).groupby(pts["spectrum"]).first()
        labels["file"] = files.reindex(labels["spectrum"]).to_numpy()
    order = {s: i for i, s in enumerate(labels["spectrum"])}
    pts["_order"] = pts["spectrum"].map(order)
    pts = pts.sort_values(["_order", "frequency_Hz"], kind="stable").drop(columns="_order")
    return SpectraTable(pts.reset_index(drop=True), labels, source)


def _spectrum_labels(
    raw: pd.DataFrame, pts: pd.DataFrame, source: str, decimal: str
) -> pd.DataFrame:
    """One row per spectrum: the labels, checked single-valued and against their rules."""
    cols = {}
    for col in LABELS:
        if col not in raw.columns:
            continue
        if col == "reference":
            cols[col] = _flag(raw, col, source)
        elif col in NUMERIC_LABELS:
            cols[col] = cells_as_numbers(raw, col, source, decimal)
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
    for col in NUMERIC_LABELS:
        if col not in first.columns:
            first[col] = np.nan
    _check_label_rules(first, raw, table, source)
    return first


def _check_label_rules(first: pd.DataFrame, raw, table, source: str) -> None:
    """The rules of the numeric labels, on the value given for each spectrum (NaN: none); an
    error names the rows of the first spectrum that breaks one."""
    for col in NUMERIC_LABELS:
        if col not in SPECTRA_TABLE.names:
            continue  # a constant of the sweep table: checked when the sweeps are validated
        v = first[col].to_numpy(float)
        checked = ~np.isnan(v)
        if col == "normal_force_N":
            # 0 N is no contact, the natural label of a reference spectrum; a measured spectrum
            # with 0 N is refused where the references are known (sweeps_from_spectra).
            checked &= v != 0
        found = broken_rule(SPECTRA_TABLE.column(col).rules, v, checked)
        if found is not None:
            r, bad = found
            sid = first["spectrum"].to_numpy()[bad][0]
            mask = (table["spectrum"] == sid).to_numpy()
            raise ContactresInputError(f"{at_cell(raw, source, mask, col)}{r.message}")


def read_spectra(
    path,
    *,
    layout: str | None = None,
    reference_impedance: float = 50.0,
    voltage: str = "amplitude",
    readers=None,
    two_port: str | None = None,
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
    readers : Readers, optional
        The registry to pick the reader from (kind ``spectra``; default
        :data:`~contactres.measurements.readers.BUILT_IN`): a folder, else a table.
    two_port : str, optional
        The S parameter of the folder's two-port Touchstone files (``.s2p``) that is the
        crystal's response: "S11", "S22" (reflection) or "S21" (the crystal in series between
        the ports); required when the folder holds one
        (:data:`~contactres.measurements.readers.TWO_PORT_PARAMETERS`).

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
    registry = BUILT_IN if readers is None else readers
    raw = registry.pick(p, "spectra").load(
        p, layout=layout, reference_impedance=z0, two_port=two_port
    )
    # A workbook's reader names its sheet too ("book.xlsx, sheet 'spectra'").
    table = validate_spectra(raw, str(raw.attrs.get("source", p)))
    if voltage == "rms":
        spectra = table.spectra.assign(drive_voltage_V=table.spectra["drive_voltage_V"] * 2**0.5)
        table = SpectraTable(table.points, spectra, table.source)
    return table
