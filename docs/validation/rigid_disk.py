"""Exact rigid-disk DCSF (package Galerkin) against an independent Fredholm integral equation.

As tests/dynamic/test_rigid_disk_isotropic.py: massless rigid disk on an isotropic lossless
half-space, K/K₀ = k + i a₀ c, K₀ = 2aE*, a₀ = k_s a; the package's ``dcsf(..., "exact",
loss=0, wavenumber="shear")`` against the Fredholm solver written in that test (in the manner of
Luco & Westmann 1971, imported from the tests folder). Tolerance 1e-6 (absolute). The four-digit
values quoted second-hand for ν = 1/3 are marked (the one at a₀ = 1 is off: see the corrections).
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from contactres import Material, dcsf
from contactres.report.figures import key_below

# the plot directive runs the script with sys.argv = [its path] (so does python script.py)
TESTS = Path(sys.argv[0]).resolve().parents[2] / "tests" / "dynamic"
sys.path.insert(0, str(TESTS))
from test_rigid_disk_isotropic import fredholm_disk  # noqa: E402

a0 = np.linspace(0.1, 2.0, 8)
fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
for i, nu in enumerate((0.25, 1 / 3, 0.45)):
    got = np.asarray(dcsf(Material.isotropic(E=1.0, nu=nu), a0, "exact", 0.0, "shear"))
    ref = np.array([fredholm_disk(x, nu) for x in a0])
    label = f"ν = {nu:.3g}"
    c = f"C{i}"
    ax1.plot(a0, ref.real, "o", color=c, mfc="none", ms=6, label=f"Fredholm, {label}")
    ax1.plot(a0, ref.imag / a0, "s", color=c, mfc="none", ms=6)
    ax1.plot(a0, got.real, "-", color=c, label=f"package (exact), {label}")
    ax1.plot(a0, got.imag / a0, "--", color=c)
    ax2.semilogy(a0, np.abs(got - ref), "o-", color=c, ms=3, label=f"package (exact), {label}")
ax1.plot([0.5, 1.0], [0.9689, 0.8826], "kx", ms=8, label="quoted 4 digits, ν = 1/3")
ax1.plot([0.5, 1.0], [0.7931, 0.8239], "kx", ms=8)
ax2.axhline(1e-6, color="C3", ls="--", label="tolerance 1e-6 (abs)")
ax1.set_ylabel("k (solid, circles), c (dashed, squares)")
ax2.set_ylabel("|K/K₀ − (K/K₀)_Fredholm| (dimensionless)")
ax1.set_title("(a) K/K₀ = k + i a₀ c", fontsize=9, loc="left")
ax2.set_title("(b) difference", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("a₀ = k_s a (dimensionless)")
fig.suptitle("Rigid disk on an isotropic lossless half-space: Galerkin vs Fredholm", fontsize=9)
key_below(fig, ncols=4)
plt.figure(fig)
