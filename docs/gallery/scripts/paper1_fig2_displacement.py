"""Paper 1, Fig. 2: |u_z(r)|/|u_z(0)| across the contact, A = 0.5, ν = 0.25, Q⁻¹ = 0.02.

Built with the documentation (matplotlib's plot directive); run it alone to get the same figure.
"""

import matplotlib.pyplot as plt

from contactres.apps.paper1 import displacement_figure

fig, table = displacement_figure()
plt.figure(fig)  # hand the figure to pyplot: the plot directive saves pyplot's figures
