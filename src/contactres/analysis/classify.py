"""One amplitude sweep at a time, all sweeps at once: low-amplitude limits, slopes, model class.

Every sweep is fitted with four descriptions of Δf(u0) and ΔΓ(u0) (paper 2, Figs. 1D and 4):

``elastic``           Δf = Δf0,                      ΔΓ = ΔΓ0                     (k = 2)
``cattaneo-mindlin``  Δf = Δf0 + s_f u0,             ΔΓ = ΔΓ0 + s_Γ u0             (k = 4, Eq. 12)
``savkoor``           Δf = Δf0 + c_f u0²,            ΔΓ = ΔΓ0 + c_Γ u0²            (k = 4, Eq. 15)
``plateau``           Δf = Δf0 + s_f max(u0-u_c, 0), ΔΓ = ΔΓ0 + s_Γ max(u0-u_c, 0)  (k = 5)

All are linear least squares once the critical amplitude u_c of the plateau is fixed, so they are
solved in closed form for every sweep at once (sweeps padded to a common length, padding weighted
0). u_c is searched on a grid: at the data amplitudes and at quarter steps between them, with at
least 2 points on the plateau and 3 on the slope. (For a contact that sticks below a critical
displacement d_c, the shifts leave the plateau smoothly, the slip annulus starting at zero width,
so the fitted u_c lies at or up to ~2 amplitude steps above d_c; see tests/test_analysis.py.)

The Cattaneo-Mindlin candidate is the better (by BIC) of the straight line and the exact loop
below (k = 3), so that sweeps reaching full sliding, which curve, are still recognised as such;
the low-amplitude limits of such a sweep come from the exact loop.

**Model choice (the stated criterion).** With separate unknown noise levels in Δf and ΔΓ, the
Bayesian information criterion of a model with k parameters is
``BIC = n ln(RSS_f/n) + n ln(RSS_Γ/n) + k ln(2n)``. The model with the lowest BIC wins, except
that a model listed earlier in :data:`MODEL_ORDER` (elastic, cattaneo-mindlin, savkoor, plateau:
simplest and most common first) is kept if its BIC is within ``delta_bic`` (default 2, "positive
evidence" on the Kass-Raftery scale) of the lowest.

**Exact Cattaneo-Mindlin loop.** The loop is self-similar: K′/κ and (K″ - ωξ)/κ depend on u0 only
through x = κu0/(μF_N) (paper 2, Eq. 4-6). Both functions are tabulated once from the package's
forward model (:func:`contactres.shifts_from_loop` on a :class:`contactres.CattaneoMindlinLoop`)
and the fit Δf = Pκ g′(θu0), ΔΓ = P[ωξ + κ g″(θu0)] with θ = κ/(μF_N) is solved by variable
projection: for fixed θ, Pκ and Pωξ follow in closed form; θ is found by a zooming grid search
(relative resolution < 1e-3), independently for every sweep. Errors come from the Jacobian in
(Pκ, Pωξ, ln θ), scaled by the residual variance. Points are weighted by the noise level of
each channel taken from the straight-line fit.

**Exact plateau loop.** A sweep classified ``plateau`` is refitted (with ``exact_loop``) with the
loop of :class:`contactres.PlateauLoop` around the Cattaneo-Mindlin loop: the contact sticks up
to the critical displacement d_c, then slips as Cattaneo-Mindlin in the excess d - d_c. In units
of μF_N/κ (x = κu0/(μF_N), c = κd_c/(μF_N), y = x - c) its shapes depend on two arguments, not
one, so the table above cannot be reused for both. From the virgin-curve form of Eq. 4-5
(slope deficit L(d) = L_CM(d - d_c) above d_c, zero below):

    K″ - ωξ = κ [ (y/x)² g″(y) + 4c s(y)/(πx²) ],   s(y) = y - F_CM(y)  (κ = μF_N = 1)
    K′/κ    = 1 - (8/(πx²)) ∫₀^y L_CM(e) √((e + c)(y - e)) de

The loss part is the table at the shifted argument y plus a closed-form term (verified against
:func:`contactres.shifts_from_loop` in tests/test_analysis.py); the storage part is not, since
√((e + c)(y - e)) is not the weight of any single Cattaneo-Mindlin amplitude. Both are therefore
integrated with the package's Masing-loop quadrature (:func:`plateau_loop_shape`, relative
accuracy 1e-9, vectorised over amplitudes). The fit Δf = Pκ G′(θu0, θd_c), ΔΓ = P[ωξ +
κ G″(θu0, θd_c)] (θ = κ/(μF_N)) uses the same variable projection for Pκ and Pωξ and
:func:`scipy.optimize.least_squares` for (ln θ, d_c), started from the hinge position and from
the Cattaneo-Mindlin loop fitted to the amplitudes in excess of it; one sweep at a time (plateau
sweeps are a few per cent). Errors come from the Jacobian in (Pκ, Pωξ, ln θ, d_c) scaled by the
residual variance; the points are weighted by the noise level of each channel taken from the
hinge fit. The low-amplitude limits of such a sweep, and its ``plateau_amplitude_m``, then come
from this fit (``limits_from`` = ``plateau-loop``).

Near d_c the shifts leave the plateau as K″ - ωξ ≈ (2/(3π)) κ²v²/(μF_N d_c) and
K′ - κ ≈ -(32/(45π)) κ²v^{5/2}/(μF_N d_c^{3/2}) in the excess v = u0 - d_c ≪ d_c, μF_N/κ
(checked numerically in tests/test_analysis.py): there is no linear onset, and the slope of the
hinge depends on how far the sweep reaches beyond d_c. No slope formula gives μ for a plateau
sweep; :func:`contactres.analyze` reports none (flag ``plateau-slope``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from ..fitting import MODELS, Model, Parameter, register_model

__all__ = [
    "MODEL_ORDER",
    "Padded",
    "cm_loop_table",
    "fit_cm_loops",
    "fit_plateau_loops",
    "fit_sweeps",
    "model_curves",
    "pad_sweeps",
    "plateau_loop_shape",
]

MODEL_ORDER = ("elastic", "cattaneo-mindlin", "savkoor", "plateau")

# Table of the exact CM loop in x = κu0/(μF_N): full sliding starts at x = 3/2; beyond X_MAX the
# contact slides grossly over almost all the cycle and the fit says so instead of extrapolating.
X_MAX = 30.0
N_TABLE = 12001
# Plateau search: points on the plateau / on the slope, and the sub-steps between amplitudes.
PLATEAU_MIN_FLAT = 2
PLATEAU_MIN_SLOPE = 3
PLATEAU_SUBSTEPS = (0.0, 0.25, 0.5, 0.75)


def _amplitude_model(key, display, extra, source, function):
    base = (
        Parameter("df0", "low-amplitude Δf0", "Hz", (-np.inf, np.inf), scale=100.0),
        Parameter("dgamma0", "low-amplitude ΔΓ0", "Hz", (-np.inf, np.inf), scale=10.0),
    )
    return register_model(
        Model(key, display, base + extra, "amplitude", "m", "df, dgamma", "Hz", source, function)
    )


_SLOPES = (
    Parameter("df_slope", "dΔf/du0", "Hz/m", (-np.inf, np.inf), scale=1e9),
    Parameter("dgamma_slope", "dΔΓ/du0", "Hz/m", (-np.inf, np.inf), scale=1e9),
)
_amplitude_model(
    "elastic",
    "no amplitude dependence",
    (),
    "paper 2, Eq. 1 (Voigt element)",
    lambda u, df0, dgamma0: (df0 + 0.0 * u, dgamma0 + 0.0 * u),
)
_amplitude_model(
    "cattaneo-mindlin",
    "linear in u0 (Cattaneo-Mindlin)",
    _SLOPES,
    "paper 2, Eq. 12",
    lambda u, df0, dgamma0, df_slope, dgamma_slope: (
        df0 + df_slope * u,
        dgamma0 + dgamma_slope * u,
    ),
)
_amplitude_model(
    "savkoor",
    "parabolic in u0 (Savkoor)",
    (
        Parameter("df_curvature", "d²Δf/du0² / 2", "Hz/m^2", (-np.inf, np.inf), scale=1e17),
        Parameter("dgamma_curvature", "d²ΔΓ/du0² / 2", "Hz/m^2", (-np.inf, np.inf), scale=1e17),
    ),
    "paper 2, Eq. 15",
    lambda u, df0, dgamma0, df_curvature, dgamma_curvature: (
        df0 + df_curvature * u**2,
        dgamma0 + dgamma_curvature * u**2,
    ),
)
_amplitude_model(
    "plateau",
    "flat below u_c, linear above",
    (*_SLOPES, Parameter("u_c", "critical amplitude u_c", "m", (0.0, 1e-6), scale=1e-9)),
    "paper 2, Fig. 4C, D (stick plateau)",
    lambda u, df0, dgamma0, df_slope, dgamma_slope, u_c: (
        df0 + df_slope * np.maximum(u - u_c, 0.0),
        dgamma0 + dgamma_slope * np.maximum(u - u_c, 0.0),
    ),
)


# Parameters shared by the loop models: Pκ, Pωξ and the loop's amplitude scale κ/(μF_N).
_LOOP_PARAMETERS = (
    Parameter("A", "Pκ (low-amplitude Δf)", "Hz", (0.0, np.inf), scale=100.0),
    Parameter("B", "Pωξ (low-amplitude ΔΓ)", "Hz", (-np.inf, np.inf), scale=10.0),
    Parameter("theta", "κ/(μF_N)", "1/m", (0.0, np.inf), scale=1e8),
)


def _cm_loop_shifts(u, A, B, theta):
    x, g1, g2, _, _ = cm_loop_table()
    xu = np.asarray(theta) * np.asarray(u)
    return A * np.interp(xu, x, g1), B + A * np.interp(xu, x, g2)


register_model(
    Model(
        key="cattaneo-mindlin-loop",
        display="exact Cattaneo-Mindlin loop with a dashpot",
        parameters=_LOOP_PARAMETERS,
        x="amplitude",
        x_unit="m",
        observable="df, dgamma",
        unit="Hz",
        source="paper 2, Eqs. 4-6 (Masing loops) and Eq. 12 (dashpot)",
        function=_cm_loop_shifts,
    )
)


def _plateau_loop_shifts(u, A, B, theta, d_c):
    g1, g2 = plateau_loop_shape(np.asarray(theta) * np.asarray(u), np.asarray(theta) * d_c)
    return A * g1, B + A * g2


register_model(
    Model(
        key="plateau-loop",
        display="exact Cattaneo-Mindlin loop behind a stick plateau, with a dashpot",
        parameters=(
            *_LOOP_PARAMETERS,
            Parameter("d_c", "critical displacement d_c", "m", (0.0, 1e-6), scale=1e-9),
        ),
        x="amplitude",
        x_unit="m",
        observable="df, dgamma",
        unit="Hz",
        source="paper 2, Eqs. 4-6 (Masing loops), Fig. 4C, D (stick plateau), Eq. 12 (dashpot)",
        function=_plateau_loop_shifts,
    )
)

#: Number of fitted parameters of each amplitude model (the k of its BIC), from the registry.
N_PARAMS = {
    m: len(MODELS[m].parameters) for m in (*MODEL_ORDER, "cattaneo-mindlin-loop", "plateau-loop")
}


@dataclass(frozen=True)
class Padded:
    """Sweeps as padded 2-D arrays (one row per sweep, amplitudes ascending, padding weight 0)."""

    sweeps: np.ndarray  # sweep ids, order of first appearance
    u: np.ndarray  # amplitude, m
    df: np.ndarray  # Hz
    dg: np.ndarray  # Hz
    w: np.ndarray  # 1 for data, 0 for padding
    n: np.ndarray  # points per sweep
    direction: np.ndarray  # "up", "down" or "mixed" (order of amplitudes in the file)


def pad_sweeps(table: pd.DataFrame) -> Padded:
    """Arrange the points of a sweep table into padded (sweeps x points) arrays."""
    codes, names = pd.factorize(table["sweep"], sort=False)
    u = table["amplitude_m"].to_numpy(float)
    order = np.lexsort((u, codes))
    codes_s = codes[order]
    counts = np.bincount(codes, minlength=len(names))
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    pos = np.arange(len(order)) - starts[codes_s]
    m = int(counts.max())
    shape = (len(names), m)
    U, DF, DG, W = (np.zeros(shape) for _ in range(4))
    U[codes_s, pos] = u[order]
    DF[codes_s, pos] = table["df_Hz"].to_numpy(float)[order]
    DG[codes_s, pos] = table["dgamma_Hz"].to_numpy(float)[order]
    W[codes_s, pos] = 1.0
    # Padding repeats the largest amplitude so that max() and grids stay meaningful.
    last = U[np.arange(len(names)), counts - 1]
    U = np.where(W > 0, U, last[:, None])
    # Direction from the file order of the amplitudes: up, down, or mixed.
    same = codes[1:] == codes[:-1]
    step = np.diff(u)
    rises = np.bincount(codes[1:][same & (step > 0)], minlength=len(names)) > 0
    falls = np.bincount(codes[1:][same & (step < 0)], minlength=len(names)) > 0
    direction = np.where(rises & falls, "mixed", np.where(falls, "down", "up"))
    return Padded(np.asarray(names), U, DF, DG, W, counts, direction)


def _line(X, Y, W):
    """Weighted straight line y = a + b x per row (closed form), both channels at once.

    X, W: (..., M); Y: (2, ..., M). Returns a, b, var_a, var_b, cov_ab, rss, each (2, ...).
    """
    S0 = W.sum(-1)
    Sx = (W * X).sum(-1)
    Sxx = (W * X * X).sum(-1)
    Sy = (W * Y).sum(-1)
    Sxy = (W * X * Y).sum(-1)
    D = S0 * Sxx - Sx**2
    ok = D > 1e-300 * np.maximum(Sxx * S0, 1e-300)
    Dsafe = np.where(ok, D, 1.0)
    b = np.where(ok, (S0 * Sxy - Sx * Sy) / Dsafe, 0.0)
    a = (Sy - b * Sx) / S0
    rss = (W * (Y - a[..., None] - b[..., None] * X) ** 2).sum(-1)
    s2 = rss / np.maximum(S0 - 2, 1)
    var_a = np.where(ok, s2 * Sxx / Dsafe, np.inf)
    var_b = np.where(ok, s2 * S0 / Dsafe, np.inf)
    cov_ab = np.where(ok, -s2 * Sx / Dsafe, 0.0)
    return a, b, var_a, var_b, cov_ab, rss


def _bic(rss, n, k):
    """BIC of a two-channel fit with separate noise levels; rss: (2, S)."""
    # Floor: a perfect fit (rss = 0, e.g. noiseless synthetic data) must not give -inf.
    floor = 1e-30
    return (
        n * np.log(np.maximum(rss[0], floor) / n)
        + n * np.log(np.maximum(rss[1], floor) / n)
        + k * np.log(2 * n)
    )


def fit_sweeps(p: Padded, delta_bic: float = 2.0, exact_loop: bool = True) -> pd.DataFrame:
    """Fit the four amplitude models to every sweep and choose one (see module docstring).

    With ``exact_loop`` the Cattaneo-Mindlin candidate is the better (by BIC) of the straight
    line (k = 4) and the exact loop (k = 3, :func:`fit_cm_loops`), so that sweeps reaching full
    sliding, which curve, are still recognised; the low-amplitude limits of such a sweep then
    come from the exact loop (no extrapolation bias).

    Returns one row per sweep (order of first appearance) with the low-amplitude limits, slopes
    and curvatures with standard errors, the critical amplitude of a plateau, the BIC of each
    model, the noise levels (from the straight line), the chosen ``model`` and, with
    ``exact_loop``, the loop fit of every sweep from u0 = 0 (the columns of :func:`fit_cm_loops`
    prefixed ``cm_``) and, for plateau sweeps, the fit of the exact plateau loop (the columns of
    :func:`fit_plateau_loops` prefixed ``pl_``; NaN for other sweeps), which then gives their
    low-amplitude limits and critical amplitude (``limits_from`` = ``plateau-loop``).
    """
    Y = np.stack([p.df, p.dg])
    n = p.n.astype(float)
    S = len(n)
    rows = {"sweep": p.sweeps, "n_points": p.n, "direction": p.direction}
    rows["u_max_m"] = np.max(np.where(p.w > 0, p.u, 0.0), axis=1)

    # elastic
    mean = (p.w * Y).sum(-1) / n
    rss_el = (p.w * (Y - mean[..., None]) ** 2).sum(-1)
    var_mean = rss_el / np.maximum(n - 1, 1) / n
    # cattaneo-mindlin (straight line); its residuals give the noise level of each channel
    lin = _line(p.u, Y, p.w)
    sigma = np.sqrt(lin[5] / np.maximum(n - 2, 1))
    # savkoor (parabola in u0: straight line in u0²)
    par = _line(p.u**2, Y, p.w)
    # plateau (hinge), grid over u_c
    t = np.asarray(PLATEAU_SUBSTEPS)
    u_next = np.concatenate([p.u[:, 1:], p.u[:, -1:]], axis=1)
    uc = p.u[:, :, None] + t[None, None, :] * (u_next - p.u)[:, :, None]  # (S, M, T)
    Xh = np.maximum(p.u[:, None, None, :] - uc[..., None], 0.0)  # (S, M, T, M)
    Wh = np.broadcast_to(p.w[:, None, None, :], Xh.shape)
    n_flat = (Wh * (Xh == 0.0)).sum(-1)  # points with u0 <= u_c
    gap = (u_next - p.u)[:, :, None] > 0
    valid = (n_flat >= PLATEAU_MIN_FLAT) & (p.n[:, None, None] - n_flat >= PLATEAU_MIN_SLOPE)
    valid &= gap | (t[None, None, :] == 0)
    Yh = Y[:, :, None, None, :]
    hin = _line(Xh, Yh, Wh)
    crit = np.where(
        valid,
        np.log(np.maximum(hin[5][0], 1e-30)) + np.log(np.maximum(hin[5][1], 1e-30)),
        np.inf,
    )
    flat = crit.reshape(S, -1)
    best = np.argmin(flat, axis=1)
    has_plateau = np.isfinite(flat[np.arange(S), best])

    def pick(arr):  # (2, S, M, T) -> (2, S)
        return arr.reshape(2, S, -1)[:, np.arange(S), best]

    hinge = tuple(pick(a) for a in hin)
    uc_best = uc.reshape(S, -1)[np.arange(S), best]

    bic_line = _bic(lin[5], n, N_PARAMS["cattaneo-mindlin"])
    use_loop = np.zeros(S, bool)
    if exact_loop:
        loop = fit_cm_loops(p.u, p.df, p.dg, p.w, sigma[0], sigma[1])
        rss_loop = np.stack([loop["rss_df"].to_numpy(), loop["rss_dgamma"].to_numpy()])
        ok = (loop["edge"].to_numpy() == "") & (loop["A_Hz"].to_numpy() > 0)
        bic_loop = np.where(ok, _bic(rss_loop, n, N_PARAMS["cattaneo-mindlin-loop"]), np.inf)
        use_loop = bic_loop < bic_line
        rows["bic_cattaneo-mindlin-line"] = bic_line
        rows["bic_cattaneo-mindlin-loop"] = bic_loop
        # The whole loop fit (cm_A_Hz, cm_theta_per_m, ...): μ_fit of the analysis reuses it.
        for col in loop.columns:
            rows[f"cm_{col}"] = loop[col].to_numpy()
    bic = {
        "elastic": _bic(rss_el, n, N_PARAMS["elastic"]),
        "cattaneo-mindlin": np.minimum(bic_line, rows.get("bic_cattaneo-mindlin-loop", np.inf)),
        "savkoor": _bic(par[5], n, N_PARAMS["savkoor"]),
        "plateau": np.where(has_plateau, _bic(hinge[5], n, N_PARAMS["plateau"]), np.inf),
    }
    B = np.stack([bic[m] for m in MODEL_ORDER])  # (4, S)
    lowest = B.min(axis=0)
    choice = np.argmax(B <= lowest + delta_bic, axis=0)  # first model within delta_bic
    models = np.asarray(MODEL_ORDER)[choice]
    for m in MODEL_ORDER:
        rows[f"bic_{m}"] = bic[m]

    # Low-amplitude limits and their errors from the chosen model.
    is_el, is_cm, is_sv, is_pl = (choice == i for i in range(4))
    for c, name in enumerate(("df", "dgamma")):
        a = np.select([is_el, is_cm, is_sv, is_pl], [mean[c], lin[0][c], par[0][c], hinge[0][c]])
        va = np.select(
            [is_el, is_cm, is_sv, is_pl], [var_mean[c], lin[2][c], par[2][c], hinge[2][c]]
        )
        if exact_loop:
            from_loop = is_cm & use_loop
            col = "A_Hz" if c == 0 else "B_Hz"
            a = np.where(from_loop, loop[col].to_numpy(), a)
            va = np.where(from_loop, loop[col.replace("_Hz", "_err_Hz")].to_numpy() ** 2, va)
        rows[f"{name}0_Hz"] = a
        rows[f"{name}0_err_Hz"] = np.sqrt(va)
        # Slope of the linear part: the hinge slope for a plateau, the straight line otherwise.
        rows[f"{name}_slope_Hz_per_m"] = np.where(is_pl, hinge[1][c], lin[1][c])
        rows[f"{name}_slope_err_Hz_per_m"] = np.sqrt(np.where(is_pl, hinge[3][c], lin[3][c]))
        cov = np.where(is_pl, hinge[4][c], lin[4][c])
        rows[f"{name}0_slope_cov"] = np.where(is_cm & use_loop, 0.0, cov)
        rows[f"{name}_curvature_Hz_per_m2"] = par[1][c]
        rows[f"{name}_curvature_err_Hz_per_m2"] = np.sqrt(par[3][c])
        rows[f"sigma_{name}_Hz"] = sigma[c]
    rows["plateau_amplitude_m"] = np.where(is_pl, uc_best, np.nan)
    rows["plateau_amplitude_err_m"] = np.full(S, np.nan)
    from_pl = np.zeros(S, bool)
    if exact_loop:
        # Plateau sweeps: the exact plateau loop, weighted by the noise of the hinge fit.
        for col in PLATEAU_LOOP_COLUMNS:
            rows[f"pl_{col}"] = np.full(S, np.nan)
        rows["pl_edge"] = np.full(S, "", dtype=object)
        idx = np.flatnonzero(is_pl)
        if idx.size:
            sig_h = np.sqrt(hinge[5][:, idx] / np.maximum(n[idx] - 3, 1))
            pl = fit_plateau_loops(
                p.u[idx], p.df[idx], p.dg[idx], p.w[idx], sig_h[0], sig_h[1], uc_best[idx]
            )
            for col in pl.columns:
                rows[f"pl_{col}"][idx] = pl[col].to_numpy()
            ok = (pl["edge"].to_numpy() == "") & (pl["A_Hz"].to_numpy() > 0)
            from_pl[idx[ok]] = True
            for name, col in (("df", "A"), ("dgamma", "B")):
                rows[f"{name}0_Hz"][idx[ok]] = pl[f"{col}_Hz"].to_numpy()[ok]
                rows[f"{name}0_err_Hz"][idx[ok]] = pl[f"{col}_err_Hz"].to_numpy()[ok]
                rows[f"{name}0_slope_cov"][idx[ok]] = 0.0
            rows["plateau_amplitude_m"][idx[ok]] = pl["d_c_m"].to_numpy()[ok]
            rows["plateau_amplitude_err_m"][idx[ok]] = pl["d_c_err_m"].to_numpy()[ok]
    rows["model"] = models
    rows["limits_from"] = np.select(
        [is_el, is_cm & use_loop, is_cm, is_sv, is_pl & from_pl, is_pl],
        ["mean", "cm-loop", "line", "parabola", "plateau-loop", "plateau"],
        default="",
    )
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------------------------
# Exact Cattaneo-Mindlin loop


@lru_cache(maxsize=1)
def cm_loop_table() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of the Cattaneo-Mindlin loop against x = κu0/(μF_N), and slopes.

    Made from the forward model (paper 2, Eq. 4-6 with Masing's rule) with κ = μF_N = 1, so
    x = u0. Returns (x, g1, g2, dg1/dx, dg2/dx) on a grid 0 <= x <= X_MAX (uniform, refined near
    full sliding at x = 3/2); linear interpolation in it is accurate to 1e-6 (a test checks).
    """
    from ..resonators.qcm import QCM, shifts_from_loop, shifts_from_stiffness
    from ..tangential import CattaneoMindlinLoop

    q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    P = float(np.asarray(shifts_from_stiffness(q, 1.0, 0.0, 1)[0]))
    # Uniform grid, refined around full sliding (x = 3/2), where K′ and K″ have a square-root
    # singularity in their derivatives: linear interpolation then stays within 1e-6 of κ.
    side = np.geomspace(1e-7, 0.6, 800)
    near = 1.5 + np.concatenate([-side, side])
    x = np.unique(np.concatenate([np.linspace(0.0, X_MAX, N_TABLE), [1.5], near]))
    loop = CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0)
    df, dg = shifts_from_loop(q, loop, x[1:], 1)
    g1 = np.concatenate([[1.0], np.asarray(df, float) / P])
    g2 = np.concatenate([[0.0], np.asarray(dg, float) / P])
    return x, g1, g2, np.gradient(g1, x), np.gradient(g2, x)


