"""Small-amplitude expansions of paper 2 (Eqs. 11 and 15) against the full loop integration.

As tests/resonators/test_qcm.py (test_expansions_match_quadrature_to_their_order): the same
Cattaneo-Mindlin and Savkoor loops as on the quadrature figure; ``cattaneo_mindlin_expansion``
(Eq. 11, coefficients 1/6, 5/288, 2/(9π), 1/(27π) derived from Eqs. 4-6) and
``savkoor_expansion`` (Eq. 15) against ``loop_stiffness`` (Eqs. 4-5), with the remainder bound
of the test, |expansion − quadrature| < 0.02 ε³ κ. The OCR coefficients of the paper's Eq. 11
(1/3, 4/(9π), see the corrections) are drawn for comparison. ε = κu0/(μF_N) (CM) or
κu0/(a²τ) (Savkoor); no dashpot.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

import contactres as cr
from contactres.report.figures import key_below
from contactres.resonators import loop_stiffness

CM = cr.CattaneoMindlinLoop(kappa=4e5, mu=0.8, normal_force=5e-3)
SV = cr.SavkoorLoop(kappa=4e5, tau=20e6, a=5e-6)

eps = np.geomspace(1e-3, 0.5, 30)
fig = Figure(figsize=(8, 3.8), layout="constrained")
ax1, ax2 = fig.subplots(1, 2)
cases = (
    ("Cattaneo-Mindlin", CM, cr.cattaneo_mindlin_expansion, CM.sliding_force / CM.kappa),
    ("Savkoor", SV, cr.savkoor_expansion, SV.a**2 * SV.tau / SV.kappa),
)
for i, (name, loop, expand, unit) in enumerate(cases):
    c = f"C{i}"
    u0 = eps * unit
    k = loop_stiffness(loop, u0) / loop.kappa
    e = expand(loop, u0, 0.0) / loop.kappa
    ax1.loglog(eps, 1 - k.real, "o", ms=3, color=c, mfc="none", label=f"{name}: quadrature")
    ax1.loglog(eps, k.imag, "s", ms=3, color=c, mfc="none")
    ax1.loglog(
        eps, 1 - e.real, "-", color=c, label=f"{name}: expansion (Eq. {11 if i == 0 else 15})"
    )
    ax1.loglog(eps, e.imag, "--", color=c)
    ax2.loglog(eps, np.abs(e - k), "o-", ms=3, color=c, label=f"{name}: |expansion − quadrature|/κ")
ocr = eps / 3 + (5 / 288) * eps**2, 4 * eps / (9 * np.pi) + eps**2 / (27 * np.pi)
ax1.loglog(eps, ocr[0], ":", color="0.4", label="CM with the OCR's 1/3, 4/(9π)")
ax1.loglog(eps, ocr[1], ":", color="0.4")
ax2.loglog(eps, 0.02 * eps**3, "--", color="C3", label="bound of the test 0.02 ε³")
ax1.set_ylabel("1 − K′/κ, K″/κ (dimensionless)")
ax2.set_ylabel("|ΔK|/κ (dimensionless)")
ax1.set_title("(a) 1 − K′/κ: solid, circles; K″/κ: dashed, squares", fontsize=9, loc="left")
ax2.set_title("(b) remainder: ε³ (CM), ε⁴ (Savkoor)", fontsize=9, loc="left")
for ax in (ax1, ax2):
    ax.set_xlabel("ε (dimensionless)")
fig.suptitle(
    "Paper 2 expansions, κ = 4e5 N/m: CM μ = 0.8, F_N = 5 mN, ε = κu0/(μF_N); "
    "Savkoor τ = 20 MPa, a = 5 µm, ε = κu0/(a²τ)",
    fontsize=9,
)
key_below(fig, ncols=3)
plt.figure(fig)
