"""The vectorised adaptive rule of the layered tests' real-axis references (adaptive_quadrature)
against closed forms: a sharp Lorentzian peak (the shape of a guided mode at Q⁻¹ = 1e-3), a
jump and a square-root end point, vector-valued as the references use it."""

from __future__ import annotations

import numpy as np
import pytest
from adaptive_quadrature import adaptive_gauss


def test_sharp_peak_jump_and_root_match_their_closed_forms():
    gamma, s0 = 1e-4, 0.61

    def f(s):
        peak = gamma / ((s - s0) ** 2 + gamma**2)  # ∫ = atan((s − s0)/γ)
        jump = np.where(s < 0.3, 1.0, -2.0)
        return np.stack([peak, jump, np.sqrt(s), np.cos(40 * s) * (1 + 1j)])

    value, error = adaptive_gauss(f, 0.0, 2.0, epsabs=1e-13, epsrel=1e-12)
    exact = np.array(
        [
            np.arctan((2.0 - s0) / gamma) - np.arctan(-s0 / gamma),
            0.3 - 2.0 * 1.7,
            2.0 / 3.0 * 2.0**1.5,
            np.sin(80.0) / 40 * (1 + 1j),
        ]
    )
    assert np.max(np.abs(value - exact)) < 1e-11 * np.max(np.abs(exact))
    assert error < 1e-11 * np.max(np.abs(exact))


def test_breakpoints_and_refusal():
    value, _ = adaptive_gauss(lambda s: s[None] ** 3, 1.0, 3.0, points=[1.5, 2.0])
    assert value[0] == pytest.approx((3.0**4 - 1.0) / 4, rel=1e-14)
    with pytest.raises(RuntimeError, match="panels"):
        adaptive_gauss(lambda s: (1 / (s - 1 / 3) ** 2)[None], 0.0, 1.0, max_panels=100)
