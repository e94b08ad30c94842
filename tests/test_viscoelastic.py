"""Viscoelastic materials (contactres.viscoelastic), checked against independent routes.

- Prony: storage and loss from a numerical Fourier integral of the relaxation function
  (scipy.integrate.quad with a sine/cosine weight), not from the closed form; the limits
  ω -> 0 and ∞; one Maxwell arm's loss peak.
- Power law: the decade ratio, the constant phase, and the Kramers–Kronig pair
  d ln|M|/d ln ω = 2φ/π by a finite difference.
- Table: nodes, monotony between nodes, the range and passivity refusals.
- Materials: constant loss = Material.with_loss, isotropic with constant ν = a complex-E
  isotropic stiffness built here from the textbook formulas, rotation consistency.
- PMMA: the published anchors (density, quasi-static E and ν, ultrasonic wave speeds),
  recomputed here from the complex wave numbers.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

import contactres as cr
from contactres.errors import ContactresInputError
from contactres.materials import (
    rotate_tensor,
    rotation_to_surface,
    tensor_to_voigt,
    voigt_to_tensor,
)
from contactres.viscoelastic import (
    PMMA_STATIC_E,
    PMMA_STATIC_FREQUENCY,
    PMMA_STATIC_POISSON,
    STATIC_FREQUENCY_HZ,
    ConstantLoss,
    ModulusTable,
    PowerLaw,
    Prony,
    ViscoelasticMaterial,
    static_solid,
)

# ------------------------------------------------------------------------------------ Prony
PRONY = Prony(1.0e9, ((2.0e9, 1e-3), (0.5e9, 2e-6)))


def _fourier_modulus(law: Prony, f: float) -> complex:
    """M*(ω) = iω ∫_0^∞ G(t) e^{-iωt} dt from the relaxation function G(t):
    M_∞ + iω ∫_0^∞ ΔG(t) e^{-iωt} dt with ΔG = G - M_∞ (the e^{iωt} convention), i.e.
    storage M_∞ + ω ∫ ΔG sin ωt dt and loss ω ∫ ΔG cos ωt dt, integrated numerically with
    quad's sine/cosine weights over the pieces [0, 40 τ_1], [40 τ_1, 40 τ_2], ... (the
    relaxation times differ by decades; beyond 40 τ_max ΔG < e^{-40} ΔG(0) is dropped)."""
    w = 2 * np.pi * f

    def dg(t):
        return sum(m * np.exp(-t / tau) for m, tau in law.terms)

    edges = [0.0, *sorted(40 * tau for _, tau in law.terms)]
    sin_part = cos_part = 0.0
    for a, b in itertools.pairwise(edges):
        sin_part += quad(dg, a, b, weight="sin", wvar=w, limit=500)[0]
        cos_part += quad(dg, a, b, weight="cos", wvar=w, limit=500)[0]
    return law.equilibrium + w * sin_part + 1j * w * cos_part


@pytest.mark.parametrize("f", [3.0, 160.0, 1e4, 8e4, 3e6])
def test_prony_equals_the_fourier_transform_of_its_relaxation_function(f):
    expected = _fourier_modulus(PRONY, f)
    got = complex(PRONY(f))
    assert got.real == pytest.approx(expected.real, rel=1e-7)
    assert got.imag == pytest.approx(expected.imag, rel=1e-7)
    assert got.imag > 0  # passive: e^{iωt}, loss positive


def test_prony_limits_are_relaxed_and_glassy():
    assert complex(PRONY(0.0)) == 1.0e9
    assert PRONY.instantaneous == 3.5e9
    assert abs(complex(PRONY(1e15)) - 3.5e9) / 3.5e9 < 1e-6
    assert abs(complex(PRONY(1e-6)) - 1.0e9) / 1.0e9 < 1e-6


def test_single_maxwell_arm_has_its_loss_peak_at_omega_tau_one():
    tau, m = 2e-5, 4e9
    law = Prony(0.0, ((m, tau),))
    # The maximum of the loss over log f, found by a bounded scalar search (not a scan).
    best = minimize_scalar(
        lambda x: -complex(law(10.0**x)).imag,
        bounds=(2.0, 6.0),
        method="bounded",
        options={"xatol": 1e-10},
    )
    assert 2 * np.pi * 10.0**best.x * tau == pytest.approx(1.0, rel=1e-6)
    assert -best.fun == pytest.approx(m / 2, rel=1e-12)


def test_from_pyvisco_normalised_series():
    # pyvisco: E(t) = E_0 [1 - Σ α_i + Σ α_i e^{-t/τ_i}]; at t = 0 it is E_0, at ∞ E_0(1 - Σα).
    law = Prony.from_pyvisco(3.0e9, [0.2, 0.3], [1e-2, 1e-5])
    assert law.instantaneous == pytest.approx(3.0e9, rel=1e-15)
    assert law.equilibrium == pytest.approx(1.5e9, rel=1e-15)
    assert [m for m, _ in law.terms] == pytest.approx([0.6e9, 0.9e9], rel=1e-15)
    with pytest.raises(ContactresInputError, match="sum to <= 1"):
        Prony.from_pyvisco(3.0e9, [0.7, 0.5], [1.0, 2.0])


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((-1.0, ()), "M_∞"),
        ((1.0, ((-2.0, 1.0),)), "M_i"),
        ((1.0, ((2.0, 0.0),)), "tau_i"),
        ((1.0, ((2.0, np.nan),)), "tau_i"),
        ((0.0, ()), "all zero"),
        ((1.0, (("a", 1.0),)), "pairs"),
    ],
)
def test_prony_refuses_active_or_bad_input(args, match):
    with pytest.raises(ContactresInputError, match=match):
        Prony(*args)


# -------------------------------------------------------------------------------- power law
def test_power_law_decade_ratio_and_constant_phase():
    phi = 0.3
    law = PowerLaw(1e9, 1e6, phi)
    f = np.array([1e3, 1e4, 1e5, 1e6, 1e7])
    m = law(f)
    ratios = np.abs(m[1:]) / np.abs(m[:-1])
    assert ratios == pytest.approx(10 ** (2 * phi / np.pi), rel=1e-13)
    assert np.angle(m) == pytest.approx(phi, abs=1e-14)
    assert abs(complex(law(1e6))) == pytest.approx(1e9, rel=1e-15)


def test_power_law_is_kramers_kronig_consistent():
    # For a minimum-phase response, d ln|M|/d ln ω = 2φ/π holds for a constant phase; checked by
    # a central difference, independent of the exponent the code uses.
    phi = 0.45
    law = PowerLaw(2e9, 5e6, phi)
    f, h = 3e5, 1e-4
    slope = (
        np.log(abs(complex(law(f * np.exp(h))))) - np.log(abs(complex(law(f * np.exp(-h)))))
    ) / (2 * h)
    assert slope == pytest.approx(2 * np.angle(complex(law(f))) / np.pi, rel=1e-8)


def test_power_law_has_no_static_limit_and_refuses_active_phases():
    with pytest.raises(ContactresInputError, match="no static limit"):
        PowerLaw(1e9, 1e6, 0.1)(0.0)
    for phi in (-0.1, np.pi / 2, 2.0, np.nan):
        with pytest.raises(ContactresInputError, match="phase"):
            PowerLaw(1e9, 1e6, phi)
    with pytest.raises(ContactresInputError, match="frequency_ref"):
        PowerLaw(1e9, 0.0, 0.1)


# ------------------------------------------------------------------------------------ table
TABLE = ModulusTable([1.0, 10.0, 1e3, 1e6], [1.0e9, 1.2e9, 1.5e9, 2.2e9], [5e7, 8e7, 0.0, 1e8])


def test_table_reproduces_its_nodes_exactly():
    m = TABLE(TABLE.frequency)
    assert np.array_equal(m.real, TABLE.storage)
    assert np.array_equal(m.imag, TABLE.loss)


def test_table_is_monotone_between_nodes_and_passive():
    for i in range(TABLE.frequency.size - 1):
        f = np.geomspace(TABLE.frequency[i], TABLE.frequency[i + 1], 201)
        m = TABLE(f)
        for part, nodes in ((m.real, TABLE.storage), (m.imag, TABLE.loss)):
            d = np.diff(part)
            assert np.all(d >= -1e-6 * nodes.max()) or np.all(d <= 1e-6 * nodes.max())
            assert part.min() >= min(nodes[i], nodes[i + 1]) * (1 - 1e-12)
            assert part.max() <= max(nodes[i], nodes[i + 1]) * (1 + 1e-12)
    # Half-way in log f between two positive nodes: the geometric mean (a power law).
    assert complex(TABLE(np.sqrt(10.0))).real == pytest.approx(np.sqrt(1.2e18), rel=1e-13)


@pytest.mark.parametrize("f", [0.0, 0.5, 2e6])
def test_table_refuses_frequencies_outside_its_range(f):
    with pytest.raises(
        ContactresInputError, match=r"outside the modulus table's range 1 to 1e\+06 Hz"
    ):
        TABLE(f)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([1.0, 2.0], [1e9, 1e9], [-1.0, 0.0]), "loss"),
        (([1.0, 2.0], [1e9, 0.0], [0.0, 0.0]), "storage"),
        (([1.0, 1.0], [1e9, 1e9], [0.0, 0.0]), "increasing"),
        (([1.0], [1e9], [0.0]), "length"),
        (([1.0, np.inf], [1e9, 1e9], [0.0, 0.0]), "frequency"),
        (([1.0, 2.0], [1e9, np.nan], [0.0, 0.0]), "storage"),
    ],
)
def test_table_refuses_bad_tables(args, match):
    with pytest.raises(ContactresInputError, match=match):
        ModulusTable(*args)


def test_constant_loss_and_frequency_checks():
    with pytest.raises(ContactresInputError, match="loss_tangent"):
        ConstantLoss(1e9, -0.01)
    with pytest.raises(ContactresInputError, match="frequency"):
        ConstantLoss(1e9, 0.01)(-1.0)
    with pytest.raises(ContactresInputError, match="frequency"):
        PRONY(np.nan)


# ------------------------------------------------------------------------------- materials
def test_proportional_constant_loss_equals_with_loss():
    cu = cr.Material.crystal("Cu").rotated((1, 1, 1))
    for q in (0.0, 0.02, 0.3):
        vm = ViscoelasticMaterial.proportional(cu, ConstantLoss(1.0, q))
        for f in (0.0, 15e6):
            got = vm.at(f)
            want = cu.with_loss(q)
            assert np.array_equal(got.C, want.C)
            assert np.array_equal(got.frame, want.frame)
            assert got.density == want.density
    # With another modulus scale the division costs at most an ulp or so.
    vm = ViscoelasticMaterial.proportional(cu, ConstantLoss(7.3e9, 0.02))
    d = np.abs(vm.at(1e6).C - cu.with_loss(0.02).C).max() / np.abs(cu.C).max()
    assert d < 1e-15


def test_proportional_scales_with_the_law_at_its_reference_frequency():
    si = cr.Material.crystal("Si")
    law = PowerLaw(3e9, 1e6, 0.2)
    vm = ViscoelasticMaterial.proportional(si, law)
    ratio = complex(law(4e6)) / complex(law(1e6)).real
    assert vm.at(4e6).C == pytest.approx(si.C * ratio, rel=1e-14)
    assert np.real(vm.at(1e6).C) == pytest.approx(si.C, rel=1e-14)


def _isotropic_complex(E: complex, nu: float) -> np.ndarray:
    """The textbook isotropic stiffness (Lamé λ, μ) with a complex Young's modulus."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    C = np.zeros((6, 6), dtype=complex)
    C[:3, :3] = lam
    C[[0, 1, 2], [0, 1, 2]] = lam + 2 * mu
    C[[3, 4, 5], [3, 4, 5]] = mu
    return C


