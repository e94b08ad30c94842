"""Paper 1, Fig. 4 with real crystals: DCSF (WA) of RbI, KCl, W, Cu, Li on their (001) faces.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import crystals_figure

fig, table = crystals_figure()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
