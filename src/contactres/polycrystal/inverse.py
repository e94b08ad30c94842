"""Inverse problem of a polycrystal map: cubic elastic constants from contact data per grain.

A measured map of contact stiffness k* (or of indentation modulus M) and the orientation of each
grain give, grain by grain, M(n; C) up to the calibration. The forward model (paper 1, Eq. 4;
Vlassak & Nix 1994): the indentation modulus of the grain,

    M(n; C) = 4π/I₀(n; C) = C11 · m(n; C12/C11, C44/C11)

(M is homogeneous of degree one in C, so m is M of the crystal with C11 = 1), in series with the
plane-strain modulus of the tip, 1/E* = 1/M + 1/M_tip, and the Hertz stiffness of a sphere of
radius R under a force F,

    a = (3 F R / (4 E*))^{1/3},   k* = 2 a E* = (6 F R)^{1/3} E*^{2/3}.

The measured value of grain i is therefore ``value_i = c · E*_i^p`` with p = 2/3 for a stiffness
map (c = (6 F R)^{1/3}, N^{1/3} m^{1/3}) and p = 1 for a modulus map (c = 1 for a map in Pa).

Parametrisation (logarithmic): ln(C12/C11), ln(C44/C11) and the scale. With a free calibration c
and a rigid tip only ln(c C11^p) is fitted (results: the ratios and the value on a (001) grain);
with a known c, ln C11 (Pa); with a compliant tip and a free c, both (C11 then enters weakly,
through E*/M). The weak combination of the ratios (~1e-5 of M per 1 %) is reported with its
error from the singular values of the weighted sensitivity (scale profiled out); one whose
relative error exceeds :data:`IDENTIFIABILITY_RTOL` is flagged and the ratios are NaN. M is exact
per grain (``rtol`` 1e-12); sensitivities are central differences (step 1e-3) of ln m.
Hexagonal crystals (four ratios) are not implemented.

Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010), Eq. 4. J. J. Vlassak and
W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..materials import Material
from .moduli import indentation_moduli

__all__ = [
    "IDENTIFIABILITY_RTOL",
    "CubicInverseResult",
    "fit_cubic_constants",
    "fit_map",
    "grain_means",
]

# Constants: relative error above which a combination is "not determined"; rtol of M (the weak
# direction needs ~1e-6 of M); central-difference step of the log-ratios; bounds of C12/C11 and
# C44/C11 (log-parametrised: C12 > 0); distance to a bound that counts as "at the bound"; the
# largest change of a log-parameter per solver iteration.
IDENTIFIABILITY_RTOL = 0.1
MODULUS_RTOL = 1e-12
LOG_STEP = 1e-3
RATIO_BOUNDS = ((1e-3, 0.99), (1e-3, 10.0))
BOUND_TOL = 1e-4
MAX_LOG_STEP = 0.2
QUANTITIES = {"stiffness": 2.0 / 3.0, "modulus": 1.0}


@dataclass(frozen=True)
class CubicInverseResult:
    """Cubic elastic constants fitted to per-grain contact data, with their identifiability.

    Values that are not determined (relative error above :data:`IDENTIFIABILITY_RTOL`, or a
    parameter at its bound) are NaN; ``warnings`` says why and which input to check.

    Attributes
    ----------
    quantity : "stiffness" (k*, N/m) or "modulus" (M, Pa)
    n_grains : number of grains fitted
    parameter_names : names of the fitted log-parameters (columns of ``covariance``)
    parameters : fitted values of the log-parameters (diagnostic, also when not determined)
    covariance : covariance of ``parameters`` (inflated by χ²/dof when that exceeds 1)
    c12_c11, c12_c11_error, c44_c11, c44_c11_error : the ratios and their standard errors
    ratio_covariance : 2x2 covariance of (C12/C11, C44/C11)
    c11, c12, c44, c11_error : Pa; NaN unless the scale of C is determined (known calibration,
        or a compliant tip that fixes it)
    calibration, calibration_error : the factor c of ``value = c E*^p`` (NaN when not separable)
    reference_value, reference_error : the measured quantity the fit predicts on a (001) grain
        (N/m or Pa), the calibration-free summary of the scale
    chi2, dof, chi2_dof : weighted residual sum, degrees of freedom and their ratio
    singular_values : of the weighted sensitivity matrix J (columns ``parameter_names``)
    ratio_singular_values : of J restricted to the two log-ratios after the scale parameters are
        profiled out (strong, weak)
    strong_direction, weak_direction : unit vectors (a, b): the combination
        a ln(C12/C11) + b ln(C44/C11), i.e. (C12/C11)^a (C44/C11)^b
    strong_combination, strong_error, weak_combination, weak_error : value of
        (C12/C11)^a (C44/C11)^b and its relative standard error (NaN value when not determined)
    strong_identified, weak_identified : relative error <= :data:`IDENTIFIABILITY_RTOL`
    at_bound : names of parameters that ended at a bound
    warnings : messages for the user (not determined, at a bound, poor fit)
    success, message, n_evaluations : of the optimiser
    """

    quantity: str
    n_grains: int
    parameter_names: tuple[str, ...]
    parameters: np.ndarray
    covariance: np.ndarray
    c12_c11: float
    c12_c11_error: float
    c44_c11: float
    c44_c11_error: float
    ratio_covariance: np.ndarray
    c11: float
    c12: float
    c44: float
    c11_error: float
    calibration: float
    calibration_error: float
    reference_value: float
    reference_error: float
    chi2: float
    dof: int
    chi2_dof: float
    singular_values: np.ndarray
    ratio_singular_values: np.ndarray
    strong_direction: np.ndarray
    weak_direction: np.ndarray
    strong_combination: float
    strong_error: float
    weak_combination: float
    weak_error: float
    strong_identified: bool
    weak_identified: bool
    at_bound: tuple[str, ...]
    warnings: tuple[str, ...]
    success: bool
    message: str
    n_evaluations: int

    def summary(self) -> str:
        """Plain-text report; quantities that are not determined are not printed as results."""
        (a, b), (sa, sb), s = self.weak_direction, self.strong_direction, self.ratio_singular_values
        weak = f"{self.weak_combination:.6g}" if self.weak_identified else "not determined"
        lines = [
            f"cubic constants from {self.n_grains} grains ({self.quantity} map)",
            f"  C12/C11 = {self.c12_c11:.5f} ± {self.c12_c11_error:.2g}",
            f"  C44/C11 = {self.c44_c11:.5f} ± {self.c44_c11_error:.2g}",
            f"  strong: (C12/C11)^{sa:.4f} (C44/C11)^{sb:.4f} = {self.strong_combination:.6g}"
            f" (rel. error {self.strong_error:.2g})",
            f"  weak: (C12/C11)^{a:.4f} (C44/C11)^{b:.4f} = {weak} (rel. error "
            f"{self.weak_error:.2g})",
            f"  ratio singular values {s[0]:.4g}, {s[1]:.4g}; chi2/dof = {self.chi2_dof:.3g}",
        ]
        if np.isfinite(self.c11):
            lines.insert(3, f"  C11 = {self.c11 / 1e9:.4g} ± {self.c11_error / 1e9:.2g} GPa")
        lines = [x.replace("nan", "not determined") for x in lines] + list(self.warnings)
        return "\n".join(lines)


def grain_means(labels, values, n_grains: int | None = None):
    """Per-grain mean, standard error and pixel count of a map (vectorised with bincount).

    Parameters
    ----------
    labels : array_like of int
        Grain label of each pixel (0 .. G−1); negative labels (unindexed pixels) are ignored,
        as are non-finite values.
    values : array_like of float, same shape
        Measured value per pixel (any unit).
    n_grains : int, optional
        G (default: the largest label + 1).

    Returns
    -------
    mean, error, count : ndarray, shape (G,)
        The mean, its standard error s/√N (sample standard deviation, ddof = 1) and N; NaN for
        grains with fewer than two pixels.
    """
    lab = np.asarray(labels).ravel()
    val = np.asarray(values, dtype=float).ravel()
    if lab.shape != val.shape:
        raise ValueError(f"labels and values differ in size: {lab.size} vs {val.size}")
    if not np.issubdtype(lab.dtype, np.integer):
        raise ValueError("labels must be integers")
    keep = (lab >= 0) & np.isfinite(val)
    lab, val = lab[keep], val[keep]
    G = int(lab.max(initial=-1)) + 1 if n_grains is None else int(n_grains)
    if lab.size and lab.max() >= G:
        raise ValueError(f"label {int(lab.max())} >= n_grains = {G}")
    count = np.bincount(lab, minlength=G).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.bincount(lab, weights=val, minlength=G) / count
        ss = np.bincount(lab, weights=(val - mean[lab]) ** 2, minlength=G)
        error = np.sqrt(ss / (count - 1) / count)
    few = count < 2
    mean[few] = np.nan
    error[few] = np.nan
    return mean, error, count.astype(int)


def _unit_moduli(r12: float, r44: float, R: np.ndarray) -> np.ndarray:
    """m = M/C11 of the orientations R for the ratios (r12, r44)."""
    return indentation_moduli(Material.cubic(1.0, r12, r44), R, rtol=MODULUS_RTOL)


def fit_cubic_constants(
    orientations,
    values,
    errors,
    quantity: str = "stiffness",
    tip_modulus: float | None = None,
    calibration: float | None = None,
    guess: dict[str, float] | None = None,
) -> CubicInverseResult:
    """Fit C12/C11, C44/C11 (and the scale) of a cubic crystal to per-grain contact data.

    Parameters
    ----------
    orientations : array_like, shape (G, 3, 3)
        Surface-frame matrices of the grains (rows = sample axes in crystal coordinates, the
        convention of :mod:`contactres.polycrystal.orientations`).
    values : array_like, shape (G,)
        Measured contact stiffness k* (N/m) or indentation modulus (Pa) per grain.
    errors : array_like, shape (G,)
        Standard errors of ``values`` (same unit), e.g. from :func:`grain_means`.
    quantity : {"stiffness", "modulus"}
        k* = c E*^{2/3} with c = (6 F R)^{1/3} (Hertz), or M = c E* (c = 1 for a map in Pa).
    tip_modulus : float, optional
        Plane-strain modulus of the tip E_t/(1 − ν_t²), Pa; None: a rigid tip.
    calibration : float, optional
        The known factor c (N^{1/3} m^{1/3} for stiffness: (6 F R)^{1/3}; 1 for a modulus map in
        Pa). None: c is free (one reference measurement fixes it only up to the crystal).
    guess : dict, optional
        Starting values: "c12_c11" (default 0.6), "c44_c11" (0.5), "c11" (Pa, default 150e9;
        the fixed scale C11 for a rigid tip with a free calibration, where it cancels).

    Returns
    -------
    CubicInverseResult
        The ratios with standard errors, the scale, χ² and the identifiability (singular values,
        strong and weak combinations of the ratios and their errors, flags).

    Notes
    -----
    Covariance (JᵀJ)⁻¹ · max(1, χ²/dof) (J: d((value − data)/error)/d ln parameter); a
    Jacobian costs five exact evaluations of M for all grains (~0.1-0.3 s for 60 Cu grains).
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {sorted(QUANTITIES)}, got {quantity!r}")
    p = QUANTITIES[quantity]
    R = np.asarray(orientations, dtype=float)
    y = np.asarray(values, dtype=float)
    sig = np.asarray(errors, dtype=float)
    G = y.size
    if R.shape != (G, 3, 3) or sig.shape != y.shape or y.ndim != 1:
        raise ValueError(
            f"need orientations (G, 3, 3), values (G,), errors (G,); got {R.shape}, "
            f"{y.shape}, {sig.shape}"
        )
    if not (np.all(np.isfinite(y)) and np.all(y > 0)):
        raise ValueError("values must be finite and positive")
    if not (np.all(np.isfinite(sig)) and np.all(sig > 0)):
        raise ValueError("errors must be finite and positive (drop grains without an error)")
    rigid = tip_modulus is None
    mt = np.inf if rigid else float(tip_modulus)
    if not mt > 0:
        raise ValueError(f"tip_modulus must be positive, got {tip_modulus!r}")
    if calibration is not None and not (np.isfinite(calibration) and calibration > 0):
        raise ValueError(f"calibration must be finite and positive, got {calibration!r}")
    g = {"c12_c11": 0.6, "c44_c11": 0.5, "c11": 150e9, **(guess or {})}
    free_c = calibration is None
    fit_c11 = not (rigid and free_c)
    names = (["ln_calibration"] if free_c else []) + (["ln_c11"] if fit_c11 else [])
    names += ["ln_c12_c11", "ln_c44_c11"]
    n_scale = len(names) - 2
    c11_fixed = float(g["c11"])
    ln_c0 = np.log(calibration) if not free_c else 0.0

    def split(theta):
        ln_c = theta[0] if free_c else ln_c0
        ln_c11 = theta[n_scale - 1] if fit_c11 else np.log(c11_fixed)
        return ln_c, ln_c11, theta[-2], theta[-1]

    def log_model(theta, orient, jacobian: bool = True):
        """ln value and d ln value/d theta (None unless ``jacobian``) for ``orient``."""
        ln_c, ln_c11, l12, l44 = split(theta)
        m0 = _unit_moduli(np.exp(l12), np.exp(l44), orient)
        M = np.exp(ln_c11) * m0
        frac = 1.0 if rigid else mt / (M + mt)  # E*/M
        ln_value = ln_c + p * np.log(M * frac)
        if not jacobian:
            return ln_value, None
        dlnm = []
        for k in (0, 1):
            lp, lm = np.array([l12, l44]), np.array([l12, l44])
            lp[k] += LOG_STEP
            lm[k] -= LOG_STEP
            mp = _unit_moduli(*np.exp(lp), orient)
            mm = _unit_moduli(*np.exp(lm), orient)
            dlnm.append((np.log(mp) - np.log(mm)) / (2 * LOG_STEP))
        cols = ([np.ones_like(M)] if free_c else []) + ([p * frac] if fit_c11 else [])
        cols += [p * frac * d for d in dlnm]
        jac = np.column_stack([c * np.ones_like(M) for c in cols])
        return ln_value, jac

    lo = np.array([-np.inf] * n_scale + [np.log(b[0]) for b in RATIO_BOUNDS])
    hi = np.array([np.inf] * n_scale + [np.log(b[1]) for b in RATIO_BOUNDS])
    theta0 = np.array(
        ([0.0] if free_c else [])
        + ([np.log(c11_fixed)] if fit_c11 else [])
        + [np.log(g["c12_c11"]), np.log(g["c44_c11"])]
    )
    counter = [0]

    def evaluate(theta, jacobian: bool):
        counter[0] += 1
        lv, jl = log_model(theta, R, jacobian)
        v = np.exp(lv)
        return (v - y) / sig, None if jl is None else (v / sig)[:, None] * jl

    if free_c:
        lv0, _ = log_model(theta0, R, False)
        theta0[0] = float(np.mean(np.log(y) - lv0))
    sol = _levenberg_marquardt(evaluate, np.clip(theta0, lo + 0.01, hi - 0.01), lo, hi)
    theta = sol[0]
    r, J = evaluate(theta, True)
    model = (names, n_scale, split, log_model)
    setup = (quantity, calibration, fit_c11, (lo, hi))
    return _result(theta, r, J, model, setup, sol, counter[0])


