"""Tests of the elliptic anisotropic Hertz contact (contactres.normal._anisotropic, issue 27
point 9): frame invariance, the circular faces, isotropic Hertz, and a second route (a direct
numerical solution of the contact on a grid)."""

import numpy as np
import pytest

from contactres import (
    Material,
    contact_ellipse,
    contact_integrals,
    hertz,
    indentation_modulus,
    sphere_contact,
)
from contactres.halfspace import static_kernel

R, F = 1e-3, np.array([0.3, 1.0, 2.5])  # m, N
TURNS = [0.0, 0.3, 1.0, 2.5, -0.7]  # rad, about the surface normal


def turned(m, psi):
    """``m`` turned about the normal: the new surface x axis is (cos ψ, sin ψ) of the old frame,
    so an axis at angle φ in the old frame lies at φ − ψ in the new one."""
    return m.rotated((0, 0, 1), (np.cos(psi), np.sin(psi), 0.0))


def axis_difference(phi1, phi2):
    """Difference of two axis angles (rad) modulo π, in [−π/2, π/2)."""
    return (phi1 - phi2 + np.pi / 2) % np.pi - np.pi / 2


@pytest.mark.parametrize(
    "name, hkl", [("Cu", (0, 1, 1)), ("Li", (0, 1, 1)), ("Cu", (1, 2, 3)), ("Si", (1, 1, 2))]
)
def test_contact_is_invariant_under_rotation_about_the_normal(name, hkl):
    base = Material.crystal(name).rotated(hkl)
    ref = sphere_contact(base, R, F)
    assert not ref.circular and ref.ellipticity < 0.99
    assert np.all(ref.semi_major >= ref.semi_minor)
    for psi in TURNS[1:]:
        c = sphere_contact(turned(base, psi), R, F)
        for field in ("semi_major", "semi_minor", "contact_radius", "depth", "stiffness"):
            np.testing.assert_allclose(getattr(c, field), getattr(ref, field), rtol=1e-8)
        np.testing.assert_allclose(c.peak_pressure, ref.peak_pressure, rtol=1e-8)
        np.testing.assert_allclose(c.mean_pressure, ref.mean_pressure, rtol=1e-8)
        assert c.ellipticity == pytest.approx(ref.ellipticity, rel=1e-8)
        assert abs(axis_difference(c.orientation, ref.orientation - psi)) < 1e-8
        assert -np.pi / 2 < c.orientation <= np.pi / 2


@pytest.mark.parametrize("name", ["Cu", "Li", "Si"])
@pytest.mark.parametrize("hkl", [(0, 0, 1), (1, 1, 1)])
def test_faces_with_a_3_or_4_fold_axis_give_hertz_with_M(name, hkl):
    for psi in (0.0, 0.4, 1.3):
        m = turned(Material.crystal(name).rotated(hkl), psi)
        M = indentation_modulus(m)
        h = hertz(M, R, F)  # Hertz with E* = M (Johnson, Contact Mechanics, Eq. 4.22-4.23)
        c = sphere_contact(m, R, F)
        assert c.circular and c.ellipticity == 1 and c.orientation == 0
        np.testing.assert_allclose(c.semi_major, h.contact_radius, rtol=1e-10)
        np.testing.assert_allclose(c.semi_minor, h.contact_radius, rtol=1e-10)
        np.testing.assert_allclose(c.contact_radius, h.contact_radius, rtol=1e-10)
        np.testing.assert_allclose(c.depth, h.depth, rtol=1e-10)
        np.testing.assert_allclose(c.stiffness, h.stiffness, rtol=1e-10)
        # the ellipse's own solution, not the circular shortcut, finds the circle too
        e = contact_ellipse(m)
        I0 = contact_integrals(m).I0
        assert e.rho < 1e-10 and e.ellipticity == pytest.approx(1, abs=1e-10)
        assert e.curvature_integral == pytest.approx(I0 / 2, rel=1e-10)
        assert e.depth_integral == pytest.approx(I0, rel=1e-10)


def test_isotropic_is_hertz_in_any_frame():
    E, nu = 70e9, 0.17
    E_star = E / (1 - nu**2)
    a = np.cbrt(3 * F * R / (4 * E_star))  # Hertz (Johnson, Contact Mechanics, Eq. 4.22)
    for m in (Material.isotropic(E, nu), Material.isotropic(E, nu).rotated((1, 2, 3))):
        c = sphere_contact(m, R, F)
        np.testing.assert_allclose(c.semi_major, a, rtol=1e-12)
        np.testing.assert_allclose(c.semi_minor, a, rtol=1e-12)
        np.testing.assert_allclose(c.depth, a**2 / R, rtol=1e-12)
        np.testing.assert_allclose(c.stiffness, 2 * a * E_star, rtol=1e-12)
        np.testing.assert_allclose(c.peak_pressure, 3 * F / (2 * np.pi * a**2), rtol=1e-12)
        e = contact_ellipse(m)
        assert e.rho == 0 and e.ellipticity == 1 and e.orientation == 0


