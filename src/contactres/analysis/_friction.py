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

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..resonators import mu_from_slopes
from ..units import MAX_MU

__all__ = [
    "COULOMB_LOOPS",
    "LOOP_OF_CLASS",
    "MU_PRIOR_MAX_REL",
    "LoopFriction",
    "SlopeFriction",
    "block_friction",
    "loop_fit_force",
    "loop_force",
    "loop_friction",
    "loop_table_force",
    "model_averaged_mu",
    "mu_out_of_range",
    "slip_sweeps",
    "slope_friction",
]


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

    ``sw``: the per-sweep fits (:func:`contactres.analysis._classify.fit_sweeps` with the sweep
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
    """μ from the exact loop, its standard error, the loop's x at the largest amplitude
    (κu0/(μF_N), or u0/d_s for Savkoor), whether the fit ends in gross sliding, and Savkoor's
    sliding force πa²τ0 with its error; one value per sweep."""

    mu_fit: np.ndarray
    mu_fit_err: np.ndarray
    x_max: np.ndarray
    gross_sliding: np.ndarray
    sliding_force: np.ndarray
    sliding_force_err: np.ndarray


def loop_force(A, A_err, theta, lntheta_err, cov, P):
    """The force scale A/(Pθ) = κ/θ of an exact-loop fit and its standard error, N.

    For the Cattaneo-Mindlin loop (θ = κ/(μF_N)) it is μF_N; for Savkoor's loop (θ = 1/d_s,
    d_s = 4a²τ0/κ) it is 4/π times the sliding force πa²τ0 (paper 2, Eqs. 13-14). The error
    propagates those of Pκ and ln θ with their covariance (all arrays).
    """
    A, A_err, theta = (np.asarray(v, dtype=float) for v in (A, A_err, theta))
    with np.errstate(divide="ignore", invalid="ignore"):
        force = A / (P * theta)
        var_ln = (A_err / A) ** 2 + np.asarray(lntheta_err) ** 2 - 2 * np.asarray(cov) / A
    return force, np.abs(force) * np.sqrt(np.maximum(var_ln, 0.0))


def loop_fit_force(frame: pd.DataFrame, P: np.ndarray):
    """:func:`loop_force` of the loop fit in the named columns ``df0_Hz``, ``df0_err_Hz``,
    ``theta_per_m``, ``lntheta_err``, ``cov_df0_lntheta``, ``edge`` of ``frame`` (the block
    table of :func:`contactres.analysis._blocks.choose_blocks`), and where it is resolved
    (Δf0 > 0 and the fit not at an edge of the loop table)."""
    col = {
        c: frame[c].to_numpy()
        for c in ("df0_Hz", "df0_err_Hz", "theta_per_m", "lntheta_err", "cov_df0_lntheta", "edge")
    }
    force, err = loop_force(
        col["df0_Hz"],
        col["df0_err_Hz"],
        col["theta_per_m"],
        col["lntheta_err"],
        col["cov_df0_lntheta"],
        P,
    )
    return force, err, (col["edge"] == "") & (col["df0_Hz"].astype(float) > 0)


#: The exact loop (key of ``Results.fits``) whose fit gives the friction of each slipping class.
LOOP_OF_CLASS = (
    ("cattaneo-mindlin", "cattaneo-mindlin-loop"),
    ("plateau", "plateau-loop"),
    ("savkoor", "savkoor-loop"),
)


def loop_table_force(table: pd.DataFrame, P: np.ndarray):
    """:func:`loop_force` of the rows of an exact loop's fit table (parameters under their
    keys, :func:`contactres.analysis._models.fit_tables`), and where it is resolved (Δf0 > 0 and
    the fit not at an edge of the loop table)."""
    df0 = table["df0"].to_numpy()
    force, err = loop_force(
        df0,
        table["df0_err"].to_numpy(),
        table["inverse_slip_scale"].to_numpy(),
        table["ln_inverse_slip_scale_err"].to_numpy(),
        table["cov_df0_ln_inverse_slip_scale"].to_numpy(),
        P,
    )
    return force, err, (table["edge"].to_numpy() == "") & (df0.astype(float) > 0)


def loop_friction(
    sw: pd.DataFrame, fits: Mapping[str, pd.DataFrame], P: np.ndarray
) -> LoopFriction:
    """μ and Savkoor's sliding force from the exact-loop fits of each sweep's class.

    The Cattaneo-Mindlin loop from u0 = 0 for a Cattaneo-Mindlin sweep, the plateau loop for a
    plateau sweep, Savkoor's loop for a Savkoor sweep (its sliding force, no μ); NaN elsewhere
    and where not resolved. ``fits``: the fit table of each loop (:data:`LOOP_OF_CLASS`), one
    row per row of ``sw``. ``gross_sliding`` marks fits that end beyond the loop table (x > 30).
    """
    S = len(sw)
    out = LoopFriction(
        np.full(S, np.nan),
        np.full(S, np.nan),
        np.full(S, np.nan),
        np.zeros(S, bool),
        np.full(S, np.nan),
        np.full(S, np.nan),
    )
    model = sw["model"].to_numpy()
    positive = sw["df0_Hz"].to_numpy() > 0
    for name, key in LOOP_OF_CLASS:
        idx = np.flatnonzero((model == name) & positive)
        if idx.size == 0:
            continue
        part = fits[key].iloc[idx]
        force, err, resolved = loop_table_force(part, P[idx])
        edge = part["edge"].to_numpy()
        if name == "savkoor":
            out.sliding_force[idx] = np.where(resolved, np.pi / 4 * force, np.nan)
            out.sliding_force_err[idx] = np.where(resolved, np.pi / 4 * err, np.nan)
        else:
            F = sw["normal_force_N"].to_numpy()[idx]
            out.mu_fit[idx] = np.where(resolved, force / F, np.nan)
            out.mu_fit_err[idx] = np.where(resolved, err / F, np.nan)
        out.x_max[idx] = part["x_max"].to_numpy(float)
        out.gross_sliding[idx] = edge == "high"
    return out


#: Largest relative error of a loop's μ that counts as resolved: beyond it the fit does not
#: resolve μ (a plateau loop whose d_c sits on its bound 0 has a degenerate Jacobian and errors
#: of hundreds of per cent). Such a μ leaves the model average (:func:`model_averaged_mu`), and
#: the μ prior is not weighed against it (the prior would waive the parameter's ln N for nothing
#: the data show, so it leaves such a fit's criterion as it is: a Coulomb loop keeps its BIC,
#: a plateau loop keeps only its d_c prior's term; :mod:`contactres.analysis._mu_prior`).
MU_PRIOR_MAX_REL = 1.0

#: The two Coulomb loops whose joint fits of a block are averaged (keys of the block fits).
COULOMB_LOOPS = ("cattaneo-mindlin-loop", "plateau-loop")


def _joint_mu(table: pd.DataFrame | None, F: np.ndarray, P: np.ndarray):
    """μ, its error and the shared BIC (column ``bic_shared``) of one loop's joint fit of every
    block, from its fit table (NaN, NaN, inf where unresolved or not fitted)."""
    nan = np.full(len(F), np.nan)
    if table is None:
        return nan, nan, np.full(len(F), np.inf)
    force, err, ok = loop_table_force(table, P)
    bic = table["bic_shared"].to_numpy(float)
    mu, mu_err = force / F, err / F
    if "mu_marginal" in table.columns:
        # The plateau loop's μ with d_c integrated over its prior, where the block has one
        # (contactres.analysis._plateau_evidence): the fit's own μ holds d_c at its optimum.
        # Only where the fit itself resolves μ (its "not resolved" verdict, e.g. at the edge of
        # the loop table, stands).
        marginal = table["mu_marginal"].to_numpy(float)
        use = np.isfinite(marginal)
        mu = np.where(use, marginal, mu)
        mu_err = np.where(use, table["mu_marginal_err"].to_numpy(float), mu_err)
    ok &= np.isfinite(mu) & np.isfinite(mu_err) & np.isfinite(bic)
    # A μ whose error exceeds MU_PRIOR_MAX_REL times itself is not resolved by the block's points
    # (the plateau loop's fit at a bound of d_c gave errors of 100x μ): averaged in with even a
    # small weight it made the block's error absurd (μ = 1.05 ± 139 in the demo), so it leaves
    # the average to the loop that resolves μ, and the block has no μ where neither does.
    with np.errstate(invalid="ignore"):
        ok &= mu_err <= MU_PRIOR_MAX_REL * np.abs(mu)
    return np.where(ok, mu, nan), np.where(ok, mu_err, nan), np.where(ok, bic, np.inf)


def mu_out_of_range(mu, err, lognormal):
    """Where μ lies above :data:`contactres.units.MAX_MU` by more than twice its error.

    Normal errors: μ - 2 err > MAX_MU. Where ``lognormal`` (the block's μ includes the plateau
    loop's μ with d_c integrated out, :mod:`contactres.analysis._plateau_evidence`, whose
    error is μ times the posterior standard deviation s of ln μ) the bound is taken in ln μ,
    exp(ln μ - 2 s) = μ exp(-2 err/μ) > MAX_MU: with s ≥ 0.5 the normal bound μ - 2 err ≤ 0
    could never exceed MAX_MU. A missing error counts as 0. All arrays; returns a boolean
    array.
    """
    mu, err = np.asarray(mu, dtype=float), np.nan_to_num(np.asarray(err, dtype=float), nan=0.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        low = np.where(lognormal, mu * np.exp(-2.0 * err / mu), mu - 2.0 * err)
    return (mu > MAX_MU) & (low > MAX_MU)


def model_averaged_mu(
    blocks: pd.DataFrame, joint: Mapping[str, pd.DataFrame], P: np.ndarray
) -> tuple[np.ndarray, ...]:
    """μ of every block averaged over the two Coulomb loops, and its unconditional error.

    Where the Cattaneo-Mindlin loop and the plateau loop both describe a block (the plateau
    nests CM; in noisy water data they often differ by a few units of BIC only), their μ can
    differ by tens of per cent: a plateau read as CM gives μ high, since the late onset of slip
    is taken for a larger friction force. So the block's μ is the average of the two joint fits
    with the BIC weights w_m ∝ exp(-BIC_m/2), and its variance the unconditional one,
    Σ w_m [σ_m² + (μ_m - μ̄)²] (Buckland, Burnham & Augustin, Biometrics 53, 603 (1997), Eq. 3;
    Burnham & Anderson, *Model Selection and Multimodel Inference*, 2nd ed., Springer 2002,
    Sec. 4.3): the spread between the models enters the error rather than being hidden by the
    choice. A decisive choice (ΔBIC ≳ 10) leaves the winner's μ and error unchanged. Where the
    plateau loop's table has ``mu_marginal`` (the blocks whose plateau evidence was integrated
    over d_c, :mod:`contactres.analysis._plateau_evidence`), that μ and ``mu_marginal_err``
    stand for the plateau loop's: its error includes what d_c leaves open, which the fit's error
    at its optimum (often on a bound of d_c) does not.

    ``joint``: the fit table of each loop of :data:`COULOMB_LOOPS` (one row per row of
    ``blocks``, with ``bic_shared``; :func:`contactres.analysis._blocks.choose_blocks`).

    Returns μ̄, its error and the weight of the plateau loop (NaN where neither loop resolves μ).
    """
    F = blocks["normal_force_N"].to_numpy(float)
    fits = [_joint_mu(joint.get(key), F, P) for key in COULOMB_LOOPS]
    mu, err, crit = (np.stack(v) for v in zip(*fits, strict=True))
    best = crit.min(axis=0)
    with np.errstate(invalid="ignore"):
        w = np.exp(-0.5 * (crit - best))
        w = w / w.sum(axis=0)
        mean = np.nansum(w * np.nan_to_num(mu), axis=0)
        var = np.nansum(w * (np.nan_to_num(err) ** 2 + (np.nan_to_num(mu) - mean) ** 2), axis=0)
    none = ~np.isfinite(best)
    return (
        np.where(none, np.nan, mean),
        np.where(none, np.nan, np.sqrt(var)),
        np.where(none, np.nan, w[1]),
    )


def block_friction(
    blocks: pd.DataFrame, joint: Mapping[str, pd.DataFrame], sw: pd.DataFrame
) -> pd.DataFrame:
    """μ (``mu``, ``mu_err``: averaged over the Cattaneo-Mindlin and plateau loops,
    :func:`model_averaged_mu`; ``mu_plateau_weight``) and Savkoor's sliding force
    (``sliding_force_N``, ``sliding_force_err_N``) from the joint fit of every shared block
    (:func:`contactres.analysis._blocks.choose_blocks`: ``blocks`` with the winner's joint fit,
    ``joint`` every model's joint fit); NaN where none. Returns a new frame."""
    blocks = blocks.copy()
    for col in ("mu", "mu_err", "mu_plateau_weight", "sliding_force_N", "sliding_force_err_N"):
        blocks[col] = np.nan
    if blocks.empty:
        return blocks
    member = sw["block"].to_numpy() >= 0
    P = (
        pd.Series(sw["P_Hz_per_N_per_m"].to_numpy()[member], index=sw["block"].to_numpy()[member])
        .groupby(level=0)
        .first()
        .reindex(blocks["block"])
        .to_numpy()
    )
    force, err, resolved = loop_fit_force(blocks, P)
    resolved &= blocks["shared"].to_numpy(bool)
    friction = resolved & blocks["model"].isin(["cattaneo-mindlin", "plateau"]).to_numpy()
    mu, mu_err, w_pl = model_averaged_mu(blocks, joint, P)
    blocks["mu"] = np.where(friction, mu, np.nan)
    blocks["mu_err"] = np.where(friction, mu_err, np.nan)
    blocks["mu_plateau_weight"] = np.where(friction, w_pl, np.nan)
    sv = resolved & (blocks["model"] == "savkoor").to_numpy()
    blocks["sliding_force_N"] = np.where(sv, np.pi / 4 * force, np.nan)
    blocks["sliding_force_err_N"] = np.where(sv, np.pi / 4 * err, np.nan)
    return blocks