def _vp_solve(g1, g2, df, dg, w, wf, wg):
    """Closed-form Pκ (A) and Pωξ (B) for fixed θ, and χ². Arrays (..., M); wf, wg (...)."""
    n = w.sum(-1)
    g2m = (w * g2).sum(-1) / n
    dgm = (w * dg).sum(-1) / n
    g2c = g2 - g2m[..., None]
    dgc = dg - dgm[..., None]
    num = wf * (w * g1 * df).sum(-1) + wg * (w * g2c * dgc).sum(-1)
    den = wf * (w * g1 * g1).sum(-1) + wg * (w * g2c * g2c).sum(-1)
    A = num / den
    B = dgm - A * g2m
    rf = df - A[..., None] * g1
    rg = dg - B[..., None] - A[..., None] * g2
    rss_f = (w * rf**2).sum(-1)
    rss_g = (w * rg**2).sum(-1)
    return A, B, wf * rss_f + wg * rss_g, rss_f, rss_g


def fit_cm_loops(u, df, dg, w, sigma_df, sigma_dg, rounds: int = 4) -> pd.DataFrame:
    """Fit the exact Cattaneo-Mindlin loop (+ dashpot) to every row of padded sweeps.

    Parameters
    ----------
    u, df, dg, w : (S, M) amplitudes (m), shifts (Hz), weights (0 for padding)
    sigma_df, sigma_dg : (S,) noise levels of the two channels, Hz

    Returns
    -------
    DataFrame with ``A_Hz`` = Pκ, ``B_Hz`` = Pωξ, ``theta_per_m`` = κ/(μF_N), their standard
    errors (``*_err``), ``cov_A_lntheta``, ``x_max`` = θ·max(u0) and ``edge`` ("low" if no slip
    is resolved, "high" if the best fit is gross sliding beyond the table, "" otherwise).
    """
    x_tab, g1_tab, g2_tab, d1_tab, d2_tab = cm_loop_table()
    S = u.shape[0]
    umax = np.maximum(np.max(np.where(w > 0, u, 0.0), axis=1), 1e-300)
    floor_f = 1e-6 * np.maximum(np.abs(df).max(axis=1), 1e-12)
    floor_g = 1e-6 * np.maximum(np.abs(dg).max(axis=1), 1e-12)
    wf = 1.0 / np.maximum(sigma_df, floor_f) ** 2
    wg = 1.0 / np.maximum(sigma_dg, floor_g) ** 2

    def chi2_at(lx):  # lx: (S, K) log10 of x_max
        theta = 10.0**lx / umax[:, None]
        xu = theta[..., None] * u[:, None, :]
        g1 = np.interp(xu, x_tab, g1_tab)
        g2 = np.interp(xu, x_tab, g2_tab)
        args = (df[:, None, :], dg[:, None, :], w[:, None, :], wf[:, None], wg[:, None])
        return _vp_solve(g1, g2, *args)[2]

    lo, hi = -2.5, np.log10(X_MAX)
    grid = np.broadcast_to(np.linspace(lo, hi, 49), (S, 49))
    chi = chi2_at(grid)
    k = np.argmin(chi, axis=1)
    edge = np.where(k == 0, "low", np.where(k == grid.shape[1] - 1, "high", ""))
    step = grid[0, 1] - grid[0, 0]
    centre = grid[np.arange(S), k]
    for _ in range(rounds):
        local = centre[:, None] + np.linspace(-step, step, 17)[None, :]
        local = np.clip(local, lo, hi)
        chi = chi2_at(local)
        centre = local[np.arange(S), np.argmin(chi, axis=1)]
        step = step / 8.0

    theta = 10.0**centre / umax
    xu = theta[:, None] * u
    g1 = np.interp(xu, x_tab, g1_tab)
    g2 = np.interp(xu, x_tab, g2_tab)
    A, B, chi2, rss_f, rss_g = _vp_solve(g1, g2, df, dg, w, wf, wg)
    # Jacobian of the weighted residuals in (A, B, ln θ).
    d1 = np.interp(xu, x_tab, d1_tab) * xu
    d2 = np.interp(xu, x_tab, d2_tab) * xu
    sf, sg = np.sqrt(wf)[:, None], np.sqrt(wg)[:, None]
    zeros = np.zeros_like(u)
    Jf = np.stack([-sf * g1, zeros, -sf * A[:, None] * d1], axis=-1) * w[..., None]
    Jg = np.stack([-sg * g2, -sg + zeros, -sg * A[:, None] * d2], axis=-1) * w[..., None]
    jtj = np.einsum("smi,smj->sij", Jf, Jf) + np.einsum("smi,smj->sij", Jg, Jg)
    n_res = 2 * w.sum(axis=1)
    cov = np.linalg.pinv(jtj) * (chi2 / np.maximum(n_res - 3, 1))[:, None, None]
    return pd.DataFrame(
        {
            "A_Hz": A,
            "A_err_Hz": np.sqrt(cov[:, 0, 0]),
            "B_Hz": B,
            "B_err_Hz": np.sqrt(cov[:, 1, 1]),
            "theta_per_m": theta,
            "lntheta_err": np.sqrt(cov[:, 2, 2]),
            "cov_A_lntheta": cov[:, 0, 2],
            "x_max": theta * umax,
            "edge": edge,
            "rss_df": rss_f,
            "rss_dgamma": rss_g,
        }
    )


