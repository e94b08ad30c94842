"""Inverse problem of a polycrystal map: hexagonal elastic constants from contact data per grain.

The model is that of the cubic case (:mod:`.inverse`, :mod:`.ratio_fit`): grain i gives
``value_i = c · E*_i^p`` (p = 2/3 for a contact-stiffness map, 1 for a modulus map), E* the
indentation modulus M(n; C) = C11 · m(n; r) of the grain (paper 1, Eq. 4; Vlassak & Nix 1994) in
series with the tip. The four log-ratios ln(C12/C11), ln(C13/C11), ln(C33/C11), ln(C44/C11) and
the scale are fitted.

A hexagonal crystal is transversely isotropic about its c axis, so M depends only on the angle
between the surface normal and the c axis: a map gives one smooth function of one angle, and of
the four combinations of the ratios only a few are determined (typically two or three for 60
grains at 1e-4 per grain). All four singular values of the ratio sensitivity (scale profiled
out) are reported with the combination directions; the individual ratios only when every
combination is determined (relative error <= ``IDENTIFIABILITY_RTOL``), else NaN with a
warning.

Stability: the fit accepts only steps whose unit stiffness (C11 = 1) is positive definite with
its smallest eigenvalue above :data:`contactres.polycrystal._ratio_fit.MIN_EIGENVALUE` (for a
hexagonal crystal: C44 > 0, C11 > ``|C12|`` and (C11 + C12) C33 > 2 C13²). A step that leaves the
region is rejected like one that raises χ² (more damping, a shorter step), with no penalty
term, so the minimum and its covariance are those of the data; the box bounds keep C12, C13 > 0
(log-parametrised: crystals with C13 < 0 are outside this fit).

Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010), Eq. 4. J. J. Vlassak and
W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._summary import Summarised
from ..materials import Material
from ._ratio_fit import (
    CONDITIONAL_NOTE,
    RatioParametrisation,
    fit_facts,
    fit_ratios,
    summary_text,
)

__all__ = ["HEXAGONAL", "HexagonalInverseResult", "fit_hexagonal_constants"]


def unit_hexagonal(ratios: np.ndarray) -> Material:
    """The hexagonal crystal with C11 = 1 and (C12, C13, C33, C44)/C11 = ``ratios``."""
    r12, r13, r33, r44 = (float(x) for x in ratios)
    return Material.hexagonal(1.0, r12, r13, r33, r44)


# Bounds: C12/C11 below 1 (C66 = (C11 − C12)/2 > 0); C13/C11 and C33/C11 wide enough for the
# hexagonal metals (Be: C13/C11 ~ 0.05; Zn, Cd: C33/C11 ~ 0.4); default guess near Mg/Ti.
HEXAGONAL = RatioParametrisation(
    lattice="hexagonal",
    names=("c12_c11", "c13_c11", "c33_c11", "c44_c11"),
    labels=("C12/C11", "C13/C11", "C33/C11", "C44/C11"),
    unit_material=unit_hexagonal,
    bounds=((1e-3, 0.99), (1e-3, 5.0), (1e-2, 10.0), (1e-3, 10.0)),
    default_guess=(0.45, 0.35, 1.0, 0.3),
    advice=(
        "M depends only on the angle between the surface normal and the c axis, so more grains "
        "or smaller errors help only slowly: fix the ratio with the largest exponent of each "
        "undetermined combination from independent data (single-crystal ultrasonic or Brillouin "
        "C33, C13, C44)"
    ),
)


# repr=False: the summary (Summarised, _facts) replaces ~40 fields and their arrays; the
# full text is summary().
@dataclass(frozen=True, repr=False)
class HexagonalInverseResult(Summarised):
    """Hexagonal elastic constants fitted to per-grain contact data, with their identifiability.

    Values that are not determined (relative error above ``IDENTIFIABILITY_RTOL``, or a
    parameter at its bound) are NaN; ``warnings`` says why and which input to check.

    Attributes
    ----------
    quantity : "stiffness" (k*, N/m) or "modulus" (M, Pa)
    n_grains : number of grains fitted
    parameter_names : tuple of str
        Names of the fitted log-parameters (columns of ``covariance``).
    parameters : fitted values of the log-parameters (diagnostic, also when not determined)
    covariance : covariance of ``parameters`` (inflated by χ²/dof when that exceeds 1)
    ratio_names : ("c12_c11", "c13_c11", "c33_c11", "c44_c11")
    ratios : C12/C11, C13/C11, C33/C11, C44/C11 (dimensionless); all NaN unless every
        combination is determined
    ratio_errors : their standard errors (large along undetermined combinations)
    ratio_covariance : 4x4 covariance of ``ratios`` (from the fitted values)
    c11, c12, c13, c33, c44, c11_error : Pa; NaN unless the ratios and the scale of C are
        determined (known calibration, or a compliant tip that fixes it)
    calibration, calibration_error : the factor c of ``value = c E*^p`` (NaN when not separable)
    reference_value, reference_error : the measured quantity the fit predicts on a basal (0001)
        grain (N/m or Pa), the calibration-free summary of the scale
    chi2, dof, chi2_dof : weighted residual sum, degrees of freedom and their ratio
    singular_values : of the weighted sensitivity matrix J (columns ``parameter_names``)
    ratio_singular_values : shape (4,), of J over the four log-ratios with the scale profiled
        out, strong to weak
    directions : shape (4, 4), rows: unit vectors v over the log-ratios (same order), the
        combination (C12/C11)^v₀ (C13/C11)^v₁ (C33/C11)^v₂ (C44/C11)^v₃, strong to weak
    combinations : shape (4,), their values (NaN when not determined)
    combination_errors : shape (4,), their relative standard errors
    identified : shape (4,) bool, combination_errors <= ``IDENTIFIABILITY_RTOL``
    n_identified : number of determined combinations (0-4)
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
    ratio_names: tuple[str, ...]
    ratios: np.ndarray
    ratio_errors: np.ndarray
    ratio_covariance: np.ndarray
    c11: float
    c12: float
    c13: float
    c33: float
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
    directions: np.ndarray
    combinations: np.ndarray
    combination_errors: np.ndarray
    identified: np.ndarray
    n_identified: int
    at_bound: tuple[str, ...]
    warnings: tuple[str, ...]
    success: bool
    message: str
    n_evaluations: int

    def _facts(self) -> list[tuple[str, str]]:
        """Grains, how many combinations of the ratios are determined, the four ratios ± errors
        (each only when all are determined), C11 where determined, χ²/dof, warnings."""
        names = [n.replace("_", "/").upper() for n in self.ratio_names]
        facts = fit_facts(self, list(zip(names, self.ratios, self.ratio_errors, strict=True)))
        determined = f"{self.n_identified} of {len(self.identified)}"
        return [*facts[:1], ("combinations determined", determined), *facts[1:]]

    def summary(self) -> str:
        """Plain-text report; quantities that are not determined are not printed as results."""
        head = f"hexagonal constants from {self.n_grains} grains ({self.quantity} map)"
        lines = [head]
        if np.all(np.isfinite(self.ratios)):
            lines += [
                f"  {label} = {r:.5f} ± {e:.2g}"
                for label, r, e in zip(
                    HEXAGONAL.labels, self.ratios, self.ratio_errors, strict=True
                )
            ]
        else:
            lines.append(
                f"  individual ratios: not determined ({self.n_identified} of 4 combinations)"
            )
        if np.isfinite(self.c11):
            lines.append(f"  C11 = {self.c11 / 1e9:.4g} ± {self.c11_error / 1e9:.2g} GPa")
        for i, (v, e, ok) in enumerate(
            zip(self.directions, self.combination_errors, self.identified, strict=True)
        ):
            value = f"{self.combinations[i]:.6g}" if ok else "not determined"
            lines.append(
                f"  combination {i + 1}: {HEXAGONAL.combination(v)} = {value} (rel. error {e:.2g})"
            )
        s = ", ".join(f"{x:.4g}" for x in self.ratio_singular_values)
        lines.append(f"  ratio singular values {s}; chi2/dof = {self.chi2_dof:.3g}")
        if not all(self.identified):
            lines.append(CONDITIONAL_NOTE)
        return summary_text(lines, self.warnings)


