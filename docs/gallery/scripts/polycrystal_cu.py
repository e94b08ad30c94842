"""A Cu polycrystal: the predicted modulus map, and the elastic ratios recovered from a noisy map.

Figure 1: a seeded synthetic Cu polycrystal (256 x 256 pixels of 1 µm, 40 Voronoi grains,
uniformly random orientations, seed 1), the indentation modulus M of every pixel (paper 1,
Eq. 4; Vlassak & Nix 1994) from the table over the standard triangle
(:func:`contactres.polycrystal.prepare_normal_table`), drawn by
:func:`contactres.report.modulus_map_figure`.

Figure 2: a synthetic contact-stiffness map (512 x 512 pixels, 60 grains, seed 1, rigid tip of
R = 20 nm at F = 1 µN, 1 % Gaussian noise per pixel;
:func:`contactres.jobs.maps.synthetic_map`) fitted with the grains' labels
(:func:`contactres.jobs.maps.fit_measured_map`): the fitted quantities over their true values
with ±1σ, and the ratio plane with the valley the data fix and the 1σ/2σ ellipse.

Built with the documentation (matplotlib's plot directive); run it alone to get the same
figures (~8 s).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from contactres import Material, indentation_modulus
from contactres.jobs.maps import TipLoad, fit_measured_map, synthetic_map
from contactres.polycrystal import (
    evaluate_map,
    folded_normals,
    map_from_dataset,
    prepare_normal_table,
    reduce_normals,
    surface_matrices_from_euler,
    synthetic_polycrystal,
)
from contactres.report import modulus_map_figure

CU = Material.crystal("Cu")

# Figure 1: the predicted map of M (Pa), interpolated over the standard triangle.
sp = synthetic_polycrystal((256, 256), 40, seed=1)
table = prepare_normal_table(CU, "cubic", rtol=1e-4)
M = evaluate_map(table.modulus, sp)
fig1 = modulus_map_figure(
    M,
    folded_normals(sp, "cubic"),
    "cubic",
    lambda n: table.modulus(normals=n),
    pixel_size=sp.step_x,
    material_name="Cu, 256 x 256 pixels, 40 grains",
)
# On the maps (a), (b): the grain boundaries (pixel edges between different labels, µm);
# on the triangles (c): the surface normals of the map's grains, in the stereographic
# projection of contactres.polycrystal._ipf, (X, Y) = (n_y, n_x)/(1 + n_z) for cubic.
um = sp.step_x * 1e6
i, j = np.nonzero(sp.labels[:, 1:] != sp.labels[:, :-1])  # between columns j and j + 1
vertical = np.stack([np.stack([j + 1, i], -1), np.stack([j + 1, i + 1], -1)], 1)
i, j = np.nonzero(sp.labels[1:] != sp.labels[:-1])  # between rows i and i + 1
horizontal = np.stack([np.stack([j, i + 1], -1), np.stack([j + 1, i + 1], -1)], 1)
boundaries = um * np.concatenate([vertical, horizontal])  # (segments, 2 ends, (x, y)), µm
R = surface_matrices_from_euler(*sp.grain_euler[np.unique(sp.labels)].T, degrees=False)
n, _ = reduce_normals(R[:, 2, :], "cubic")
ax_m, ax_ipf, ax_tri, ax_key = fig1.axes[:4]
for ax in (ax_m, ax_ipf):
    ax.add_collection(LineCollection(boundaries, colors="k", linewidths=0.4))
for ax in (ax_tri, ax_key):
    ax.plot(n[:, 1] / (1 + n[:, 2]), n[:, 0] / (1 + n[:, 2]), "o", mfc="none", mec="k", ms=3)
plt.figure(fig1)  # hand the figure to pyplot: the plot directive saves pyplot's figures

# Figure 2: the inverse on a noisy synthetic stiffness map (the grains' labels known).
ds = synthetic_map(
    CU,
    "cubic",
    TipLoad(radius=20e-9, force=1e-6),
    shape=(512, 512),
    n_grains=60,
    seed=1,
    noise=0.01,
)
res, _, _ = fit_measured_map(
    map_from_dataset(ds), ds["k_star_N_per_m"].values, quantity="stiffness"
)
true = np.array([CU.C[0, 1] / CU.C[0, 0], CU.C[3, 3] / CU.C[0, 0]])  # C12/C11, C44/C11
ln_true = np.log(true)
a111 = indentation_modulus(CU.rotated((1, 1, 1))) / indentation_modulus(CU)

names = ["C12/C11", "C44/C11", "weak\ncombination", "M(111)/M(001)"]
fitted = np.array([res.c12_c11, res.c44_c11, res.weak_combination, res.anisotropy_111])
truth = np.array([*true, np.exp(res.weak_direction @ ln_true), a111])
sigma = np.array(
    [
        res.c12_c11_error,
        res.c44_c11_error,
        res.weak_error * res.weak_combination,  # a relative error made absolute
        res.anisotropy_111_error,
    ]
)

fig2 = Figure(figsize=(10.0, 4.8), layout="constrained")
ax1, ax2 = fig2.subplots(1, 2)
x = np.arange(len(names))
ax1.axhline(1.0, color="0.4", lw=1, label="truth")
ax1.errorbar(
    x, fitted / truth, yerr=sigma / truth, fmt="o", color="C0", capsize=4, label="fit ± 1σ"
)
ax1.set_xticks(x, names, fontsize=8)
ax1.set_xlim(-0.5, len(names) - 0.5)
ax1.set_ylabel("fitted / true value")
ax1.set_title("(a) fitted over true values", fontsize=9)

# (b) The plane of the log-ratios: the 1σ and 2σ ellipses of the fit (principal axes = the
# strong and weak directions) and the two directions through the fitted point.
i = [res.parameter_names.index(f"ln_{n}") for n in ("c12_c11", "c44_c11")]
centre = res.parameters[i]
w, v = np.linalg.eigh(res.covariance[np.ix_(i, i)])
t = np.linspace(0.0, 2.0 * np.pi, 200)
circle = np.stack([np.cos(t), np.sin(t)])
for k, style in ((1, "-"), (2, "--")):
    ell = centre[:, None] + k * (v * np.sqrt(w)) @ circle
    ax2.plot(ell[0], ell[1], color="C0", lw=2, ls=style, label=f"{k}σ ellipse")
span = np.array([-0.1, 0.1])  # ±0.1 in ln, i.e. about ±10 %
for direction, color, label in (
    (res.strong_direction, "C2", "strong direction"),
    (res.weak_direction, "C1", "weak direction"),
):
    line = centre[:, None] + np.outer(direction, span)
    ax2.plot(*line, color=color, lw=1, ls=":", zorder=1, label=label)
ax2.plot(*centre, "o", color="C0", label="fit")
ax2.plot(*ln_true, "*", color="C3", ms=11, label="truth (Cu)")
ax2.set_aspect("equal", adjustable="datalim")
ax2.set_xlabel("ln(C12/C11)")
ax2.set_ylabel("ln(C44/C11)")
ax2.set_title("(b) the log-ratio plane", fontsize=9)
fig2.legend(loc="outside lower center", ncols=7, fontsize=8)
(a, b), (sa, sb) = res.strong_direction, res.weak_direction
fig2.suptitle(
    "Cu, 512 x 512 pixels, 60 grains, 1 % noise per pixel, grains labelled\n"
    f"strong: (C12/C11)^{a:.2f} (C44/C11)^{b:.2f} to ±{100 * res.strong_error:.2f} %; "
    f"weak: (C12/C11)^{sa:.2f} (C44/C11)^{sb:.2f} to ±{100 * res.weak_error:.1f} %",
    fontsize=9,
)
plt.figure(fig2)
