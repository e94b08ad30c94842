"""The analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion.

:func:`analyze` is a pure function of (sweep table, settings) and returns a
:class:`contactres.report.Results`. Its steps:

1. **Per sweep** (:mod:`contactres.analysis_sweep`, all sweeps at once): low-amplitude limits Δf0,
   ΔΓ0, slopes and curvatures with standard errors, the model class (``elastic``,
   ``cattaneo-mindlin``, ``savkoor``, ``plateau``; lowest BIC with a preference for the simpler
   model within ``delta_bic``) and the critical amplitude of a plateau.
2. **Contact stiffness** (paper 2, Eq. 2): κ = Δf0/P, ωξ = ΔΓ0/P, P = n_P/(2nπ²A_eff Z_q), and the
   loss tangent ΔΓ0/Δf0.
3. **Friction** for ``cattaneo-mindlin`` and ``plateau`` sweeps. From the slopes (Cattaneo-Mindlin
   sweeps only): μ from the Δf slope (μ = -κ²/(6F_N dK′/du0)) and from the ΔΓ slope
   (μ = 2κ²/(9πF_N dK″/du0)), physics.md Eq. 11-12. From a fit of an exact loop with a dashpot
   (no linearisation, so it stays unbiased when u0 nears the full-sliding displacement
   3μF_N/(2κ)): the Cattaneo-Mindlin loop for a ``cattaneo-mindlin`` sweep; for a ``plateau``
   sweep the Cattaneo-Mindlin loop behind a stick plateau (:class:`contactres.PlateauLoop`:
   linear up to the critical displacement d_c, then Cattaneo-Mindlin in the excess), with κ,
   μ, ωξ and d_c free and d_c started from the hinge that the classifier found; its Δf0, ΔΓ0 and
   d_c (``plateau_amplitude_m``) are reported too. A plateau sweep gets no slope-based μ
   (NaN, flag ``plateau-slope``): above d_c the shifts rise from the plateau as (u0 - d_c)² in
   ΔΓ and (u0 - d_c)^(5/2) in Δf, with no linear term for Eq. 11-12 to use, and treating the
   part above d_c as a Cattaneo-Mindlin sweep of amplitude u0 - d_c (as this analysis once did)
   biased μ: on noise-free sweeps with d_c = 0.2 (0.4) of the largest amplitude, μ from the Δf
   slope came out 10-20 % (50-70 %) high, from the ΔΓ slope 20-30 % low, and from a
   Cattaneo-Mindlin loop fitted to u0 - d_c ~1.5 % (25-35 %) high. The plateau-loop fit
   recovers μ, κ, ωξ and d_c to rounding (< 1e-12) on such sweeps (tests/test_analysis.py),
   and within its errors on sweeps with light noise. Limitation: where the slip signal above
   d_c is comparable to the noise (e.g. the water sweeps of the bundled example: 0.6 Hz noise,
   u0 <= 5 nm), few plateau sweeps are recognised, those that are owe their hinge partly to the
   noise, and their μ_fit reads low with an error (linearised, from the Jacobian) that is too
   small: in simulations of that recipe it reads 40-65 % low, in some sweeps by 3-7 times its
   error (the air recipe, 0.3 Hz noise and u0 <= 10 nm: unbiased, z standard deviation 1.2).
4. **Flags**: ``first-ramp`` (ramp 1 set aside as running-in unless ``keep_first_ramp``),
   ``few-points`` (< 4 points: not used), ``drift`` (the used ramps of one load of one experiment
   are offset from each other beyond noise: F test of per-ramp offsets on a common quadratic,
   false-alarm probability ``drift_p``),
   ``junction-growth`` (Δf rises with u0 by more than 2 standard errors), ``gross-sliding`` (the
   exact loop fits best beyond x = κu0/(μF_N) = 30; for a plateau, its excess beyond d_c),
   ``small-load`` (|Δf|/f > 1e-3), ``plateau-slope`` (a plateau sweep: no μ from the slopes).
5. **Per load** (configuration, medium, normal force): the used sweeps of each experiment are
   averaged, then mean and standard deviation over experiments (NaN values, e.g. the slope μ of
   plateau sweeps, are skipped; a load without any value gets NaN).
6. **Per configuration and medium** (Table 1): κ(F_N) of every experiment and load fitted with
   JKR (Eq. 9) + Mindlin (κ = 2G*a, Eq. 7, 8, 10) with E1 = E2 = E and ν fixed (column
   ``poisson``), E and γ free; standard errors from the Jacobian scaled by the residual
   variance, and a bootstrap over experiments (``bootstrap`` resamples, seeded).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
from scipy.stats import f as f_dist

from ..fitting import Model, Parameter, fit, register_model
from ..measurements.sweeps import validate_sweeps
from ..resonators.qcm import QCM, SMALL_LOAD_LIMIT, mu_from_slopes
from ..tangential import kappa_jkr_mindlin
from .classify import MODEL_ORDER, X_MAX, fit_sweeps, pad_sweeps

__all__ = ["AnalysisSettings", "analyze", "fit_jkr_mindlin", "kappa_jkr_mindlin"]

#: Slopes more than this many standard errors above zero mean Δf rises: junction growth.
JUNCTION_SIGMAS = 2.0


@dataclass(frozen=True)
class AnalysisSettings:
    """Settings of :func:`analyze` (all recorded in ``summary.json``).

    Attributes
    ----------
    keep_first_ramp : use ramp 1 of every load (default: set aside as running-in)
    delta_bic : BIC margin within which the simpler amplitude model is kept
    drift_p : false-alarm probability of the drift test
    bootstrap : number of bootstrap resamples over experiments for E and γ (0: none)
    seed : seed of the bootstrap
    exact_loop : fit the exact Cattaneo-Mindlin loop (μ_fit), behind a stick plateau for
        ``plateau`` sweeps
    zq : shear-wave impedance of the quartz, kg m⁻² s⁻¹
    """

    keep_first_ramp: bool = False
    delta_bic: float = 2.0
    drift_p: float = 1e-3
    bootstrap: int = 200
    seed: int = 0
    exact_loop: bool = True
    zq: float = 8.8e6

    def __post_init__(self):
        if not self.delta_bic >= 0:
            raise ValueError(f"delta_bic must be >= 0, got {self.delta_bic!r}")
        if not 0 < self.drift_p < 1:
            raise ValueError(f"drift_p must lie in (0, 1), got {self.drift_p!r}")
        if int(self.bootstrap) != self.bootstrap or self.bootstrap < 0:
            raise ValueError(f"bootstrap must be a whole number >= 0, got {self.bootstrap!r}")
        if not self.zq > 0:
            raise ValueError(f"zq must be > 0, got {self.zq!r}")


# --------------------------------------------------------------------------------------------
# The JKR + Mindlin model of κ(F_N)


JKR_MINDLIN = register_model(
    Model(
        key="jkr-mindlin",
        display="JKR + Mindlin tangential stiffness",
        parameters=(
            Parameter("E", "Young's modulus E", "Pa", (1e6, 1e13), scale=1e10),
            Parameter("gamma", "energy of adhesion γ", "J/m^2", (0.0, 1e3), scale=0.1),
            Parameter("radius", "sphere radius R", "m", (1e-9, 1.0), fixed=True, scale=1e-3),
            Parameter("poisson", "Poisson ratio ν", "-", (-0.99, 0.499), fixed=True),
        ),
        x="normal_force",
        x_unit="N",
        observable="kappa",
        unit="N/m",
        source="paper 2, Eqs. 7-10 and κ = 2G*a",
        function=kappa_jkr_mindlin,
    )
)


def fit_jkr_mindlin(force, kappa, radius: float, poisson: float, start=None):
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
        JKR_MINDLIN, F, k, start=start, fixed={"radius": float(radius), "poisson": float(poisson)}
    )


# --------------------------------------------------------------------------------------------
# Per-sweep quantities


INFO_COLUMNS = (
    "sweep",
    "experiment",
    "configuration",
    "medium",
    "normal_force_N",
    "ramp",
    "fundamental_Hz",
    "overtone",
    "area_m2",
    "n_contacts",
    "sphere_radius_m",
    "poisson",
)


def _sweep_info(table: pd.DataFrame) -> pd.DataFrame:
    cols = list(INFO_COLUMNS)
    return table.drop_duplicates("sweep", keep="first")[cols].reset_index(drop=True)


def _sensitivity(info: pd.DataFrame, zq: float) -> np.ndarray:
    """P = n_P/(2nπ²A_eff Z_q) of every sweep, Hz per N/m (paper 2, Eq. 1)."""
    keys = ["fundamental_Hz", "overtone", "area_m2", "n_contacts"]
    P = np.empty(len(info))
    for key, idx in info.groupby(keys, sort=False).indices.items():
        q = QCM(fundamental=key[0], overtone=int(key[1]), area=key[2], zq=zq)
        P[idx] = q.sensitivity(int(key[3]))
    return P


def _slip_sweeps(sw: pd.DataFrame) -> np.ndarray:
    """True for sweeps that slip (Cattaneo-Mindlin or plateau) with a positive Δf0."""
    slip = sw["model"].isin(["cattaneo-mindlin", "plateau"]).to_numpy()
    return slip & (sw["df0_Hz"].to_numpy() > 0)


def _friction(sw: pd.DataFrame, P: np.ndarray) -> None:
    """μ from the Δf and ΔΓ slopes (physics.md Eq. 11-12) with propagated errors, in place.

    Cattaneo-Mindlin sweeps only: above a stick plateau the shifts have no linear onset (module
    docstring of :mod:`contactres.analysis_sweep`), so a plateau sweep gets NaN and the flag
    ``plateau-slope`` instead of a biased number.
    """
    df0 = sw["df0_Hz"].to_numpy()
    slip = _slip_sweeps(sw) & (sw["model"].to_numpy() == "cattaneo-mindlin")
    mu = {"df": np.full(len(sw), np.nan), "dgamma": np.full(len(sw), np.nan)}
    mu["df"][slip], mu["dgamma"][slip] = mu_from_slopes(
        P[slip],
        df0[slip] / P[slip],
        sw["normal_force_N"].to_numpy()[slip],
        sw["df_slope_Hz_per_m"].to_numpy()[slip],
        sw["dgamma_slope_Hz_per_m"].to_numpy()[slip],
    )
    for name in ("df", "dgamma"):
        s = sw[f"{name}_slope_Hz_per_m"].to_numpy()
        s_err = sw[f"{name}_slope_err_Hz_per_m"].to_numpy()
        # μ ∝ Δf0²/slope: relative error from both, with their covariance for the Δf slope.
        with np.errstate(divide="ignore", invalid="ignore"):
            rel_f0 = sw["df0_err_Hz"].to_numpy() / df0
            rel_s = s_err / np.abs(s)
            cov = sw["df0_slope_cov"].to_numpy() / (df0 * s) if name == "df" else 0.0
            rel = np.sqrt(np.maximum(4 * rel_f0**2 + rel_s**2 - 4 * cov, 0.0))
        sw[f"mu_{name}"] = mu[name]
        sw[f"mu_{name}_err"] = np.abs(mu[name]) * rel
    plateau = (sw["model"] == "plateau").to_numpy()
    sw.loc[plateau, "flags"] = sw.loc[plateau, "flags"].map(lambda f: _add(f, "plateau-slope"))


def _exact_loop(sw: pd.DataFrame, P: np.ndarray) -> None:
    """μ from the exact loop, in place (NaN where not a slip sweep).

    Uses the loop fits that :func:`fit_sweeps` made: the Cattaneo-Mindlin loop from u0 = 0
    (``cm_*`` columns) for a Cattaneo-Mindlin sweep, the plateau loop (``pl_*``) for a plateau
    sweep. μ = κ/(θF_N) with θ = κ/(μF_N) and κ = A/P from the same fit.
    """
    slip = _slip_sweeps(sw)
    sw["mu_fit"] = np.nan
    sw["mu_fit_err"] = np.nan
    sw["x_max"] = np.nan
    idx = np.flatnonzero(slip)
    if idx.size == 0:
        return
    names = ["A_Hz", "A_err_Hz", "theta_per_m", "lntheta_err", "cov_A_lntheta", "x_max", "edge"]
    plateau = (sw["model"].to_numpy() == "plateau")[idx]
    res = pd.DataFrame(
        {
            c: np.where(plateau, sw[f"pl_{c}"].to_numpy()[idx], sw[f"cm_{c}"].to_numpy()[idx])
            for c in names
        }
    )
    F = sw["normal_force_N"].to_numpy()[idx]
    A = res["A_Hz"].to_numpy(float)
    theta = res["theta_per_m"].to_numpy(float)
    mu = A / (P[idx] * theta * F)
    var_ln = (res["A_err_Hz"] / A) ** 2 + res["lntheta_err"] ** 2 - 2 * res["cov_A_lntheta"] / A
    err = mu * np.sqrt(np.maximum(var_ln.to_numpy(float), 0.0))
    resolved = (res["edge"] == "").to_numpy() & (A > 0)
    sw.loc[idx, "mu_fit"] = np.where(resolved, mu, np.nan)
    sw.loc[idx, "mu_fit_err"] = np.where(resolved, err, np.nan)
    sw.loc[idx, "x_max"] = res["x_max"].to_numpy(float)
    high = np.zeros(len(sw), bool)
    high[idx] = (res["edge"] == "high").to_numpy()
    sw.loc[high, "flags"] = sw.loc[high, "flags"].map(lambda f: _add(f, "gross-sliding"))


def _add(flags: str, flag: str) -> str:
    return flag if not flags else f"{flags};{flag}"


def _drift(sw: pd.DataFrame, padded, p: float) -> np.ndarray:
    """True for the used sweeps of a load (experiment, configuration, medium, F_N) that drifts.

    Model-free test on the points themselves: all used ramps of the load are fitted with one
    common quadratic in u0, with and without an offset per ramp; the offsets are significant if
    the F statistic exceeds its ``1 - p/2`` quantile in Δf or in ΔΓ (two channels, Bonferroni).
    Up and down ramps of a history-free (Masing) contact must coincide, so a significant offset
    means the baseline moved between ramps.
    """
    keys = ["experiment", "configuration", "medium", "normal_force_N"]
    flag = np.zeros(len(sw), bool)
    used = np.flatnonzero(sw["used"].to_numpy())
    row_of = {s: i for i, s in enumerate(padded.sweeps)}
    padded_row = np.array([row_of[s] for s in sw["sweep"]], dtype=int)
    for pos in sw.iloc[used].groupby(keys, sort=False).indices.values():
        idx = used[pos]  # positions in sw
        k = len(idx)
        if k < 2:
            continue
        rows = padded_row[idx]
        m = padded.w[rows] > 0
        u = padded.u[rows][m]
        ramp = np.repeat(np.arange(k), m.sum(axis=1))
        n = u.size
        if n - 3 - (k - 1) < 2:
            continue
        scale = u.max() if u.max() > 0 else 1.0
        base = np.column_stack([np.ones(n), u / scale, (u / scale) ** 2])
        dummies = (ramp[:, None] == np.arange(1, k)[None, :]).astype(float)
        full = np.column_stack([base, dummies])
        pvals = []
        for y in (padded.df[rows][m], padded.dg[rows][m]):
            r0 = y - base @ np.linalg.lstsq(base, y, rcond=None)[0]
            r1 = y - full @ np.linalg.lstsq(full, y, rcond=None)[0]
            rss0, rss1 = r0 @ r0, r1 @ r1
            d1, d2 = k - 1, n - full.shape[1]
            if rss1 <= 0:
                pvals.append(0.0 if rss0 > 0 else 1.0)
                continue
            fstat = ((rss0 - rss1) / d1) / (rss1 / d2)
            pvals.append(float(f_dist.sf(fstat, d1, d2)))
        if min(pvals) < p / 2:
            flag[idx] = True
    return flag


# --------------------------------------------------------------------------------------------
# Aggregation


LOAD_QUANTITIES = (
    "df0_Hz",
    "dgamma0_Hz",
    "kappa_N_per_m",
    "omega_xi_N_per_m",
    "loss_tangent",
    "mu_df",
    "mu_dgamma",
    "mu_fit",
)
GROUP_KEYS = ["configuration", "medium"]
LOAD_KEYS = ["configuration", "medium", "normal_force_N"]


def _per_experiment(sw: pd.DataFrame) -> pd.DataFrame:
    used = sw[sw["used"]]
    keys = [*LOAD_KEYS, "experiment"]
    g = used.groupby(keys, sort=True)
    exp = g[list(LOAD_QUANTITIES)].mean()
    exp["n_sweeps"] = g.size()
    for c in ("sphere_radius_m", "poisson", "P_Hz_per_N_per_m"):
        exp[c] = g[c].first()
    return exp.reset_index()


def _per_load(exp: pd.DataFrame) -> pd.DataFrame:
    g = exp.groupby(LOAD_KEYS, sort=True)
    out = g.size().rename("n_experiments").to_frame()
    out["n_sweeps"] = g["n_sweeps"].sum()
    for q in LOAD_QUANTITIES:
        out[f"{q}_mean"] = g[q].mean()
        out[f"{q}_sd"] = g[q].std(ddof=1)
    return out.reset_index()


def _bootstrap_jkr(pts: pd.DataFrame, R: float, nu: float, res, B: int, seed: int):
    """Standard deviations of E and γ over ``B`` resamples of the experiments (with replacement).

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


