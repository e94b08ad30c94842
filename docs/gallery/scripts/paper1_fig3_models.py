"""Paper 1, Fig. 3: DCSF of the five displacement models and the exact punch, A = 0.5, ν = 0.25.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import fig3_models

fig, table = fig3_models()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