def test_ellipse_stiffness_is_the_derivative_and_pressure_carries_the_force():
    m = turned(Material.crystal("Li").rotated((0, 1, 1)), 0.5)
    f, h = 0.7, 1e-4
    w = sphere_contact(m, 2e-3, np.array([f * (1 - h), f * (1 + h)])).depth
    c = sphere_contact(m, 2e-3, f)
    assert 2 * f * h / (w[1] - w[0]) == pytest.approx(c.stiffness, rel=1e-7)
    # ∫ p dA over the ellipse = (2π/3) p0 a b = F; the mean pressure is F/(π a b)
    ab = c.semi_major * c.semi_minor
    assert 2 * np.pi / 3 * c.peak_pressure * ab == pytest.approx(f, rel=1e-12)
    assert c.mean_pressure * np.pi * ab == pytest.approx(f, rel=1e-12)
    assert c.contact_radius == pytest.approx(np.sqrt(ab), rel=1e-14)
    assert c.ellipticity == pytest.approx(c.semi_minor / c.semi_major, rel=1e-12)


def test_circular_approximation_with_M_is_close_but_not_equal_on_cu011():
    # The maps' route (Hertz with M, a circle) against the ellipse: close (Vlassak et al. 2003
    # find the indentation modulus nearly independent of the contact's shape), not equal.
    m = Material.crystal("Cu").rotated((0, 1, 1))
    c, h = sphere_contact(m, R, 1.0), hertz(indentation_modulus(m), R, 1.0)
    assert c.stiffness == pytest.approx(h.stiffness, rel=2e-3)
    assert c.stiffness != pytest.approx(h.stiffness, rel=1e-4)


def test_ellipse_quadrature_converges():
    m = turned(Material.crystal("Li").rotated((0, 1, 1)), 0.2)
    loose, fine = contact_ellipse(m, rtol=1e-6), contact_ellipse(m, rtol=1e-14)
    assert loose.n_theta < fine.n_theta
    assert loose.rho == pytest.approx(fine.rho, abs=1e-6)
    assert loose.depth_integral == pytest.approx(fine.depth_integral, rel=1e-6)
    assert loose.curvature_integral == pytest.approx(fine.curvature_integral, rel=1e-6)


def test_contact_ellipse_refuses_loss_and_bad_rtol():
    cu = Material.crystal("Cu").rotated((0, 1, 1))
    with pytest.raises(ValueError, match="undamped"):
        contact_ellipse(cu.with_loss(0.01))
    with pytest.raises(ValueError, match="rtol"):
        contact_ellipse(cu, rtol=1.0)


# ------------------------------------------------------- second route: the contact on a grid
def _real_space(m, sphere=None):
    """The normal displacement under a unit point force in real space, w = g(α)/r.

    From û = Ĝ(θ) p̂/η: the inverse transform of Ĝ(θ)/η along the direction α of x picks the
    wave vectors normal to x (∫₀^∞ cos(η r cos(θ − α)) dη = π δ(r cos(θ − α))), so
    g(α) = Ĝ(α + π/2)/(2π) (isotropic: 1/(π E* r), Boussinesq). Ĝ is tabulated on 4096 angles
    of [0, π] and interpolated linearly (error ~1e-7). An isotropic elastic ``sphere`` adds its
    own Boussinesq compliance 2/E*_sphere to Ĝ."""
    n = 4096
    t = np.pi * np.arange(n + 1) / n
    G = static_kernel(m, t[:-1])
    if sphere is not None:
        E, nu = sphere
        G = G + 2 * (1 - nu**2) / E
    G = np.append(G, G[0])
    return lambda alpha: np.interp(np.mod(alpha + np.pi / 2, np.pi), t, G) / (2 * np.pi)