# --------------------------------------------------------------------------------------------
# Exact plateau loop

#: Numeric columns of :func:`fit_plateau_loops` (besides ``edge``).
PLATEAU_LOOP_COLUMNS = (
    "A_Hz",
    "A_err_Hz",
    "B_Hz",
    "B_err_Hz",
    "theta_per_m",
    "lntheta_err",
    "cov_A_lntheta",
    "x_max",
    "d_c_m",
    "d_c_err_m",
    "rss_df",
    "rss_dgamma",
)


class _UnitPlateauLoops:
    """:class:`contactres.PlateauLoop` around ``CattaneoMindlinLoop(1, 1, 1)`` for an array of
    critical displacements ``c`` (one per amplitude), in the form that the Masing quadrature of
    :mod:`contactres.qcm` integrates (breaks and singular points per amplitude, last axis)."""

    def __init__(self, c):
        from ..tangential import CattaneoMindlinLoop

        self.inner = CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0)
        self.kappa = 1.0
        self.c = np.asarray(c, dtype=float)[..., None]

    @property
    def breaks(self):
        return np.concatenate([self.c, self.c + self.inner.slip_displacement], axis=-1)

    @property
    def singular_points(self):
        return self.c + self.inner.slip_displacement

    def slopes(self, d):
        return self.inner.slopes(np.maximum(d - self.c, 0.0))