def test_isotropic_with_constant_poisson_is_the_complex_E_solid():
    nu = 0.3
    law = Prony(1e9, ((2e9, 1e-6),))
    vm = ViscoelasticMaterial.isotropic(law, poisson=nu, density=1200.0)
    for f in (0.0, 1e4, 1.6e5, 1e7):
        E = 2 * (1 + nu) * complex(law(f))
        got = vm.at(f).C
        assert got == pytest.approx(_isotropic_complex(E, nu), rel=1e-14, abs=1e-5)
        assert got == pytest.approx(cr.Material.isotropic(1.0, nu).C * E, rel=1e-14, abs=1e-5)
    assert vm.density == 1200.0
    assert vm.is_lossy


def test_isotropic_with_bulk_law():
    g, k = PowerLaw(1e9, 1e6, 0.1), 4e9
    vm = ViscoelasticMaterial.isotropic(g, bulk=k)
    G = complex(g(2e6))
    C = vm.at(2e6).C
    assert C[0, 0] == pytest.approx(k + 4 * G / 3, rel=1e-15)
    assert C[0, 1] == pytest.approx(k - 2 * G / 3, rel=1e-15)
    assert C[5, 5] == pytest.approx(G, rel=1e-15)
    with pytest.raises(ContactresInputError, match="exactly one"):
        ViscoelasticMaterial.isotropic(g, poisson=0.3, bulk=k)
    with pytest.raises(ContactresInputError, match="exactly one"):
        ViscoelasticMaterial.isotropic(g)
    with pytest.raises(ContactresInputError, match="static limit"):
        vm.static()