def _influence(g, N, h):
    """Displacement at a cell's centre from a unit pressure on the cell at offset (i, j) h,
    −N < i, j < N: 4x4 Gauss points on each cell, the own cell exactly (∫ g(α) ρ(α) dα, ρ the
    distance from the centre to the square's edge)."""
    idx = np.arange(-N + 1, N) * h
    X, Y = np.meshgrid(idx, idx, indexing="ij")
    xg, wg = np.polynomial.legendre.leggauss(4)
    K = np.zeros(X.shape)
    for xi, wi in zip(xg, wg, strict=True):
        for yj, wj in zip(xg, wg, strict=True):
            dx, dy = X + xi * h / 2, Y + yj * h / 2
            K += wi * wj / 4 * h * h * g(np.arctan2(dy, dx)) / np.hypot(dx, dy)
    al = 2 * np.pi * (np.arange(4096) + 0.5) / 4096
    rho = h / 2 / np.maximum(abs(np.cos(al)), abs(np.sin(al)))
    K[N - 1, N - 1] = np.sum(g(al) * rho) * 2 * np.pi / 4096
    return K[::-1, ::-1]  # the response at x to a load at x' depends on x − x'


def _grid_contact(m, radius, force, half, N=64, sphere=None):
    """Frictionless contact of a rigid sphere on a grid of N x N cells over [−half, half]²:
    the conjugate-gradient method of Polonsky & Keer (Wear 231, 206 (1999)) for a fixed load,
    p >= 0, the convolution by FFT on a zero-padded 2N x 2N grid. Returns x, y, p, δ."""
    h = 2 * half / N
    x = (np.arange(N) - (N - 1) / 2) * h
    X, Y = np.meshgrid(x, x, indexing="ij")
    Kp = np.zeros((2 * N, 2 * N))
    Kp[: 2 * N - 1, : 2 * N - 1] = _influence(_real_space(m, sphere), N, h)
    Kf = np.fft.rfft2(np.roll(Kp, (-(N - 1), -(N - 1)), axis=(0, 1)))

    def conv(p):
        P = np.zeros((2 * N, 2 * N))
        P[:N, :N] = p
        return np.fft.irfft2(np.fft.rfft2(P) * Kf, s=(2 * N, 2 * N))[:N, :N]

    gap = (X**2 + Y**2) / (2 * radius)
    p = np.where(X**2 + Y**2 < (half / 2) ** 2, 1.0, 0.0)
    p *= force / (p.sum() * h * h)
    t, G_old, conjugate = np.zeros_like(p), 1.0, False
    for _ in range(2000):
        g = conv(p) + gap  # u + r²/(2R): δ where p > 0, above δ elsewhere
        on = p > 0
        g = g - g[on].mean()
        G = np.sum(g[on] ** 2)
        t = np.where(on, g + (G / G_old if conjugate else 0.0) * t, 0.0)
        G_old = G
        r = conv(t)
        r = r - r[on].mean()
        tau = np.sum(g[on] * t[on]) / np.sum(r[on] * t[on])
        p_old = p
        p = np.where(on, p - tau * t, 0.0)
        p[p < 0] = 0
        overlap = (p == 0) & (g < 0)
        conjugate = not overlap.any()
        p[overlap] -= tau * g[overlap]
        p *= force / (p.sum() * h * h)
        if np.abs(p - p_old).sum() * h * h / force < 1e-11:
            break
    else:
        raise AssertionError("the grid contact did not converge")
    delta = (conv(p) + gap)[p > 0].mean()
    return X, Y, p, delta


def _fit_ellipse(X, Y, p):
    """a, b, φ, p0 of p² = p0² (1 − xᵀA⁻¹x), fitted on the cells with p > 0.3 max p."""
    sel = p > 0.3 * p.max()
    A = np.stack([np.ones(sel.sum()), X[sel] ** 2, X[sel] * Y[sel], Y[sel] ** 2], axis=1)
    c = np.linalg.lstsq(A, p[sel] ** 2, rcond=None)[0]
    ev, vec = np.linalg.eigh(-np.array([[c[1], c[2] / 2], [c[2] / 2, c[3]]]) / c[0])
    return 1 / np.sqrt(ev[0]), 1 / np.sqrt(ev[1]), np.arctan2(vec[1, 0], vec[0, 0]), np.sqrt(c[0])