def _result(theta, r, J, model, setup, sol, nfev: int) -> CubicInverseResult:
    """Covariance, identifiability and the reported values of a finished fit."""
    names, n_scale, split, log_model = model
    quantity, calibration, fit_c11, (lo, hi) = setup
    (G, P), chi2 = J.shape, float(r @ r)
    dof = G - P
    chi2_dof = chi2 / dof if dof > 0 else np.nan
    inflate = max(1.0, chi2_dof) if dof > 0 else 1.0
    _, s, Vt = np.linalg.svd(J, full_matrices=False)
    tiny = s.max() * 1e-14
    inv_s2 = np.where(s > tiny, 1.0 / np.where(s > tiny, s, 1.0) ** 2, np.inf)
    with np.errstate(invalid="ignore"):
        cov = (Vt.T * inv_s2) @ Vt * inflate
    cov = np.where(np.isnan(cov), np.inf, cov)
    Jr = J[:, n_scale:]
    if n_scale:
        Q, _ = np.linalg.qr(J[:, :n_scale])
        Jr = Jr - Q @ (Q.T @ Jr)
    _, sr, Vr = np.linalg.svd(Jr, full_matrices=False)
    dirs = []
    for v in Vr:
        v = v / np.linalg.norm(v)
        dirs.append(v if v[np.argmax(np.abs(v))] > 0 else -v)
    strong, weak = dirs
    lr = theta[n_scale:]
    rel = [np.sqrt(inflate) / x if x > 0 else np.inf for x in sr]
    strong_ok, weak_ok = (e <= IDENTIFIABILITY_RTOL for e in rel)

    at_bound = tuple(
        n
        for n, t, a, b in zip(names, theta, lo, hi, strict=True)
        if t - a < BOUND_TOL or b - t < BOUND_TOL
    )
    warnings = []
    if at_bound:
        warnings.append(
            f"{', '.join(at_bound)} at the bound: values not reported; check the orientations "
            "(frame convention), the quantity ('stiffness' vs 'modulus') and the errors"
        )
    if not weak_ok:
        warnings.append(
            f"the weak combination (C12/C11)^{weak[0]:.3f} (C44/C11)^{weak[1]:.3f} is not "
            f"determined (relative error {rel[1]:.2g} > {IDENTIFIABILITY_RTOL:g}): the ratios "
            "are not reported; more grains or smaller errors per grain are needed"
        )
    if not strong_ok:
        warnings.append(
            f"even the strong combination is not determined (relative error {rel[0]:.2g}): "
            "check that the map varies with orientation"
        )
    if dof > 0 and chi2_dof > 3.0:
        warnings.append(
            f"chi2/dof = {chi2_dof:.3g}: the errors are underestimated or the model misses "
            "something (tip, calibration drift, wrong orientations); errors inflated"
        )
    if not sol[1]:
        warnings.append(f"optimiser: {sol[2]}")
    ratio_ok = weak_ok and strong_ok and not any(n in at_bound for n in names[n_scale:])
    ratios = np.exp(lr)
    rcov = cov[n_scale:, n_scale:] * np.outer(ratios, ratios)

    def nan_unless(ok, x):  # values not determined are NaN, never printed
        return float(x) if ok else np.nan

    ln_c, ln_c11, _, _ = split(theta)
    c11_ok = fit_c11 and ratio_ok and np.sqrt(cov[n_scale - 1, n_scale - 1]) <= IDENTIFIABILITY_RTOL
    c11 = np.exp(ln_c11)
    c11_err = c11 * np.sqrt(cov[n_scale - 1, n_scale - 1]) if fit_c11 else np.nan
    if fit_c11 and not c11_ok:
        warnings.append(
            f"C11 not determined (relative error {c11_err / c11:.2g}): give the calibration "
            "(F R) or a measurement on a reference of known modulus"
        )
    free_c = calibration is None
    cal_ok = free_c and fit_c11 and np.sqrt(cov[0, 0]) <= IDENTIFIABILITY_RTOL
    cal = np.exp(ln_c) if (cal_ok or not free_c) else np.nan
    cal_err = (
        np.exp(ln_c) * np.sqrt(cov[0, 0]) if free_c and fit_c11 else (0.0 if not free_c else np.nan)
    )
    lv_ref, j_ref = log_model(theta, np.eye(3)[None])
    ref = float(np.exp(lv_ref[0]))
    ref_var = float(j_ref[0] @ np.where(np.isfinite(cov), cov, 0.0) @ j_ref[0])
    ref_ok = bool(np.all(np.isfinite(cov[:n_scale, :n_scale]))) and not at_bound
    return CubicInverseResult(
        quantity=quantity,
        n_grains=G,
        parameter_names=tuple(names),
        parameters=theta.copy(),
        covariance=cov,
        c12_c11=nan_unless(ratio_ok, ratios[0]),
        c12_c11_error=float(np.sqrt(rcov[0, 0])),
        c44_c11=nan_unless(ratio_ok, ratios[1]),
        c44_c11_error=float(np.sqrt(rcov[1, 1])),
        ratio_covariance=rcov,
        c11=nan_unless(c11_ok, c11),
        c12=nan_unless(c11_ok, c11 * ratios[0]),
        c44=nan_unless(c11_ok, c11 * ratios[1]),
        c11_error=float(c11_err),
        calibration=float(cal),
        calibration_error=float(cal_err),
        reference_value=nan_unless(ref_ok, ref),
        reference_error=float(ref * np.sqrt(ref_var)),
        chi2=chi2,
        dof=dof,
        chi2_dof=float(chi2_dof),
        singular_values=s,
        ratio_singular_values=sr,
        strong_direction=strong,
        weak_direction=weak,
        strong_combination=nan_unless(strong_ok, np.exp(strong @ lr)),
        strong_error=float(rel[0]),
        weak_combination=nan_unless(weak_ok and strong_ok, np.exp(weak @ lr)),
        weak_error=float(rel[1]),
        strong_identified=bool(strong_ok),
        weak_identified=bool(weak_ok),
        at_bound=at_bound,
        warnings=tuple(warnings),
        success=bool(sol[1]),
        message=str(sol[2]),
        n_evaluations=nfev,
    )