def test_rotated_turns_the_constants_at_every_frequency():
    cu = cr.Material.crystal("Cu")
    vm = ViscoelasticMaterial.proportional(cu, Prony(1.0, ((0.4, 1e-6),)))
    n, x = (1, 1, 1), (1, -1, 0)
    R = rotation_to_surface(n, x)
    for f in (0.0, 2e5):
        want = vm.at(f).rotated(n, x)
        got = vm.rotated(n, x).at(f)
        assert got.C == pytest.approx(want.C, rel=1e-13, abs=1e-13 * np.abs(want.C).max())
        assert np.allclose(got.frame, R)
        by_hand = tensor_to_voigt(rotate_tensor(voigt_to_tensor(vm.at(f).C), R))
        assert got.C == pytest.approx(by_hand, rel=1e-13, abs=1e-13 * np.abs(by_hand).max())


def test_material_at_is_itself_and_a_fluid_has_no_static_limit():
    m = cr.Material.isotropic(70e9, 0.22)
    assert m.at(15e6) is m
    fluid = ViscoelasticMaterial.isotropic(Prony(0.0, ((1e9, 1e-6),)), bulk=2e9)
    with pytest.raises(ContactresInputError, match="no solid"):
        fluid.at(0.0)
    assert fluid.at(1e6).C[3, 3].imag > 0
    with pytest.raises(ContactresInputError, match="one frequency"):
        fluid.at([1.0, 2.0])
    with pytest.raises(ContactresInputError, match="elastic material"):
        ViscoelasticMaterial.proportional(m.with_loss(0.01), ConstantLoss(1.0, 0.01))


