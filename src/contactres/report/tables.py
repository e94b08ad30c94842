"""The results folder of a sweep analysis: tables and JSON (the figures: :mod:`.figures`).

:func:`write_report` writes the folder as one :class:`contactres.fileio.ResultSet`: nothing is
written if a file of the set would replace an input (the sweep table, by default) or another run
is writing into the folder, the files appear together or not at all (a killed run leaves the
earlier set), ``manifest.json`` lists them, and files of an earlier set that this one does not
write (e.g. its figures) are removed. The columns are those of
:mod:`contactres.measurements.schema` (``SWEEP_RESULTS``, ``LOAD_RESULTS``, ``GROUP_RESULTS``):

``sweeps.csv``
    one row per sweep, in the order of the schema: the 18 columns of the paper's analysis, then
    the uncertainties and derived quantities. ``model``: the amplitude class (elastic,
    cattaneo-mindlin, savkoor, plateau). ``plateau_amplitude_m`` (± ``plateau_amplitude_err_m``):
    the critical displacement d_c of a plateau sweep, from the fit of the exact plateau loop
    (the hinge of the plateau model if that fit is off or unresolved; then no error). ``df0_Hz``,
    ``dgamma0_Hz``: low-amplitude limits. ``df_slope_Hz_per_m``, ``dgamma_slope_Hz_per_m``: the
    straight line, or for a plateau the hinge slope above the plateau (descriptive only).
    ``mu_df``, ``mu_dgamma``: μ from those slopes (paper 2, Eq. 12), Cattaneo-Mindlin
    sweeps only; empty for a plateau sweep (flag ``plateau-slope``: the shifts leave a plateau
    with no linear term, so no slope formula holds). ``mu_fit``: μ from the fit of the exact
    loop (Cattaneo-Mindlin, or Cattaneo-Mindlin behind the plateau). ``flags``: ';'-separated
    (:class:`contactres.analysis.flags.Flag`; the README explains each).
``loads.csv``
    one row per (configuration, medium, normal force): ``n_experiments``, ``n_sweeps`` and
    ``<quantity>_mean``, ``<quantity>_sd`` (standard deviation over experiments, ddof = 1) of
    Δf0, ΔΓ0 (Hz), κ, ωξ (N/m), the loss tangent ΔΓ0/Δf0 and μ (from Δf, from ΔΓ, from the fit).
``summary.json``
    ``{"groups": [...], "settings": {...}, "version": ..., "conventions": {...}}``; one group per
    (configuration, medium) with the JKR + Mindlin fit (Table 1 of paper 2); with the radiation
    table also ``"radiation": {"sphere_material", "plate_material", "file", "groups": [...]}``
    (:func:`contactres.analysis.radiation.radiation_summary`: per group the ranges of a and
    tan δ_rad, the medians of tan δ_rad and of its share of the measured loss tangent).
``radiation.csv``
    only when the analysis was given the two materials (``--sphere-material`` and
    ``--plate-material``): one row per load, the columns of
    :data:`contactres.analysis.radiation.RADIATION_RESULTS` (the radiation loss of the contact
    against the measured one).
``fig4_*.png``, ``fig5_*.png``, ``fig7_*.png``, ``fig8_*.png``
    ``fig4_sweeps.png``, ``fig5_df0_vs_load.png``, ``fig7_dissipation_vs_load.png`` and
    ``fig8_friction_vs_load.png``: the figures of paper 2 for these data
    (:mod:`contactres.report.figures`; none when no sweep is used, with a
    :class:`~contactres.measurements.sweeps.SweepWarning`), and with the radiation table
    ``radiation_loss.png`` (measured and radiation loss tangent per load).
``manifest.json``
    written last: the files of the set with their sizes and SHA-256 sums.

Conventions: Δf is the frequency shift (not Δf/n); ΔΓ the half-bandwidth at half height (not D);
amplitudes in m; forces per contact in N; a number that is not finite (NaN where not
applicable, an infinite slope error or loss tangent) is an empty cell in CSV and null in JSON.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.flags import render
from ..analysis.radiation import RADIATION_RESULTS, radiation_summary
from ..analysis.results import Results
from ..errors import ContactresInputError
from ..fileio import CSV_FLOAT_FORMAT, ResultSet, write_csv, write_text
from ..measurements.schema import CONVENTIONS, GROUP_RESULTS, LOAD_RESULTS, SWEEP_RESULTS
from .figures import FIGURE_FILES, RADIATION_FIGURE

__all__ = [
    "FORMATS",
    "loads_table",
    "radiation_table",
    "report_files",
    "summary",
    "sweeps_table",
    "write_report",
]

#: What :func:`write_report` can write: csv (sweeps.csv, loads.csv), json (summary.json),
#: png (the figures).
FORMATS = ("csv", "json", "png")
#: The files of each format.
FILES = {"csv": ("sweeps.csv", "loads.csv"), "json": ("summary.json",), "png": FIGURE_FILES}
#: The further files of each format when the results hold the radiation table.
RADIATION_FILES = {"csv": ("radiation.csv",), "json": (), "png": (RADIATION_FIGURE,)}


def _clean(value):
    """JSON-safe: NaN/inf -> None, numpy scalars -> Python."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _finite_or_nan(table: pd.DataFrame) -> pd.DataFrame:
    """``table`` with ±inf as NaN (an empty cell in CSV): an infinite error or ratio is 'not
    applicable', as NaN is, and the README promises empty cells for both."""
    out = table.copy()
    for col in out.select_dtypes(include="floating").columns:
        values = out[col].to_numpy()
        out[col] = np.where(np.isinf(values), np.nan, values)
    return out


