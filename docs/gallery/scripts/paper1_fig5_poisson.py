"""Paper 1, Fig. 5: DCSF (WA model and exact) at A = 2 for ν = 0.1 ... 0.4.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import fig5_poisson

fig, table = fig5_poisson()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
