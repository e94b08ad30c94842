"""Attached particles on a QCM (contactres.resonators._particles): limits, an independent
solution of the equations of motion, the hydrodynamic force against Landau-Lifshitz §24, and
Kanazawa-Gordon against its published form."""

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq, minimize_scalar

from contactres.errors import ContactresInputError
from contactres.resonators import (
    AIR,
    QCM,
    WATER,
    Medium,
    Particle,
    coupled_resonance,
    kanazawa_gordon,
    medium_named,
    particle_model_validity,
    particle_shifts,
    particle_stiffness,
    penetration_depth,
    shifts_from_stiffness,
    sphere_drag,
)

F0 = 5e6
N = np.arange(1, 14, 2)
SPHERE = Particle.sphere(radius=1e-6, density=2000.0)
# a particle that is not a sphere: I/(mR²) = 0.7
ODD = Particle(mass=3e-15, moment_of_inertia=0.7 * 3e-15 * (2e-6) ** 2, radius=2e-6)


# --- exact limits ---------------------------------------------------------------------------


def test_a_rigid_contact_with_locked_rotation_is_sauerbrey_with_the_full_mass():
    f = N * F0
    w = 2 * np.pi * f
    k = particle_stiffness(SPHERE, f, 1e25, 0.0, rocking="locked")
    np.testing.assert_allclose(k, -SPHERE.mass * w**2, rtol=1e-12, atol=0)
    # Sauerbrey in its usual form: Δf_n = -2 n f_F² (m N/A)/Z_q
    cov = 1e11
    df, dg = particle_shifts(F0, N, SPHERE, 1e25, 0.0, cov, rocking="locked")
    np.testing.assert_allclose(df, -2 * N * F0**2 * SPHERE.mass * cov / 8.8e6, rtol=1e-12)
    np.testing.assert_allclose(dg, 0.0, atol=1e-12 * np.abs(df).max())


@pytest.mark.parametrize("particle", [SPHERE, ODD])
def test_a_rigid_contact_on_a_free_particle_loads_the_sensor_with_the_rolling_mass(particle):
    m, i, r = particle.mass, particle.moment_of_inertia, particle.radius
    f = N * F0
    k = particle_stiffness(particle, f, 1e25, 0.0, rocking="free")
    np.testing.assert_allclose(k, -m * i / (i + m * r * r) * (2 * np.pi * f) ** 2, rtol=1e-12)


def test_a_free_sphere_rolls_with_two_sevenths_of_its_mass():
    f = N * F0
    k = particle_stiffness(SPHERE, f, 1e25, 0.0, rocking="free")
    np.testing.assert_allclose(k / (-SPHERE.mass * (2 * np.pi * f) ** 2), 2 / 7, rtol=1e-12)


@pytest.mark.parametrize("rocking", ["locked", "free", 3e-9])
def test_heavy_particles_give_paper_2_eq_1_with_its_overtone_scaling(rocking):
    heavy = Particle(mass=1e30, moment_of_inertia=1e30, radius=1e-3)
    kappa, xi, cov = 1200.0, 2e-7, 3e8
    df, dg = particle_shifts(F0, N, heavy, kappa, xi, cov, rocking=rocking)
    for j, n in enumerate(N):
        ref = shifts_from_stiffness(QCM(F0, int(n), area=1.0), kappa, xi, n_contacts=cov)
        np.testing.assert_allclose([df[j], dg[j]], ref, rtol=1e-12)


# --- the coupled resonance -------------------------------------------------------------------


