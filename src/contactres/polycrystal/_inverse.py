"""Inverse problem of a polycrystal map: cubic elastic constants from contact data per grain.

The measured value of grain i is ``value_i = c · E*_i^p`` (p = 2/3 for a contact-stiffness map,
1 for a modulus map), E* the indentation modulus M(n; C) of the grain (paper 1, Eq. 4; Vlassak &
Nix 1994) in series with the tip; the model and the fit shared with the hexagonal case are in
:mod:`.ratio_fit`, the solver in :mod:`contactres.fitting`, the hexagonal crystal in
:mod:`.inverse_hexagonal`.

Parametrisation (logarithmic): ln(C12/C11), ln(C44/C11) and the scale. With a free calibration c
and a rigid tip only ln(c C11^p) is fitted (results: the ratios and the value on a (001) grain);
with a known c, ln C11 (Pa); with a compliant tip and a free c, both (C11 then enters weakly,
through E*/M). The weak combination of the ratios (~1e-5 of M per 1 %) is reported with its
error from the singular values of the weighted sensitivity (scale profiled out); one whose
relative error exceeds :data:`IDENTIFIABILITY_RTOL` is flagged and the ratios are NaN.
:func:`fit_map` fits a pixel map of either lattice.

Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010), Eq. 4. J. J. Vlassak and
W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, plus_minus
from ..errors import ContactresInputError
from ..materials import Material
from ._inverse_hexagonal import HexagonalInverseResult, fit_hexagonal_constants
from ._moduli import stacked_indentation_moduli
from ._orientations import surface_matrix_from_miller
from ._ratio_fit import (
    CONDITIONAL_NOTE,
    IDENTIFIABILITY_RTOL,
    LOG_STEP,
    RatioParametrisation,
    fit_facts,
    fit_ratios,
    summary_text,
)

__all__ = [
    "IDENTIFIABILITY_RTOL",
    "CubicInverseResult",
    "anisotropy_111",
    "fit_cubic_constants",
    "fit_map",
    "grain_means",
]


def unit_cubic(ratios: np.ndarray) -> Material:
    """The cubic crystal with C11 = 1 and (C12/C11, C44/C11) = ``ratios``."""
    return Material.cubic(1.0, float(ratios[0]), float(ratios[1]))


# Bounds of C12/C11 (log-parametrised: C12 > 0; below 1, so C11 > C12 keeps it stable) and of
# C44/C11.
CUBIC = RatioParametrisation(
    lattice="cubic",
    names=("c12_c11", "c44_c11"),
    labels=("C12/C11", "C44/C11"),
    unit_material=unit_cubic,
    bounds=((1e-3, 0.99), (1e-3, 10.0)),
    default_guess=(0.6, 0.5),
    advice="more grains or smaller errors per grain are needed",
)


# repr=False: the summary (Summarised, _facts) replaces ~40 fields and their arrays; the
# full text is summary().
@dataclass(frozen=True, repr=False)
class CubicInverseResult(Summarised):
    """Cubic elastic constants fitted to per-grain contact data, with their identifiability.

    Values that are not determined (relative error above :data:`IDENTIFIABILITY_RTOL`, or a
    parameter at its bound) are NaN; ``warnings`` says why and which input to check.

    Attributes
    ----------
    quantity : "stiffness" (k*, N/m) or "modulus" (M, Pa)
    n_grains : number of grains fitted
    parameter_names : tuple of str
        Names of the fitted log-parameters (columns of ``covariance``).
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
    anisotropy_111, anisotropy_111_error : M(111)/M(001) of the fitted crystal and its standard
        error: what the map's orientation dependence fixes, whether or not the weak combination
        is determined (the fitted ratios lie anywhere along the curved valley of equal
        predictions, and this prediction is nearly constant along it); NaN unless the strong
        combination is determined
    at_bound : tuple of str
        Names of parameters that ended at a bound.
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
    anisotropy_111: float
    anisotropy_111_error: float
    at_bound: tuple[str, ...]
    warnings: tuple[str, ...]
    success: bool
    message: str
    n_evaluations: int

    def _facts(self) -> list[tuple[str, str]]:
        """Grains, the two ratios ± errors, the strong combination (determined even where the
        ratios one by one are not), C11 where determined, χ²/dof, warnings."""
        ratios = [
            ("C12/C11", self.c12_c11, self.c12_c11_error),
            ("C44/C11", self.c44_c11, self.c44_c11_error),
        ]
        facts = fit_facts(self, ratios)
        if self.strong_identified:
            value = self.strong_combination
            facts.insert(3, ("strong combination", plus_minus(value, value * self.strong_error)))
        return facts

    def summary(self) -> str:
        """Plain-text report; quantities that are not determined are not printed as results."""
        (a, b), (sa, sb), s = self.weak_direction, self.strong_direction, self.ratio_singular_values
        weak = f"{self.weak_combination:.6g}" if self.weak_identified else "not determined"
        lines = [
            f"cubic constants from {self.n_grains} grains ({self.quantity} map)",
            _ratio_line("C12/C11", self.c12_c11, self.c12_c11_error),
            _ratio_line("C44/C11", self.c44_c11, self.c44_c11_error),
            f"  strong: (C12/C11)^{sa:.4f} (C44/C11)^{sb:.4f} = {self.strong_combination:.6g}"
            f" (rel. error {self.strong_error:.2g})",
            f"  weak: (C12/C11)^{a:.4f} (C44/C11)^{b:.4f} = {weak} (rel. error "
            f"{self.weak_error:.2g})",
            f"  ratio singular values {s[0]:.4g}, {s[1]:.4g}; chi2/dof = {self.chi2_dof:.3g}",
        ]
        if np.isfinite(self.anisotropy_111):
            lines.insert(
                3,
                f"  M(111)/M(001) = {self.anisotropy_111:.5f} ± {self.anisotropy_111_error:.2g}"
                " (the anisotropy the map shows)",
            )
        if np.isfinite(self.c11):
            lines.insert(3, f"  C11 = {self.c11 / 1e9:.4g} ± {self.c11_error / 1e9:.2g} GPa")
        if not self.weak_identified:
            lines.append(CONDITIONAL_NOTE)
        return summary_text(lines, self.warnings)


