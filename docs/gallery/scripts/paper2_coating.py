"""Paper 2's coatings: does 250 nm of PMMA explain Table 1's E = 70 GPa against 100 GPa on SiO2?

Paper 2 (Vlachová et al., Beilstein J. Nanotechnol. 6, 845 (2015)) fitted E from κ(F_N) with
JKR + Mindlin for the same glass spheres (R = 1.1 mm) on quartz resonators coated with sputtered
SiO2 or 250 nm of spin-cast PMMA, ignoring the films (E and ν = 0.17 the same on both sides).
Here the films are kept: the contact of a glass sphere on AT-cut quartz coated with 250 nm of
either film is solved with the layered surface response, and the κ(F_N) it gives is fitted as
the paper did, force by force, to the apparent E of the homogeneous model.

- Normal contact (static load): the contact radius a of the elastic glass sphere on the coated
  plate, solved with the layered solid's surface response (contactres.sphere_contact with
  indenter=: the sphere's compliance added to the plate's; the pressure is not Hertzian), the
  film at its relaxed modulus (PMMA at 1 Hz).
- Tangential stiffness at 15 MHz (n = 3): the sphere's Mindlin stiffness 8Ga/(2 − ν) in series
  with the coated plate's, the bonded rigid punch of radius a (contactres.flat_punch_stiffness,
  direction x = the shear direction of the AT cut), the film at its 15 MHz modulus
  (contactres.pmma, correspondence principle). The plate's dynamic correction at k a ~ 0.1 is
  below 1 % and left out (the film is 400 times thinner than its shear wavelength).
- PMMA's 15 MHz shear modulus is uncertain: the built-in law gives G' = 2.34 GPa (2.22–2.49 over
  its anchors); the band spans 1.5–2.5 GPa. Sphere and SiO2 film: E = 70 GPa, ν = 0.17 (the
  paper's ν).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from scipy.optimize import brentq

import contactres as cr
from contactres.report.figures import key_below
from contactres.tangential import kappa_jkr_mindlin

R, E_SPHERE, NU = 1.1e-3, 70e9, 0.17  # glass sphere: m, Pa, -
H, FREQUENCY = 250e-9, 15e6  # film thickness (m), third overtone of 5 MHz (Hz)
# Per contact: (tripod 0.5 g + 0 ... 2.5 g added) g / 3, N
FORCES = np.array([0.5, 1.0, 2.0, 3.0]) * 1e-3 * 9.81 / 3

quartz = cr.at_cut_quartz()  # x = the crystal X axis, the shear direction
silica = cr.Material.isotropic(E_SPHERE, NU, density=2200.0, name="SiO2")
sphere = cr.Material.isotropic(E_SPHERE, NU, name="glass")
pmma = cr.pmma()
pmma_relaxed = pmma.storage(1.0)  # the elastic solid of its 1 Hz storage constants
pmma_15 = pmma.at(FREQUENCY)
g_15 = float(np.real(pmma_15.C[3, 3]))


def contact_radius(static_plate):
    """a(F) of the glass sphere on the plate (both elastic: the sphere's compliance added), m."""
    return cr.sphere_contact(static_plate, R, FORCES, indenter=sphere).contact_radius


def apparent_modulus(a, dynamic_plate):
    """E that the paper's homogeneous JKR (γ = 0) + Mindlin model needs for the same κ, Pa."""
    g_sphere = E_SPHERE / (2 * (1 + NU))
    plate = np.real(cr.flat_punch_stiffness(dynamic_plate, a, direction="tangential"))
    kappa = 1 / (1 / (8 * g_sphere * a / (2 - NU)) + 1 / plate)
    return np.array(
        [
            brentq(lambda e, f=f, k=k: float(kappa_jkr_mindlin(f, e, 0.0, R, NU)) - k, 1e9, 1e12)
            for f, k in zip(FORCES, kappa, strict=True)
        ]
    )


a_sio2 = contact_radius(cr.LayeredMaterial(quartz, [(silica, H)]))
e_sio2 = apparent_modulus(a_sio2, cr.LayeredMaterial(quartz, [(silica, H)]))
a_pmma = contact_radius(cr.LayeredMaterial(quartz, [(pmma_relaxed, H)]))
ratios = {}
for g in (1.5e9, g_15, 2.5e9):  # PMMA's shear modulus at 15 MHz, Pa
    film = cr.Material.from_voigt(pmma_15.C * (g / g_15), density=pmma.density)
    ratios[g] = apparent_modulus(a_pmma, cr.LayeredMaterial(quartz, [(film, H)])) / e_sio2

print(f"contact radius on SiO2  {np.round(a_sio2 * 1e6, 2)} µm")
print(f"contact radius on PMMA  {np.round(a_pmma * 1e6, 2)} µm")
print(f"apparent E on SiO2      {np.round(e_sio2 / 1e9, 1)} GPa")
for g, r in ratios.items():
    print(f"E(PMMA)/E(SiO2), G' = {g / 1e9:.2f} GPa: {np.round(r, 3)}")

fig = Figure(figsize=(6.4, 3.8), layout="constrained")
ax = fig.subplots()
force_mn = FORCES * 1e3
low, mid, high = (ratios[g] for g in sorted(ratios))
ax.fill_between(force_mn, low, high, color="C1", alpha=0.3, label="G'(PMMA) 1.5–2.5 GPa")
ax.plot(force_mn, mid, "o-", color="C1", label=f"G'(PMMA) = {g_15 / 1e9:.2f} GPa (built-in)")
ax.axhspan(0.70 - 0.03, 0.70 + 0.03, color="0.8", label="Table 1: 70 ± 2 over 100 ± 3 GPa")
ax.axhline(1.0, color="0.4", lw=0.8)
ax.set_xlabel("normal force per contact F_N (mN)")
ax.set_ylabel("apparent E on PMMA / on SiO2")
ax.set_ylim(0.4, 1.05)
key_below(fig, ncols=1)
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
