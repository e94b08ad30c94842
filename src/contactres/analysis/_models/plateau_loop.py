"""``plateau-loop``: the exact Cattaneo-Mindlin loop behind a stick plateau of width d_c, with
a dashpot (paper 2, Eqs. 4-6 with Masing's rule, Fig. 4C, D, and Eq. 12).

Linear up to the critical displacement d_c, then the Cattaneo-Mindlin loop in the excess
(:class:`contactres.PlateauLoop`, :func:`contactres.analysis._loops.plateau_loop_shape`; the
model function evaluates it in closed form, :func:`~contactres.analysis._models.cm_loop.
loop_shape`).
Fitted by :func:`contactres.analysis._plateau.fit_plateau_loops` (the batched
Levenberg-Marquardt solver), started from the hinge (``hinge``) and from the Cattaneo-Mindlin
loop (``cm``), both fitted before it.
"""

from __future__ import annotations

import numpy as np

from ...fitting import Model, Parameter
from .._amplitude import PLATEAU_MIN_FLAT, PLATEAU_MIN_SLOPE
from .._plateau import PLATEAU_LOOP_COLUMNS, fit_plateau_loops
from .base import LOOP_TABLE, SweepFit, loop_parameters
from .cm_loop import loop_shape

__all__ = ["FIT", "MODEL", "fit_plateaus", "plateau_start"]


def plateau_loop(u, df0, dgamma0, inverse_slip_scale, critical_displacement):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop behind a plateau of width d_c."""
    theta = np.asarray(inverse_slip_scale)
    g1, g2 = loop_shape(theta * np.asarray(u), theta * critical_displacement)
    return df0 * g1, dgamma0 + df0 * g2


MODEL = Model(
    "plateau-loop",
    "exact Cattaneo-Mindlin loop behind a stick plateau, with a dashpot",
    (
        *loop_parameters(),
        Parameter(
            "critical_displacement",
            "critical displacement d_c",
            "m",
            "critical_displacement",
            (0.0, 1e-6),
            scale=1e-9,
        ),
    ),
    "amplitude",
    "m",
    "df, dgamma",
    "Hz",
    "paper 2, Eqs. 4-6 (Masing loops), Fig. 4C, D (stick plateau), Eq. 12 (dashpot)",
    plateau_loop,
)


def fit_plateaus(b, found, u_c, rss, theta, table, plateau: np.ndarray) -> dict[str, np.ndarray]:
    """The exact plateau loop fitted to the sweeps ``plateau`` of the block ``b`` that are long
    enough (the others get NaN).

    Started at the hinge where one was ``found`` (at ``u_c``), else at 0.3 of the largest
    amplitude; weighted by the noise of the hinge fit (``rss``, (2, S): of the straight line
    where no hinge was found); θ started from the Cattaneo-Mindlin loop fitted to the whole
    sweep (``theta``).
    """
    S = len(b.n)
    out = {col: np.full(S, np.nan) for col in PLATEAU_LOOP_COLUMNS}
    out["edge"] = np.full(S, "", dtype=object)
    # Enough distinct amplitudes for a plateau and a slope (a block may repeat amplitudes).
    distinct = (b.w > 0) & np.concatenate([np.ones((S, 1), bool), np.diff(b.u, axis=1) > 0], axis=1)
    fit = (distinct.sum(axis=1) >= PLATEAU_MIN_FLAT + PLATEAU_MIN_SLOPE) & plateau
    if not fit.any():
        return out
    n = b.n.astype(float)
    u_max = np.max(np.where(b.w > 0, b.u, 0.0), axis=1)
    sig = np.sqrt(rss / np.maximum(n - np.where(found, 3, 2), 1))
    u_c = np.where(found, u_c, 0.3 * u_max)
    i = np.flatnonzero(fit)
    res = fit_plateau_loops(
        b.u[i], b.df[i], b.dg[i], b.w[i], sig[0, i], sig[1, i], u_c[i], table, theta[i]
    )
    for col in res.columns:
        out[col][i] = res[col].to_numpy()
    return out


def plateau_start(hinge: dict, line: dict) -> tuple:
    """``found``, ``u_c`` and the residual sums (2, S) that start and weight the plateau loop:
    the hinge's where it was found, else the straight line's."""
    found = np.asarray(hinge["found"], bool)
    rss = np.where(
        found,
        np.stack([hinge["rss_df"], hinge["rss_dgamma"]]),
        np.stack([line["rss_df"], line["rss_dgamma"]]),
    )
    return found, hinge["u_c_m"], rss


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The plateau loop fitted to the sweeps of the block ``b`` chosen in ``inputs.plateau``."""
    found, u_c, rss = plateau_start(done["hinge"], done["line"])
    theta = done["cm"]["theta_per_m"]
    return fit_plateaus(b, found, u_c, rss, theta, inputs.tables.cm, inputs.plateau)


FIT = SweepFit(
    "plateau-loop",
    "pl",
    True,
    fit,
    {
        **LOOP_TABLE,
        "d_c_m": "critical_displacement",
        "d_c_err_m": "critical_displacement_err",
        "cov_df0_d_c": "cov_df0_critical_displacement",
        "cov_lntheta_d_c": "cov_ln_inverse_slip_scale_critical_displacement",
    },
)