def sweeps_table(results: Results) -> pd.DataFrame:
    """The ``sweeps.csv`` table: the columns of ``SWEEP_RESULTS``, flags as text."""
    table = _finite_or_nan(results.sweeps[list(SWEEP_RESULTS.names)])
    table["flags"] = render(table["flags"].to_numpy())
    return table


def loads_table(results: Results) -> pd.DataFrame:
    """The ``loads.csv`` table: the columns of ``LOAD_RESULTS``."""
    return _finite_or_nan(results.loads[list(LOAD_RESULTS.names)])


def radiation_table(results: Results) -> pd.DataFrame:
    """The ``radiation.csv`` table: the columns of ``RADIATION_RESULTS`` (results with one)."""
    if results.radiation is None:
        raise ContactresInputError(
            "these results have no radiation table (no materials were given)"
        )
    return _finite_or_nan(results.radiation[list(RADIATION_RESULTS.names)])


def _radiation_record(table: pd.DataFrame) -> dict:
    first: pd.Series | dict = table.iloc[0] if len(table) else {}
    return {
        "sphere_material": first.get("sphere_material"),
        "plate_material": first.get("plate_material"),
        "file": "radiation.csv",
        "groups": radiation_summary(table),
    }


def summary(results: Results) -> dict:
    """The ``summary.json`` record (JSON-safe): groups in the key order of ``GROUP_RESULTS``,
    and the radiation section where the results have the radiation table."""
    groups = []
    for g in results.groups:
        unknown = sorted(set(g) - set(GROUP_RESULTS.names))
        if unknown:
            raise KeyError(f"group keys {unknown} are missing from the schema GROUP_RESULTS")
        groups.append({k: g[k] for k in GROUP_RESULTS.names if k in g})
    source = None if results.table is None else results.table.source
    record = {
        "groups": groups,
        "settings": results.settings,
        "version": results.version,
        "source": source,
        "messages": list(results.messages),
        "conventions": CONVENTIONS,
    }
    if results.radiation is not None:
        record["radiation"] = _radiation_record(results.radiation)
    return _clean(record)


def _formats(formats) -> tuple[str, ...]:
    formats = (formats,) if isinstance(formats, str) else tuple(formats)
    unknown = sorted(set(formats) - set(FORMATS))
    if unknown:
        raise ContactresInputError(f"unknown report format(s) {unknown}; allowed: {list(FORMATS)}")
    return formats


def report_files(formats=FORMATS, *, radiation: bool = False) -> tuple[str, ...]:
    """The names of the files :func:`write_report` may write for ``formats`` (figures are left
    out when there is nothing to draw); with ``radiation`` also those of the radiation table
    (``radiation.csv``, ``radiation_loss.png``)."""
    chosen = [f for f in FORMATS if f in _formats(formats)]
    names = [name for f in chosen for name in FILES[f]]
    if radiation:
        names += [name for f in chosen for name in RADIATION_FILES[f]]
    return tuple(names)


def write_report(results: Results, folder, formats=FORMATS, *, inputs=None) -> list[Path]:
    """Write the results folder (see the module docstring); return the paths written.

    Parameters
    ----------
    results : what :func:`contactres.analyze` returned
    folder : the results folder, created if missing (a path that exists and is not a folder is
        an error); or a :class:`~contactres.fileio.ResultSet` opened by the caller (declared
        with :func:`report_files`, ``radiation=True`` for results with the radiation table),
        which moves the files into place when its block ends
    formats : one of :data:`FORMATS` or a sequence of them
    inputs : files that must not be overwritten (default: the sweep table the results came
        from); ignored when ``folder`` is a ResultSet (it was given its inputs)

    Returns
    -------
    list of Path : the files of the set (not ``manifest.json``), where they are once in place

    Raises
    ------
    contactres.fileio.OutputError
        Before anything is written: the folder cannot be written, a file of the set is one of
        ``inputs``, or another run is writing into the folder.
    """
    formats = _formats(formats)
    if isinstance(folder, ResultSet):
        return _write_into(results, folder, formats)
    if inputs is None:
        source = None if results.table is None else results.table.source
        inputs = () if source is None or source == "<table>" else (source,)
    names = report_files(formats, radiation=results.radiation is not None)
    owned = report_files(FORMATS, radiation=True)
    with ResultSet(folder, names=names, inputs=inputs, owned=owned) as rs:
        return _write_into(results, rs, formats)


def _write_into(results: Results, rs: ResultSet, formats: tuple[str, ...]) -> list[Path]:
    names = []
    if "csv" in formats:
        write_csv(rs.path("sweeps.csv"), sweeps_table(results), float_format=CSV_FLOAT_FORMAT)
        write_csv(rs.path("loads.csv"), loads_table(results), float_format=CSV_FLOAT_FORMAT)
        names += ["sweeps.csv", "loads.csv"]
        if results.radiation is not None:
            write_csv(
                rs.path("radiation.csv"), radiation_table(results), float_format=CSV_FLOAT_FORMAT
            )
            names.append("radiation.csv")
    if "json" in formats:
        text = json.dumps(summary(results), indent=1, ensure_ascii=False) + "\n"
        write_text(rs.path("summary.json"), text)
        names.append("summary.json")
    if "png" in formats:
        from .figures import write_figures  # matplotlib only when figures are asked for

        names += [p.name for p in write_figures(results, rs.path)]
    return [rs.final(name) for name in names]