# ------------------------------------------------------------------------------------- PMMA
def _phase_velocity(modulus: complex, density: float) -> float:
    # k = ω √(ρ/M*) (e^{iωt}, k with Re k > 0 and Im k < 0 for a decaying wave); c = ω/Re k.
    return 1.0 / np.real(np.sqrt(density / modulus))


def test_pmma_reproduces_its_published_anchors():
    # Anchors cited in contactres.viscoelastic.pmma: ρ = 1190 kg/m³; quasi-static (1 Hz)
    # E = 3.0 GPa and ν = 0.37 (handbook values for cast PMMA); ultrasonic phase velocities at
    # 5 MHz c_T = 1370 m/s and c_L = 2700 m/s (B. Hartmann and J. Jarzynski, J. Acoust. Soc.
    # Am. 56, 1469 (1974), range 1340-1400 and 2690-2750 m/s).
    p = cr.pmma()
    assert p.density == 1190.0
    C = p.at(5e6).C
    assert _phase_velocity(C[3, 3], 1190.0) == pytest.approx(1370.0, rel=1e-9)
    assert _phase_velocity(C[0, 0], 1190.0) == pytest.approx(2700.0, rel=1e-9)
    C1 = p.at(1.0).C
    g, k = C1[3, 3], C1[0, 0] - 4 * C1[3, 3] / 3
    # |E| and ν of the two magnitudes at 1 Hz (the laws are anchored on |M|).
    E = 9 * abs(k) * abs(g) / (3 * abs(k) + abs(g))
    nu = (3 * abs(k) - 2 * abs(g)) / (2 * (3 * abs(k) + abs(g)))
    assert E == pytest.approx(3.0e9, rel=1e-9)
    assert nu == pytest.approx(0.37, rel=1e-9)
    # The shear loss tangent and storage modulus at 15 MHz quoted in the docstring.
    g15 = p.at(15e6).C[3, 3]
    assert g15.real / 1e9 == pytest.approx(2.34, abs=0.005)
    assert g15.imag / g15.real == pytest.approx(0.073, abs=0.0005)
    with pytest.raises(ContactresInputError, match="no static limit"):
        p.static()
    assert ViscoelasticMaterial.pmma().at(1e6).C == pytest.approx(p.at(1e6).C, rel=0)