@pytest.mark.parametrize(
    "name, psi, sphere", [("Li", 0.4, None), ("Cu", 0.0, None), ("Li", 1.2, (70e9, 0.17))]
)
def test_grid_solution_gives_the_same_ellipse(name, psi, sphere):
    m = turned(Material.crystal(name).rotated((0, 1, 1)), psi)
    force = 1.0
    half = 1.3 * hertz(indentation_modulus(m), R, force).contact_radius  # room for the ellipse
    X, Y, p, delta = _grid_contact(m, R, force, half, sphere=sphere)
    a, b, phi, p0 = _fit_ellipse(X, Y, p)
    indenter = None if sphere is None else Material.isotropic(*sphere)
    c = sphere_contact(m, R, force, indenter=indenter)
    # measured with 64 x 64 cells: within 6e-4 (a, b), 1e-4 (δ, p0), 0.02° (φ)
    assert a == pytest.approx(c.semi_major, rel=3e-3)
    assert b == pytest.approx(c.semi_minor, rel=3e-3)
    assert b / a < 0.95  # the grid's contact is elliptic, as the analysis says
    assert delta == pytest.approx(c.depth, rel=1e-3)
    assert p0 == pytest.approx(c.peak_pressure, rel=1e-3)
    assert abs(axis_difference(phi, c.orientation)) < np.radians(0.2)


# ------------------------------------------------------------------ an elastic sphere
GLASS = Material.isotropic(70e9, 0.17)


def test_elastic_sphere_on_a_noncircular_face_is_the_ellipse_of_both_compliances():
    import contactres as cr
    from contactres.normal import AnisotropicContact

    face = Material.crystal("Cu").rotated((0, 1, 1))
    ref = cr.sphere_contact(face, R, F, indenter=GLASS)  # the public dispatcher
    assert isinstance(ref, AnisotropicContact) and not ref.circular
    # softer than on the rigid sphere, and a rounder ellipse (the glass adds a constant)
    rigid = sphere_contact(face, R, F)
    assert np.all(ref.stiffness < rigid.stiffness)
    assert rigid.ellipticity < ref.ellipticity < 1
    E_glass = 70e9 / (1 - 0.17**2)
    M = 1 / (1 / indentation_modulus(face) + 1 / E_glass)
    assert ref.indentation_modulus == pytest.approx(M, rel=1e-12)
    for psi in (0.3, 2.0):
        c = cr.sphere_contact(turned(face, psi), R, F, indenter=GLASS)
        np.testing.assert_allclose(c.semi_major, ref.semi_major, rtol=1e-8)
        np.testing.assert_allclose(c.semi_minor, ref.semi_minor, rtol=1e-8)
        np.testing.assert_allclose(c.stiffness, ref.stiffness, rtol=1e-8)
        assert abs(axis_difference(c.orientation, ref.orientation - psi)) < 1e-8
    # a sphere 1e5 times stiffer than the plate is the rigid sphere
    hard = sphere_contact(face, R, F, indenter=Material.isotropic(1e16, 0.3))
    np.testing.assert_allclose(hard.semi_major, rigid.semi_major, rtol=1e-5)
    np.testing.assert_allclose(hard.stiffness, rigid.stiffness, rtol=1e-5)


def test_anisotropic_sphere_is_seen_mirrored_through_the_plate_frame():
    """The sphere's frame is the plate's turned by π about x (y -> −y): a Cu(011) sphere on a
    nearly rigid plate makes the contact of a rigid sphere on Cu(011) mirrored, φ -> −φ."""
    hard_plate = Material.isotropic(1e16, 0.3)
    for psi in (0.0, 0.4, 1.1):
        cu = turned(Material.crystal("Cu").rotated((0, 1, 1)), psi)
        on_cu = sphere_contact(cu, R, F)
        c = sphere_contact(hard_plate, R, F, indenter=cu)
        np.testing.assert_allclose(c.semi_major, on_cu.semi_major, rtol=1e-5)
        np.testing.assert_allclose(c.semi_minor, on_cu.semi_minor, rtol=1e-5)
        assert abs(axis_difference(c.orientation, -on_cu.orientation)) < 1e-4


def test_circular_pairs_keep_the_axisymmetric_route():
    import contactres as cr
    from contactres.normal import LayeredContact

    steel = Material.isotropic(210e9, 0.3)
    for plate in (GLASS, Material.crystal("Cu").rotated((1, 1, 1))):
        assert isinstance(cr.sphere_contact(plate, R, F, indenter=steel), LayeredContact)


def test_an_axis_of_symmetry_along_x_gives_an_orientation_of_exactly_0_or_90_degrees():
    """The X axis of quartz is a 2-fold axis and lies in the AT-cut plate: the contact ellipse is
    symmetric about it, so its major axis is along x or y, reported without round-off."""
    from contactres.materials import at_cut_quartz
    from contactres.normal import contact_ellipse

    phi = contact_ellipse(at_cut_quartz()).orientation
    assert phi in (0.0, np.pi / 2)
