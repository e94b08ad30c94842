"""JKR and DMT adhesive contact against closed forms written here.

As tests/normal/test_normal_isotropic.py: E = 70 GPa, ν = 0.17 (two identical bodies,
E* = E/(2(1 − ν²))), R = 1.1 mm, γ = 0.05 J/m². JKR (paper 2, Eq. 9; ``jkr``) against the energy
balance F = 4E*a³/(3R) − √(8πwE*a³), w = 2γ, tolerance 1e-9 of 3πγR; DMT (``dmt``) against Hertz
at the load F + 4πγR, a = (3R(F + 4πγR)/(4E*))^(1/3), tolerance 1e-14 (relative).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

import contactres as cr
from contactres.report.figures import key_below

E, NU, R, GAMMA = 70e9, 0.17, 1.1e-3, 0.05
ESTAR = E / (2 * (1 - NU**2))
FC = 3 * np.pi * GAMMA * R  # JKR pull-off force magnitude

f = np.r_[np.linspace(-0.999, 0.0, 12)[:-1], np.geomspace(1e-3, 50.0, 20)]
F = f * FC
jkr = cr.jkr(ESTAR, R, F, GAMMA)
a = jkr.contact_radius
F_eb = 4 * ESTAR * a**3 / (3 * R) - np.sqrt(8 * np.pi * 2 * GAMMA * ESTAR * a**3)
Fd = F[F > -4 * np.pi * GAMMA * R]
dmt = cr.dmt(ESTAR, R, Fd, GAMMA)
a_dmt = np.cbrt(3 * R * (Fd + 4 * np.pi * GAMMA * R) / (4 * ESTAR))

fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2)
aa = np.linspace(0, a.max(), 300)
ax1.plot(
    (4 * ESTAR * aa**3 / (3 * R) - np.sqrt(16 * np.pi * GAMMA * ESTAR * aa**3)) / FC,
    aa * 1e6,
    color="0.6",
    lw=3,
    label="JKR energy balance",
)
ax1.plot(f, a * 1e6, "o", ms=3, color="C0", label="package jkr")
ax1.plot(Fd / FC, a_dmt * 1e6, color="C1", lw=1, label="Hertz at F + 4πγR")
ax1.plot(Fd / FC, dmt.contact_radius * 1e6, "s", ms=3, mfc="none", color="C1", label="package dmt")
ax1.set_xscale("symlog", linthresh=1.0)
ax1.set_xlabel("F/(3πγR) (dimensionless; symlog)")
ax1.set_ylabel("contact radius a (µm)")
ax2.semilogy(
    f,
    np.maximum(np.abs(F - F_eb) / FC, 1e-17),
    "o-",
    ms=3,
    color="C0",
    label="JKR |F − F_balance|/(3πγR)",
)
ax2.axhline(1e-9, color="C0", ls="--", label="JKR tolerance 1e-9")
ax2.semilogy(
    Fd / FC,
    np.maximum(np.abs(dmt.contact_radius / a_dmt - 1), 1e-17),
    "s-",
    ms=3,
    mfc="none",
    color="C1",
    label="DMT |a/a_Hertz − 1|",
)
ax2.axhline(1e-14, color="C1", ls=":", label="DMT tolerance 1e-14")
ax2.set_xscale("symlog", linthresh=1.0)
ax2.set_xlabel("F/(3πγR) (dimensionless; symlog)")
ax2.set_ylabel("error (dimensionless; 0 at 1e-17)")
ax1.set_title("(a) a(F)", fontsize=9, loc="left")
ax2.set_title("(b) error", fontsize=9, loc="left")
fig.suptitle(
    f"Adhesive sphere: E* = {ESTAR / 1e9:.3g} GPa, R = {R * 1e3:g} mm, γ = {GAMMA:g} J/m²",
    fontsize=9,
)
key_below(fig, ncols=4)
plt.figure(fig)
