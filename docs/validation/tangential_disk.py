"""Tangential dynamic stiffness of a rigid disk (isotropic) against an independent Galerkin.

As tests/dynamic/test_tangential_dynamic.py (test_isotropic_against_independent_reference):
relaxed contact, K_t/K_t0 = k_t + i a₀ c_t, K_t0 = 8Ga/(2 − ν) (Mindlin), a₀ = k_s a; the
package's ``tangential_dcsf`` against ``tangential_disk`` of
tests/dynamic/tangential_isotropic_reference.py (imported from the tests folder; nothing
shared with the package). G = 30 GPa, ρ = 2500 kg/m³. Tolerance 1e-6 (relative).
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from contactres import Material
from contactres.dynamic import tangential_dcsf
from contactres.report.figures import key_below

# the plot directive runs the script with sys.argv = [its path] (so does python script.py)
TESTS = Path(sys.argv[0]).resolve().parents[2] / "tests" / "dynamic"
sys.path.insert(0, str(TESTS))
from tangential_isotropic_reference import tangential_disk  # noqa: E402

G = 30e9
a0 = np.linspace(0.1, 2.0, 8)
fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2, sharex=True)
for i, nu in enumerate((0.17, 0.25, 1 / 3)):
    got = tangential_dcsf(Material.isotropic(2 * G * (1 + nu), nu, density=2500.0), a0)
    ref = np.array([tangential_disk(x, nu) for x in a0])
    label = f"ν = {nu:.3g}"
    c = f"C{i}"
    ax1.plot(a0, ref.real, "o", color=c, mfc="none", ms=6, label=f"reference Galerkin, {label}")
    ax1.plot(a0, ref.imag / a0, "s", color=c, mfc="none", ms=6)
    ax1.plot(a0, got.real, "-", color=c, label=f"package, {label}")
    ax1.plot(a0, got.imag / a0, "--", color=c)
    ax2.semilogy(a0, np.abs(got / ref - 1), "o-", color=c, ms=3, label=f"package, {label}")
ax2.axhline(1e-6, color="C3", ls="--", label="tolerance 1e-6")
ax1.set_ylabel("k_t (solid, circles), c_t (dashed, squares)")
ax2.set_ylabel("|K_t/K_t,ref − 1| (dimensionless)")
ax1.set_title("(a) K_t/K_t0 = k_t + i a₀ c_t", fontsize=9, loc="left")
ax2.set_title("(b) relative error", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("a₀ = k_s a (dimensionless)")
fig.suptitle(
    "Tangential rigid disk, isotropic, relaxed contact: package vs independent Galerkin", fontsize=9
)
key_below(fig, ncols=3)
plt.figure(fig)
