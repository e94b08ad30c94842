"""The displacement models of paper 1 ranked by their largest error against the exact rigid punch.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import model_ranking

fig, table = model_ranking()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
