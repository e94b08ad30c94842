"""Paper 2, Fig. 7: the loss tangents against the load, from the bundled example.

The analysis of ``contactres qcm analyze src/contactres/data/example_sweeps.csv`` (without the
bootstrap); the figure is the one that command writes. Built with the documentation (matplotlib's
plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt
from _example import results

from contactres.report.figures import figure_dissipation

fig = figure_dissipation(results())
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
