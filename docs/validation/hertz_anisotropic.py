"""Hertz contact on an isotropic solid computed through the anisotropic path (paper 1, Eqs. 1-4).

As tests/normal/test_normal_anisotropic.py (test_isotropic_integrals_and_hertz): the package's
``sphere_contact`` (contact integrals I₀, I₁ of the surface kernel) for a rigid sphere on an
isotropic solid, E = 70 GPa, R = 1 mm, against Hertz (Johnson, *Contact Mechanics*, Eq. 4.22):
a = (3FR/(4E*))^(1/3), δ = a²/R, K = 2aE*, E* = E/(1 − ν²). Tolerance 1e-12 (relative).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from contactres import Material, sphere_contact
from contactres.report.figures import key_below

E, R = 70e9, 1e-3
F = np.geomspace(1e-6, 10.0, 15)
fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
markers = {"contact radius a": "o", "depth δ": "s", "stiffness K": "^"}
for i, nu in enumerate((0.0, 0.17, 0.3, 0.45)):
    c = f"C{i}"
    E_star = E / (1 - nu**2)
    got = sphere_contact(Material.isotropic(E, nu), R, F)
    a = np.cbrt(3 * F * R / (4 * E_star))
    ax1.loglog(F, a * 1e6, color="0.6", lw=3)
    ax1.loglog(F, got.contact_radius * 1e6, "o", color=c, ms=3, label=f"ν = {nu:g}")
    pairs = {
        "contact radius a": (got.contact_radius, a),
        "depth δ": (got.depth, a**2 / R),
        "stiffness K": (got.stiffness, 2 * a * E_star),
    }
    for name, (g, r) in pairs.items():
        err = np.maximum(np.abs(g / r - 1), 1e-17)
        ax2.semilogy(F, err, markers[name], color=c, ms=4, mfc="none", ls="-", lw=0.5)
ax2.axhline(1e-12, color="C3", ls="--", label="tolerance 1e-12")
ax2.set_xscale("log")
ax1.set_ylabel("contact radius a (µm)")
ax2.set_ylabel("|package/Hertz − 1| (dimensionless)")
ax1.set_title("(a) a(F): points package, grey Hertz", fontsize=9, loc="left")
ax2.set_title("(b) relative error of a, δ, K (exact 0 at 1e-17)", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("normal force F (N)")
extra = [(Line2D([], [], color="0.6", lw=3), "Hertz (Johnson Eq. 4.22)")]
extra += [
    (Line2D([], [], marker=m, color="k", mfc="none", ls="none"), n) for n, m in markers.items()
]
fig.suptitle(
    f"Rigid sphere on isotropic solid, E = {E / 1e9:g} GPa, R = {R * 1e3:g} mm", fontsize=9
)
key_below(fig, extra=extra, ncols=5)
plt.figure(fig)