def test_a_static_contact_on_pmma_names_its_storage_solid_and_that_solid_works():
    """The power law has no static limit, so sphere_contact and indentation_modulus_at refuse a
    stack with pmma(); the one-line refusal names the way out, storage(f): the real part of
    the constants at f (checked against at(f) and, for the homogeneous solid, Hertz with the
    E* of those constants written out here)."""
    quartz = cr.Material.isotropic(72e9, 0.17, density=2650.0)
    stack = cr.LayeredMaterial(quartz, [(cr.pmma(), 250e-9)])
    for call in (
        lambda m: cr.sphere_contact(m, 1e-3, 1e-3),
        lambda m: cr.indentation_modulus_at(m, 1e-6),
        lambda m: cr.sphere_contact(m.layers[0][0].at(1.0), 1e-3, 1e-3),
    ):
        with pytest.raises(ContactresInputError, match="storage") as info:
            call(stack)
        assert "\n" not in str(info.value)
    with pytest.raises(ContactresInputError, match=r"storage\(f_Hz\)"):
        cr.sphere_contact(cr.pmma(), 1e-3, 1e-3)
    solid = cr.pmma().storage(1.0)
    assert not solid.is_lossy and solid.density == 1190.0
    assert np.array_equal(solid.C, cr.pmma().at(1.0).C.real)
    g, lam = solid.C[3, 3], solid.C[0, 1]
    nu = lam / (2 * (lam + g))
    e_star = 2 * g * (1 + nu) / (1 - nu**2)
    got = cr.sphere_contact(solid, 1e-3, 1e-3)
    want = cr.hertz(e_star, 1e-3, 1e-3)
    assert got.contact_radius == pytest.approx(want.contact_radius, rel=1e-12)
    # The way out for the stack: its film as the storage solid.
    coated = cr.sphere_contact(cr.LayeredMaterial(quartz, [(solid, 250e-9)]), 1e-3, 1e-3)
    assert want.contact_radius > coated.contact_radius > 0


def test_a_tables_static_refusal_keeps_the_tables_reason_and_pandas_gets_no_hint():
    """Review R22a: at(0) of a table not reaching 0 Hz says the table's own range (no storage
    modulus was computed, so none is quoted), then the way out; require_material's hint about
    frequency-dependent solids is for those only, not for a pandas object (its ``at``
    accessor)."""
    import pandas as pd

    from contactres.materials import require_material

    table = ModulusTable([10.0, 100.0, 1000.0], [1e9, 1.2e9, 1.5e9], [1e8] * 3)
    solid = ViscoelasticMaterial.isotropic(table, poisson=0.35, density=1190.0, name="tabled")
    with pytest.raises(ContactresInputError) as info:
        solid.at(0.0)
    text = str(info.value)
    assert "range 10 to 1000 Hz" in text and "storage(f_Hz)" in text
    assert "Pa)" not in text and "\n" not in text
    with pytest.raises(ContactresInputError) as info:
        require_material(pd.DataFrame({"a": [1.0]}))
    assert str(info.value) == "m must be a contactres.Material, got DataFrame"
    with pytest.raises(ContactresInputError, match="layered_dcsf"):
        require_material(solid)


# ------------------------------------------------------------ the solid of a static contact
def test_a_constant_loss_gives_the_same_static_solid_as_a_material_or_as_a_law():
    """One solid, two spellings: C (1 + i tan δ) as Material.with_loss and as a
    ViscoelasticMaterial with a ConstantLoss law. Its static solid is the elastic C either way
    (the storage constants, real), at any loading frequency; an elastic Material is itself."""
    cu = cr.Material.crystal("Cu").rotated((1, 1, 0))
    assert static_solid(cu) is cu
    lossy = cu.with_loss(0.05)
    law = ViscoelasticMaterial.proportional(cu, ConstantLoss(1.0, 0.05))
    for f in (0.0, STATIC_FREQUENCY_HZ, 15e6):
        for m in (lossy, law):
            solid = static_solid(m, f)
            assert solid.C.dtype == float and not solid.is_lossy
            assert solid.C == pytest.approx(cu.C, rel=1e-15, abs=1e-15 * cu.C.max())
            assert solid.density == cu.density and solid.name == cu.name
            assert np.array_equal(solid.frame, cu.frame)
    # A lossless law still evaluates to complex constants: the static solid is real anyway.
    assert static_solid(ViscoelasticMaterial.proportional(cu, 1.0)).C.dtype == float


