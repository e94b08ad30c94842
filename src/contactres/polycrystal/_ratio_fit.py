"""The fit shared by every lattice: ratios Cij/C11 and the scale from per-grain contact data.

A measured map of contact stiffness k* (or of indentation modulus M) and the orientation of each
grain give, grain by grain, M(n; C) up to the calibration. The forward model (paper 1, Eq. 4;
Vlassak & Nix 1994): the indentation modulus of the grain,

    M(n; C) = 4π/I₀(n; C) = C11 · m(n; r)

(M is homogeneous of degree one in C, so m is M of the crystal with C11 = 1 and the other
constants r = (Cij/C11)), in series with the plane-strain modulus of the tip,
1/E* = 1/M + 1/M_tip, and the Hertz stiffness of a sphere of radius R under a force F,

    a = (3 F R / (4 E*))^{1/3},   k* = 2 a E* = (6 F R)^{1/3} E*^{2/3}.

The measured value of grain i is therefore ``value_i = c · E*_i^p`` with p = 2/3 for a stiffness
map (c = (6 F R)^{1/3}, N^{1/3} m^{1/3}) and p = 1 for a modulus map (c = 1 for a map in Pa).

A lattice enters only through a :class:`RatioParametrisation`: the names of its ratios, the unit
crystal (C11 = 1) they define, and their bounds. The fit is in ln r and the scale: with a free
calibration c and a rigid tip only ln(c C11^p); with a known c, ln C11 (Pa); with a compliant tip
and a free c, both (C11 then enters weakly, through E*/M). The identifiability comes from the
singular values of the weighted sensitivity with the scale profiled out: the combination
``v · ln r`` of singular value s has the relative error 1/s; one above
:data:`IDENTIFIABILITY_RTOL` is not determined. M is exact per grain (``rtol`` 1e-12);
sensitivities are central differences (step 1e-3) of ln m.

Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010), Eq. 4. J. J. Vlassak and
W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from .._summary import number, plus_minus
from ..errors import ContactresInputError
from ..fitting import LMOptions, levenberg_marquardt
from ..materials import Material
from ._moduli import moduli_and_points

__all__ = [
    "CONDITIONAL_NOTE",
    "IDENTIFIABILITY_RTOL",
    "QUANTITIES",
    "RatioFit",
    "RatioParametrisation",
    "fit_ratios",
    "summary_text",
]

# Constants: relative error above which a combination is "not determined"; rtol of M (a weak
# direction needs ~1e-6 of M); central-difference step of the log-ratios; distance to a bound
# that counts as "at the bound"; the smallest eigenvalue of the unit stiffness (C11 = 1, Voigt)
# accepted during a fit: positive definiteness with a margin that keeps the central differences
# (0.1 % steps of the ratios) inside the stable region too.
IDENTIFIABILITY_RTOL = 0.1

MODULUS_RTOL = 1e-12
LOG_STEP = 1e-3
BOUND_TOL = 1e-4
MIN_EIGENVALUE = 1e-2
QUANTITIES = {"stiffness": 2.0 / 3.0, "modulus": 1.0}

#: The largest change of a log-parameter per step: the valleys of the fits are long and curved,
#: and a linearised step much longer than this leaves them.
MAX_LOG_STEP = 0.2

#: The Levenberg-Marquardt iteration of the fit (:func:`contactres.fitting.levenberg_marquardt`):
#: all parameters are logarithms, so Levenberg's damping λ s₀² I (s₀ the largest singular value
#: of the weighted sensitivity), divided or multiplied by 10 (at least 1e-9, starting at 1e-6);
#: geodesic acceleration (Transtrum & Sethna 2012) with h = 0.1 bends the steps along the curved
#: valleys; steps of at most MAX_LOG_STEP. Converged when a step moves every log-parameter by
#: <= 1e-9 or lowers χ² by <= 1e-9 max(χ², 1) (accepted steps only); failed after 12 rejected
#: steps in a row or 30 accepted ones. A stiffness that is not positive definite is outside the
#: admissible region: the step is rejected, as one that raises χ², so no penalty term biases the
#: minimum.
RATIO_LM = LMOptions(
    damping="levenberg",
    update="tenfold",
    lam0=1e-6,
    lam_min=1e-9,
    max_reject=12,
    geodesic=0.1,
    max_step=MAX_LOG_STEP,
    xtol=0.0,
    x_abs=1e-9,
    ftol=1e-9,
    chi2_floor=1.0,
    judge_failed=False,
    max_iter=30 * 13,  # never reached first: 30 accepted steps, each after <= 11 failures
    max_accepted=30,
)

#: Said under a summary when a combination is not determined: the errors printed are those of a
#: linearisation at the fitted point, which the curved valley of the undetermined combination
#: can make too small.
CONDITIONAL_NOTE = (
    "  (errors of the determined combinations hold with the undetermined one fixed at its "
    "fitted value; along it the valley is curved and they can be too small)"
)

#: Width of a summary's lines (characters): a note or a warning longer than this is wrapped,
#: its continuation indented, so that a terminal of 100 columns shows it whole.
SUMMARY_WIDTH = 100


def fit_facts(result, ratios) -> list[tuple[str, str]]:
    """The summary of a cubic or hexagonal fit (its ``repr``): the quantity and grains, the
    ``ratios`` given as (name, value, error), C11 (GPa) where determined, χ²/dof, warnings."""
    facts = [("", f"{result.quantity} map, {result.n_grains} grains")]
    facts += [(name, plus_minus(v, e)) for name, v, e in ratios]
    if np.isfinite(result.c11):
        facts.append(("C11", plus_minus(result.c11, result.c11_error, "GPa", 1e9)))
    facts.append(("χ²/dof", number(result.chi2_dof)))
    return [*facts, ("warnings", str(len(result.warnings)))]


def summary_text(lines, warnings) -> str:
    """A fit's summary: its ``lines`` ("nan" read as "not determined") and its ``warnings``,
    each wrapped at :data:`SUMMARY_WIDTH` characters with the continuation indented."""
    import textwrap

    out = []
    for line in [x.replace("nan", "not determined") for x in lines] + list(warnings):
        indent = " " * (len(line) - len(line.lstrip()) + 2)
        wrapped = textwrap.wrap(
            line, SUMMARY_WIDTH, subsequent_indent=indent, break_on_hyphens=False
        )
        out += wrapped or [line]  # an empty line stays
    return "\n".join(out)


@dataclass(frozen=True)
class RatioParametrisation:
    """What a lattice contributes to the fit: its ratios Cij/C11 and the unit crystal.

    Attributes
    ----------
    lattice : str
        Name of the lattice ("cubic", "hexagonal").
    names : keys of the ratios (``guess`` keys, e.g. "c12_c11")
    labels : printed names of the ratios (e.g. "C12/C11")
    unit_material : ratios (dimensionless array) -> the crystal with C11 = 1 in its crystal frame
    bounds : (low, high) of each ratio (dimensionless, positive: the fit is in ln r)
    default_guess : starting ratios
    advice : what to do when a combination is not determined (ends a warning)
    """

    lattice: str
    names: tuple[str, ...]
    labels: tuple[str, ...]
    unit_material: Callable[[np.ndarray], Material]
    bounds: tuple[tuple[float, float], ...]
    default_guess: tuple[float, ...]
    advice: str

    def combination(self, direction) -> str:
        """``(C12/C11)^a (C44/C11)^b ...``: the product ``exp(direction · ln r)`` as text."""
        return " ".join(f"({n})^{a:.3f}" for n, a in zip(self.labels, direction, strict=True))

    def admissible(self, ratios: np.ndarray) -> bool:
        """True when the unit stiffness is positive definite with the margin MIN_EIGENVALUE."""
        try:
            C = np.asarray(self.unit_material(ratios).C).real
        except ValueError:  # Material itself refuses a stiffness that is not positive definite
            return False
        return bool(np.linalg.eigvalsh(C)[0] > MIN_EIGENVALUE)


@dataclass(frozen=True)
class RatioFit:
    """The raw outcome of :func:`fit_ratios`; the lattice results decide what to print.

    Attributes
    ----------
    quantity : "stiffness" (k*, N/m) or "modulus" (M, Pa)
    n_grains, n_scale : grains fitted; number of scale parameters (first columns)
    parameter_names, parameters, covariance : the log-parameters, their values and covariance
        (inflated by χ²/dof when that exceeds 1)
    ratios, ratio_covariance : fitted Cij/C11 (also when not determined) and their covariance
    singular_values : of the weighted sensitivity J
    ratio_singular_values : of J over the log-ratios with the scale profiled out (descending)
    directions : rows: unit vectors over the log-ratios, strong to weak (largest entry > 0)
    combinations, combination_errors : ``exp(direction · ln r)`` and its relative error
    identified : combination_errors <= :data:`IDENTIFIABILITY_RTOL`
    ratios_determined : every combination identified and no ratio at a bound
    c11, c11_error, c11_determined : Pa (fitted or the fixed guess)
    calibration, calibration_error : c (NaN when not separable)
    reference_value, reference_error : the prediction on the grain with the crystal z axis
        normal to the surface ((001) cubic, (0001) hexagonal), N/m or Pa; NaN when not determined
    chi2, dof, chi2_dof, at_bound, warnings, success, message, n_evaluations : as named
    """

    quantity: str
    n_grains: int
    n_scale: int
    parameter_names: tuple[str, ...]
    parameters: np.ndarray
    covariance: np.ndarray
    ratios: np.ndarray
    ratio_covariance: np.ndarray
    singular_values: np.ndarray
    ratio_singular_values: np.ndarray
    directions: np.ndarray
    combinations: np.ndarray
    combination_errors: np.ndarray
    identified: np.ndarray
    ratios_determined: bool
    c11: float
    c11_error: float
    c11_determined: bool
    calibration: float
    calibration_error: float
    reference_value: float
    reference_error: float
    chi2: float
    dof: int
    chi2_dof: float
    at_bound: tuple[str, ...]
    warnings: tuple[str, ...]
    success: bool
    message: str
    n_evaluations: int


def check_inputs(orientations, values, errors, quantity: str, tip_modulus, calibration):
    """Validated (R (G, 3, 3), values (G,), errors (G,), p, tip modulus in Pa or inf)."""
    if quantity not in QUANTITIES:
        raise ContactresInputError(
            f"quantity must be one of {sorted(QUANTITIES)}, got {quantity!r}"
        )
    R = np.asarray(orientations, dtype=float)
    y = np.asarray(values, dtype=float)
    sig = np.asarray(errors, dtype=float)
    G = y.size
    if R.shape != (G, 3, 3) or sig.shape != y.shape or y.ndim != 1:
        raise ContactresInputError(
            f"need orientations (G, 3, 3), values (G,), errors (G,); got {R.shape}, "
            f"{y.shape}, {sig.shape}"
        )
    if not (np.all(np.isfinite(y)) and np.all(y > 0)):
        raise ContactresInputError("values must be finite and positive")
    if not (np.all(np.isfinite(sig)) and np.all(sig > 0)):
        raise ContactresInputError(
            "errors must be finite and positive (drop grains without an error)"
        )
    mt = np.inf if tip_modulus is None else float(tip_modulus)
    if not mt > 0:
        raise ContactresInputError(f"tip_modulus must be positive, got {tip_modulus!r}")
    if calibration is not None and not (np.isfinite(calibration) and calibration > 0):
        raise ContactresInputError(f"calibration must be finite and positive, got {calibration!r}")
    return R, y, sig, QUANTITIES[quantity], mt


def fit_ratios(
    param: RatioParametrisation,
    orientations,
    values,
    errors,
    quantity: str = "stiffness",
    tip_modulus: float | None = None,
    calibration: float | None = None,
    guess: Mapping[str, float] | None = None,
) -> RatioFit:
    """Fit ln(Cij/C11) of ``param`` and the scale to per-grain contact data.

    Parameters
    ----------
    param : RatioParametrisation
        The lattice.
    orientations, values, errors, quantity, tip_modulus, calibration
        As :func:`contactres.polycrystal.fit_cubic_constants`: surface matrices
        (G, 3, 3); k* (N/m) or M (Pa) per grain and its standard errors; tip plane-strain
        modulus (Pa, None: rigid); the factor c of ``value = c E*^p`` (None: free).
    guess : mapping, optional
        Starting ratios by ``param.names`` and "c11" (Pa, default 150e9; the fixed scale for a
        rigid tip with a free calibration, where it cancels).

    Returns
    -------
    RatioFit
    """
    R, y, sig, p, mt = check_inputs(
        orientations, values, errors, quantity, tip_modulus, calibration
    )
    k = len(param.names)
    unknown = set(guess or {}) - {*param.names, "c11"}
    if unknown:
        raise ContactresInputError(
            f"unknown guess keys {sorted(unknown)}; use {[*param.names, 'c11']}"
        )
    g = {**dict(zip(param.names, param.default_guess, strict=True)), "c11": 150e9, **(guess or {})}
    rigid, free_c = np.isinf(mt), calibration is None
    fit_c11 = not (rigid and free_c)
    names = (["ln_calibration"] if free_c else []) + (["ln_c11"] if fit_c11 else [])
    n_scale = len(names)
    names += [f"ln_{n}" for n in param.names]
    ln_c11_fixed = np.log(float(g["c11"]))
    ln_c0 = 0.0 if calibration is None else np.log(calibration)  # free_c: None

    def split(theta):
        ln_c = theta[0] if free_c else ln_c0
        return ln_c, (theta[n_scale - 1] if fit_c11 else ln_c11_fixed), theta[n_scale:]

    # m of the grains R per unit crystal of the previous evaluation, by the bits of its ratios:
    # the iteration asks for a trial's point again for its Jacobian, and the covariance asks
    # for the last point again (12 of 55 and 12 of 53 moduli rows in two cubic test fits were
    # such repeats; no repeat comes from further back). A row is the same bits alone as in any
    # stack (moduli_and_points), so a kept row is the row the call would compute.
    last: dict[bytes, np.ndarray] = {}
    # θ points of M's rule that the fastest row of the last evaluation on the grains needed:
    # the next rows (ratios a step away, as many points) take them in one stacked call
    # instead of one call per doubling; the same points of the same rule, so the same bits.
    points: list[int | None] = [None]

    def log_model(theta, orient, jacobian: bool = True):
        """ln value and d ln value/d theta (None unless ``jacobian``) for ``orient``."""
        ln_c, ln_c11, lr = split(theta)
        # The unit crystal at lr, then (with the Jacobian) at lr ± LOG_STEP along each ratio:
        # the rows kept from the previous evaluation, the others from one stacked evaluation
        # (each row the bits of its own indentation_moduli call either way).
        steps = [np.zeros(k)] + (
            [s * LOG_STEP * np.eye(k)[j] for j in range(k) for s in (1, -1)] if jacobian else []
        )
        ratios = [np.exp(lr + step) for step in steps]
        keys = [r.tobytes() for r in ratios]
        rows = dict(last) if orient is R else {}  # (the reference face of assemble is not R)
        new = [i for i, key in enumerate(keys) if key not in rows]
        if new:
            units = [param.unit_material(ratios[i]) for i in new]
            if orient is R:
                fresh, points[0] = moduli_and_points(units, R, MODULUS_RTOL, points[0])
            else:
                fresh, _ = moduli_and_points(units, orient, MODULUS_RTOL)
            rows.update((keys[i], row) for i, row in zip(new, fresh, strict=True))
        m = np.stack([rows[key] for key in keys])
        if orient is R:
            last.clear()
            last.update(zip(keys, m, strict=True))
        M = np.exp(ln_c11) * m[0]
        frac = 1.0 if rigid else mt / (M + mt)  # E*/M
        ln_value = ln_c + p * np.log(M * frac)
        if not jacobian:
            return ln_value, None
        cols = ([np.ones_like(M)] if free_c else []) + (
            [p * frac * np.ones_like(M)] if fit_c11 else []
        )
        for j in range(k):
            d = np.log(m[1 + 2 * j] / m[2 + 2 * j])
            cols.append(p * frac * d / (2 * LOG_STEP))
        return ln_value, np.column_stack(cols)

    lo = np.array([-np.inf] * n_scale + [np.log(b[0]) for b in param.bounds])
    hi = np.array([np.inf] * n_scale + [np.log(b[1]) for b in param.bounds])
    # The central differences reach LOG_STEP beyond theta: keep them inside the bounds too.
    lo_in, hi_in = lo + 2 * LOG_STEP, hi - 2 * LOG_STEP
    counter = [0]

    def evaluate(theta, jacobian: bool):
        counter[0] += 1
        if not param.admissible(np.exp(theta[n_scale:])):
            return None, None
        lv, jl = log_model(theta, R, jacobian)
        v = np.exp(lv)
        return (v - y) / sig, None if jl is None else (v / sig)[:, None] * jl

    theta0 = np.array(
        ([0.0] if free_c else [])
        + ([ln_c11_fixed] if fit_c11 else [])
        + [np.log(g[n]) for n in param.names]
    )
    theta0 = np.clip(theta0, lo + 0.01, hi - 0.01)
    if not param.admissible(np.exp(theta0[n_scale:])):
        raise ContactresInputError(
            f"the guess {dict(zip(param.names, np.exp(theta0[n_scale:]), strict=True))} is not a "
            f"stable {param.lattice} crystal (stiffness not positive definite)"
        )
    if free_c:
        theta0[0] = float(np.mean(np.log(y) - log_model(theta0, R, False)[0]))

    def batch(p, rows, jacobian):  # one problem: a batch of one
        r, jac = evaluate(p[0], jacobian)
        if r is None:  # outside the admissible region
            return {"residuals": np.full((1, y.size), np.nan)}
        return {"residuals": r[None], "jacobian": None if jac is None else jac[None]}

    res = levenberg_marquardt(batch, theta0, lo_in, hi_in, RATIO_LM)
    if not np.isfinite(res.chi2[0]):
        raise ContactresInputError("the starting point is outside the admissible region")
    sol = (res.x[0], bool(res.converged[0]), res.message(0))
    theta = sol[0]
    r, J = evaluate(theta, True)
    model = (param, names, n_scale, split, log_model, (lo, hi))
    return assemble(theta, r, J, model, (quantity, calibration, fit_c11), sol, counter[0])


def profiled_ratio_svd(J: np.ndarray, n_scale: int):
    """Singular values and sign-fixed right singular vectors of J over the ratios, scale profiled.

    The columns of the scale parameters are projected out of the ratio columns (what the ratios
    must explain beyond a change of scale); each direction has its largest entry positive.
    """
    Jr = J[:, n_scale:]
    if n_scale:
        Q, _ = np.linalg.qr(J[:, :n_scale])
        Jr = Jr - Q @ (Q.T @ Jr)
    _, sr, Vr = np.linalg.svd(Jr, full_matrices=False)
    signs = np.sign(Vr[np.arange(len(Vr)), np.argmax(np.abs(Vr), axis=1)])
    return sr, Vr * signs[:, None]


def assemble(theta, r, J, model, setup, sol, nfev: int) -> RatioFit:
    """Covariance, identifiability, warnings and the scale of a finished fit."""
    param, names, n_scale, split, log_model, (lo, hi) = model
    quantity, calibration, fit_c11 = setup
    (G, P), chi2 = J.shape, float(r @ r)
    dof = G - P
    chi2_dof = chi2 / dof if dof > 0 else np.nan
    inflate = max(1.0, chi2_dof) if dof > 0 else 1.0
    finite_j = bool(np.isfinite(J).all())
    if finite_j:
        _, s, Vt = np.linalg.svd(J, full_matrices=False)
        tiny = s.max() * 1e-14
        inv_s2 = np.where(s > tiny, 1.0 / np.where(s > tiny, s, 1.0) ** 2, np.inf)
        with np.errstate(invalid="ignore"):
            cov = (Vt.T * inv_s2) @ Vt * inflate
        cov = np.where(np.isnan(cov), np.inf, cov)
        sr, dirs = profiled_ratio_svd(J, n_scale)
    else:
        # The solver stopped where the model's derivatives are not finite (its message, in
        # the warnings, says so): no curvature there, so no error is finite and no combination
        # of the ratios is determined (LAPACK's SVD of such a J raised an internal error).
        s, cov = np.full(P, np.nan), np.full((P, P), np.inf)
        sr, dirs = np.full(P - n_scale, np.nan), np.eye(P - n_scale)
    lr = theta[n_scale:]
    with np.errstate(divide="ignore"):
        rel = np.where(sr > 0, np.sqrt(inflate) / np.where(sr > 0, sr, 1.0), np.inf)
    identified = rel <= IDENTIFIABILITY_RTOL
    at_bound = tuple(
        n
        for n, t, a, b in zip(names, theta, lo, hi, strict=True)
        if t - a < BOUND_TOL + 2 * LOG_STEP or b - t < BOUND_TOL + 2 * LOG_STEP
    )
    warnings = []
    if at_bound:
        warnings.append(
            f"{', '.join(at_bound)} at the bound: values not reported; check the orientations "
            "(frame convention), the quantity ('stiffness' vs 'modulus') and the errors"
        )
    n_ok, k = int(identified.sum()), len(lr)
    if not finite_j:
        warnings.append(
            "no error and no combination of the ratios determined: the model's derivatives "
            "are not finite at the last point of the fit"
        )
    elif n_ok < k:
        missing = "; ".join(
            f"{param.combination(d)} (relative error {e:.2g})"
            for d, e in zip(dirs[n_ok:], rel[n_ok:], strict=True)
        )
        warnings.append(
            f"{n_ok} of {k} combinations of the ratios determined; not determined (relative "
            f"error > {IDENTIFIABILITY_RTOL:g}): {missing}. The individual ratios are not "
            f"reported; {param.advice}"
        )
    if n_ok == 0 and finite_j:
        warnings.append(
            f"even the strongest combination is not determined (relative error {rel[0]:.2g}): "
            "check that the map varies with orientation"
        )
    if dof > 0 and chi2_dof > 3.0:
        warnings.append(
            f"chi2/dof = {chi2_dof:.3g}: the errors are underestimated or the model misses "
            "something (tip, calibration drift, wrong orientations); errors inflated"
        )
    if not sol[1]:
        warnings.append(f"optimiser: {sol[2]}")
    ratios_ok = n_ok == k and not any(n in at_bound for n in names[n_scale:])
    ratios = np.exp(lr)
    ln_c, ln_c11, _ = split(theta)
    c11 = float(np.exp(ln_c11))
    var_c11 = cov[n_scale - 1, n_scale - 1] if fit_c11 else np.nan
    c11_ok = bool(fit_c11 and ratios_ok and np.sqrt(var_c11) <= IDENTIFIABILITY_RTOL)
    c11_err = c11 * np.sqrt(var_c11)
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
    return RatioFit(
        quantity=quantity,
        n_grains=G,
        n_scale=n_scale,
        parameter_names=tuple(names),
        parameters=theta.copy(),
        covariance=cov,
        ratios=ratios,
        ratio_covariance=cov[n_scale:, n_scale:] * np.outer(ratios, ratios),
        singular_values=s,
        ratio_singular_values=sr,
        directions=dirs,
        combinations=np.exp(dirs @ lr),
        combination_errors=rel,
        identified=identified,
        ratios_determined=bool(ratios_ok),
        c11=c11,
        c11_error=float(c11_err),
        c11_determined=c11_ok,
        calibration=float(cal),
        calibration_error=float(cal_err),
        reference_value=ref if ref_ok else np.nan,
        reference_error=float(ref * np.sqrt(ref_var)),
        chi2=chi2,
        dof=dof,
        chi2_dof=float(chi2_dof),
        at_bound=at_bound,
        warnings=tuple(warnings),
        success=bool(sol[1]),
        message=str(sol[2]),
        n_evaluations=nfev,
    )