def _ratio_line(label: str, value: float, error: float) -> str:
    if np.isfinite(value):
        return f"  {label} = {value:.5f} ± {error:.2g}"
    return f"  {label} = not determined (standard error would be {error:.2g})"


def anisotropy_111(ratios, log_covariance) -> tuple[float, float]:
    """M(111)/M(001) of a cubic crystal with ratios (C12/C11, C44/C11) and its standard error.

    The error propagates ``log_covariance`` (covariance of ln(C12/C11), ln(C44/C11)) through
    central differences (step :data:`~contactres.polycrystal._ratio_fit.LOG_STEP`) of
    ln(M(111)/M(001)); M from :func:`~contactres.polycrystal.indentation_moduli` (paper 1,
    Eq. 4; Vlassak & Nix 1994).
    """
    R = np.stack([np.eye(3), surface_matrix_from_miller((1, 1, 1), (1, -1, 0))])
    lr = np.log(np.asarray(ratios, dtype=float))
    steps = np.vstack([np.zeros(2), np.eye(2) * LOG_STEP, -np.eye(2) * LOG_STEP]) + lr
    # One stacked evaluation of the five crystals: each row the bits of its own call.
    M = stacked_indentation_moduli([Material.cubic(1.0, *np.exp(x)) for x in steps], R)
    ln_a = np.log(M[:, 1] / M[:, 0])
    grad = (ln_a[1:3] - ln_a[3:5]) / (2 * LOG_STEP)
    cov = np.asarray(log_covariance, dtype=float)
    var = float(grad @ np.where(np.isfinite(cov), cov, 0.0) @ grad)
    a = float(np.exp(ln_a[0]))
    return a, (a * np.sqrt(var) if np.all(np.isfinite(cov)) else np.inf)


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
        raise ContactresInputError(f"labels and values differ in size: {lab.size} vs {val.size}")
    if not np.issubdtype(lab.dtype, np.integer):
        raise ContactresInputError("labels must be integers")
    keep = (lab >= 0) & np.isfinite(val)
    lab, val = lab[keep], val[keep]
    G = int(lab.max(initial=-1)) + 1 if n_grains is None else int(n_grains)
    if lab.size and lab.max() >= G:
        raise ContactresInputError(f"label {int(lab.max())} >= n_grains = {G}")
    count = np.bincount(lab, minlength=G).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.bincount(lab, weights=val, minlength=G) / count
        ss = np.bincount(lab, weights=(val - mean[lab]) ** 2, minlength=G)
        error = np.sqrt(ss / (count - 1) / count)
    few = count < 2
    mean[few] = np.nan
    error[few] = np.nan
    return mean, error, count.astype(int)


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
        convention of :mod:`contactres.polycrystal._orientations`).
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
    The fit itself is :func:`contactres.polycrystal._ratio_fit.fit_ratios`.
    """
    fit = fit_ratios(CUBIC, orientations, values, errors, quantity, tip_modulus, calibration, guess)
    ok = fit.ratios_determined
    strong_ok, weak_ok = (bool(x) for x in fit.identified)
    ratios, rcov = fit.ratios, fit.ratio_covariance

    def nan_unless(flag, x):  # values not determined are NaN, never printed
        return float(x) if flag else np.nan

    c11_ok = fit.c11_determined
    n_scale = fit.n_scale
    a111, a111_err = anisotropy_111(ratios, fit.covariance[n_scale:, n_scale:])
    return CubicInverseResult(
        quantity=fit.quantity,
        n_grains=fit.n_grains,
        parameter_names=fit.parameter_names,
        parameters=fit.parameters,
        covariance=fit.covariance,
        c12_c11=nan_unless(ok, ratios[0]),
        c12_c11_error=float(np.sqrt(rcov[0, 0])),
        c44_c11=nan_unless(ok, ratios[1]),
        c44_c11_error=float(np.sqrt(rcov[1, 1])),
        ratio_covariance=rcov,
        c11=nan_unless(c11_ok, fit.c11),
        c12=nan_unless(c11_ok, fit.c11 * ratios[0]),
        c44=nan_unless(c11_ok, fit.c11 * ratios[1]),
        c11_error=fit.c11_error,
        calibration=fit.calibration,
        calibration_error=fit.calibration_error,
        reference_value=fit.reference_value,
        reference_error=fit.reference_error,
        chi2=fit.chi2,
        dof=fit.dof,
        chi2_dof=fit.chi2_dof,
        singular_values=fit.singular_values,
        ratio_singular_values=fit.ratio_singular_values,
        strong_direction=fit.directions[0],
        weak_direction=fit.directions[1],
        strong_combination=nan_unless(strong_ok, fit.combinations[0]),
        strong_error=float(fit.combination_errors[0]),
        weak_combination=nan_unless(weak_ok and strong_ok, fit.combinations[1]),
        weak_error=float(fit.combination_errors[1]),
        strong_identified=strong_ok,
        weak_identified=weak_ok,
        anisotropy_111=nan_unless(strong_ok, a111),
        anisotropy_111_error=a111_err,
        at_bound=fit.at_bound,
        warnings=fit.warnings,
        success=fit.success,
        message=fit.message,
        n_evaluations=fit.n_evaluations,
    )


# The fit of each lattice that :func:`fit_map` dispatches to (a constant lookup table).
LATTICE_FITS: dict[str, Callable[..., CubicInverseResult | HexagonalInverseResult]] = {
    "cubic": fit_cubic_constants,
    "hexagonal": fit_hexagonal_constants,
}


def fit_map(
    labels, values, grain_orientations, lattice: str = "cubic", **kwargs
) -> CubicInverseResult | HexagonalInverseResult:
    """Fit a pixel map: per-grain means and standard errors (:func:`grain_means`), then the fit.

    Parameters
    ----------
    labels : array_like of int, shape (H, W)
        Grain label per pixel (0 .. G−1; negative: unindexed). An unlabelled EBSD map needs a
        grain reconstruction first.
    values : array_like, shape (H, W)
        k* (N/m) or M (Pa) per pixel.
    grain_orientations : array_like, shape (G, 3, 3)
        Surface matrices of the grains, indexed by label.
    lattice : {"cubic", "hexagonal"}
        :func:`fit_cubic_constants` or
        :func:`contactres.polycrystal.fit_hexagonal_constants`.
    **kwargs
        Passed to the fit (quantity, tip_modulus, calibration, guess).

    Returns
    -------
    CubicInverseResult or HexagonalInverseResult
        Grains with fewer than two pixels are left out.
    """
    if lattice not in LATTICE_FITS:
        raise ContactresInputError(
            f"lattice must be one of {sorted(LATTICE_FITS)}, got {lattice!r}"
        )
    R = np.asarray(grain_orientations, dtype=float)
    if R.ndim != 3 or R.shape[1:] != (3, 3):
        raise ContactresInputError(f"grain_orientations must have shape (G, 3, 3), got {R.shape}")
    mean, err, _ = grain_means(labels, values, n_grains=R.shape[0])
    ok = np.isfinite(mean) & np.isfinite(err) & (err > 0)
    if not ok.any():
        # Nothing to weight a fit with: say why instead of failing inside it.
        measured = np.isfinite(mean) & np.isfinite(err)
        if measured.any():
            raise ContactresInputError(
                f"no contrast to fit: the values are constant within each of the "
                f"{int(measured.sum())} grain(s) with two or more measured pixels (standard "
                f"error 0{', and equal in all' if np.ptp(mean[measured]) == 0 else ''}); a "
                "measured map has noise, so this is not one"
            )
        raise ContactresInputError(
            "no grain has two or more measured pixels (finite values inside the grains): "
            "nothing to fit"
        )
    return LATTICE_FITS[lattice](R[ok], mean[ok], err[ok], **kwargs)