def test_static_solid_is_the_storage_modulus_at_the_loading_frequency():
    """A Maxwell arm on a spring, storage M_∞ + M_1 ω²τ²/(1 + ω²τ²) written out here: M_∞ at
    0 Hz (the relaxed solid), M_∞ + M_1/2 at ωτ = 1; and the built-in PMMA at the default
    frequency: its shear storage modulus |G*| cos φ with |G*| from the published 1 Hz anchors
    (E, ν), which only 1 Hz gives (its power law has no static limit: 0 Hz is refused)."""
    tau, m_inf, m_1 = 1e-6, 1e9, 2e9
    solid = ViscoelasticMaterial.isotropic(Prony(m_inf, [(m_1, tau)]), poisson=0.3)
    for f in (0.0, 1 / (2 * np.pi * tau), 3e5):
        wt2 = (2 * np.pi * f * tau) ** 2
        want = m_inf + m_1 * wt2 / (1 + wt2)
        assert static_solid(solid, f).C[3, 3] == pytest.approx(want, rel=1e-14)
    assert STATIC_FREQUENCY_HZ == PMMA_STATIC_FREQUENCY  # the default's reason: the anchors
    g_anchor = PMMA_STATIC_E / (2 * (1 + PMMA_STATIC_POISSON))
    phase = np.angle(cr.pmma().at(PMMA_STATIC_FREQUENCY).C[3, 3])
    assert static_solid(cr.pmma()).C[3, 3] == pytest.approx(g_anchor * np.cos(phase), rel=1e-12)
    with pytest.raises(ContactresInputError, match="no static limit"):
        static_solid(cr.pmma(), 0.0)


def test_static_solid_refuses_an_at_that_gives_no_material():
    class Odd:
        def at(self, frequency):
            return "steel"

    with pytest.raises(ContactresInputError, match=r"Odd.at\(1.0\) must return a contactres"):
        static_solid(Odd())


@pytest.mark.parametrize("bad", ["steel", 70e9, None, np.eye(6)])
def test_static_solid_refuses_what_is_no_material_in_one_line(bad):
    """A name or a number reached ``.at`` and raised AttributeError; now the caller's error, in
    one line that names what static_solid takes and what it got (also with a bad frequency)."""
    for f in (STATIC_FREQUENCY_HZ, -1.0):
        with pytest.raises(ContactresInputError) as info:
            static_solid(bad, f)
        text = str(info.value)
        assert "\n" not in text
        assert text.startswith("static_solid takes a contactres.Material or a frequency-dependent")
        assert (repr(bad) if isinstance(bad, str) else type(bad).__name__) in text


def test_the_contact_job_finds_the_one_static_frequency():
    from contactres.jobs import contact

    assert contact.STATIC_FREQUENCY_HZ is STATIC_FREQUENCY_HZ


@pytest.mark.parametrize("bad", [-5.0, np.nan, np.inf, -np.inf, None, "one Hz", 1j])
def test_static_solid_checks_the_frequency_of_every_material(bad):
    """A Material does not depend on the frequency, but a bad one is still the caller's error,
    refused in the words a ViscoelasticMaterial's is (the module's one frequency rule)."""
    cu = cr.Material.crystal("Cu")
    messages = set()
    for m in (cu, cu.with_loss(0.05), cr.pmma()):
        with pytest.raises(ContactresInputError, match="frequency must be") as info:
            static_solid(m, bad)
        messages.add(str(info.value))
    assert len(messages) == 1
    for m in (cu, cr.pmma()):
        with pytest.raises(ContactresInputError, match="one frequency"):
            static_solid(m, [1.0, 2.0])


def test_static_solid_takes_one_material_not_a_stack():
    """A LayeredMaterial has no one static solid (its layers and substrate each have one): the
    refusal says so, whatever the stack holds (before: '.at(1.0) must return a Material')."""
    cu = cr.Material.crystal("Cu")
    for layer in (cr.pmma(), cu.with_loss(0.05), cu):
        with pytest.raises(ContactresInputError, match="one material, not a stack"):
            static_solid(cr.LayeredMaterial(cu, [(layer, 1e-7)]))
