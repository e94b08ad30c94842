"""The load dependence: κ(F_N) fitted with JKR + Mindlin, per configuration and medium.

κ(F_N) of every experiment and load is fitted with JKR (paper 2, Eq. 9) + Mindlin (κ = 2G*a,
Eqs. 7, 8, 10) with E1 = E2 = E and ν fixed, E and γ free (the model ``jkr-mindlin`` of
:data:`contactres.analysis.models.REGISTRY`); standard errors from the Jacobian scaled by the
residual variance, and a bootstrap over experiments (seeded).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..fitting import FitResult, fit
from ..tangential import kappa_jkr_mindlin
from .models import REGISTRY

__all__ = ["bootstrap_jkr", "fit_group", "fit_jkr_mindlin"]


def fit_jkr_mindlin(force, kappa, radius: float, poisson: float, start=None) -> FitResult:
    """Fit κ(F_N) with JKR + Mindlin (E and γ free); returns a :class:`.FitResult`.

    ``force`` N per contact, ``kappa`` N/m (one point per experiment and load), ``radius`` m.
    The start of E comes from the Hertz limit (κ ∝ E^(2/3) at γ = 0) in closed form.
    """
    F = np.asarray(force, dtype=float)
    k = np.asarray(kappa, dtype=float)
    if start is None:
        k_unit = kappa_jkr_mindlin(F, 1e9, 0.0, radius, poisson)  # κ at E = 1 GPa, γ = 0
        ratio = np.exp(np.mean(np.log(np.maximum(k, 1e-300) / k_unit)))
        start = {"E": 1e9 * ratio**1.5 * 0.8, "gamma": 0.05}
    return fit(
        REGISTRY["jkr-mindlin"],
        F,
        k,
        start=start,
        fixed={"radius": float(radius), "poisson": float(poisson)},
    )


def bootstrap_jkr(
    pts: pd.DataFrame, R: float, nu: float, res: FitResult, n_resamples: int, seed: int
):
    """Standard deviations of E and γ over ``n_resamples`` resamples of the experiments.

    Resampled with replacement.

    The same least-squares estimator as :func:`fit_jkr_mindlin`, solved for all resamples at
    once: κ = E^(2/3) h(F_N, γ) (E enters Eqs. 7-10 only as this power, since E* and G* are
    proportional to E), so for fixed γ the best E^(2/3) is linear least squares; γ is found on
    a grid (1201 points from 0 to well beyond the fitted value) refined by a parabola.
    """
    F = pts["normal_force_N"].to_numpy(float)
    kappa = pts["kappa_N_per_m"].to_numpy(float)
    codes, names = pd.factorize(pts["experiment"])
    g_hat, g_err = res.values["gamma"], np.nan_to_num(res.errors["gamma"])
    top = max(4.0 * g_hat + 8.0 * g_err, 1e-3)
    grid = np.linspace(0.0, top, 1201)
    # h(F, γ) = κ at E = 1 Pa (then κ = E^(2/3) h)
    h = kappa_jkr_mindlin(F[:, None], 1.0, grid[None, :], R, nu)
    rng = np.random.default_rng(seed)
    B = n_resamples
    pick = rng.integers(0, len(names), size=(B, len(names)))
    counts = (pick[:, :, None] == np.arange(len(names))[None, None, :]).sum(axis=1)
    W = counts[:, codes].astype(float)  # (B, points)
    skh = W @ (kappa[:, None] * h)
    shh = W @ (h * h)
    skk = W @ (kappa * kappa)
    rss = skk[:, None] - skh**2 / shh
    j = np.clip(np.argmin(rss, axis=1), 1, len(grid) - 2)
    rows = np.arange(B)
    r0, r1, r2 = rss[rows, j - 1], rss[rows, j], rss[rows, j + 1]
    denom = r0 - 2 * r1 + r2
    shift = np.where(denom > 0, 0.5 * (r0 - r2) / np.where(denom > 0, denom, 1.0), 0.0)
    step = grid[1] - grid[0]
    gam = np.clip(grid[j] + np.clip(shift, -1, 1) * step, 0.0, top)
    C = skh[rows, j] / shh[rows, j]
    E = C**1.5
    return float(np.std(E, ddof=1)), float(np.std(gam, ddof=1))


def fit_group(exp: pd.DataFrame, key, bootstrap: int, seed: int) -> dict:
    """The JKR + Mindlin fit of one (configuration, medium) from its per-experiment points.

    Returns the group's record (the keys of
    :data:`contactres.measurements.schema.GROUP_RESULTS` that the fit gives).
    """
    config, medium = key
    radii = exp["sphere_radius_m"].unique()
    nus = exp["poisson"].unique()
    for name, vals, unit in (("sphere_radius_m", radii, "m"), ("poisson", nus, "")):
        if len(vals) > 1:
            raise ValueError(
                f"configuration {config!r}, medium {medium!r}: several values of {name} "
                f"({sorted(vals.tolist())} {unit}); one configuration has one geometry"
            )
    R, nu = float(radii[0]), float(nus[0])
    ok = np.isfinite(exp["kappa_N_per_m"].to_numpy()) & (exp["kappa_N_per_m"].to_numpy() > 0)
    pts = exp[ok]
    out = {
        "configuration": config,
        "medium": medium,
        "E_Pa": np.nan,
        "E_err_Pa": np.nan,
        "gamma_J_m2": np.nan,
        "gamma_err_J_m2": np.nan,
        "E_bootstrap_sd_Pa": np.nan,
        "gamma_bootstrap_sd_J_m2": np.nan,
        "sphere_radius_m": R,
        "poisson": nu,
        "n_points_fitted": len(pts),
        "fit_rms_N_per_m": np.nan,
    }
    if pts["normal_force_N"].nunique() < 2 or len(pts) < 3:
        out["note"] = "JKR fit needs at least 3 points at 2 or more loads"
        return out
    res = fit_jkr_mindlin(pts["normal_force_N"], pts["kappa_N_per_m"], R, nu)
    out.update(
        E_Pa=res.values["E"],
        E_err_Pa=res.errors["E"],
        gamma_J_m2=res.values["gamma"],
        gamma_err_J_m2=res.errors["gamma"],
        fit_rms_N_per_m=float(np.sqrt(res.rss / res.n_points)),
    )
    if bootstrap > 0 and pts["experiment"].nunique() >= 3:
        E_sd, g_sd = bootstrap_jkr(pts, R, nu, res, int(bootstrap), seed)
        out["E_bootstrap_sd_Pa"] = E_sd
        out["gamma_bootstrap_sd_J_m2"] = g_sd
    return out