def _group_fit(exp: pd.DataFrame, settings: AnalysisSettings, key) -> dict:
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
    experiments = pts["experiment"].unique()
    if settings.bootstrap > 0 and len(experiments) >= 3:
        E_sd, g_sd = _bootstrap_jkr(pts, R, nu, res, int(settings.bootstrap), settings.seed)
        out["E_bootstrap_sd_Pa"] = E_sd
        out["gamma_bootstrap_sd_J_m2"] = g_sd
    return out


# --------------------------------------------------------------------------------------------


def analyze(
    table: pd.DataFrame,
    q: QCM | None = None,
    settings: AnalysisSettings | None = None,
    progress: Callable[[str], None] | None = None,
):
    """Analyse a validated sweep table (:func:`contactres.read_sweeps`); see the module docstring.

    Parameters
    ----------
    table : the sweep table (every constant filled in)
    q : optional :class:`~contactres.QCM`; if given, its fundamental, overtone, area and Z_q
        replace the table's for every sweep
    settings : :class:`AnalysisSettings` (defaults if None)
    progress : optional callback called with the name of each step as it starts

    Returns
    -------
    contactres.report.Results
    """
    from .. import __version__
    from ..report import Results

    settings = settings or AnalysisSettings()
    say = progress or (lambda step: None)
    table = table.copy()
    if q is not None:
        table["fundamental_Hz"] = q.fundamental
        table["overtone"] = q.overtone
        table["area_m2"] = q.area
        settings = AnalysisSettings(**{**asdict(settings), "zq": q.zq})
    if not set(INFO_COLUMNS) <= set(table.columns) or "line" not in table.columns:
        # Not from read_sweeps(): validate it the same way (constants from q if given).
        given = {}
        if q is not None:
            given = {"fundamental_Hz": q.fundamental, "overtone": q.overtone, "area_m2": q.area}
        table = validate_sweeps(table, source="<table>", constants=given)

    say("fitting the amplitude models of every sweep")
    padded = pad_sweeps(table)
    sw = fit_sweeps(padded, delta_bic=settings.delta_bic, exact_loop=settings.exact_loop)
    info = _sweep_info(table)
    sw = info.merge(sw, on="sweep", how="right", validate="one_to_one")
    P = _sensitivity(sw, settings.zq)
    sw["P_Hz_per_N_per_m"] = P

    flags = [""] * len(sw)
    few = sw["n_points"].to_numpy() < 4
    first = (sw["ramp"].to_numpy() == 1) & (not settings.keep_first_ramp)
    sw["used"] = ~few & ~first
    for i in np.flatnonzero(first):
        flags[i] = _add(flags[i], "first-ramp")
    for i in np.flatnonzero(few):
        flags[i] = _add(flags[i], "few-points")
    rises = (
        sw["df_slope_Hz_per_m"].to_numpy()
        > JUNCTION_SIGMAS * sw["df_slope_err_Hz_per_m"].to_numpy()
    )
    rises &= sw["model"].to_numpy() != "elastic"
    for i in np.flatnonzero(rises):
        flags[i] = _add(flags[i], "junction-growth")
    f_res = sw["fundamental_Hz"].to_numpy() * sw["overtone"].to_numpy()
    big = np.abs(sw["df0_Hz"].to_numpy()) > SMALL_LOAD_LIMIT * f_res
    for i in np.flatnonzero(big):
        flags[i] = _add(flags[i], "small-load")
    sw["flags"] = flags

    say("contact stiffness and friction")
    sw["kappa_N_per_m"] = sw["df0_Hz"] / P
    sw["omega_xi_N_per_m"] = sw["dgamma0_Hz"] / P
    with np.errstate(divide="ignore", invalid="ignore"):
        sw["loss_tangent"] = sw["dgamma0_Hz"] / sw["df0_Hz"]
    _friction(sw, P)
    sw.loc[rises, ["mu_df", "mu_df_err"]] = np.nan
    if settings.exact_loop:
        say("friction from the exact loops")
        _exact_loop(sw, P)
    else:
        sw["mu_fit"] = np.nan
        sw["mu_fit_err"] = np.nan
        sw["x_max"] = np.nan

    drift = _drift(sw, padded, settings.drift_p)
    sw.loc[drift, "flags"] = sw.loc[drift, "flags"].map(lambda f: _add(f, "drift"))

    say("statistics per load")
    exp = _per_experiment(sw)
    loads = _per_load(exp)

    groups = []
    for key, part in exp.groupby(GROUP_KEYS, sort=True):
        say(f"JKR fit: {key[0]}, {key[1]}")
        g = _group_fit(part, settings, key)
        used = sw[sw["used"] & (sw["configuration"] == key[0]) & (sw["medium"] == key[1])]
        g["n_experiments"] = int(part["experiment"].nunique())
        g["n_sweeps_used"] = len(used)
        g["models"] = {m: int((used["model"] == m).sum()) for m in MODEL_ORDER}
        g["P_Hz_per_N_per_m"] = float(part["P_Hz_per_N_per_m"].mean())
        groups.append(g)

    record = asdict(settings)
    record["x_max_table"] = X_MAX
    return Results(
        sweeps=sw,
        loads=loads,
        experiments=exp,
        groups=groups,
        settings=record,
        version=__version__,
        table=table,
        padded=padded,
    )
