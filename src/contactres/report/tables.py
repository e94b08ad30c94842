"""The results folder of a sweep analysis: tables and JSON (the figures: :mod:`.figures`).

:func:`write_report` writes, each file atomically (:mod:`contactres.fileio`); the columns are those
of :mod:`contactres.measurements.schema` (``SWEEP_RESULTS``, ``LOAD_RESULTS``, ``GROUP_RESULTS``):

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
    (configuration, medium) with the JKR + Mindlin fit (Table 1 of paper 2).
``fig4_sweeps.png``, ``fig5_df0_vs_load.png``, ``fig7_dissipation_vs_load.png``,
``fig8_friction_vs_load.png``
    the figures of paper 2 for these data (:mod:`contactres.report.figures`).

Conventions: Δf is the frequency shift (not Δf/n); ΔΓ the half-bandwidth at half height (not D);
amplitudes in m; forces per contact in N; NaN (CSV: empty; JSON: null) where not applicable.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd

from ..analysis.flags import render
from ..analysis.results import Results
from ..fileio import ensure_dir, write_csv, write_text
from ..measurements.schema import CONVENTIONS, GROUP_RESULTS, LOAD_RESULTS, SWEEP_RESULTS

__all__ = ["FORMATS", "loads_table", "summary", "sweeps_table", "write_report"]

#: What :func:`write_report` can write: csv (sweeps.csv, loads.csv), json (summary.json),
#: png (the figures).
FORMATS = ("csv", "json", "png")


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


def sweeps_table(results: Results) -> pd.DataFrame:
    """The ``sweeps.csv`` table: the columns of ``SWEEP_RESULTS``, flags as text."""
    table = results.sweeps[list(SWEEP_RESULTS.names)].copy()
    table["flags"] = render(table["flags"].to_numpy())
    return table


def loads_table(results: Results) -> pd.DataFrame:
    """The ``loads.csv`` table: the columns of ``LOAD_RESULTS``."""
    return results.loads[list(LOAD_RESULTS.names)]


def summary(results: Results) -> dict:
    """The ``summary.json`` record (JSON-safe): groups in the key order of ``GROUP_RESULTS``."""
    groups = []
    for g in results.groups:
        unknown = sorted(set(g) - set(GROUP_RESULTS.names))
        if unknown:
            raise KeyError(f"group keys {unknown} are missing from the schema GROUP_RESULTS")
        groups.append({k: g[k] for k in GROUP_RESULTS.names if k in g})
    source = None if results.table is None else results.table.source
    return _clean(
        {
            "groups": groups,
            "settings": results.settings,
            "version": results.version,
            "source": source,
            "conventions": CONVENTIONS,
        }
    )


def write_report(results: Results, folder, formats=FORMATS) -> list[Path]:
    """Write the results folder (see the module docstring); return the paths written.

    Parameters
    ----------
    results : what :func:`contactres.analyze` returned
    folder : the results folder, created if missing (a path that exists and is not a folder is
        an error); files of the same names in it are replaced, each atomically
    formats : one of :data:`FORMATS` or a sequence of them
    """
    formats = (formats,) if isinstance(formats, str) else tuple(formats)
    unknown = sorted(set(formats) - set(FORMATS))
    if unknown:
        raise ValueError(f"unknown report format(s) {unknown}; allowed: {list(FORMATS)}")
    out = ensure_dir(folder)
    written = []
    if "csv" in formats:
        written.append(write_csv(out / "sweeps.csv", sweeps_table(results)))
        written.append(write_csv(out / "loads.csv", loads_table(results)))
    if "json" in formats:
        text = json.dumps(summary(results), indent=1, ensure_ascii=False) + "\n"
        written.append(write_text(out / "summary.json", text))
    if "png" in formats:
        from .figures import write_figures  # matplotlib only when figures are asked for

        written.extend(write_figures(results, out))
    return written
