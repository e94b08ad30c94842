"""Paper 2, Fig. 2C-D: a viscoelastic (Voigt) loop and Cattaneo-Mindlin partial-slip loops.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper2 import loops_figure

fig, table = loops_figure()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