def fit_hexagonal_constants(
    orientations,
    values,
    errors,
    quantity: str = "stiffness",
    tip_modulus: float | None = None,
    calibration: float | None = None,
    guess: dict[str, float] | None = None,
) -> HexagonalInverseResult:
    """Fit C12/C11, C13/C11, C33/C11, C44/C11 (and the scale) of a hexagonal crystal.

    Parameters
    ----------
    orientations : array_like, shape (G, 3, 3)
        Surface-frame matrices of the grains (rows = sample axes in crystal coordinates, crystal
        z = c axis; the convention of :mod:`contactres.polycrystal._orientations`).
    values : array_like, shape (G,)
        Measured contact stiffness k* (N/m) or indentation modulus (Pa) per grain.
    errors : array_like, shape (G,)
        Standard errors of ``values`` (same unit), e.g. from
        :func:`contactres.polycrystal.grain_means`.
    quantity : {"stiffness", "modulus"}
        k* = c E*^{2/3} with c = (6 F R)^{1/3} (Hertz), or M = c E* (c = 1 for a map in Pa).
    tip_modulus : float, optional
        Plane-strain modulus of the tip E_t/(1 − ν_t²), Pa; None: a rigid tip.
    calibration : float, optional
        The known factor c (N^{1/3} m^{1/3} for stiffness; 1 for a modulus map in Pa). None: free.
    guess : dict, optional
        Starting values: "c12_c11" (default 0.45), "c13_c11" (0.35), "c33_c11" (1.0),
        "c44_c11" (0.3), "c11" (Pa, default 150e9). Must be a stable crystal. Along the
        undetermined combinations the fit stays near the guess.

    Returns
    -------
    HexagonalInverseResult
        The singular values, combination directions and their errors and flags; the ratios
        and constants when determined.

    Notes
    -----
    A Jacobian costs nine exact evaluations of M for all grains. The fit is
    :func:`contactres.polycrystal._ratio_fit.fit_ratios` with :data:`HEXAGONAL`.

    The directions and errors are linearised at the fitted point. When a combination is not
    determined the fit can end far along it (tens of per cent in the ratios) where the valley
    of χ² is curved: the determined combinations then describe the data near the fitted point,
    and their errors are conditional on the undetermined ones, not marginal (for Zn, 60 grains
    at 1e-4, the strongest one moved by up to ~20 of its errors between noise draws). Read them
    as constraints, and fix the undetermined ratios from independent data before quoting
    values.
    """
    fit = fit_ratios(
        HEXAGONAL, orientations, values, errors, quantity, tip_modulus, calibration, guess
    )
    ok = fit.ratios_determined
    ratios = fit.ratios if ok else np.full(4, np.nan)
    scale = fit.c11 if fit.c11_determined else np.nan
    c12, c13, c33, c44 = scale * ratios
    return HexagonalInverseResult(
        quantity=fit.quantity,
        n_grains=fit.n_grains,
        parameter_names=fit.parameter_names,
        parameters=fit.parameters,
        covariance=fit.covariance,
        ratio_names=HEXAGONAL.names,
        ratios=ratios,
        ratio_errors=np.sqrt(np.diag(fit.ratio_covariance)),
        ratio_covariance=fit.ratio_covariance,
        c11=float(scale),
        c12=float(c12),
        c13=float(c13),
        c33=float(c33),
        c44=float(c44),
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
        directions=fit.directions,
        combinations=np.where(fit.identified, fit.combinations, np.nan),
        combination_errors=fit.combination_errors,
        identified=fit.identified,
        n_identified=int(fit.identified.sum()),
        at_bound=fit.at_bound,
        warnings=fit.warnings,
        success=fit.success,
        message=fit.message,
        n_evaluations=fit.n_evaluations,
    )
