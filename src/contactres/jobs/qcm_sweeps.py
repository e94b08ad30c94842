"""Job ``qcm_sweeps``: the analysis of QCM amplitude sweeps (paper 2): contact stiffness, loss
tangent, friction, E and γ per configuration and medium.

Inputs: the path of a sweep table (one row per point: sweep, amplitude_m, df_Hz, dgamma_Hz,
normal_force_N, ...) or of admittance spectra (a table with frequency_Hz and G_S, or a folder
with index.csv), which are fitted and turned into the sweep table first with the defaults of
the ``qcm_spectra`` job. Settings: the constants missing from the input (else from a TOML file
beside the table), the choices of :class:`contactres.analysis.AnalysisSettings` and the two
bodies of the contact for the radiation loss (both or neither). The analysis is
:func:`contactres.analyze`.

Two stages, so that a caller can show a progress bar of known length: :func:`read` (the sweep
table and what reading it said) and :func:`run` (reads unless given a :class:`Reading`, then
analyses; :func:`stages` gives the length of a progress bar over it).

The Result's tables are those of the results folder, each bound to its schema
(:func:`sweeps_table`, :func:`loads_table` and, with the two bodies, :func:`radiation_table`),
and its values the ``summary.json`` record (:func:`summary`): a report writes them as it writes
every job's (:func:`contactres.report.write_report`; the folder's files are described in
:func:`contactres.report.report_files`).
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..measurements.schema import (
    COATING_CONVENTIONS,
    CONVENTIONS,
    CURVE_RESULTS,
    GROUP_RESULTS,
    JKR_CURVE_RESULTS,
    LOAD_RESULTS,
    RADIATION_RESULTS,
    SWEEP_RESULTS,
)
from .contract import JobResult, Progress, json_value

if TYPE_CHECKING:
    import pandas as pd

    from ..analysis import Results
    from ..measurements import SweepTable

__all__ = [
    "Reading",
    "Result",
    "Settings",
    "coating_layers",
    "loads_table",
    "radiation_table",
    "read",
    "run",
    "stages",
    "summary",
    "sweeps_table",
    "warning_lines",
]

#: From this many sweeps on, ``workers=None`` uses every core.
_MANY_SWEEPS = 10_000


@dataclass(frozen=True)
class Settings:
    """The constants and the choices of the analysis.

    Parameters
    ----------
    area_m2, overtone, fundamental_Hz, n_contacts, poisson, sphere_radius_m
        Constants missing from the input (None: from the input or a TOML file beside it):
        effective area A_eff (m^2), overtone order n, fundamental f_F (Hz), number of contacts,
        Poisson ratio, sphere radius R (m).
    keep_first_ramp, keep_drift, remove_drift, law_per_load, bootstrap
        As in :class:`contactres.analysis.AnalysisSettings` (``law_per_load``: one law per
        load, not pooled over experiments).
    workers : int or None
        Processes; None: every core from 10,000 sweeps on, else 1.
    sphere_material, plate_material : str or None
        The bodies of the contact (names of
        :func:`contactres.analysis.material_by_name`) for the radiation loss.
    coating : str, sequence of str, or None
        The film(s) on the plate, ``"MATERIAL:THICKNESS"`` (m) each, top first
        (:func:`contactres.jobs.contact.parse_coating`; thickness at most 1 m): E and γ fitted
        on the coated plate (:mod:`contactres.analysis._coating`). With the materials, the radiation
        loss on the coated plate.
    figures : bool
        Whether figures are drawn from the Result (Fig. 4 draws the fitted curves of the
        sweeps it shows on its own 100-point grid, which the analysis then computes for
        those sweeps); False: the curves are computed on the 30-point grid of ``curves.csv``
        and of the page only (:func:`contactres.analysis.analyze`'s ``curve_grids``), the
        same tables.
    """

    area_m2: float | None = None
    overtone: int | None = None
    fundamental_Hz: float | None = None
    n_contacts: int | None = None
    poisson: float | None = None
    sphere_radius_m: float | None = None
    keep_first_ramp: bool = False
    keep_drift: bool = False
    remove_drift: bool = False
    law_per_load: bool = False
    bootstrap: int = 200
    workers: int | None = None
    sphere_material: str | None = None
    plate_material: str | None = None
    coating: str | tuple[str, ...] | None = None
    figures: bool = True

    def constants(self) -> dict:
        """The constants, as :func:`contactres.read_sweeps` takes them."""
        names = ("area_m2", "overtone", "fundamental_Hz", "n_contacts", "poisson",
                 "sphere_radius_m")  # fmt: skip
        return {name: getattr(self, name) for name in names}


@dataclass(frozen=True)
class Reading:
    """The sweep table read from the input, the spectra left out (one line each) and the
    warnings met on the way (one line each, :func:`warning_lines`)."""

    table: SweepTable
    left_out: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class Result(JobResult):
    """``analysis``: the :class:`contactres.analysis.Results`; ``reading``: what reading said
    (None for Results analysed elsewhere, :meth:`of`); ``warnings``: the analysis's warnings,
    one line each.

    Its tables (:meth:`tables`) are those of the results folder: ``sweeps`` and ``loads``, bound
    to :data:`~contactres.measurements.schema.SWEEP_RESULTS` and
    :data:`~contactres.measurements.schema.LOAD_RESULTS`, ``radiation``
    (:data:`~contactres.measurements.schema.RADIATION_RESULTS`) where the analysis has the
    radiation loss, and the fitted curves where the analysis computed them: ``curves`` (the
    model of each sweep, :data:`~contactres.measurements.schema.CURVE_RESULTS`) and
    ``jkr_curves`` (κ(F_N) of each group,
    :data:`~contactres.measurements.schema.JKR_CURVE_RESULTS`); its values (:meth:`values`) the
    ``summary.json`` record.
    """

    NOT_VALUES = ("analysis", "reading", "warnings")
    NAME = "summary"

    analysis: Results
    reading: Reading | None = None
    warnings: tuple[str, ...] = ()

    @classmethod
    def of(cls, analysis: Results) -> Result:
        """The Result that carries ``analysis`` (what :func:`contactres.analyze` returned), so
        that it is reported as the job's is."""
        return cls(analysis=analysis)

    @classmethod
    def table_names(cls) -> tuple[str, ...]:
        """Every table a Result can hold: ``radiation`` only with the radiation loss, the
        curves only where the analysis computed them."""
        return ("sweeps", "loads", "radiation", "curves", "jkr_curves")

    def tables(self):
        """The tables of the results folder with their schemas (see the class docstring)."""
        tables = {
            "sweeps": (sweeps_table(self.analysis), SWEEP_RESULTS),
            "loads": (loads_table(self.analysis), LOAD_RESULTS),
        }
        if self.analysis.radiation is not None:
            tables["radiation"] = (radiation_table(self.analysis), RADIATION_RESULTS)
        # (getattr: a Results made by hand may carry neither)
        curves = getattr(self.analysis, "curves", None)
        jkr = getattr(self.analysis, "jkr", None)
        if curves is not None:
            tables["curves"] = (_curves_table(curves), CURVE_RESULTS)
        if jkr is not None:
            tables["jkr_curves"] = (
                _finite_or_nan(jkr[list(JKR_CURVE_RESULTS.names)]),
                JKR_CURVE_RESULTS,
            )
        return MappingProxyType(tables)

    def summary_tables(self):
        """``table1``: Table 1 of paper 2, one row per (configuration, medium) fitted
        (its ``_table1_table``), for the workbook and the NetCDF file."""
        return MappingProxyType({"table1": (_table1_table(self.analysis), GROUP_RESULTS)})

    def values(self) -> dict:
        """The ``summary.json`` record (:func:`summary`)."""
        return summary(self.analysis)

    def input_files(self) -> tuple[str, ...]:
        """The sweep table the analysis read, when it came from a file."""
        table = self.analysis.table
        source = None if table is None else table.source
        return () if source is None or source == "<table>" else (source,)


def _finite_or_nan(table: pd.DataFrame) -> pd.DataFrame:
    """``table`` with ±inf as NaN (an empty cell in CSV): an infinite error or ratio is 'not
    applicable', as NaN is, and the README promises empty cells for both. A column without an
    infinity is shared with ``table``, not copied (pandas copies on write): 10^5 sweeps'
    curve table is 3·10^6 rows."""
    import numpy as np

    out = table.copy(deep=False)
    for col in out.select_dtypes(include="floating").columns:
        values = out[col].to_numpy()
        infinite = np.isinf(values)
        if infinite.any():
            out[col] = np.where(infinite, np.nan, values)
    return out


def _curves_table(curves: pd.DataFrame) -> pd.DataFrame:
    """The ``curves.csv`` table: the rows of the coarsest grid of ``curves`` (the HTML page's,
    30 points) of the sweeps with a model (a Δf somewhere on the grid), the columns of
    ``CURVE_RESULTS``; 10^5 sweeps give 3·10^6 rows, not 10^7 (issue 31's large studies).
    Selected in one step, and the sweeps looked up only where some have no model: the table is
    the largest the analysis writes."""
    names = list(CURVE_RESULTS.names)
    grid = curves["grid_points"]
    coarse = (grid == grid.min()).to_numpy()
    part = curves[names] if coarse.all() else curves.loc[coarse, names]
    model = part["df_model_Hz"].notna()
    if not model.all():
        model = model.groupby(part["sweep"], sort=False).transform("any")
        part = part[model.to_numpy(dtype=bool)]
    return _finite_or_nan(part.reset_index(drop=True))


def sweeps_table(results: Results) -> pd.DataFrame:
    """The ``sweeps.csv`` table: the columns of ``SWEEP_RESULTS``, flags as text."""
    from ..analysis import render

    table = _finite_or_nan(results.sweeps[list(SWEEP_RESULTS.names)])
    table["flags"] = render(table["flags"].to_numpy())
    return table


#: The columns of Table 1 in the one-file formats: the group, E and γ with their errors, the
#: counts, and why a value is withheld (``checks``, ``note``); SI units, named in the headers.
_TABLE1_COLUMNS = (
    "configuration", "medium", "E_Pa", "E_err_Pa", "gamma_J_m2", "gamma_err_J_m2", "t95",
    "n_experiments", "n_sweeps_used", "error_method", "checks", "note",
)  # fmt: skip


def _table1_table(results: Results) -> pd.DataFrame:
    """Table 1 of paper 2 as a table: one row per group, the ``_TABLE1_COLUMNS`` of its
    ``summary.json`` record (``checks`` ';'-separated; E and γ NaN where withheld)."""
    import pandas as pd

    rows = [
        {
            c: ";".join(g.get(c) or ()) if c == "checks" else g.get(c, float("nan"))
            for c in _TABLE1_COLUMNS
        }
        for g in results.groups
    ]
    return _finite_or_nan(pd.DataFrame(rows, columns=list(_TABLE1_COLUMNS)))


def loads_table(results: Results) -> pd.DataFrame:
    """The ``loads.csv`` table: the columns of ``LOAD_RESULTS``."""
    return _finite_or_nan(results.loads[list(LOAD_RESULTS.names)])


def radiation_table(results: Results) -> pd.DataFrame:
    """The ``radiation.csv`` table: the columns of ``RADIATION_RESULTS`` (results with one)."""
    if results.radiation is None:  # the caller asked for a table these results do not hold
        raise RuntimeError("these results have no radiation table (no materials were given)")
    return _finite_or_nan(results.radiation[list(RADIATION_RESULTS.names)])


def _radiation_record(table: pd.DataFrame) -> dict:
    from ..analysis import radiation_summary

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
    if "coating" in results.settings:
        record["conventions"] = {**CONVENTIONS, **COATING_CONVENTIONS}
    if results.radiation is not None:
        record["radiation"] = _radiation_record(results.radiation)
    return json_value(record)


def warning_lines(caught) -> tuple[str, ...]:
    """Each distinct caught warning as one line: the data's (SweepWarning) as they are, any
    other (a numpy RuntimeWarning, say) with where it arose, never with a source line."""
    from ..measurements import SweepWarning

    lines: list[str] = []
    for w in caught:
        text = " ".join(str(w.message).split())
        where = f"{Path(w.filename).name}, line {w.lineno}"
        if issubclass(w.category, SweepWarning):
            line = text
        elif issubclass(w.category, RuntimeWarning):  # numpy: NaN or inf met on the way
            line = f"numerical: {text} ({where}); NaN and inf results are written as empty cells"
        else:
            line = f"{w.category.__name__}: {text} ({where})"
        if line not in lines:
            lines.append(line)
    return tuple(lines)


def read(inputs: str | os.PathLike, settings: Settings) -> Reading:
    """The sweep table of ``inputs`` (a sweep table, or spectra fitted first)."""
    from ..measurements import is_spectra_input, read_spectra_sweeps, read_sweeps

    source, left_out = Path(inputs), ()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if is_spectra_input(source):
            # Admittance spectra: fitted and turned into the sweep table first, with the
            # defaults of the qcm_spectra job (run it for other choices).
            table, _, _, lines = read_spectra_sweeps(source, **settings.constants())
            left_out = tuple(lines)
        else:
            table = read_sweeps(inputs, **settings.constants())
    return Reading(table, left_out, warning_lines(caught))


def stages(reading: Reading, settings: Settings) -> int:
    """The length of a progress bar over :func:`run` of ``reading`` and the writing of the
    tables: at most 6 analysis stages (the fitted curves the last), one per (configuration,
    medium) group and one for the radiation loss, then one for the tables (a caller drawing
    figures adds one more)."""
    from ..numerics import run_starts  # here: the job's module loads no numpy when imported

    data = reading.table.data
    firsts = data.iloc[
        run_starts(*(data[c].to_numpy(dtype=object) for c in ("configuration", "medium")))
    ]
    n_groups = firsts.groupby(["configuration", "medium"]).ngroups
    coated = n_groups + 1 if settings.coating else 0  # the table, then a fit per group
    return 7 + n_groups + (settings.sphere_material is not None) + coated


def coating_layers(settings: Settings):
    """The checked layers of ``settings.coating`` ((material, thickness_m) pairs, top first), or
    None: names by :func:`contactres.jobs.contact.parse_coating`, thickness (0, 1 m] and the
    materials by :class:`contactres.analysis.AnalysisSettings`.
    Raises ContactresInputError (one line)."""
    if not settings.coating:
        return None
    from ..analysis import AnalysisSettings
    from .contact import parse_coating

    layers = parse_coating(settings.coating)
    AnalysisSettings(
        coating=layers,
        sphere_material=settings.sphere_material,
        plate_material=settings.plate_material,
    )
    return layers


@one_blas_thread()
def run(
    inputs: str | os.PathLike | Reading, settings: Settings, progress: Progress | None = None
) -> Result:
    """Analyse the sweeps of ``inputs`` (a path, or what :func:`read` returned)."""
    from ..analysis import PAGE_POINTS, AnalysisSettings, analyze
    from ..errors import ContactresInputError

    s = settings
    if (s.sphere_material is None) != (s.plate_material is None):
        raise ContactresInputError(
            "the radiation loss needs both bodies: sphere_material and plate_material"
        )
    coating = coating_layers(s)
    reading = inputs if isinstance(inputs, Reading) else read(inputs, s)
    workers = s.workers
    if workers is None:
        data = reading.table.data
        from ..numerics import column_run_starts

        # (each sweep's id starts a run of its rows: those alone are counted; every row where
        # the ids are Arrow strings, which pandas counts faster whole)
        firsts = column_run_starts(data["sweep"])
        ids = data["sweep"] if firsts is None else data["sweep"].iloc[firsts]
        many = ids.nunique() >= _MANY_SWEEPS
        workers = max(1, os.cpu_count() or 1) if many else 1
    chosen = AnalysisSettings(
        workers=workers,
        keep_first_ramp=s.keep_first_ramp,
        keep_drift=s.keep_drift,
        remove_drift=s.remove_drift,
        pool_experiments=not s.law_per_load,
        bootstrap=s.bootstrap,
        sphere_material=s.sphere_material,
        plate_material=s.plate_material,
        coating=coating,
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # None: the page's grid for every sweep and Fig. 4's for the sweeps it draws.
        grids = None if s.figures else (PAGE_POINTS,)
        results = analyze(reading.table, settings=chosen, progress=progress, curve_grids=grids)
    return Result(analysis=results, reading=reading, warnings=warning_lines(caught))
