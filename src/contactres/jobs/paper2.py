"""Job ``paper2``: the numbers of paper 2's forward figures: the force-displacement loops of
Fig. 2C-D and Δf(u0), ΔΓ(u0) of Fig. 1D for both partial-slip models.

The parameters (:class:`Paper2Example`) are those of the paper's experiment (glass spheres,
R = 1.1 mm, ν = 0.17, a tripod on a 5 MHz crystal, 3rd overtone) with a round E = 70 GPa,
μ = 1 and a loss tangent ωξ/κ = 0.1; the Savkoor traction is chosen so that both models slide
at the same force μF_N. Inputs: none (pass None). The figures are drawn by
:mod:`contactres.apps.paper2`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import pandas as pd

from .._threads import one_blas_thread
from ..measurements.schema import PAPER2_LOOPS, PAPER2_SHIFTS, PAPER2_TURNING
from ..normal import effective_modulus, jkr_contact_radius
from ..resonators import QCM, shifts_from_loop
from ..tangential import (
    CattaneoMindlinLoop,
    SavkoorLoop,
    VoigtLoop,
    kappa_jkr_mindlin,
    with_dashpot,
)
from .contract import JobResult, Progress, say

__all__ = [
    "Paper2Example",
    "Result",
    "Settings",
    "loops_table",
    "run",
    "shifts_table",
]


@dataclass(frozen=True)
class Paper2Example:
    """One contact of the paper's tripod (SI units) and the loops it gives."""

    youngs_modulus: float = 70e9
    poisson: float = 0.17
    sphere_radius: float = 1.1e-3
    gamma: float = 0.0
    normal_force: float = 1.5e-3 * 9.81 / 3  # tripod 0.5 g + 1 g added, per contact
    mu: float = 1.0
    loss_tangent: float = 0.1
    qcm: QCM = field(default_factory=lambda: QCM(fundamental=5e6, overtone=3, area=1e-5))
    n_contacts: int = 3

    @property
    def contact_radius(self) -> float:
        """JKR contact radius a (paper 2, Eq. 9; E1 = E2), m."""
        E_star = effective_modulus(self.youngs_modulus, self.poisson)
        return jkr_contact_radius(E_star, self.sphere_radius, self.normal_force, self.gamma)

    @property
    def kappa(self) -> float:
        """Mindlin stiffness κ = 2G*a of the JKR contact (paper 2, Eqs. 7-10), N/m."""
        return kappa_jkr_mindlin(
            self.normal_force, self.youngs_modulus, self.gamma, self.sphere_radius, self.poisson
        )

    @property
    def xi(self) -> float:
        return self.loss_tangent * self.kappa / self.qcm.omega

    def cattaneo_mindlin(self, viscous: bool = True):
        loop = CattaneoMindlinLoop(self.kappa, self.mu, self.normal_force)
        return with_dashpot(loop, self.xi, self.qcm.omega) if viscous else loop

    def savkoor(self, viscous: bool = True):
        a = self.contact_radius
        tau = self.mu * self.normal_force / (np.pi * a**2)
        loop = SavkoorLoop(self.kappa, tau, a)
        return with_dashpot(loop, self.xi, self.qcm.omega) if viscous else loop

    def voigt(self):
        return VoigtLoop(self.kappa, self.xi, self.qcm.omega)


def _loop_cases(example: Paper2Example):
    """The loops of Fig. 2C-D: (name, loop) of the Voigt contact and of Cattaneo-Mindlin
    without dashpot."""
    return (("voigt", example.voigt()), ("cattaneo_mindlin", example.cattaneo_mindlin(False)))


def _loop_table(name, loop, u0, n=201):
    u = np.linspace(-u0, u0, n)
    up, down = loop.branches(u, u0)
    return pd.DataFrame({"model": name, "u0_m": u0, "u_m": u, "F_plus_N": up, "F_minus_N": down})


def loops_table(example: Paper2Example, amplitudes=(10e-9, 20e-9)):
    """Every loop of Fig. 2C-D at every amplitude: (table, turning). ``table``: model, u0_m,
    u_m, F_plus_N, F_minus_N (201 points a loop); ``turning``: model, u0_m and the force at the
    turning point F(u0), N (Δf ∝ F(u0)/u0)."""
    tables, turning = [], []
    for name, loop in _loop_cases(example):
        for u0 in amplitudes:
            tables.append(_loop_table(name, loop, u0))
            turning.append({"model": name, "u0_m": u0, "F_u0_N": loop.branches(u0, u0)[0]})
    return pd.concat(tables, ignore_index=True), pd.DataFrame(turning)


def shifts_table(example: Paper2Example, u0=None) -> pd.DataFrame:
    """Fig. 1D: u0 (m) and Δf, ΔΓ (Hz) of Cattaneo-Mindlin and Savkoor, both with the same
    dashpot (loss tangent ``example.loss_tangent``)."""
    ex = example
    u0 = np.linspace(0.0, 20e-9, 81) if u0 is None else np.asarray(u0, dtype=float)
    df_cm, dg_cm = shifts_from_loop(ex.qcm, ex.cattaneo_mindlin(), u0, ex.n_contacts)
    df_sv, dg_sv = shifts_from_loop(ex.qcm, ex.savkoor(), u0, ex.n_contacts)
    return pd.DataFrame(
        {
            "u0_m": u0,
            "df_cm_Hz": df_cm,
            "dgamma_cm_Hz": dg_cm,
            "df_savkoor_Hz": df_sv,
            "dgamma_savkoor_Hz": dg_sv,
        }
    )


@dataclass(frozen=True)
class Settings:
    """The contact (``example``; None: :class:`Paper2Example`), the loops' amplitudes (m) and
    the amplitudes of the shifts (m; None: 81 from 0 to 20 nm)."""

    example: Paper2Example | None = None
    amplitudes: tuple[float, ...] = (10e-9, 20e-9)
    u0: np.ndarray | None = None


@dataclass(frozen=True)
class Result(JobResult):
    """``loops`` and ``turning`` (:func:`loops_table`;
    :data:`~contactres.measurements.schema.PAPER2_LOOPS`,
    :data:`~contactres.measurements.schema.PAPER2_TURNING`), ``shifts`` (:func:`shifts_table`;
    :data:`~contactres.measurements.schema.PAPER2_SHIFTS`) and the ``example`` they belong to."""

    SCHEMAS = MappingProxyType(
        {"loops": PAPER2_LOOPS, "turning": PAPER2_TURNING, "shifts": PAPER2_SHIFTS}
    )
    NOT_VALUES = ("example", "warnings")

    loops: pd.DataFrame
    turning: pd.DataFrame
    shifts: pd.DataFrame
    example: Paper2Example


@one_blas_thread()
def run(inputs: None = None, settings: Settings | None = None, progress: Progress | None = None):
    """The numbers of paper 2's forward figures (see the module docstring)."""
    s = settings or Settings()
    ex = s.example or Paper2Example()
    say(progress, "loops (Fig. 2C-D)")
    loops, turning = loops_table(ex, s.amplitudes)
    say(progress, "shifts (Fig. 1D)")
    return Result(loops=loops, turning=turning, shifts=shifts_table(ex, s.u0), example=ex)
