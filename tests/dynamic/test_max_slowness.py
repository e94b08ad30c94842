"""The largest in-plane slowness of bulk waves (contactres.dynamic._table.max_slowness).

max_slowness(m) is max over in-plane directions n = (cos θ, sin θ, 0) (θ on a 1° grid over
[0, π]) of 1/sqrt(λ_min(Γ(n)/C44)), Γ_ik = c_ijkl n_j n_l the Christoffel matrix and C44 the
surface-frame shear stiffness: the slowness of the slowest bulk wave along the surface, in
units of 1/c_s with c_s = sqrt(C44/ρ) (ρ cancels). The two values below follow from Γ by hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import Material
from contactres.dynamic._table import max_slowness


def test_isotropic_solid_has_the_shear_slowness():
    """Isotropic: Γ = μ I + (λ + μ) n nᵀ, eigenvalues μ, μ, λ + 2μ; the smallest is μ = C44 in
    every direction, so the slowness is 1/c_s: 1 in these units."""
    for nu in (0.0, 0.25, 0.45):
        assert max_slowness(Material.isotropic(70e9, nu, 2700.0)) == pytest.approx(1.0, rel=1e-14)


@pytest.mark.parametrize(
    ("c11", "c12", "c44"),
    [
        (168.4e9, 121.4e9, 75.4e9),  # Cu, (C11 − C12)/2 < C44
        (522.4e9, 204.4e9, 160.6e9),  # W, nearly isotropic
        (1.0, 0.2, 0.3),  # (C11 − C12)/2 > C44: the z-polarised wave is the slowest
    ],
)
def test_cubic_001_face_has_the_slowness_of_the_softer_shear(c11, c12, c44):
    """Cubic (001), n = (cos θ, sin θ, 0): the z polarisation decouples with Γ_33 = C44; the
    in-plane block has trace C11 + C44 and eigenvalues
    λ± = (C11 + C44)/2 ± sqrt(((C11 − C44)/2)² cos² 2θ + ((C12 + C44)/2)² sin² 2θ).
    λ− is monotone in sin² 2θ, so its extremes are at θ = 0 (λ− = C44, for C11 > C44) and
    θ = 45° ((C11 − C12)/2); both lie on the 1° grid. The smallest eigenvalue over θ is
    min(C44, (C11 − C12)/2), and the largest slowness 1/sqrt(min(C44, (C11 − C12)/2)/C44)."""
    expected = 1.0 / np.sqrt(min(c44, (c11 - c12) / 2) / c44)
    np.testing.assert_allclose(max_slowness(Material.cubic(c11, c12, c44)), expected, rtol=1e-14)
