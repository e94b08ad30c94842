"""K′ + iK″ of hysteresis loops: the package's quadrature of paper 2, Eqs. 4-5, against Eq. 3.

As tests/resonators/test_qcm.py: a Cattaneo-Mindlin loop (κ = 4e5 N/m, μ = 0.8, F_N = 5 mN,
full sliding at u0 = d* = 3μF_N/(2κ) = 15 nm) and a Savkoor loop (κ = 4e5 N/m,
τ = 20 MPa, a = 5 µm, full sliding at u0 = 4a²τ/κ = 5 nm); ``loop_stiffness`` against (i)
Eq. 3 in the time domain, (2/u0)⟨F(t) e^{−iωt}⟩ by FFT with 2¹⁵ samples (tolerance 1e-8 of
|K|), and (ii) scipy's adaptive quadrature of Eq. 4 from the branches (tolerance 1e-9, used
next to the onset of full sliding).
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from scipy.integrate import IntegrationWarning, quad

import contactres as cr
from contactres.report.figures import key_below
from contactres.resonators import loop_stiffness

warnings.simplefilter("ignore", IntegrationWarning)  # quad at epsrel 1e-14: round-off notes
LOOPS = {
    "Cattaneo-Mindlin": cr.CattaneoMindlinLoop(kappa=4e5, mu=0.8, normal_force=5e-3),
    "Savkoor": cr.SavkoorLoop(kappa=4e5, tau=20e6, a=5e-6),
}


def fft_stiffness(loop, u0, n=2**15):
    """Eq. 3: u = u0 cos ωt, F on the descending branch for 0 < ωt < π."""
    theta = 2 * np.pi * np.arange(n) / n
    up, down = loop.branches(u0 * np.cos(theta), u0)
    force = np.where(theta < np.pi, down, up)
    return 2.0 / u0 * np.fft.fft(force)[1] / n


def quad_stiffness(loop, u0):
    """Eqs. 4-5 by adaptive quadrature from the branches (x = sin t), split at the kinks."""
    kinks = sorted(np.arcsin(x) for x in np.ravel(loop.kinks(u0)) if np.isfinite(x))

    def g(t, part):
        up, down = loop.branches(u0 * np.sin(t), u0)
        return (up + down) * np.sin(t) if part == 0 else (up - down) * np.cos(t)

    val = [
        quad(
            g,
            -np.pi / 2,
            np.pi / 2,
            args=(p,),
            points=kinks or None,
            epsabs=1e-16 * loop.kappa * u0,
            epsrel=1e-14,
            limit=500,
        )[0]
        for p in (0, 1)
    ]
    return complex(val[0], val[1]) / (np.pi * u0)


fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
for i, (name, loop) in enumerate(LOOPS.items()):
    b = max(loop.breaks)
    x = np.geomspace(0.05, 20, 17)
    u0 = x * b
    k = loop_stiffness(loop, u0)
    kf = np.array([fft_stiffness(loop, u) for u in u0])
    kq = np.array([quad_stiffness(loop, u) for u in u0])
    c = f"C{i}"
    ax1.semilogx(x, kf.real / loop.kappa, "o", color=c, mfc="none", label=f"{name}: Eq. 3 by FFT")
    ax1.semilogx(x, kf.imag / loop.kappa, "s", color=c, mfc="none")
    ax1.semilogx(x, k.real / loop.kappa, "-", color=c, label=f"{name}: package (Eqs. 4-5)")
    ax1.semilogx(x, k.imag / loop.kappa, "--", color=c)
    ax2.loglog(
        x,
        np.maximum(np.abs(k - kf) / np.abs(k), 1e-17),
        "o-",
        ms=3,
        color=c,
        label=f"{name}: |K − K_FFT|/|K|",
    )
    ax2.loglog(
        x,
        np.maximum(np.abs(k - kq) / np.abs(k), 1e-17),
        "^:",
        ms=3,
        color=c,
        label=f"{name}: |K − K_quad|/|K|",
    )
ax2.axhline(1e-8, color="C3", ls="--", label="tolerance 1e-8 (FFT)")
ax2.axhline(1e-9, color="C3", ls=":", label="tolerance 1e-9 (adaptive quad)")
ax1.set_ylabel("K′/κ, K″/κ (dimensionless)")
ax2.set_ylabel("relative error (dimensionless)")
ax1.set_title("(a) K′/κ: solid, circles; K″/κ: dashed, squares", fontsize=9, loc="left")
ax2.set_title("(b) error (exact 0 at 1e-17)", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("u0 / (amplitude of full sliding) (dimensionless)")
fig.suptitle(
    "QCM loops, κ = 4e5 N/m: CM μ = 0.8, F_N = 5 mN; Savkoor τ = 20 MPa, a = 5 µm", fontsize=9
)
key_below(fig, ncols=3)
plt.figure(fig)
