"""Job ``qcm_spectra``: admittance spectra -> resonance fits -> the sweep table (Δf, ΔΓ, u0).

Inputs: a tidy CSV of spectra (one row per frequency point) or a folder of network-analyser
files with an ``index.csv`` (:func:`contactres.measurements.read_spectra_sweeps`).
Settings: the reference spectra, the layout and reference impedance of delimited files, how the
drive voltage is given and how it becomes the amplitude (u0 = 4 d26 Q U/(nπ)², Q = f_r/(2Γ),
or a measured calibration u0/U). Every spectrum is fitted for its resonance frequency f_r and
half-bandwidth Γ; Δf and ΔΓ are taken against the reference spectra of the same overtone.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..measurements.schema import SPECTRA_FITS, SPECTRA_SWEEPS
from .contract import JobResult, Progress

if TYPE_CHECKING:
    import os

    import pandas as pd

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """How to read and reduce the spectra.

    Parameters
    ----------
    reference : tuple of str or None
        Ids of the no-contact reference spectra (None: the column ``reference``).
    layout : str or None
        What the two columns of delimited files hold ("G/B", "Y-RI", "S11-RI", "Y-MA") when
        their header does not say it.
    reference_impedance : float
        Z0 of S11 in delimited files, Ω.
    voltage : str
        "amplitude" (peak) or "rms": what drive_voltage_V is.
    d26 : float or None
        Piezoelectric strain constant of the quartz, m/V (None: 3.1e-12, AT cut).
    calibration : float or None
        Measured amplitude per drive volt, m/V (replaces the d26 formula).
    two_port : str or None
        The S parameter of two-port Touchstone files (``.s2p``) that is the crystal's
        response: "S11", "S22" (reflection) or "S21" (the crystal in series between the
        ports); None: no two-port file is expected.
    """

    reference: tuple[str, ...] | None = None
    layout: str | None = None
    reference_impedance: float = 50.0
    voltage: str = "amplitude"
    d26: float | None = None
    calibration: float | None = None
    two_port: str | None = None


@dataclass(frozen=True)
class Result(JobResult):
    """``sweeps``: the sweep table (the input of the QCM analysis: the columns of
    :data:`contactres.measurements.schema.SWEEP_TABLE` with the errors and the spectrum's own,
    :data:`~contactres.measurements.schema.SPECTRA_SWEEPS`); ``fits``: the resonance fit of
    every spectrum (:data:`~contactres.measurements.schema.SPECTRA_FITS`); ``conventions``: how the
    spectra were read; ``warnings``: one line per spectrum left out."""

    SCHEMAS = MappingProxyType({"sweeps": SPECTRA_SWEEPS, "fits": SPECTRA_FITS})

    sweeps: pd.DataFrame
    fits: pd.DataFrame
    conventions: dict
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(
    inputs: str | os.PathLike, settings: Settings | None = None, progress: Progress | None = None
) -> Result:
    """The sweep table of the spectra ``inputs`` (see the module docstring)."""
    from ..measurements import D26_AT, read_spectra_sweeps

    s = settings or Settings()
    _validated, rows, fitted, left_out = read_spectra_sweeps(
        inputs,
        reference=None if s.reference is None else list(s.reference),
        layout=s.layout,
        reference_impedance=s.reference_impedance,
        voltage=s.voltage,
        d26=D26_AT if s.d26 is None else s.d26,
        calibration_m_per_V=s.calibration,
        validate=False,
        progress=progress,
        two_port=s.two_port,
    )
    conventions = dict(rows.attrs.get("conventions", {}))
    if s.two_port is not None:
        from ..measurements.readers import TWO_PORT_PARAMETERS

        conventions["two_port"] = f"{s.two_port} ({TWO_PORT_PARAMETERS[s.two_port]})"
    if s.voltage == "rms":
        conventions["voltage"] = "drive_voltage_V read as rms, times √2"
    return Result(
        sweeps=rows.drop(columns=["quality"]),
        fits=fitted,
        conventions=conventions,
        warnings=tuple(left_out),
    )