def _levenberg_marquardt(
    evaluate, theta, lo, hi, max_iter: int = 30
) -> tuple[np.ndarray, bool, str]:
    """Levenberg-Marquardt with geodesic acceleration (Transtrum & Sethna, arXiv:1201.5885): the
    weak valley is long and curved in the log-ratios; the second-order term bends the step."""
    r, J = evaluate(theta, True)
    chi2 = float(r @ r)
    lam = 1e-6
    h = 0.1
    for _ in range(max_iter):
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        keep = s > s[0] * 1e-13
        s_k, U_k, V_k = s[keep], U[:, keep], Vt[keep].T
        for _ in range(12):
            filt = s_k / (s_k**2 + lam * s[0] ** 2)
            v = -(V_k @ (filt * (U_k.T @ r)))
            v *= min(1.0, MAX_LOG_STEP / max(float(np.max(np.abs(v))), 1e-300))
            r_h, _ = evaluate(np.clip(theta + h * v, lo, hi), False)
            rvv = (2.0 / h) * ((r_h - r) / h - J @ v)
            acc = -(V_k @ (filt * (U_k.T @ rvv)))
            ok = 2 * np.linalg.norm(acc) <= 0.75 * np.linalg.norm(v)
            if ok:
                trial = np.clip(theta + v + 0.5 * acc, lo, hi)
                r_t, _ = evaluate(trial, False)
                chi2_t = float(r_t @ r_t)
                if chi2_t <= chi2:
                    break
            lam = lam * 10.0
        else:
            return theta, False, "no step lowers chi2 (damping exhausted)"
        moved = float(np.max(np.abs(trial - theta)))
        improved = chi2 - chi2_t
        theta = trial
        lam = max(lam / 10.0, 1e-9)
        if moved < 1e-9 or improved <= 1e-9 * max(chi2, 1.0):
            return theta, True, f"converged (last step {moved:.2g})"
        r, J = evaluate(theta, True)
        chi2 = chi2_t
    return theta, False, f"no convergence in {max_iter} iterations"


def fit_map(labels, values, grain_orientations, **kwargs) -> CubicInverseResult:
    """Fit a pixel map: per-grain means and standard errors (:func:`grain_means`), then the fit.

    ``labels`` (H, W) int: grain label per pixel (0 .. G−1; negative: unindexed); ``values``
    (H, W): k* (N/m) or M (Pa); ``grain_orientations`` (G, 3, 3) indexed by label; ``kwargs`` go
    to :func:`fit_cubic_constants`. Grains with fewer than two pixels are left out. An
    unlabelled EBSD map needs a grain reconstruction first.
    """
    R = np.asarray(grain_orientations, dtype=float)
    mean, err, _ = grain_means(labels, values, n_grains=R.shape[0])
    ok = np.isfinite(mean) & np.isfinite(err) & (err > 0)
    return fit_cubic_constants(R[ok], mean[ok], err[ok], **kwargs)
