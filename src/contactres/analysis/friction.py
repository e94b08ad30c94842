"""Friction coefficients of the slipping sweeps, from the slopes and from the exact loops.

From the slopes (Cattaneo-Mindlin sweeps only; paper 2, Eq. 12 with the coefficients of the
small-amplitude expansion Eq. 11): μ = -κ²/(6F_N dK′/du0) from the Δf slope and
μ = 2κ²/(9πF_N dK″/du0) from the ΔΓ slope. A plateau sweep gets none: above the critical
displacement d_c the shifts rise as (u0 - d_c)² in ΔΓ and (u0 - d_c)^(5/2) in Δf, with no linear
term for Eq. 12 to use (flag ``plateau-slope``).

From the fit of an exact loop with a dashpot (no linearisation, so it stays unbiased where u0
nears the full-sliding displacement 3μF_N/(2κ)): μ = κ/(θF_N) with θ = κ/(μF_N) and κ = A/P from
the same fit — the Cattaneo-Mindlin loop for a ``cattaneo-mindlin`` sweep, the loop behind a
stick plateau for a ``plateau`` sweep.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..resonators.qcm import mu_from_slopes

__all__ = ["LoopFriction", "SlopeFriction", "loop_friction", "slip_sweeps", "slope_friction"]


def slip_sweeps(sw: pd.DataFrame) -> np.ndarray:
    """True for sweeps that slip (Cattaneo-Mindlin or plateau) with a positive Δf0."""
    slip = sw["model"].isin(["cattaneo-mindlin", "plateau"]).to_numpy()
    return slip & (sw["df0_Hz"].to_numpy() > 0)


@dataclass(frozen=True)
class SlopeFriction:
    """μ from the slopes and its standard error, one value per sweep (NaN where none)."""

    mu_df: np.ndarray
    mu_df_err: np.ndarray
    mu_dgamma: np.ndarray
    mu_dgamma_err: np.ndarray


def slope_friction(sw: pd.DataFrame, P: np.ndarray) -> SlopeFriction:
    """μ from the Δf and ΔΓ slopes with propagated errors (NaN where not a CM sweep).

    ``sw``: the per-sweep fits (:func:`contactres.analysis.classify.fit_sweeps` with the sweep
    labels); ``P``: the sensitivity of each sweep, Hz per N/m (paper 2, Eq. 1).
    """
    df0 = sw["df0_Hz"].to_numpy()
    cm = slip_sweeps(sw) & (sw["model"].to_numpy() == "cattaneo-mindlin")
    mu = {"df": np.full(len(sw), np.nan), "dgamma": np.full(len(sw), np.nan)}
    mu["df"][cm], mu["dgamma"][cm] = mu_from_slopes(
        P[cm],
        df0[cm] / P[cm],
        sw["normal_force_N"].to_numpy()[cm],
        sw["df_slope_Hz_per_m"].to_numpy()[cm],
        sw["dgamma_slope_Hz_per_m"].to_numpy()[cm],
    )
    out = {}
    for name in ("df", "dgamma"):
        s = sw[f"{name}_slope_Hz_per_m"].to_numpy()
        s_err = sw[f"{name}_slope_err_Hz_per_m"].to_numpy()
        # μ ∝ Δf0²/slope: relative error from both, with their covariance for the Δf slope.
        with np.errstate(divide="ignore", invalid="ignore"):
            rel_f0 = sw["df0_err_Hz"].to_numpy() / df0
            rel_s = s_err / np.abs(s)
            cov = sw["df0_slope_cov"].to_numpy() / (df0 * s) if name == "df" else 0.0
            rel = np.sqrt(np.maximum(4 * rel_f0**2 + rel_s**2 - 4 * cov, 0.0))
        out[f"mu_{name}"] = mu[name]
        out[f"mu_{name}_err"] = np.abs(mu[name]) * rel
    return SlopeFriction(**out)


@dataclass(frozen=True)
class LoopFriction:
    """μ from the exact loop, its standard error, κu0/(μF_N) at the largest amplitude, and
    whether the fit ends in gross sliding; one value per sweep."""

    mu_fit: np.ndarray
    mu_fit_err: np.ndarray
    x_max: np.ndarray
    gross_sliding: np.ndarray


def loop_friction(sw: pd.DataFrame, P: np.ndarray) -> LoopFriction:
    """μ from the exact-loop fits that :func:`~contactres.analysis.classify.fit_sweeps` made.

    The Cattaneo-Mindlin loop from u0 = 0 (``cm_*`` columns) for a Cattaneo-Mindlin sweep, the
    plateau loop (``pl_*``) for a plateau sweep; NaN where not a slip sweep or not resolved.
    ``gross_sliding`` marks fits that end beyond the loop table (κu0/(μF_N) > 30).
    """
    S = len(sw)
    out = LoopFriction(
        mu_fit=np.full(S, np.nan),
        mu_fit_err=np.full(S, np.nan),
        x_max=np.full(S, np.nan),
        gross_sliding=np.zeros(S, bool),
    )
    idx = np.flatnonzero(slip_sweeps(sw))
    if idx.size == 0:
        return out
    names = [
        "df0_Hz",
        "df0_err_Hz",
        "theta_per_m",
        "lntheta_err",
        "cov_df0_lntheta",
        "x_max",
        "edge",
    ]
    plateau = (sw["model"].to_numpy() == "plateau")[idx]
    res = pd.DataFrame(
        {
            c: np.where(plateau, sw[f"pl_{c}"].to_numpy()[idx], sw[f"cm_{c}"].to_numpy()[idx])
            for c in names
        }
    )
    F = sw["normal_force_N"].to_numpy()[idx]
    A = res["df0_Hz"].to_numpy(float)
    theta = res["theta_per_m"].to_numpy(float)
    mu = A / (P[idx] * theta * F)
    var_ln = (res["df0_err_Hz"] / A) ** 2 + res["lntheta_err"] ** 2 - 2 * res["cov_df0_lntheta"] / A
    err = mu * np.sqrt(np.maximum(var_ln.to_numpy(float), 0.0))
    resolved = (res["edge"] == "").to_numpy() & (A > 0)
    out.mu_fit[idx] = np.where(resolved, mu, np.nan)
    out.mu_fit_err[idx] = np.where(resolved, err, np.nan)
    out.x_max[idx] = res["x_max"].to_numpy(float)
    out.gross_sliding[idx] = (res["edge"] == "high").to_numpy()
    return out
