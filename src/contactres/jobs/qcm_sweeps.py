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
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..measurements.schema import LOAD_RESULTS, SWEEP_RESULTS
from .contract import JobResult, Progress

if TYPE_CHECKING:
    from ..analysis import Results
    from ..measurements.sweeps import SweepTable

__all__ = ["Reading", "Result", "Settings", "read", "run", "stages", "warning_lines"]

#: From this many sweeps on, ``workers=None`` uses every core.
MANY_SWEEPS = 10_000


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
        Processes; None: every core from :data:`MANY_SWEEPS` sweeps on, else 1.
    sphere_material, plate_material : str or None
        The bodies of the contact (names of
        :func:`contactres.analysis.radiation.material_by_name`) for the radiation loss.
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
    """``analysis``: the :class:`contactres.analysis.Results` (its tables ``sweeps`` and
    ``loads``, bound to :data:`~contactres.measurements.schema.SWEEP_RESULTS` and
    :data:`~contactres.measurements.schema.LOAD_RESULTS`); ``reading``: what reading said;
    ``warnings``: the analysis's warnings, one line each."""

    NOT_VALUES = ("analysis", "reading", "warnings")
    NAME = "summary"

    analysis: Results
    reading: Reading
    warnings: tuple[str, ...] = ()

    def tables(self):
        """The analysis's per-sweep and per-load tables with their schemas."""
        return MappingProxyType(
            {
                "sweeps": (self.analysis.sweeps, SWEEP_RESULTS),
                "loads": (self.analysis.loads, LOAD_RESULTS),
            }
        )


def warning_lines(caught) -> tuple[str, ...]:
    """Each distinct caught warning as one line: the data's (SweepWarning) as they are, any
    other (a numpy RuntimeWarning, say) with where it arose, never with a source line."""
    from ..measurements.sweeps import SweepWarning

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
    from ..measurements.shifts import is_spectra_input, read_spectra_sweeps
    from ..measurements.sweeps import read_sweeps

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
    n_groups = reading.table.data.groupby(["configuration", "medium"]).ngroups
    return 7 + n_groups + (settings.sphere_material is not None)


def run(
    inputs: str | os.PathLike | Reading, settings: Settings, progress: Progress | None = None
) -> Result:
    """Analyse the sweeps of ``inputs`` (a path, or what :func:`read` returned)."""
    from ..analysis import AnalysisSettings, analyze
    from ..errors import ContactresInputError

    s = settings
    if (s.sphere_material is None) != (s.plate_material is None):
        raise ContactresInputError(
            "the radiation loss needs both bodies: sphere_material and plate_material"
        )
    reading = inputs if isinstance(inputs, Reading) else read(inputs, s)
    workers = s.workers
    if workers is None:
        many = reading.table.data["sweep"].nunique() >= MANY_SWEEPS
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
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = analyze(reading.table, settings=chosen, progress=progress)
    return Result(analysis=results, reading=reading, warnings=warning_lines(caught))
