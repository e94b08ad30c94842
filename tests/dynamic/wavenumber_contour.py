"""Quadrature rules shared by the independent isotropic rigid-disk references of the tests.

The Hankel-type wavenumber integrals of the lossless half-space have branch points at the
longitudinal and shear wavenumbers and a pole at the Rayleigh wavenumber, all at η <= 1.15 a₀
(η = wavenumber times a, a₀ = k_s a). The rule runs on a half-ellipse from 0 to 2.5 a₀ above them
(the limit loss -> 0⁺), then on real Gauss panels: geometric (ratio 1.5) up to η = 8, uniform
beyond up to ``tail_end``.
"""

from __future__ import annotations

import math

import numpy as np


def gauss(a, b, n):
    """n-point Gauss-Legendre nodes and weights on [a, b]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def wavenumber_rule(a0, n_contour, tail_end, tail_width, per_panel):
    """Nodes and weights (complex on the contour) of ∫₀^{tail_end} dη (module notes).

    ``n_contour`` nodes on the half-ellipse, uniform panels of width <= ``tail_width`` beyond
    η = 8, ``per_panel`` Gauss nodes per real panel.
    """
    t, wt = gauss(0.0, 1.0, n_contour)
    t0, h = 2.5 * a0, 0.5 * a0
    eta = 0.5 * t0 * (1 - np.cos(np.pi * t)) + 1j * h * np.sin(np.pi * t)
    deta = (0.5 * t0 * np.pi * np.sin(np.pi * t) + 1j * h * np.pi * np.cos(np.pi * t)) * wt
    edges = [t0]
    while edges[-1] * 1.5 < 8.0:
        edges.append(edges[-1] * 1.5)
    start = max(8.0, t0)
    n_tail = max(1, math.ceil((tail_end - start) / tail_width))
    edges = np.unique(np.concatenate([edges, np.linspace(start, tail_end, n_tail + 1)]))
    x, w = np.polynomial.legendre.leggauss(per_panel)
    lo, hi = edges[:-1, None], edges[1:, None]
    xs = (0.5 * (hi - lo) * x + 0.5 * (hi + lo)).ravel()
    ws = (0.5 * (hi - lo) * w).ravel()
    return np.concatenate([eta, xs]), np.concatenate([deta, ws])
