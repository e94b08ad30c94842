"""Convergence of the two exact rigid-punch solutions: error against resolution.

(a, b) The package's Galerkin (``dcsf(..., "exact")``; :mod:`contactres.dynamic._exact`) on cubic
(001) faces, Q⁻¹ = 0.02, k_l a = 0.4 ... 2, as tests/dynamic/test_dynamic_exact.py
(test_convergence_in_terms_and_resolution): the largest |DCSF/DCSF_ref − 1| when the number of
radial terms (a) or of angular harmonics (b) is cut, the other at its default, the reference
being twice both at the doubled kernel-table resolution (tolerance 1e-6: the default must stay
below it). (c) The independent Fredholm solver of tests/dynamic/test_rigid_disk_isotropic.py
(ν = 1/3, lossless): absolute error against its own solution with 32 nodes and 64
wave-number nodes (the test doubles 16/32 to 32/64 and allows 1e-7).
"""

import math
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from contactres import Material
from contactres.dynamic._exact import GalerkinSize, exact_n, galerkin_size
from contactres.dynamic._table import kernel_table, resolution_for
from contactres.report.figures import key_below

# the plot directive runs the script with sys.argv = [its path] (so does python script.py)
TESTS = Path(sys.argv[0]).resolve().parents[2] / "tests" / "dynamic"
sys.path.insert(0, str(TESTS))
from test_rigid_disk_isotropic import fredholm_disk  # noqa: E402

Q = 0.02
FLOOR = 1e-16
fig = Figure(figsize=(9.5, 3.8), layout="constrained")
ax1, ax2, ax3 = fig.subplots(1, 3, sharey=True)
for i, (A, nu) in enumerate(((0.25, 0.25), (4.0, 0.3))):
    m = Material.cubic_from_ratios(zener=A, poisson=nu)
    kl = np.linspace(0.4, 2.0, 5)
    ksa = kl * math.sqrt(m.C[2, 2] / m.C[3, 3])
    size = galerkin_size(float(ksa.max()))
    res = resolution_for(1e-6)
    base = kernel_table(m, Q, res)
    fine = kernel_table(m, Q, res.doubled())
    ref = fine.n_static / exact_n(fine, ksa, size.doubled())

    def err(s, base=base, ksa=ksa, ref=ref):
        return max(np.max(np.abs(base.n_static / exact_n(base, ksa, s) / ref - 1)), FLOOR)

    nr = np.arange(1, size.n_radial + 1)
    nh = np.arange(0, size.n_harmonics + 1)
    c = f"C{i}"
    label = f"A = {A:g}, ν = {nu:g}"
    ax1.semilogy(
        nr, [err(GalerkinSize(n, size.n_harmonics)) for n in nr], "o-", color=c, ms=4, label=label
    )
    ax1.plot(size.n_radial, err(size), "*", color=c, ms=12, mfc="none")
    ax2.semilogy(nh, [err(GalerkinSize(size.n_radial, n)) for n in nh], "o-", color=c, ms=4)
    ax2.plot(size.n_harmonics, err(size), "*", color=c, ms=12, mfc="none")

nodes = np.array([4, 6, 8, 12, 16, 20])
for j, a0 in enumerate((0.5, 2.0)):
    ref = fredholm_disk(a0, 1 / 3, 32, 64)
    e = [max(abs(fredholm_disk(a0, 1 / 3, n, 2 * n) - ref), FLOOR) for n in nodes]
    ax3.semilogy(nodes, e, "s--", color=f"C{j + 4}", ms=4, label=f"Fredholm, a₀ = k_s a = {a0:g}")
for ax in (ax1, ax2):
    ax.axhline(1e-6, color="C3", ls="--", lw=1)
ax3.axhline(1e-7, color="k", ls=":", lw=1)
ax1.set_ylabel("error (dimensionless; (c) absolute)")
ax1.set_xlabel("radial terms")
ax2.set_xlabel("harmonics (|n| <= step × value)")
ax3.set_xlabel("nodes N (wave-number nodes 2N)")
ax1.set_title("(a) Galerkin, radial terms", fontsize=9, loc="left")
ax2.set_title("(b) Galerkin, harmonics", fontsize=9, loc="left")
ax3.set_title("(c) Fredholm (tests)", fontsize=9, loc="left")
extra = [
    (plt.Line2D([], [], marker="*", ms=10, mfc="none", color="k", ls="none"), "default size"),
    (plt.Line2D([], [], color="C3", ls="--"), "tolerance 1e-6 (Galerkin)"),
    (plt.Line2D([], [], color="k", ls=":"), "tolerance 1e-7 abs (Fredholm, doubled)"),
]
fig.suptitle(
    "Exact rigid punch: error against resolution; (a, b) cubic (001), Q⁻¹ = 0.02, "
    "k_l a <= 2; (c) isotropic ν = 1/3, lossless",
    fontsize=9,
)
key_below(fig, extra=extra, ncols=4)
plt.figure(fig)