@pytest.mark.parametrize("rocking", ["locked", "free"])
def test_df_changes_sign_and_dgamma_peaks_at_the_coupled_resonance(rocking):
    kappa = 800.0
    f_c = coupled_resonance(SPHERE, kappa, rocking=rocking)
    xi = kappa / (2 * np.pi * f_c) * 1e-4  # quality factor 1e4

    def k(f):
        return particle_stiffness(SPHERE, f, kappa, xi, rocking=rocking)

    zero = brentq(lambda f: k(f).real, 0.9 * f_c, 1.1 * f_c, xtol=1e-6, rtol=1e-15)
    peak = minimize_scalar(
        lambda f: -k(f).imag,
        bounds=(0.999 * f_c, 1.001 * f_c),
        method="bounded",
        options={"xatol": 1e-6},
    ).x
    # with ξ -> 0 both go to f_c; at Q = 1e4 they move by O(1/Q²)
    assert abs(zero / f_c - 1) < 1e-6
    assert abs(peak / f_c - 1) < 1e-6
    # below the resonance the particle follows (mass-like, Δf < 0), above it is clamped (Δf > 0)
    assert k(0.5 * f_c).real < 0 < k(2 * f_c).real


def test_coupled_resonances_are_the_eigenfrequencies_of_particle_on_contact():
    kappa, kr = 900.0, 4e-9
    m, i, r = SPHERE.mass, SPHERE.moment_of_inertia, SPHERE.radius
    stiff = np.array([[kappa, -kappa * r], [-kappa * r, kappa * r * r + kr]])
    lam = eigh(stiff, np.diag([m, i]), eigvals_only=True)
    np.testing.assert_allclose(
        coupled_resonance(SPHERE, kappa, rocking=kr), np.sqrt(lam) / (2 * np.pi), rtol=1e-12
    )
    assert coupled_resonance(SPHERE, kappa, rocking="locked") == pytest.approx(
        np.sqrt(kappa / m) / (2 * np.pi), rel=1e-14
    )
    assert coupled_resonance(SPHERE, kappa) == pytest.approx(
        np.sqrt(3.5 * kappa / m) / (2 * np.pi), rel=1e-14
    )


def test_the_coupled_resonance_in_a_liquid_includes_the_liquids_inertia():
    p = Particle.sphere(3e-6, 1050.0)
    kappa = 2e4
    f = coupled_resonance(p, kappa, rocking="locked", medium=WATER)
    zt, _ = sphere_drag(WATER, p.radius, f)
    w = 2 * np.pi * f
    # ω² (m + Im Z_t/ω) = κ at the returned frequency
    assert w**2 * (p.mass + zt.imag / w) == pytest.approx(kappa, rel=1e-12)


# --- a second derivation: the equations of motion as a linear system --------------------------


def _solve_dofs(particle, f, kappa, xi, kr, medium):
    """K_L from the 3-DOF system (surface u = 1, centre x, rotation θ) assembled element by
    element and solved with numpy: the contact spring on b · (u, x, θ), the rotational spring,
    and, in a liquid, dashpots iωZ between the particle and the shear wave at its centre (whose
    displacement and rotation are w u and ϑ u: a lever from the surface), with LL §24 in its
    published (real) form for Z_t."""
    w = 2 * np.pi * f
    m, i, r = particle.mass, particle.moment_of_inertia, particle.radius
    k = kappa + 1j * w * xi
    b = np.array([-1.0, 1.0, -r])  # spring extension = b · (u, x, θ)
    dyn = k * np.outer(b, b) + np.diag([0.0, 0.0, kr]) - w**2 * np.diag([0.0, m, i])
    if medium is not None:
        eta, rho = medium.viscosity, medium.density
        delta = np.sqrt(2 * eta / (rho * w))
        # LL §24: F = 6πηR(1 + R/δ) v + 3πR²√(2ηρ/ω)(1 + 2R/9δ) dv/dt
        zt = 6 * np.pi * eta * r * (1 + r / delta) + 1j * w * 3 * np.pi * r**2 * np.sqrt(
            2 * eta * rho / w
        ) * (1 + 2 * r / (9 * delta))
        qq = (1 + 1j) / delta
        zr = 8 * np.pi / 3 * eta * r**3 * (3 + 3 * qq * r + (qq * r) ** 2) / (1 + qq * r)
        wave = np.exp(-qq * r)
        spin = -0.5 * qq * wave  # ½ ∂/∂z of the wave e^{-qz}
        for z_el, lever in ((zt, np.array([-wave, 1.0, 0.0])), (zr, np.array([-spin, 0.0, 1.0]))):
            dyn = dyn + 1j * w * z_el * np.outer(lever, lever)
    if kr == 0.0 or np.isfinite(kr):
        q = np.linalg.solve(dyn[1:, 1:], -dyn[1:, 0])
        q = np.array([1.0, *q])
    else:  # locked rotation: θ = 0, a 2-DOF system
        x = -dyn[1, 0] / dyn[1, 1]
        q = np.array([1.0, x, 0.0])
    # row u: the force that holds the surface on its path = -(the particle's force on it) = K_L
    return dyn[0] @ q


