"""Dynamic surface kernel g(κ, θ) of an isotropic solid against Lamb's closed form.

As tests/test_halfspace.py (test_isotropic_dynamic_kernel_matches_lamb_closed_form_with_loss):
E = 1, θ = 0.7, loss Q⁻¹ = 0.02 and 1e-3, κ = η/k_s from 0.02 to 50 and through the Rayleigh
pole κ_R = c_s/c_R. Lamb's form is written out here (not the package's):
g = −Ω² v_p/(c̃44² F), Ω = 1/κ, c̃44 = 1 + iQ⁻¹, c̃11 = (C11/C44) c̃44,
v = √(1 − Ω²/c̃), F = (2 − x)² − 4 v_p v_s, x = Ω²/c̃44 (direct form: exact enough for κ <= 50,
see the corrections on the validation page). Tolerance 1e-10 (relative).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from scipy.optimize import brentq

from contactres import Material
from contactres.halfspace import dynamic_kernel
from contactres.report.figures import key_below

NU = 0.25


def lamb(kappa, ratio, loss):
    c44 = 1 + 1j * loss
    c11 = ratio * c44
    om2 = 1 / np.asarray(kappa, dtype=complex) ** 2
    vp, vs = np.sqrt(1 - om2 / c11), np.sqrt(1 - om2 / c44)
    x = om2 / c44
    return -om2 * vp / (c44**2 * ((2 - x) ** 2 - 4 * vp * vs))


m = Material.isotropic(1.0, NU)
ratio = m.C[0, 0] / m.C[3, 3]


def rayleigh(k):
    om2 = 1 / k**2
    return (2 - om2) ** 2 - 4 * np.sqrt(1 - om2 / ratio) * np.sqrt(1 - om2)


kr = brentq(rayleigh, 1 + 1e-12, 2.0, xtol=1e-15)
kappa = np.unique(np.r_[np.geomspace(0.02, 50, 200), kr * (1 + np.linspace(-0.03, 0.03, 61))])

fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
for q, color in ((0.02, "C0"), (1e-3, "C1")):
    g = dynamic_kernel(m.with_loss(q), kappa, 0.7)
    ref = lamb(kappa, ratio, q)
    ax1.loglog(
        kappa, np.abs(ref), color="0.6", lw=3, label="Lamb's closed form" if q == 0.02 else None
    )
    ax1.loglog(kappa, np.abs(g), color=color, lw=1, label=f"package, Q⁻¹ = {q:g}")
    err = np.abs(g / ref - 1)
    ax2.loglog(kappa, np.maximum(err, 1e-17), color=color, lw=1, label=f"package, Q⁻¹ = {q:g}")
ax2.axhline(1e-10, color="C3", ls="--", label="tolerance 1e-10")
for ax in (ax1, ax2):
    ax.axvline(kr, color="0.5", lw=0.6, ls=":")
    ax.set_xlabel("κ = η/k_s (dimensionless)")
ax1.set_ylabel("|g(κ, θ = 0.7)| (dimensionless)")
ax2.set_ylabel("|g/Lamb − 1| (dimensionless)")
ax1.set_title("(a) kernel; dotted: Rayleigh pole κ_R", fontsize=9, loc="left")
ax2.set_title("(b) error", fontsize=9, loc="left")
fig.suptitle(f"Dynamic kernel vs Lamb, isotropic, ν = {NU:g}, κ_R = {kr:.4f}", fontsize=9)
key_below(fig, ncols=3)
plt.figure(fig)
