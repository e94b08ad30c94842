"""The table of the model ranking (paper 1's models against the exact rigid punch).

The numbers come from :func:`contactres.apps.paper1.model_ranking` (ν = 0.25, Q⁻¹ = 0.02):
for each Zener ratio A, the largest relative error max |DCSF_model/DCSF_exact − 1| over
k_l a <= 1 and over k_l a <= 2, and the rank over k_l a <= 1 (1 = closest to the exact punch).
Built with the documentation; run it alone to get the same figure.
"""

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from contactres.apps.paper1 import model_ranking

_, table = model_ranking()
zeners = sorted(table.zener.unique())
models = list(dict.fromkeys(table.model))

fig = Figure(figsize=(7, 4.6), layout="constrained")
axes = fig.subplots(2, 1)
for ax, col, title in zip(
    axes,
    ("max_rel_error_kla_le_1", "max_rel_error_kla_le_2"),
    ("(a) k_l a <= 1: error (rank)", "(b) k_l a <= 2: error"),
    strict=True,
):
    cells = []
    for m in models:
        row = []
        for A in zeners:
            r = table[(table.model == m) & (table.zener == A)].iloc[0]
            text = f"{r[col]:.3g}"
            if col.endswith("1"):
                text += f" ({int(r.rank_kla_le_1)})"
            row.append(text)
        cells.append(row)
    ax.axis("off")
    tab = ax.table(
        cellText=cells,
        rowLabels=models,
        colLabels=[f"A = {A:g}" for A in zeners],
        loc="center",
        cellLoc="center",
    )
    tab.auto_set_font_size(False)
    tab.set_fontsize(8)
    tab.scale(1.0, 1.25)
    # the best model of each column in bold
    for j, A in enumerate(zeners):
        sub = table[table.zener == A]
        best = models.index(sub.loc[sub[col].idxmin(), "model"])
        tab[best + 1, j].get_text().set_fontweight("bold")
    ax.set_title(title, fontsize=9)
fig.suptitle(
    "Largest relative error max |DCSF_model/DCSF_exact − 1| (dimensionless)\n"
    "ν = 0.25, Q⁻¹ = 0.02; bold: the smallest of its column",
    fontsize=9,
)
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
