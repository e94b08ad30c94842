"""Paper 2, Fig. 1D: Δf(u0) and ΔΓ(u0) of a QCM for Cattaneo-Mindlin and Savkoor contacts.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper2 import shifts_figure

fig, table = shifts_figure()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