@pytest.mark.parametrize("medium", [None, WATER])
@pytest.mark.parametrize("kr", [np.inf, 0.0, 5e-9])
def test_the_load_agrees_with_a_direct_solution_of_the_equations_of_motion(kr, medium):
    f = N * F0
    kappa, xi = 700.0, 3e-7
    rocking = "locked" if np.isinf(kr) else ("free" if kr == 0 else kr)
    got = particle_stiffness(SPHERE, f, kappa, xi, rocking=rocking, medium=medium)
    ref = [_solve_dofs(SPHERE, fj, kappa, xi, kr, medium) for fj in f]
    np.testing.assert_allclose(got, ref, rtol=1e-10)


@pytest.mark.parametrize("rocking", ["free", "locked", 1e-9])
def test_the_load_in_vacuum_is_passive(rocking):
    """Im K_L >= 0 (with e^{iωt} a passive load only takes energy from the surface) for any
    contact and frequency, and Im K_L = 0 without loss (ξ = 0). In a liquid K_L is the change
    against the bare liquid, which need not be passive (a particle riding with the liquid
    replaces lossy liquid by a rigid body), so no such test there."""
    rng = np.random.default_rng(7)
    kappa = np.exp(rng.uniform(np.log(1e-2), np.log(1e6), 500))
    xi = np.exp(rng.uniform(np.log(1e-13), np.log(1e-5), 500))
    f = rng.choice(N, 500) * F0
    for particle in (SPHERE, ODD):
        k = particle_stiffness(particle, f, kappa, xi, rocking=rocking)
        assert np.all(k.imag >= 0)
        k0 = particle_stiffness(particle, f, kappa, 0.0, rocking=rocking)
        assert np.all(np.abs(k0.imag) <= 1e-12 * np.abs(k0))


# --- hydrodynamics ---------------------------------------------------------------------------


def test_sphere_drag_is_landau_lifshitz_24_and_stokes_at_low_frequency():
    r = np.array([0.2e-6, 1e-6, 5e-6])
    f = 15e6
    eta, rho = WATER.viscosity, WATER.density
    w = 2 * np.pi * f
    delta = np.sqrt(2 * eta / (rho * w))
    zt, zr = sphere_drag(WATER, r, f)
    np.testing.assert_allclose(zt.real, 6 * np.pi * eta * r * (1 + r / delta), rtol=1e-13)
    np.testing.assert_allclose(
        zt.imag,
        w * 3 * np.pi * r**2 * np.sqrt(2 * eta * rho / w) * (1 + 2 * r / (9 * delta)),
        rtol=1e-13,
    )
    # the torque of rotary oscillations, as LL give it for e^{-iωt} (hence the conjugate)
    x = r / delta
    ll = 8 * np.pi / 3 * eta * r**3 * (3 + 3 * x * (1 - 1j) - 2j * x**2) / (1 + x * (1 - 1j))
    np.testing.assert_allclose(zr, np.conj(ll), rtol=1e-13)
    # steady limit: Stokes drag and the rotlet
    zt0, zr0 = sphere_drag(WATER, r, 1e-12)  # R/δ < 1e-7
    np.testing.assert_allclose(zt0, 6 * np.pi * eta * r, rtol=1e-7)
    np.testing.assert_allclose(zr0, 8 * np.pi * eta * r**3, rtol=1e-7)


