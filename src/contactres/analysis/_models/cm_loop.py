"""``cattaneo-mindlin-loop``: the exact Cattaneo-Mindlin loop with a dashpot (paper 2,
Eqs. 4-6, Masing loops, and Eq. 12).

Δf = Pκ g1(x), ΔΓ = Pωξ + Pκ g2(x) with x = θu0, θ = κ/(μF_N)
(:func:`contactres.analysis._loops.cm_loop_shape`). Fitted by variable projection on the loop
table (:func:`contactres.analysis._loops.fit_cm_loops`), each channel weighted by the noise
level of the straight line (``line``, fitted before it).
"""

from __future__ import annotations

import numpy as np

from ...fitting import Model
from .._loops import cm_loop_shape, fit_cm_loops
from .base import LOOP_TABLE, SweepFit, loop_parameters

__all__ = ["FIT", "MODEL", "line_noise"]


def cm_loop(u, df0, dgamma0, inverse_slip_scale):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop with Pκ = df0, Pωξ = dgamma0."""
    # Δf0 = Pκ and ΔΓ0 = Pωξ; the loop's shape depends on u0 only through κu0/(μF_N).
    g1, g2 = cm_loop_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
    return df0 * g1, dgamma0 + df0 * g2


MODEL = Model(
    "cattaneo-mindlin-loop",
    "exact Cattaneo-Mindlin loop with a dashpot",
    loop_parameters(),
    "amplitude",
    "m",
    "df, dgamma",
    "Hz",
    "paper 2, Eqs. 4-6 (Masing loops) and Eq. 12 (dashpot)",
    cm_loop,
)


def line_noise(b, done) -> np.ndarray:
    """(2, S): the noise levels of Δf and ΔΓ of every sweep, from the residuals of its
    straight line (n - 2 degrees of freedom)."""
    rss = np.stack([done["line"]["rss_df"], done["line"]["rss_dgamma"]])
    return np.sqrt(rss / np.maximum(b.n.astype(float) - 2, 1))


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The exact loop fitted to every sweep of the block ``b``."""
    sigma = line_noise(b, done)
    loop = fit_cm_loops(b.u, b.df, b.dg, b.w, sigma[0], sigma[1], inputs.tables.cm)
    return {col: loop[col].to_numpy() for col in loop.columns}


FIT = SweepFit("cattaneo-mindlin-loop", "cm", True, fit, LOOP_TABLE)
