"""The load dependence: κ(F_N) fitted with JKR + Mindlin, per configuration and medium.

κ(F_N) of every experiment and load is fitted with JKR (paper 2, Eq. 9) + Mindlin (κ = 2G*a,
Eqs. 7, 8, 10) with E1 = E2 = E and ν fixed, E and γ free (the model ``jkr-mindlin`` of
:data:`contactres.analysis.REGISTRY`); standard errors from the Jacobian scaled by the
residual variance, and a bootstrap over experiments (seeded).
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..fitting import FitResult, fit
from ..tangential import kappa_jkr_mindlin
from ._distributions import student_t_quantile
from ._models import REGISTRY

__all__ = [
    "E_RANGE_PA",
    "GAMMA_RANGE_J_M2",
    "HOMOGENEOUS",
    "Check",
    "LoadLaw",
    "bootstrap_jkr",
    "bootstrap_jkr_sweeps",
    "error_dof",
    "fit_correlation",
    "fit_group",
    "fit_jkr_mindlin",
    "fitted_points",
    "left_out_note",
    "t95_factor",
]


# Distinct loads up to which the bootstrap's grid estimator sums the weights per load by a
# product with a 0/1 (points x loads) matrix (BLAS: 4x faster than summing runs of columns
# for 5 loads); beyond, that matrix's size (points x loads) would be the cost.
_FEW_LOADS = 64


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


def _resampled_fits(F, kappa, W, R: float, nu: float, res: FitResult):
    """E and γ of the JKR + Mindlin least-squares fit for every row of weights ``W`` (B, points).

    κ = E^(2/3) h(F_N, γ) (E enters paper 2, Eqs. 7-10 only as this power, since E* and G* are
    proportional to E), so for fixed γ the best E^(2/3) is weighted linear least squares; γ is
    found on a grid (1201 points from 0 to well beyond the fitted value) refined by a parabola.
    The same estimator as :func:`fit_jkr_mindlin`, for all resamples at once.
    """
    g_hat, g_err = res.values["gamma"], np.nan_to_num(res.errors["gamma"])
    top = max(4.0 * g_hat + 8.0 * g_err, 1e-3)
    grid = np.linspace(0.0, top, 1201)
    # h(F, γ) = κ at E = 1 Pa (then κ = E^(2/3) h), elementwise in F: evaluated at the few
    # distinct loads and spread to the points, the same numbers at a fraction of the cost.
    loads, at = np.unique(F, return_inverse=True)
    h_load = kappa_jkr_mindlin(loads[:, None], 1.0, grid[None, :], R, nu)
    at = at.reshape(-1)
    # The weights summed per load first (B x loads), then one product with the loads' h: the
    # same sums as W @ (κ h[at]) and W @ (h²)[at], without spreading the (points x grid)
    # arrays (0.9 s -> 0.03 s at 10^5 sweeps; the sums' rounding differs, ~1e-15 relative).
    if loads.size <= _FEW_LOADS:
        # A few programmed loads: one BLAS product with the 0/1 (points x loads) matrix.
        per_load = np.zeros((F.size, loads.size))
        per_load[np.arange(F.size), at] = 1.0
        skh = (W @ (kappa[:, None] * per_load)) @ h_load
        shh = (W @ per_load) @ (h_load * h_load)
    else:
        # Measured forces make every point a load of its own (loads are exact forces): that
        # matrix would grow as points² (review R27c: 20 GB at 5 10^4 points, 5x the CPU of h
        # at every point at 10^4), so each load's run of columns is summed instead.
        by_load = np.argsort(at, kind="stable")
        runs = np.searchsorted(at[by_load], np.arange(loads.size))  # every load has a point
        Wl = W[:, by_load]  # one copy of W, then weighted by κ in place
        shh = np.add.reduceat(Wl, runs, axis=1) @ (h_load * h_load)
        Wl *= kappa[by_load]
        skh = np.add.reduceat(Wl, runs, axis=1) @ h_load
    skk = W @ (kappa * kappa)
    rss = skk[:, None] - skh**2 / shh
    j = np.clip(np.argmin(rss, axis=1), 1, len(grid) - 2)
    rows = np.arange(W.shape[0])
    r0, r1, r2 = rss[rows, j - 1], rss[rows, j], rss[rows, j + 1]
    denom = r0 - 2 * r1 + r2
    shift = np.where(denom > 0, 0.5 * (r0 - r2) / np.where(denom > 0, denom, 1.0), 0.0)
    step = grid[1] - grid[0]
    gam = np.clip(grid[j] + np.clip(shift, -1, 1) * step, 0.0, top)
    C = skh[rows, j] / shh[rows, j]
    return C**1.5, gam


def bootstrap_jkr(
    pts: pd.DataFrame,
    R: float,
    nu: float,
    res: FitResult,
    n_resamples: int,
    seed: int,
    resampled: Callable | None = None,
):
    """Standard deviations of E and γ over ``n_resamples`` resamples of the experiments, and
    the correlation coefficient of E and γ over them: (sd E (Pa), sd γ (J/m²), corr).

    ``pts``: one row per (experiment, load) with ``normal_force_N``, ``kappa_N_per_m`` and
    ``experiment``; the experiments are drawn with replacement (each keeps all its loads), and
    each resample is fitted as :func:`fit_jkr_mindlin` fits the data (or by ``resampled``,
    the estimator of another :class:`LoadLaw`).
    """
    F = pts["normal_force_N"].to_numpy(float)
    kappa = pts["kappa_N_per_m"].to_numpy(float)
    # Experiments numbered by name: the resamples do not depend on the order of the rows.
    codes, names = pd.factorize(pts["experiment"], sort=True)
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, len(names), size=(n_resamples, len(names)))
    # How often each resample drew each experiment: one bincount over all resamples (row b's
    # draws shifted by b x experiments), not a (resamples, experiments, experiments) compare.
    offset = (np.arange(n_resamples) * len(names))[:, None]
    counts = np.bincount((offset + pick).ravel(), minlength=pick.size).reshape(pick.shape)
    E, gam = (resampled or _resampled_fits)(F, kappa, counts[:, codes].astype(float), R, nu, res)
    return _spread(E, gam)


def bootstrap_jkr_sweeps(
    sweeps: pd.DataFrame,
    R: float,
    nu: float,
    res: FitResult,
    n_resamples: int,
    seed: int,
    resampled: Callable | None = None,
):
    """Standard deviations of E and γ over resamples of the repeated sweeps of each load, and
    their correlation coefficient over them: (sd E (Pa), sd γ (J/m²), corr).

    For one experiment: ``sweeps`` has one row per used sweep (``normal_force_N``,
    ``kappa_N_per_m``); within every load the sweeps are drawn with replacement, each load keeps
    its number of sweeps and the weight 1 of its mean (the estimator of :func:`fit_jkr_mindlin`
    on per-load means; or ``resampled``, as in :func:`bootstrap_jkr`). This is the spread of
    repeated sweeps, not of remounted samples.
    """
    F = sweeps["normal_force_N"].to_numpy(float)
    kappa = sweeps["kappa_N_per_m"].to_numpy(float)
    # Loads by force and sweeps by name: the resamples do not depend on the order of the rows.
    load, _ = pd.factorize(sweeps["normal_force_N"], sort=True)
    name = (
        pd.factorize(sweeps["sweep"].astype(str), sort=True)[0]
        if "sweep" in sweeps
        else np.arange(F.size)
    )
    rng = np.random.default_rng(seed)
    W = np.zeros(n_resamples * F.size)
    offset = (np.arange(n_resamples) * F.size)[:, None]
    for ell in range(load.max() + 1):  # a handful of loads
        members = np.flatnonzero(load == ell)
        members = members[np.argsort(name[members], kind="stable")]
        pick = members[rng.integers(0, members.size, size=(n_resamples, members.size))]
        W += np.bincount((offset + pick).ravel(), minlength=W.size) / members.size
    weights = W.reshape(n_resamples, F.size)
    E, gam = (resampled or _resampled_fits)(F, kappa, weights, R, nu, res)
    return _spread(E, gam)


def _spread(E: np.ndarray, gam: np.ndarray) -> tuple[float, float, float]:
    """Standard deviations of the replicates E (Pa) and γ (J/m²) and their correlation
    coefficient (NaN where a replicate set does not vary, e.g. γ = 0 in every resample)."""
    sd_E, sd_g = float(np.std(E, ddof=1)), float(np.std(gam, ddof=1))
    if not (sd_E > 0 and sd_g > 0):
        return sd_E, sd_g, float("nan")
    return sd_E, sd_g, float(np.corrcoef(E, gam)[0, 1])


@dataclass(frozen=True)
class LoadLaw:
    """The model of κ(F_N) that :func:`fit_group` fits, with its two estimators.

    Attributes
    ----------
    model : the :class:`~contactres.fitting.Model` (its bounds are the checks' bounds)
    fit : (F, κ, R, ν) -> :class:`~contactres.fitting.FitResult`, E and γ free
    resampled : (F, κ, W, R, ν, fit) -> (E, γ) arrays, the same estimator for every row of
        weights W (bootstrap resamples)
    """

    model: object
    fit: Callable[..., FitResult]
    resampled: Callable


#: Paper 2's law: JKR + Mindlin with E1 = E2 = E (homogeneous sphere and plate).
HOMOGENEOUS = LoadLaw(REGISTRY["jkr-mindlin"], fit_jkr_mindlin, _resampled_fits)


class Check(enum.Enum):
    """Why a group's E and γ are not given as results (each explained in the README)."""

    TOO_FEW_LOADS = "too-few-loads"
    AT_BOUND = "fit-at-bound"
    E_RANGE = "E-out-of-range"
    GAMMA_RANGE = "gamma-out-of-range"


#: Physically plausible ranges of the fitted quantities (outside: a unit slip or a wrong model).
E_RANGE_PA = (0.1e9, 1500e9)  # soft polymers ... diamond
GAMMA_RANGE_J_M2 = (0.0, 10.0)  # adhesion energies of solids are below ~1 J/m²


def _checks(res: FitResult, model=None) -> list[tuple[Check, str]]:
    """The plausibility checks of a JKR + Mindlin fit, with a hint on the input to check."""
    model = model or REGISTRY["jkr-mindlin"]
    bounds = {p.key: p.bounds for p in model.parameters}
    E, gamma = res.values["E"], res.values["gamma"]
    found = []
    lo, hi = bounds["E"]
    if not lo * (1 + 1e-6) < E < hi * (1 - 1e-6) or gamma >= bounds["gamma"][1] * (1 - 1e-6):
        found.append(
            (Check.AT_BOUND, f"the fit ended at a bound (E = {E:.3g} Pa, γ = {gamma:.3g} J/m²)")
        )
    if not E_RANGE_PA[0] <= E <= E_RANGE_PA[1]:
        hint = (
            "check area_m2 (m², e.g. 2.5e-5, not mm²) and n_contacts"
            if E > E_RANGE_PA[1]
            else "check normal_force_N (N per contact, not mN) and sphere_radius_m (m)"
        )
        found.append(
            (
                Check.E_RANGE,
                f"E = {E / 1e9:.3g} GPa is outside {E_RANGE_PA[0] / 1e9:g}-{E_RANGE_PA[1] / 1e9:g}"
                f" GPa: {hint}",
            )
        )
    if not GAMMA_RANGE_J_M2[0] <= gamma <= GAMMA_RANGE_J_M2[1]:
        found.append(
            (
                Check.GAMMA_RANGE,
                f"γ = {gamma:.3g} J/m² is outside {GAMMA_RANGE_J_M2[0]:g}-{GAMMA_RANGE_J_M2[1]:g}"
                " J/m²: check normal_force_N (N per contact) and sphere_radius_m (m)",
            )
        )
    return found


def fit_correlation(res: FitResult) -> float:
    """The correlation coefficient of E and γ in the fit's covariance (``inv(JᵀJ)·RSS/(N -
    p)``, :func:`contactres.fitting.fit`): with the standard errors ``E_fit_err_Pa`` and
    ``gamma_fit_err_J_m2`` it gives the whole covariance, which the band of the fitted curve
    needs (:func:`contactres.analysis._curves.jkr_curves`). NaN where the covariance is not
    finite or a variance is not positive (the fit does not identify E and γ)."""
    i, j = res.free.index("E"), res.free.index("gamma")
    cov = np.asarray(res.covariance, dtype=float)
    if cov.shape != (len(res.free),) * 2 or not np.isfinite(cov[np.ix_((i, j), (i, j))]).all():
        return float("nan")
    if not (cov[i, i] > 0 and cov[j, j] > 0):
        return float("nan")
    return float(cov[i, j] / np.sqrt(cov[i, i] * cov[j, j]))


def _joined(*texts: str) -> str:
    return "; ".join(t for t in texts if t)


def _at_loads(n: int, what: str, force: np.ndarray, why: str) -> str:
    loads = ", ".join(f"{v:.4g}" for v in np.unique(force)[:5])
    return f"{n} point(s) with {what} left out of the JKR fit, at normal force(s) {loads} N: {why}"


def fitted_points(kappa: np.ndarray) -> np.ndarray:
    """Which points the JKR fit takes, by their κ (N/m): finite and > 0 (a κ <= 0 is a shift of
    the wrong sign, a NaN no κ: :func:`left_out_note` says which were left out and why)."""
    return np.isfinite(kappa) & (kappa > 0)


def left_out_note(force: np.ndarray, kappa: np.ndarray) -> str:
    """What a group's note says of the points (one per experiment and load) that the JKR fit
    leaves out, one clause per cause, each naming the input to check ("" if none is left out).

    ``force`` (N) and ``kappa`` (N/m) are the points' arrays. A κ <= 0 (Δf0 <= 0) is no contact
    stiffness but a shift of the wrong sign (the sweeps below 0 beyond the noise carry the
    ``negative-stiffness`` flag). A κ that is not a number comes from a Δf0 that the used sweeps'
    class does not give: each of them has fewer distinct amplitudes than the class has
    parameters to identify (:func:`contactres.analysis._bad_rows.identified`; the exact loops
    refuse such a sweep by their own count), which the sign of df_Hz has nothing to do with.
    """
    negative = kappa <= 0
    missing = ~fitted_points(kappa) & ~negative
    causes = (
        (
            negative,
            "κ <= 0 (Δf0 <= 0)",
            "check the sign of df_Hz, as a contact raises the frequency (the sweeps whose Δf0 is "
            "below 0 by more than twice its error are flagged negative-stiffness)",
        ),
        (
            missing,
            "no κ (Δf0 not given)",
            "each used sweep of the load has fewer distinct amplitudes (amplitude_m) than its "
            "class (column model) has parameters to identify: check the sweeps' amplitudes",
        ),
    )
    return _joined(
        *(_at_loads(int(m.sum()), what, force[m], why) for m, what, why in causes if m.any())
    )


def fit_group(
    exp: pd.DataFrame,
    key,
    bootstrap: int,
    seed: int,
    sweeps: pd.DataFrame | None = None,
    law: LoadLaw = HOMOGENEOUS,
) -> dict:
    """The JKR + Mindlin fit of one (configuration, medium) from its per-experiment points.

    ``exp``: one row per (experiment, load) of the group (the means of its used sweeps);
    ``sweeps``: the group's used sweeps (for the error of a single experiment); ``law``: the
    model of κ(F_N) and its estimators (default paper 2's, :data:`HOMOGENEOUS`).

    The error of E and γ (``E_err_Pa``, ``gamma_err_J_m2``) respects the experiment structure;
    ``error_method`` says which one was used: the standard deviation over ``bootstrap``
    resamples of the experiments (3 or more experiments); half the difference of the fits of the
    two experiments (2); over resamples of the repeated sweeps of each load (1 experiment:
    within-experiment errors, labelled so); the Jacobian of the fit (``E_fit_err_Pa``, always
    given) only when none of these is possible. ``E_gamma_corr`` is the correlation of E and γ
    that goes with these errors: over the resamples where a bootstrap gives them, else the
    fit's (``E_gamma_fit_corr``); with them it is the covariance that the band of the fitted
    curve propagates (:func:`contactres.analysis._curves.jkr_curves`). E and γ are withheld
    (NaN, ``checks`` and ``note`` say why) when the fit is not plausible (:class:`Check`).
    """
    config, medium = key
    radii = exp["sphere_radius_m"].unique()
    nus = exp["poisson"].unique()
    for name, vals, unit in (("sphere_radius_m", radii, "m"), ("poisson", nus, "")):
        if len(vals) > 1:
            raise ContactresInputError(
                f"configuration {config!r}, medium {medium!r}: several values of {name} "
                f"({sorted(vals.tolist())} {unit}); one configuration has one geometry"
            )
    R, nu = float(radii[0]), float(nus[0])
    kappa = exp["kappa_N_per_m"].to_numpy(float)
    ok = fitted_points(kappa)
    pts = exp[ok]
    left_out = left_out_note(exp["normal_force_N"].to_numpy(float), kappa)
    out = {
        "configuration": config,
        "medium": medium,
        "E_Pa": np.nan,
        "E_err_Pa": np.nan,
        "gamma_J_m2": np.nan,
        "gamma_err_J_m2": np.nan,
        "error_method": "",
        "E_fit_err_Pa": np.nan,
        "gamma_fit_err_J_m2": np.nan,
        "E_gamma_fit_corr": np.nan,
        "E_gamma_corr": np.nan,
        "E_bootstrap_sd_Pa": np.nan,
        "gamma_bootstrap_sd_J_m2": np.nan,
        "sphere_radius_m": R,
        "poisson": nu,
        "n_points_fitted": len(pts),
        "fit_rms_N_per_m": np.nan,
        "checks": [],
        "err_dof": np.nan,
        "t95": np.nan,
        "note": left_out,
    }
    n_loads = pts["normal_force_N"].nunique()
    if n_loads < 2 or len(pts) < 3:
        out["checks"] = [Check.TOO_FEW_LOADS.value]
        out["note"] = _joined(
            f"JKR fit needs at least 3 points at 2 or more loads; found {len(pts)} point(s) at "
            f"{n_loads} load(s)",
            left_out,
        )
        return out
    res = law.fit(pts["normal_force_N"], pts["kappa_N_per_m"], R, nu)
    found = _checks(res, law.model)
    out["fit_rms_N_per_m"] = float(np.sqrt(res.rss / res.n_points))
    if found:
        out["checks"] = [c.value for c, _ in found]
        out["note"] = _joined(*(text for _, text in found), left_out)
        out["rejected_fit"] = {"E_Pa": res.values["E"], "gamma_J_m2": res.values["gamma"]}
        return out
    out.update(
        E_Pa=res.values["E"],
        gamma_J_m2=res.values["gamma"],
        E_fit_err_Pa=res.errors["E"],
        gamma_fit_err_J_m2=res.errors["gamma"],
        E_gamma_fit_corr=fit_correlation(res),
        # The correlation that goes with Table 1's errors: the fit's, unless a bootstrap
        # gives those errors (then its resamples' own, set below).
        E_gamma_corr=fit_correlation(res),
    )
    n_exp = pts["experiment"].nunique()
    if bootstrap > 0 and n_exp >= 3:
        E_sd, g_sd, rho = bootstrap_jkr(pts, R, nu, res, int(bootstrap), seed, law.resampled)
        out.update(E_bootstrap_sd_Pa=E_sd, gamma_bootstrap_sd_J_m2=g_sd, E_gamma_corr=rho)
        # The bootstrap variance of a mean of n is (n - 1)/n of the unbiased one: with a few
        # experiments that bias matters (n = 4: 13 % in the error), so it is undone.
        small = np.sqrt(n_exp / (n_exp - 1))
        out.update(E_err_Pa=E_sd * small, gamma_err_J_m2=g_sd * small)
        out["error_method"] = (
            f"bootstrap over the {n_exp} experiments ({int(bootstrap)} resamples, sd x "
            f"√(n/(n-1)) = {small:.3f})"
        )
    elif n_exp == 2:
        fits = [
            law.fit(part["normal_force_N"], part["kappa_N_per_m"], R, nu)
            for _, part in pts.groupby("experiment", sort=True)
            if part["normal_force_N"].nunique() >= 2
        ]
        if len(fits) == 2:
            out["E_err_Pa"] = abs(fits[0].values["E"] - fits[1].values["E"]) / 2
            out["gamma_err_J_m2"] = abs(fits[0].values["gamma"] - fits[1].values["gamma"]) / 2
            out["error_method"] = "half the difference of the fits of the 2 experiments"
    elif (
        n_exp == 1
        and bootstrap > 0
        and sweeps is not None
        and sweeps.groupby("normal_force_N").size().min() >= 2
    ):
        E_sd, g_sd, rho = bootstrap_jkr_sweeps(
            sweeps, R, nu, res, int(bootstrap), seed, law.resampled
        )
        out.update(E_err_Pa=E_sd, gamma_err_J_m2=g_sd, E_gamma_corr=rho)
        out["error_method"] = (
            f"within one experiment: bootstrap over its repeated sweeps ({int(bootstrap)} "
            "resamples; remounting the sample is not included)"
        )
    if not out["error_method"]:
        out.update(E_err_Pa=res.errors["E"], gamma_err_J_m2=res.errors["gamma"])
        # Say why the repeats were not resampled: the user switched the bootstrap off, or
        # there are none to resample.
        why = "bootstrap off (--bootstrap 0)" if bootstrap <= 0 else "no repeats to resample"
        out["error_method"] = f"fit residuals (Jacobian), {why}"
        dof = len(pts) - 2
    elif n_exp >= 2:
        dof = n_exp - 1
    else:  # repeated sweeps of one experiment: sweeps minus the per-load means
        assert sweeps is not None  # only the bootstrap over them leaves this case
        dof = len(sweeps) - sweeps["normal_force_N"].nunique()
    out.update(error_dof(dof))
    return out


def error_dof(dof: float) -> dict:
    """``err_dof`` and ``t95``: the degrees of freedom behind an error estimated from a few
    repeats, and the Student-t factor of its two-sided 95 % interval (value ± t95 x error).

    An error from n experiments has n - 1 degrees of freedom; with 4 experiments the 95 %
    interval is ±3.18 errors, not ±1.96, and a deviation of 3 errors happens in 5.8 % of cases
    (Student, Biometrika 6, 1 (1908)). NaN below one degree of freedom.
    """
    dof = float(dof)
    if not dof >= 1:
        return {"err_dof": np.nan, "t95": np.nan}
    return {"err_dof": int(dof), "t95": float(t95_factor(dof))}


def t95_factor(dof):
    """The Student-t factor of a two-sided 95 % interval for ``dof`` degrees of freedom (array
    or scalar; NaN below 1): t(0.975; 1) = 12.706, t(0.975; 3) = 3.182, → 1.960."""
    dof = np.asarray(dof, dtype=float)
    # The inverse of Student's t distribution function (what scipy.stats.t.ppf evaluates),
    # in numpy alone: a first analysis does not pay the import of scipy.special. The Newton
    # iteration costs ~0.1 ms a value, and a table's loads share a handful of degrees of
    # freedom, so each distinct one is solved once (the same numbers: the solve is elementwise).
    dof = np.where(dof >= 1, dof, np.nan)
    distinct, where = np.unique(dof, return_inverse=True)
    return student_t_quantile(0.975, distinct)[where].reshape(dof.shape)
