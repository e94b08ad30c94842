"""fit_ratios where the model's derivatives are not finite (contactres.polycrystal._ratio_fit).

The solver stops a fit at its last accepted point when the Jacobian there is not finite; the
summary of the fit must then say so rather than take LAPACK's SVD of that Jacobian (which
raised "SVD did not converge", an internal error).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from contactres import Material
from contactres.polycrystal import _ratio_fit
from contactres.polycrystal._inverse import CUBIC
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._orientations import random_orientations

CU = Material.cubic(168.4e9, 121.4e9, 75.4e9)  # C12/C11 = 0.721
EDGE = 0.7  # the model's moduli are NaN beyond this C12/C11


def test_a_jacobian_that_is_not_finite_gives_a_flagged_fit_without_errors(monkeypatch):
    # Copper's data, a model NaN for C12/C11 > 0.7: the fit climbs from 0.65 toward 0.721,
    # and the central differences (± LOG_STEP in ln C12/C11) cross the edge before the point
    # does. The point's χ² stays finite (a step past the edge is refused), its Jacobian not.
    R = random_orientations(6, seed=3)
    m = indentation_moduli(CU, R)
    ratios_of: dict[int, np.ndarray] = {}

    def unit(ratios: np.ndarray) -> Material:
        mat = CUBIC.unit_material(ratios)
        ratios_of[id(mat)] = np.array(ratios, dtype=float)
        return mat

    real = _ratio_fit.moduli_and_points

    def beyond_the_edge_nan(units, orient, rtol, first_points=None):
        out, points = real(units, orient, rtol, first_points)
        past = np.array([ratios_of[id(u)][0] > EDGE for u in units])
        return np.where(past[:, None], np.nan, out), points

    monkeypatch.setattr(_ratio_fit, "moduli_and_points", beyond_the_edge_nan)
    param = dataclasses.replace(CUBIC, unit_material=unit)
    fit = _ratio_fit.fit_ratios(
        param, R, m, 1e-4 * m, quantity="modulus", guess={"c12_c11": 0.65, "c44_c11": 0.5}
    )
    assert not fit.success
    assert fit.message == "the derivatives are not finite at the last accepted point"
    # Stopped on this side of the edge, within the differences' reach of it.
    c12_c11 = fit.ratios[0]
    assert EDGE * np.exp(-_ratio_fit.LOG_STEP) < c12_c11 <= EDGE
    assert np.isinf(fit.covariance).all() and np.isnan(fit.singular_values).all()
    assert not fit.identified.any() and not fit.ratios_determined
    assert np.isnan(fit.reference_value)
    assert any("derivatives are not finite" in w and "no error" in w for w in fit.warnings)
