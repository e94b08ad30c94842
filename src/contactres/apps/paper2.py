"""The forward figures of paper 2: loops (Fig. 2C-D) and Δf(u0), ΔΓ(u0) (Fig. 1D).

The parameters are those of the paper's experiment (glass spheres, R = 1.1 mm, ν = 0.17, a
tripod on a 5 MHz crystal, 3rd overtone) with a round E = 70 GPa, μ = 1 and a loss tangent
ωξ/κ = 0.1; the Savkoor traction is chosen so that both models slide at the same force μF_N.
Every figure is written as PNG together with the CSV of the plotted numbers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ..fileio import CSV_FLOAT_FORMAT, ensure_dir, save_figure, write_csv
from ..normal.isotropic import effective_modulus, jkr_contact_radius
from ..report.figures import key_below
from ..resonators.qcm import QCM, shifts_from_loop
from ..tangential import (
    CattaneoMindlinLoop,
    SavkoorLoop,
    VoigtLoop,
    kappa_jkr_mindlin,
    with_dashpot,
)

__all__ = ["Paper2Example", "loops_figure", "shifts_figure", "write_paper2_figures"]


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


def _loop_table(name, loop, u0, n=201):
    u = np.linspace(-u0, u0, n)
    up, down = loop.branches(u, u0)
    return pd.DataFrame({"model": name, "u0_m": u0, "u_m": u, "F_plus_N": up, "F_minus_N": down})


def loops_figure(example: Paper2Example | None = None, amplitudes=(10e-9, 20e-9)):
    """Fig. 2C-D: a viscoelastic (Voigt) loop and Cattaneo-Mindlin loops (no dashpot).

    Returns (figure, table); the table holds u (m) and F₊, F₋ (N) of every loop drawn. The full
    dots mark the turning points (Δf ∝ force/displacement there), the hatch the loop area
    (ΔΓ ∝ area/u0²).
    """
    ex = example or Paper2Example()
    fig = Figure(figsize=(8, 4.2), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    tables = []
    for ax, (name, loop, title) in zip(
        axes,
        [
            ("voigt", ex.voigt(), "C: viscoelastic (Voigt) contact"),
            ("cattaneo_mindlin", ex.cattaneo_mindlin(viscous=False), "D: partial slip (CM)"),
        ],
        strict=True,
    ):
        for u0 in amplitudes:
            t = _loop_table(name, loop, u0)
            tables.append(t)
            x = t.u_m * 1e9
            ax.plot(x, t.F_plus_N * 1e3, color="C0", label="branch F₊(u)")
            ax.plot(x, t.F_minus_N * 1e3, "--", color="C1", label="branch F₋(u)")
            ax.fill_between(
                x,
                t.F_minus_N * 1e3,
                t.F_plus_N * 1e3,
                hatch="//",
                color="0.5",
                alpha=0.2,
                label="loop area (ΔΓ ∝ area/u0²)",
            )
            Fu0 = loop.branches(u0, u0)[0]
            ax.plot(
                [u0 * 1e9, -u0 * 1e9],
                [Fu0 * 1e3, -Fu0 * 1e3],
                "ko",
                ls="none",
                label="turning points ±u0 (Δf ∝ F(u0)/u0)",
            )
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("displacement u (nm)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.axvline(0, color="0.7", lw=0.5)
    axes[0].set_ylabel("tangential force F (mN)")
    amps = ", ".join(f"{u0 * 1e9:g}" for u0 in amplitudes)
    fig.suptitle(
        f"u0 = {amps} nm; F_N = {ex.normal_force * 1e3:.2f} mN, κ = {ex.kappa:.3g} N/m, "
        f"μ = {ex.mu:g}, Voigt loss tangent ωξ/κ = {ex.loss_tangent:g}",
        fontsize=9,
    )
    key_below(fig, ncols=4, fontsize=7)
    return fig, pd.concat(tables, ignore_index=True)


def shifts_figure(example: Paper2Example | None = None, u0=None):
    """Fig. 1D: Δf(u0) and ΔΓ(u0) for Cattaneo-Mindlin (linear) and Savkoor (parabolic).

    Both with the same dashpot (loss tangent ``example.loss_tangent``). Returns (figure, table)
    with u0 (m) and the shifts (Hz) of both models.
    """
    ex = example or Paper2Example()
    u0 = np.linspace(0.0, 20e-9, 81) if u0 is None else np.asarray(u0, dtype=float)
    df_cm, dg_cm = shifts_from_loop(ex.qcm, ex.cattaneo_mindlin(), u0, ex.n_contacts)
    df_sv, dg_sv = shifts_from_loop(ex.qcm, ex.savkoor(), u0, ex.n_contacts)
    table = pd.DataFrame(
        {
            "u0_m": u0,
            "df_cm_Hz": df_cm,
            "dgamma_cm_Hz": dg_cm,
            "df_savkoor_Hz": df_sv,
            "dgamma_savkoor_Hz": dg_sv,
        }
    )
    fig = Figure(figsize=(8, 4.0), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, sharex=True)
    x = u0 * 1e9
    ax1.plot(x, df_cm, label="Cattaneo-Mindlin")
    ax1.plot(x, df_sv, "--", label="Savkoor")
    ax2.plot(x, dg_cm, label="Cattaneo-Mindlin")
    ax2.plot(x, dg_sv, "--", label="Savkoor")
    ax1.set_ylabel("Δf (Hz)")
    ax2.set_ylabel("ΔΓ (Hz)")
    for ax, tag in ((ax1, "(a)"), (ax2, "(b)")):
        ax.set_xlabel("amplitude u0 (nm)")
        ax.set_title(tag, fontsize=9, loc="left")
    fig.suptitle(
        f"{ex.qcm.fundamental / 1e6:g} MHz QCM, n = {ex.qcm.overtone}, {ex.n_contacts} contacts; "
        f"F_N = {ex.normal_force * 1e3:.2f} mN, κ = {ex.kappa:.3g} N/m, μ = {ex.mu:g}, "
        f"loss tangent ωξ/κ = {ex.loss_tangent:g}",
        fontsize=9,
    )
    key_below(fig, ncols=2, fontsize=8)
    return fig, table


def write_paper2_figures(out, example: Paper2Example | None = None) -> list[Path]:
    """Write Fig. 2C-D and Fig. 1D of paper 2 (PNG + CSV) into folder ``out``; return the paths."""
    folder = ensure_dir(out)
    written = []
    for stem, make in (("paper2_fig2_loops", loops_figure), ("paper2_fig1d_shifts", shifts_figure)):
        fig, table = make(example)
        written.append(write_csv(folder / f"{stem}.csv", table, float_format=CSV_FLOAT_FORMAT))
        written.append(save_figure(folder / f"{stem}.png", fig))
    return written
