"""Paper 1, Fig. 4: DCSF (WA model and exact) for Zener ratios A = 0.25 ... 4, ν = 0.25.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import fig4_anisotropy

fig, table = fig4_anisotropy()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