def test_far_from_the_surface_the_particle_feels_the_drag_in_still_liquid():
    # R = 60 δ: the shear wave at the centre is e^{-60}; a rigid contact then gives
    # K_L = -mω² + iω Z_t (the particle's inertia plus the force of still liquid, LL §24)
    f = 15e6
    r = 60 * penetration_depth(WATER, f)
    p = Particle.sphere(r, 1050.0)
    w = 2 * np.pi * f
    zt, _ = sphere_drag(WATER, r, f)
    k = particle_stiffness(p, f, 1e30, 0.0, rocking="locked", medium=WATER)
    np.testing.assert_allclose(k, -p.mass * w**2 + 1j * w * zt, rtol=1e-12)


def test_kanazawa_gordon_is_its_published_form():
    rho_q, mu_q = 2648.0, 2.947e10
    zq = np.sqrt(rho_q * mu_q)
    for medium in (WATER, Medium("glycerol-water", 1150.0, 6e-3)):
        df, dg = kanazawa_gordon(F0, N, medium, zq=zq)
        # Kanazawa & Gordon (1985): Δf = -f0^{3/2} √(ρ_L η_L/(π ρ_q μ_q)), on overtone n ×√n
        ref = (
            -np.sqrt(N)
            * F0**1.5
            * np.sqrt(medium.density * medium.viscosity / (np.pi * rho_q * mu_q))
        )
        np.testing.assert_allclose(df, ref, rtol=1e-13)
        np.testing.assert_allclose(dg, -ref, rtol=1e-13)


def test_penetration_depth_of_water():
    # δ = √(η/(π ρ f)), a rearrangement of √(2η/(ρω))
    f = np.array([5e6, 65e6])
    np.testing.assert_allclose(
        penetration_depth(WATER, f),
        np.sqrt(WATER.viscosity / (np.pi * WATER.density * f)),
        rtol=1e-14,
    )


def test_particles_smaller_than_the_penetration_depth_in_liquid_are_flagged():
    small = Particle.sphere(100e-9, 1050.0)
    reason = particle_model_validity(small, N * F0, WATER)
    assert reason is not None and "penetration depth" in reason
    assert particle_model_validity(Particle.sphere(1e-6, 1050.0), N * F0, WATER) is None
    assert particle_model_validity(small, N * F0, None) is None
    # in air the drag on micron particles is far below their inertia: no flag
    assert particle_model_validity(Particle.sphere(2e-6, 1050.0), N * F0, AIR) is None


# --- input ---------------------------------------------------------------------------------


def test_bad_input_is_one_line():
    with pytest.raises(ContactresInputError, match="density"):
        Particle.sphere(1e-6, -1.0)
    with pytest.raises(ContactresInputError, match="radius"):
        Particle(1e-15, 1e-27, 0.0)
    with pytest.raises(ContactresInputError, match="unknown medium"):
        medium_named("honey")
    with pytest.raises(ContactresInputError, match="rocking"):
        particle_stiffness(SPHERE, F0, 1.0, 0.0, rocking="wobbly")
    with pytest.raises(ContactresInputError, match="kappa"):
        particle_stiffness(SPHERE, F0, -1.0, 0.0)
    with pytest.raises(ContactresInputError, match="overtones"):
        particle_shifts(F0, [1.5], SPHERE, 1.0, 0.0, 1e10)
    assert medium_named(" Water ") is WATER and medium_named("AIR") is AIR


def test_shifts_broadcast_over_time_steps_and_overtones():
    kappa = np.array([[500.0], [900.0]])
    df, dg = particle_shifts(F0, N, SPHERE, kappa, 1e-7, 1e11, medium=WATER)
    assert df.shape == dg.shape == (2, N.size)
    one, _ = particle_shifts(F0, N, SPHERE, 900.0, 1e-7, 1e11, medium=WATER)
    np.testing.assert_array_equal(df[1], one)


def test_shifts_beyond_the_small_load_limit_warn():
    # a monolayer of heavy 10 µm spheres rigidly attached: |Δf|/f of order 1e-2
    big = Particle.sphere(10e-6, 8000.0)
    with pytest.warns(RuntimeWarning, match="small-load"):
        particle_shifts(F0, N, big, 1e25, 0.0, 2.5e9, rocking="locked")