def plateau_loop_shape(x, c) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of a Cattaneo-Mindlin loop behind a stick plateau.

    The loop is :class:`contactres.PlateauLoop` (critical displacement d_c) around
    :class:`contactres.CattaneoMindlinLoop`; ``x`` = κu0/(μF_N) and ``c`` = κd_c/(μF_N)
    (broadcast together). Paper 2, Eqs. 4-6 with Masing's rule, integrated with the quadrature
    of :func:`contactres.loop_stiffness` (relative accuracy 1e-9), vectorised.
    """
    from ..resonators.qcm import DEFAULT_NODES, masing_stiffness

    x, c = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(c, dtype=float))
    if np.any(~(x >= 0)) or np.any(~(c >= 0)):
        raise ValueError("plateau_loop_shape needs x >= 0 and c >= 0")
    k1, k2 = masing_stiffness(_UnitPlateauLoops(c.ravel()), x.ravel(), DEFAULT_NODES)
    return k1.reshape(x.shape), k2.reshape(x.shape)


def _fit_one_plateau(u, df, dg, sigma_df, sigma_dg, floors, uc0, y0):
    """Fit of the exact plateau loop to one sweep (its points only); see
    :func:`fit_plateau_loops`. Returns a dict of its columns."""
    n = u.size
    umax = u.max()
    w = np.ones(n)
    lo_y, hi_y = np.log(10.0**-2.5), np.log(X_MAX)
    # d_c/umax: from 0 (no plateau) to the amplitude that leaves PLATEAU_MIN_SLOPE - 1 above it.
    hi_d = np.sort(u)[n - PLATEAU_MIN_SLOPE] / umax

    def shapes(p):
        p = np.asarray(p, dtype=float)
        ly, dl = p[..., 0, None], p[..., 1, None]
        theta = np.exp(ly) / (umax * (1.0 - dl))  # θ(u_max - d_c) = e^ly
        return theta[..., 0], plateau_loop_shape(theta * u, theta * dl * umax)

    def solve(starts, wf, wg):
        sf, sg = np.sqrt(wf), np.sqrt(wg)

        def residuals(p):  # p: (..., 2) -> (..., 2n), Pκ and Pωξ solved for (projected)
            _, (g1, g2) = shapes(p)
            A, B, _, _, _ = _vp_solve(g1, g2, df, dg, w, wf, wg)
            rf = sf * (df - A[..., None] * g1)
            return np.concatenate([rf, sg * (dg - B[..., None] - A[..., None] * g2)], axis=-1)

        def jacobian(p):  # forward differences, the three points in one quadrature call
            step = 1e-6 * np.array([1.0, 0.1])
            r = residuals(np.vstack([p, p + np.diag(step)]))
            return ((r[1:] - r[0]) / step[:, None]).T

        best = None
        for start in starts:
            r = least_squares(
                residuals,
                start,
                jac=jacobian,
                bounds=([lo_y, 0.0], [hi_y, hi_d]),
                x_scale=[1.0, 0.1],
                xtol=1e-10,
                ftol=1e-10,
                gtol=1e-10,
                max_nfev=200,
            )
            if best is None or r.cost < best.cost:
                best = r
        return best.x

    def weights(sig_f, sig_g):
        return 1.0 / max(sig_f, floors[0]) ** 2, 1.0 / max(sig_g, floors[1]) ** 2

    # Pass 1, weighted by the noise of the hinge fit; started at the hinge and at the amplitude
    # below it (the hinge sits at or above d_c), θ from the loop fitted to the excess.
    first = min(uc0 / umax, hi_d)
    below = u[u < uc0 * (1.0 - 1e-9)]
    starts = []
    for dl0 in [first] + ([below.max() / umax] if below.size else []):
        ly0 = np.log(max(y0, 1e-300) * (1.0 - dl0) / max(1.0 - uc0 / umax, 1e-12))
        starts.append((np.clip(ly0, lo_y, hi_y), dl0))
    wf, wg = weights(sigma_df, sigma_dg)
    x1 = solve(starts, wf, wg)
    # Pass 2, weighted by the noise of this fit's own residuals (the hinge misfits the onset).
    theta, (g1, g2) = shapes(x1)
    _, _, _, rss_f, rss_g = _vp_solve(g1, g2, df, dg, w, wf, wg)
    dof = max(n - 2, 1)
    wf, wg = weights(np.sqrt(rss_f / dof), np.sqrt(rss_g / dof))
    ly, dl = solve([x1], wf, wg)
    theta, (g1, g2) = shapes((ly, dl))
    A, B, chi2, rss_f, rss_g = _vp_solve(g1, g2, df, dg, w, wf, wg)
    d_c = dl * umax
    # Jacobian of the weighted residuals in (A, B, ln θ, d_c), central differences of the shapes.
    h, hd = 1e-5, 1e-5 * umax
    gp = plateau_loop_shape(theta * np.exp(h) * u, theta * np.exp(h) * d_c)
    gm = plateau_loop_shape(theta * np.exp(-h) * u, theta * np.exp(-h) * d_c)
    cp = plateau_loop_shape(theta * u, theta * (d_c + hd))
    cm = plateau_loop_shape(theta * u, theta * max(d_c - hd, 0.0))
    dc_step = hd + min(d_c, hd)
    zeros = np.zeros(n)
    Jf = np.sqrt(wf) * np.column_stack(
        [-g1, zeros, -A * (gp[0] - gm[0]) / (2 * h), -A * (cp[0] - cm[0]) / dc_step]
    )
    Jg = np.sqrt(wg) * np.column_stack(
        [-g2, -1.0 + zeros, -A * (gp[1] - gm[1]) / (2 * h), -A * (cp[1] - cm[1]) / dc_step]
    )
    J = np.vstack([Jf, Jg])
    # Columns scaled to unit norm first: d_c in m makes JᵀJ too ill-scaled for pinv's cutoff.
    norm = np.linalg.norm(J, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    Js = J / norm
    cov = np.linalg.pinv(Js.T @ Js) / np.outer(norm, norm) * chi2 / max(2 * n - 4, 1)
    edge = "high" if ly > hi_y - 1e-6 else ("low" if ly < lo_y + 1e-6 else "")
    return {
        "A_Hz": A,
        "A_err_Hz": np.sqrt(cov[0, 0]),
        "B_Hz": B,
        "B_err_Hz": np.sqrt(cov[1, 1]),
        "theta_per_m": theta,
        "lntheta_err": np.sqrt(cov[2, 2]),
        "cov_A_lntheta": cov[0, 2],
        "x_max": theta * umax,
        "d_c_m": d_c,
        "d_c_err_m": np.sqrt(cov[3, 3]),
        "edge": edge,
        "rss_df": rss_f,
        "rss_dgamma": rss_g,
    }


def fit_plateau_loops(u, df, dg, w, sigma_df, sigma_dg, u_c) -> pd.DataFrame:
    """Fit the exact plateau loop (+ dashpot) to every row of padded sweeps (module docstring).

    Parameters
    ----------
    u, df, dg, w : (S, M) amplitudes (m), shifts (Hz), weights (0 for padding)
    sigma_df, sigma_dg : (S,) noise levels of the two channels, Hz
    u_c : (S,) start of the critical displacement (the hinge of the plateau model), m

    Returns
    -------
    DataFrame with the columns of :func:`fit_cm_loops` (``theta_per_m`` = κ/(μF_N), ``x_max``
    = θ·max(u0); ``edge`` "high" if the excess beyond d_c reaches gross sliding beyond
    x = X_MAX, "low" if no slip is resolved) plus ``d_c_m`` and ``d_c_err_m``.
    """
    u_c = np.asarray(u_c, dtype=float)
    floor_f = 1e-6 * np.maximum(np.abs(df).max(axis=1), 1e-12)
    floor_g = 1e-6 * np.maximum(np.abs(dg).max(axis=1), 1e-12)
    # Start of θ: the Cattaneo-Mindlin loop fitted to the amplitudes in excess of the hinge.
    start = fit_cm_loops(np.maximum(u - u_c[:, None], 0.0), df, dg, w, sigma_df, sigma_dg)
    y0 = start["x_max"].to_numpy()
    rows = []
    for i in range(u.shape[0]):
        m = w[i] > 0
        point = (u[i][m], df[i][m], dg[i][m], sigma_df[i], sigma_dg[i])
        rows.append(_fit_one_plateau(*point, (floor_f[i], floor_g[i]), u_c[i], y0[i]))
    return pd.DataFrame(rows, index=range(u.shape[0]))


# Output column of each parameter of the registered amplitude models.
_COLUMN_OF = {
    "df0": "df0_Hz",
    "dgamma0": "dgamma0_Hz",
    "df_slope": "df_slope_Hz_per_m",
    "dgamma_slope": "dgamma_slope_Hz_per_m",
    "df_curvature": "df_curvature_Hz_per_m2",
    "dgamma_curvature": "dgamma_curvature_Hz_per_m2",
    "u_c": "plateau_amplitude_m",
    "A": "df0_Hz",
    "B": "dgamma0_Hz",
    "theta": "cm_theta_per_m",
    "d_c": "plateau_amplitude_m",
}
# Where a model's parameter lives in another column than _COLUMN_OF says.
_COLUMN_OVERRIDES = {"plateau-loop": {"theta": "pl_theta_per_m"}}


def model_curves(row, u) -> tuple[np.ndarray, np.ndarray]:
    """Δf(u0), ΔΓ(u0) in Hz of the model chosen for one sweep (a row of :func:`fit_sweeps`).

    Evaluates the registered model function (:data:`contactres.fitting.MODELS`) with the
    sweep's fitted values; a sweep whose limits come from an exact loop (Cattaneo-Mindlin or
    plateau) is drawn as that loop.
    """
    u = np.asarray(u, dtype=float)
    key = row["model"]
    exact = {"cm-loop": "cattaneo-mindlin-loop", "plateau-loop": "plateau-loop"}
    key = exact.get(row.get("limits_from"), key)
    model = MODELS[key]
    columns = {**_COLUMN_OF, **_COLUMN_OVERRIDES.get(key, {})}
    values = {p.key: row[columns[p.key]] for p in model.parameters}
    df, dg = model.function(u, **values)
    return np.broadcast_to(df, u.shape).astype(float), np.broadcast_to(dg, u.shape).astype(float)
