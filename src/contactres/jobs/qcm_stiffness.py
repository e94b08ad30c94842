"""Job ``qcm_stiffness``: the contact stiffness κ + iωξ against time from a QCM-D export
(paper 2, Eq. 2).

Inputs: the path of the instrument's text export (QSense, AWSensors, QCM-I, openQCM), read by
the plug-ins of :mod:`contactres.measurements.readers.exports`. Settings: the effective area,
the number of contacts, the reader and the conventions the file does not state, the impedance
of the quartz. For every point and overtone n: κ + iωξ = (Δf + iΔΓ)/P with
P = n_P/(2nπ² A_eff Z_q) (:func:`contactres.stiffness_from_shifts`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..measurements.schema import STIFFNESS_CSV
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import pandas as pd

__all__ = ["COLUMN_UNITS", "EQUATION", "Result", "Settings", "run", "stiffness_table"]

#: Units of the columns of the stiffness table (recorded with the result).
COLUMN_UNITS = MappingProxyType(
    {
        "time_s": "s",
        "overtone": "1",
        "df_Hz": "Hz (Δf, not divided by n)",
        "dgamma_Hz": "Hz (ΔΓ, half-bandwidth)",
        "kappa_N_per_m": "N/m (per contact)",
        "omega_xi_N_per_m": "N/m (per contact)",
    }
)
EQUATION = "κ + iωξ = (Δf + iΔΓ)/P, P = n_P/(2nπ² A_eff Z_q) (paper 2, Eqs. 1-2)"


@dataclass(frozen=True)
class Settings:
    """The constants of the contact and how to read the export.

    Parameters
    ----------
    area : float
        Effective area A_eff of the electrode, m^2.
    n_contacts : int
        Number of equal contacts n_P.
    reader : str or None
        The export reader's name (None: recognised from the header).
    conventions : dict
        What the file does not say, as
        :func:`contactres.measurements.readers.exports.read_export` takes it
        (``df_divided_by_n``, ``dissipation_scale``, ``baseline``, ``time_unit``, ``channel``,
        ``overtone``, ``fundamental``; None: from the file).
    zq : float
        Acoustic impedance Z_q of AT-cut quartz, kg m^-2 s^-1.
    """

    area: float
    n_contacts: int
    reader: str | None = None
    conventions: dict | None = None
    zq: float = 8.8e6


@dataclass(frozen=True)
class Result(JobResult):
    """``stiffness``: the export's rows (time_s, overtone, df_Hz, dgamma_Hz) with κ and ωξ of
    one contact (N/m), :data:`contactres.measurements.schema.STIFFNESS_CSV`; the conventions the
    file was read with, the constants, the equation and the units of the columns; ``source`` the
    file's name and ``warnings`` what the reader left out (overtones, rows, comment lines), the
    distinct small-load warnings (``|Δf|``/f above 1e-3) and the overtones of negative median κ
    or ωξ."""

    SCHEMAS = MappingProxyType({"stiffness": STIFFNESS_CSV})
    NOT_VALUES = ("source", "warnings")
    NAME = "stiffness"

    stiffness: pd.DataFrame
    conventions: dict
    constants: dict
    equation: str
    columns: dict
    source: str = ""
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(inputs: str | os.PathLike, settings: Settings, progress: Progress | None = None) -> Result:
    """κ and ωξ of the export ``inputs`` (see the module docstring)."""
    from ..measurements.readers.exports import ExportWarning, read_export

    source, s = Path(inputs), settings
    say(progress, f"reading {source.name}")
    # What the reader left out (overtones without a column, rows without a value) is said
    # with the other warnings (the CLI prints them), never only in the JSON.
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always", ExportWarning)
        table = read_export(source, s.reader, **(s.conventions or {}))
    left_out = [" ".join(str(w.message).split()) for w in seen if w.category is ExportWarning]
    for w in seen:
        if w.category is not ExportWarning:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    say(progress, f"κ and ωξ of {len(table.data)} points")
    result, caught = stiffness_table(table, s.area, s.n_contacts, s.zq)
    caught = [*left_out, *caught, *_sign_warnings(result)]
    return Result(
        stiffness=result,
        conventions=dict(table.conventions),
        constants={
            "area_m2": s.area,
            "n_contacts": s.n_contacts,
            "zq_kg_per_m2_s": s.zq,
            "fundamental_Hz": table.conventions["fundamental_Hz"],
        },
        equation=EQUATION,
        columns=dict(COLUMN_UNITS),
        source=source.name,
        warnings=tuple(caught),
    )


def _sign_warnings(result) -> list[str]:
    """Lines saying which overtones have a negative median κ or ωξ: a contact spring raises the
    frequency and adds damping (paper 2, Eq. 2), so a negative κ is mass loading (a film, a
    liquid, adsorbed material), not a contact, and a negative ωξ less damping than the
    reference (issue 27: such medians were printed without a word)."""
    import numpy as np

    lines = []
    for n, part in result.groupby("overtone"):
        for col, what in (
            ("kappa_N_per_m", "κ < 0: a negative Δf is mass loading (a film or a liquid), not a "
             "contact spring; Eq. 2 holds for point contacts"),
            ("omega_xi_N_per_m", "ωξ < 0: less damping than the reference; check the baseline "
             "and the sign of ΔΓ or D"),
        ):  # fmt: skip
            values = part[col].to_numpy(dtype=float)
            if np.isfinite(values).any() and np.nanmedian(values) < 0:
                share = int(np.sum(values < 0))
                lines.append(f"overtone {n}: {share} of {len(values)} points have {what}")
    return lines


def stiffness_table(table, area: float, n_contacts: int, zq: float):
    """The export's rows with κ and ωξ per contact (paper 2, Eq. 2), and the distinct warnings
    of the small-load check (``|Δf|``/f above 1e-3) as text lines."""
    import numpy as np

    from ..resonators import QCM, stiffness_from_shifts

    data = table.data.copy()
    kappa = np.full(len(data), np.nan)
    omega_xi = np.full(len(data), np.nan)
    fundamental = table.conventions["fundamental_Hz"]
    lines: list[str] = []
    for n, index in data.groupby("overtone").groups.items():
        q = QCM(fundamental=fundamental, overtone=int(n), area=area, zq=zq)
        part = data.loc[index]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            df, dg = part["df_Hz"].to_numpy(float), part["dgamma_Hz"].to_numpy(float)
            k, xi = stiffness_from_shifts(q, df, dg, n_contacts)
        for w in caught:
            line = f"overtone {n}: {' '.join(str(w.message).split())}"
            if line not in lines:
                lines.append(line)
        kappa[data.index.get_indexer(index)] = k
        omega_xi[data.index.get_indexer(index)] = np.asarray(xi) * q.omega
    data["kappa_N_per_m"] = kappa
    data["omega_xi_N_per_m"] = omega_xi
    return data, lines
