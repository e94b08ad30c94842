"""Static surface kernel Ĝ(θ) of an isotropic solid against Boussinesq, 2(1 − ν²)/E.

As tests/test_halfspace.py (test_isotropic_static_kernel_is_boussinesq): E = 70 GPa, 13
directions θ in [0, 2π]; here ν runs from −0.5 to 0.49. Tolerance 1e-12 (relative).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from contactres import Material
from contactres.halfspace import static_kernel
from contactres.report.figures import key_below

E = 70e9
theta = np.linspace(0.0, 2 * np.pi, 13)
nus = np.linspace(-0.5, 0.49, 34)
got = np.array([static_kernel(Material.isotropic(E, nu), theta) for nu in nus])  # (ν, θ)
ref = 2 * (1 - nus**2) / E  # Boussinesq
err = np.max(np.abs(got / ref[:, None] - 1), axis=1)

fig = Figure(figsize=(8, 3.6), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
ax1.plot(nus, ref * E / 2, color="0.6", lw=3, label="Boussinesq 2(1 − ν²)/E")
ax1.plot(nus, got.max(axis=1) * E / 2, "o", ms=3, color="C0", label="package Ĝ(θ), 13 θ")
ax1.set_ylabel("Ĝ E/2 (dimensionless)")
ax1.set_title("(a) kernel", fontsize=9, loc="left")
ax2.semilogy(nus, np.maximum(err, 1e-17), "o-", ms=3, color="C0", label="max over θ of |Ĝ/ref − 1|")
ax2.axhline(1e-12, color="C3", ls="--", label="tolerance 1e-12")
ax2.set_ylabel("relative error (dimensionless)")
ax2.set_title("(b) error (zero plotted at 1e-17)", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("Poisson's ratio ν")
fig.suptitle(f"Static kernel vs Boussinesq, isotropic, E = {E / 1e9:g} GPa", fontsize=9)
key_below(fig, ncols=4)
plt.figure(fig)
