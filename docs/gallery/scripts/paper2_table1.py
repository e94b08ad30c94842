"""Paper 2, Table 1: E and γ of every configuration and medium, from the bundled example.

The table ``contactres qcm analyze src/contactres/data/example_sweeps.csv`` prints
(:func:`contactres.report.table1_text`; the numbers are in its ``summary.json``), drawn
as a figure because the plot directive makes figures. Built with the documentation; run it alone
to get the same figure.
"""

import matplotlib.pyplot as plt
from _example import results
from matplotlib.figure import Figure

from contactres.report import table1_text

table = table1_text(results())
# a note common to every row goes under the table, not into each cell
notes = [f"errors: {table['errors'].iloc[0]}"] if table["errors"].nunique() == 1 else []
shown = table.drop(columns=["errors"]) if notes else table

fig = Figure(figsize=(7, 0.3 * (len(shown) + 1) + 0.7), layout="constrained")
ax = fig.subplots()
ax.axis("off")
tab = ax.table(
    cellText=shown.astype(str).to_numpy(),
    colLabels=list(shown.columns),
    loc="center",
    cellLoc="center",
)
tab.auto_set_font_size(False)
tab.set_fontsize(8)
tab.scale(1.0, 1.4)
fig.suptitle(
    "Table 1 (example data): E and γ ± standard error; the 95 % interval is value ± t95 × error"
    + "".join(f"\n{n}" for n in notes),
    fontsize=9,
)
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
