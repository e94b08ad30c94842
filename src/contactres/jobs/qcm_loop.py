"""Job ``qcm_loop``: Δf(u0), ΔΓ(u0) of a QCM loaded by partial-slip contacts (paper 2,
Eqs. 4-5), from the force-displacement loop of one contact.

Inputs: none (a forward model; pass None). Settings: the loop model (Cattaneo-Mindlin, Eq. 6;
Savkoor, Eqs. 13-14; or a linear Voigt element) and its parameters, the amplitudes u0 and the
resonator. The shifts are :func:`contactres.shifts_from_loop`; K′, K″ = (Δf, ΔΓ)/P with
P the sensitivity of the resonator (:meth:`contactres.QCM.sensitivity`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..measurements.schema import QCM_LOOP_TABLE
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

    from ..tangential import MasingLoop

__all__ = ["MODELS", "Result", "Settings", "run"]

#: The loop models: Cattaneo-Mindlin, Savkoor, linear Voigt element.
MODELS = ("cm", "savkoor", "voigt")


@dataclass(frozen=True)
class Settings:
    """The contact loop and the resonator.

    Parameters
    ----------
    kappa : float
        Low-amplitude stiffness κ of one contact, N/m.
    model : str
        "cm" (Cattaneo-Mindlin: needs ``mu`` and ``normal_force``), "savkoor" (needs ``tau`` and
        ``contact_radius``) or "voigt" (linear).
    mu, normal_force, tau, contact_radius : float or None
        Friction coefficient μ, normal force F_N (N), sliding traction τ0 (Pa), contact radius
        a (m).
    xi : float
        Linear drag ξ of a dashpot in parallel, kg/s (0: none).
    plateau : float
        Critical displacement d_c (m) below which the contact edge sticks (cm, savkoor; 0: none).
    u0 : array
        Amplitudes u0, m.
    fundamental, overtone, area, zq, n_contacts
        The QCM: f_F (Hz), overtone order n (odd), effective area A_eff (m^2), acoustic
        impedance Z_q (kg m^-2 s^-1), number of equal contacts n_P.
    """

    kappa: float
    model: str = "cm"
    mu: float | None = None
    normal_force: float | None = None
    tau: float | None = None
    contact_radius: float | None = None
    xi: float = 0.0
    plateau: float = 0.0
    u0: np.ndarray = field(default_factory=lambda: np.linspace(0.0, 20e-9, 21))
    fundamental: float = 5e6
    overtone: int = 3
    area: float = 1e-5
    zq: float = 8.8e6
    n_contacts: int = 1


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: u0_m, df_Hz, dgamma_Hz (ΔΓ the half-bandwidth) and K1_N_per_m, K2_N_per_m
    (K′, K″ of one contact): :data:`contactres.measurements.schema.QCM_LOOP_TABLE`;
    ``warnings``: the library's small-load warnings (paper 2, Eq. 1)."""

    SCHEMAS = MappingProxyType({"table": QCM_LOOP_TABLE})

    table: pd.DataFrame
    warnings: tuple[str, ...] = ()


def _build_loop(s: Settings, omega: float):
    """The loop of the settings ``s`` at angular frequency ``omega`` (rad/s), as
    :func:`contactres.shifts_from_loop` takes it (ContactresInputError naming a missing
    parameter)."""
    from ..tangential import CattaneoMindlinLoop, PlateauLoop, SavkoorLoop, VoigtLoop, with_dashpot

    def need(name, value):
        if value is None:
            # Named both ways: the setting of the Python API and the option of the command line.
            raise ContactresInputError(
                f"model {s.model!r} needs {name} (--{name.replace('_', '-')} on the command line)"
            )
        return value

    if s.model not in MODELS:
        raise ContactresInputError(f"model must be one of {', '.join(MODELS)}, got {s.model!r}")
    if s.model == "voigt":
        if s.plateau:
            raise ContactresInputError(
                "plateau (--plateau) applies to model 'cm' or 'savkoor' only"
            )
        return VoigtLoop(s.kappa, s.xi, omega)
    if s.model == "cm":
        loop: MasingLoop = CattaneoMindlinLoop(
            s.kappa, need("mu", s.mu), need("normal_force", s.normal_force)
        )
    else:
        loop = SavkoorLoop(s.kappa, need("tau", s.tau), need("contact_radius", s.contact_radius))
    if s.plateau:
        loop = PlateauLoop(loop, s.plateau)
    return with_dashpot(loop, s.xi, omega) if s.xi > 0 else loop


@one_blas_thread()
def run(inputs: None, settings: Settings, progress: Progress | None = None) -> Result:
    """The shifts of ``settings`` (``inputs``: None; see the module docstring)."""
    import pandas as pd

    from ..resonators import QCM, shifts_from_loop

    s = settings
    q = QCM(fundamental=s.fundamental, overtone=s.overtone, area=s.area, zq=s.zq)
    loop = _build_loop(s, q.omega)
    u0 = np.atleast_1d(np.asarray(s.u0, dtype=float))  # a single amplitude: one row
    say(progress, f"shifts at {u0.size} amplitudes")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        df, dgamma = shifts_from_loop(q, loop, u0, s.n_contacts)
    P = q.sensitivity(s.n_contacts)
    table = pd.DataFrame(
        {
            "u0_m": u0,
            "df_Hz": df,
            "dgamma_Hz": dgamma,
            "K1_N_per_m": np.asarray(df) / P,
            "K2_N_per_m": np.asarray(dgamma) / P,
        }
    )
    return Result(table=table, warnings=tuple(str(w.message) for w in caught))
