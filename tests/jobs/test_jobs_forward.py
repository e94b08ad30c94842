"""The forward jobs (contact, dcsf, qcm_loop) through their Python API, and the one wave-number
function they share, each against an independent computation."""

import math

import numpy as np
import pytest

from contactres import QCM, Material, dcsf, shifts_from_loop
from contactres.dynamic import normalised_wavenumber, wave_modulus
from contactres.errors import ContactresInputError
from contactres.jobs import contact, qcm_loop
from contactres.jobs import dcsf as dcsf_job
from contactres.tangential import CattaneoMindlinLoop


def test_normalised_wavenumber_is_omega_a_over_the_wave_speed():
    # k a = ω a / v with v = √(C/ρ): the same number written through the wave speed.
    rho, c, f, a = 8960.0, 75.4e9, 3e6, 2e-6
    v = math.sqrt(c / rho)
    assert normalised_wavenumber(f, a, rho, c) == pytest.approx(2 * math.pi * f * a / v, 1e-14)
    out = normalised_wavenumber(np.array([1e6, 2e6]), a, rho, np.array([c, 4 * c]))
    assert out[1] == pytest.approx(out[0], rel=1e-14)  # twice f, a stiffer wave by 4: same k a


def test_wave_modulus_picks_c44_or_c33_of_the_face():
    cu = Material.crystal("Cu").rotated((0, 0, 1))
    assert wave_modulus(cu, "shear") == pytest.approx(75.4e9, rel=0.02)
    assert wave_modulus(cu, "longitudinal") == pytest.approx(168.4e9, rel=0.02)
    with pytest.raises(ContactresInputError, match="wavenumber"):
        wave_modulus(cu, "bulk")


def test_contact_job_on_an_isotropic_solid_is_hertz():
    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    s = contact.Settings(radius=np.array([1e-3]), force=np.array([0.5, 1.0]))
    result = contact.run(glass, s)
    # Rigid sphere on an isotropic flat: a³ = 3FR/(4E*), E* = E/(1 − ν²) (Johnson, Ch. 4).
    a = (3 * np.array([0.5, 1.0]) * 1e-3 / (4 * 70e9 / (1 - 0.22**2))) ** (1 / 3)
    assert result.table["contact_radius_m"].to_numpy() == pytest.approx(a, rel=1e-9)
    assert result.circular
    assert list(result.tables()) == ["table"]
    assert result.values() == {"circular": True, "noncircularity": pytest.approx(0, abs=1e-12)}


def test_contact_job_dynamic_column_is_ksa_times_dcsf():
    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    s = contact.Settings(radius=np.array([1e-3]), force=np.array([1.0]), frequency=np.array([2e6]))
    row = contact.run(glass, s).table.iloc[0]
    g = 70e9 / (2 * 1.22)
    assert row["ks_a"] == pytest.approx(
        2 * math.pi * 2e6 * row["contact_radius_m"] / math.sqrt(g / 2500), 1e-12
    )
    k = row["stiffness_N_per_m"] * dcsf(glass, row["ks_a"], wavenumber="shear")
    assert row["dynamic_stiffness_real_N_per_m"] == pytest.approx(k.real, rel=1e-9)


def test_contact_job_takes_single_values_from_python_and_checks_the_frequency():
    """Floats, as a Python user passes them, make one row (the CLI passes arrays); a negative
    frequency is the user's error, not pandas'."""
    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    one = contact.run(glass, contact.Settings(radius=1e-3, force=1.0, frequency=2e6)).table
    rows = contact.Settings(
        radius=np.array([1e-3]), force=np.array([1.0]), frequency=np.array([2e6])
    )
    assert one.equals(contact.run(glass, rows).table)
    with pytest.raises(ContactresInputError, match="frequency must be finite and >= 0"):
        contact.run(glass, contact.Settings(radius=1e-3, force=1.0, frequency=-5.0))


def test_dcsf_and_loop_jobs_take_single_values_from_python():
    """A float where the CLI passes an array gives one row per model (one amplitude), and a
    negative frequency is named as such."""
    cu = Material.crystal("Cu")
    one = dcsf_job.run(cu, dcsf_job.Settings(ka=0.5, models=("WA",))).table
    assert len(one) == 1
    assert complex(one["re"].iloc[0], one["im"].iloc[0]) == pytest.approx(dcsf(cu, 0.5, "WA"))
    s = dcsf_job.Settings(models=("WA",), radius=1e-6, force=1e-6, frequency=1e6)
    assert len(dcsf_job.run(cu, s).table) == 1
    with pytest.raises(ContactresInputError, match="frequency must be finite and >= 0"):
        dcsf_job.run(cu, dcsf_job.Settings(models=("WA",), radius=1e-6, force=1e-6, frequency=-1.0))
    loop = qcm_loop.Settings(model="cm", kappa=1e5, mu=0.3, normal_force=1e-3, u0=1e-9)
    assert len(qcm_loop.run(None, loop).table) == 1


def test_contact_job_refuses_a_frequency_without_density():
    m = Material.cubic(168.4e9, 121.4e9, 75.4e9)
    s = contact.Settings(radius=np.array([1e-3]), force=np.array([1.0]), frequency=np.array([1e6]))
    with pytest.raises(ContactresInputError, match="density"):
        contact.run(m, s)


def test_dcsf_job_at_small_ka_tends_to_one():
    cu = Material.crystal("Cu").rotated((0, 0, 1))
    result = dcsf_job.run(cu, dcsf_job.Settings(ka=np.array([1e-4]), models=("exact", "WA")))
    assert list(result.table["model"]) == ["exact", "WA"]
    assert result.table["re"].to_numpy() == pytest.approx(1.0, abs=1e-3)
    rho = cu.density
    assert result.face["v_s_m_per_s"] == pytest.approx(math.sqrt(result.face["C44_Pa"] / rho))
    with pytest.raises(ContactresInputError, match="either"):
        dcsf_job.run(cu, dcsf_job.Settings())


def test_qcm_loop_job_matches_the_library_shifts():
    s = qcm_loop.Settings(kappa=1e5, mu=0.5, normal_force=1e-3, u0=np.array([1e-9, 5e-9]))
    result = qcm_loop.run(None, s)
    q = QCM(fundamental=5e6, overtone=3, area=1e-5, zq=8.8e6)
    df, dg = shifts_from_loop(q, CattaneoMindlinLoop(1e5, 0.5, 1e-3), np.array([1e-9, 5e-9]), 1)
    assert result.table["df_Hz"].to_numpy() == pytest.approx(df, rel=1e-12)
    assert result.table["dgamma_Hz"].to_numpy() == pytest.approx(dg, rel=1e-12, abs=1e-30)
    with pytest.raises(ContactresInputError, match="--mu"):
        qcm_loop.run(None, qcm_loop.Settings(kappa=1e5))


# ------------------------------------------------------------------------------ coated faces
_COLUMNS = ("contact_radius_m", "peak_pressure_Pa", "depth_m", "stiffness_N_per_m",
            "indentation_modulus_Pa")  # fmt: skip


def _table(face, coating=(), frequency=None, tangential=False, force=(0.0, 1e-3, 1e-2)):
    s = contact.Settings(np.array([1e-3]), np.array(force), frequency, tangential, 0.0, coating)
    return contact.run(face, s).table


@pytest.mark.parametrize(
    "frequency, tangential",
    [(None, True), (np.array([15e6]), False), (np.array([15e6]), True)],
)
def test_coating_of_the_substrate_itself_gives_the_bare_numbers(frequency, tangential):
    """A film of the substrate's own material is no film: every column of the bare face, to
    1e-8 (the bare face's numbers come from the homogeneous Hertz and DCSF, another route)."""
    glass = Material.crystal("fused-silica")
    bare = _table(glass, frequency=frequency, tangential=tangential)
    coated = _table(glass, ("fused-silica:1e-6",), frequency, tangential)
    # The bare face's ellipse columns (a circle on glass) are not written on a coating.
    ellipse = ["semi_major_m", "semi_minor_m", "ellipticity", "orientation_deg"]
    assert not set(ellipse) & set(coated.columns)
    assert (bare["ellipticity"] == 1).all() and (bare["semi_major_m"] == bare["semi_minor_m"]).all()
    for col in bare.columns.drop(ellipse):
        np.testing.assert_allclose(coated[col], bare[col], rtol=1e-8, atol=0, err_msg=col)
    assert (coated["coating"] == "fused-silica 1 µm").all()
    assert np.isnan(coated["film_share"][0])  # no contact at F = 0
    np.testing.assert_allclose(coated["film_share"][1:], 0.0, atol=1e-8)


def test_thick_pmma_film_gives_bulk_pmma_hertz():
    """h >> a (1 mm of PMMA, a ≈ 7 µm): Hertz on PMMA's 1 Hz storage constants, to 1 %; the
    film then takes almost all the stiffness of the silicon nitride face."""
    from contactres import hertz, pmma

    C = np.real(pmma().at(contact.STATIC_FREQUENCY_HZ).C)
    c11, c44 = C[0, 0], C[3, 3]
    e_star = 4 * c44 * (c11 - c44) / c11  # E/(1 − ν²) of an isotropic solid from C11, C44
    t = _table(Material.crystal("Si3N4"), ("pmma:1e-2",), force=(1e-3, 1e-2))
    h = hertz(e_star, 1e-3, np.array([1e-3, 1e-2]))
    np.testing.assert_allclose(t["contact_radius_m"], h.contact_radius, rtol=0.01)
    np.testing.assert_allclose(t["stiffness_N_per_m"], 2 * h.contact_radius * e_star, rtol=0.01)
    np.testing.assert_allclose(t["indentation_modulus_Pa"], e_star, rtol=0.01)
    assert (t["film_share"] > 0.9).all()


def test_pmma_on_fused_silica_is_softer_than_bare():
    glass = Material.crystal("fused-silica")
    bare, coated = _table(glass), _table(glass, ("pmma:250e-9",))
    assert (coated["contact_radius_m"][1:] > bare["contact_radius_m"][1:]).all()
    assert (coated["stiffness_N_per_m"][1:] < bare["stiffness_N_per_m"][1:]).all()
    share = coated["film_share"][1:]
    assert ((share > 0) & (share < 1)).all()
    # A larger force makes a wider contact that reaches deeper below the film.
    assert share.iloc[1] < share.iloc[0]
    assert (coated["coating"] == "PMMA 250 nm").all()


def test_a_layered_material_as_inputs_equals_the_coating_setting():
    from contactres import LayeredMaterial, pmma

    glass = Material.crystal("fused-silica")
    stack = LayeredMaterial(glass, [(pmma(), 250e-9)])
    a, b = _table(stack), _table(glass, ("pmma:250e-9",))
    assert a.equals(b)
    assert _table(glass, [("PMMA", 250e-9)]).equals(b)
    assert _table(glass, "pmma:250e-9").equals(b)  # one layer as a bare string
    with pytest.raises(ContactresInputError, match="not both"):
        _table(stack, ("pmma:1e-7",))


def test_a_lossy_film_has_the_static_columns_of_its_elastic_part():
    """A film C (1 + i tan δ) (Material.with_loss): the static contact takes its storage
    constants, C, as it takes a viscoelastic film's (contactres.viscoelastic.static_solid), so
    every static column is the undamped film's, exactly; the loss shows in the dynamic
    columns only, where the stiffness gains an imaginary part."""
    from contactres import LayeredMaterial

    glass, film = Material.crystal("fused-silica"), Material.crystal("Si3N4")
    f = np.array([15e6])
    elastic = _table(LayeredMaterial(glass, [(film, 250e-9)]), frequency=f, tangential=True)
    lossy = _table(
        LayeredMaterial(glass, [(film.with_loss(0.05), 250e-9)]), frequency=f, tangential=True
    )
    static = ["contact_radius_m", "peak_pressure_Pa", "depth_m", "stiffness_N_per_m"]
    static += ["indentation_modulus_Pa", "film_share", "ks_a"]
    for col in static:
        np.testing.assert_array_equal(lossy[col], elastic[col], err_msg=col)
    for col in ("dynamic_stiffness_imag_N_per_m", "tangential_stiffness_imag_N_per_m"):
        assert (lossy[col][1:] > elastic[col][1:] + 1e-3 * elastic["stiffness_N_per_m"][1:]).all()


def test_the_notes_name_every_material_whose_loss_the_static_columns_leave_out():
    """A lossy Material's static columns are its elastic part's (test above): a note says so,
    as it says a viscoelastic film's are its storage constants at 1 Hz; an unnamed one is
    named by its place (film or substrate); an undamped stack has no such note."""
    from contactres import LayeredMaterial, pmma

    glass, film = Material.crystal("fused-silica"), Material.crystal("Si3N4")
    unnamed = Material.isotropic(70e9, 0.2, density=2500.0)

    def notes(stack, frequency=None):
        s = contact.Settings(np.array([1e-3]), np.array([1e-3]), frequency)
        return [w for w in contact.run(stack, s).warnings if w.startswith("the static columns")]

    assert notes(LayeredMaterial(glass, [(film, 250e-9)])) == []
    lossy_film = LayeredMaterial(glass, [(film.with_loss(0.05), 250e-9)])
    (static,) = notes(lossy_film)
    assert "elastic part" in static and "Si3N4 (lossy)" in static and "dynamic" not in static
    (dynamic,) = notes(lossy_film, np.array([15e6]))
    assert dynamic.startswith(static) and "the dynamic ones its complex constants" in dynamic
    assert "substrate (lossy)" in notes(LayeredMaterial(unnamed.with_loss(0.05), [(film, 1e-7)]))[0]
    both = notes(LayeredMaterial(glass.with_loss(0.05), [(pmma(), 250e-9)]))
    assert "PMMA (viscoelastic)" in both[0] and "fused-silica (lossy)" in both[1]


def test_a_lossy_face_is_refused_bare_and_taken_under_a_coating():
    """The rule the module docstrings state: the bare static contact needs real constants and
    the bare kernels take the loss as the factor loss=, so a bare lossy face is refused (the
    contact job, the dcsf job for contacts and for k a); the same face under a coating runs."""
    lossy = Material.crystal("fused-silica").with_loss(0.02)
    R, F, f = np.array([1e-3]), np.array([1e-2]), np.array([1e6])
    for settings in (contact.Settings(R, F), contact.Settings(R, F, f)):
        with pytest.raises(ContactresInputError, match="the contact job's bare face") as info:
            contact.run(lossy, settings)
        assert "\n" not in str(info.value)
        for remedy in ("static_solid(m)", "loss=Q⁻¹", "coating="):
            assert remedy in str(info.value)
    for settings in (
        dcsf_job.Settings(radius=R, force=F, frequency=f),
        dcsf_job.Settings(ka=np.array([0.5])),
        dcsf_job.Settings(ka=np.array([0.5]), loss=0.02),
    ):
        with pytest.raises(ContactresInputError, match="the dcsf job's bare face") as info:
            dcsf_job.run(lossy, settings)
        assert "\n" not in str(info.value)
        # The factor named, and the way to take it: the elastic part and loss=.
        for remedy in ("static_solid(m)", "loss=0.02)", "coating="):
            assert remedy in str(info.value)
    # A loss that is not one factor (C44 alone lossy) is not named as one.
    C = np.array(Material.crystal("fused-silica").C, dtype=complex)
    C[3, 3] *= 1 + 0.05j
    with pytest.raises(ContactresInputError, match="the dcsf job's bare face") as info:
        dcsf_job.run(Material(C=C, density=lossy.density), dcsf_job.Settings(ka=np.array([0.5])))
    assert "loss=Q⁻¹, or put" in str(info.value) and "here C" not in str(info.value)
    # The remedy the message names runs, and its damping is loss='s: the same as the kernels'.
    from contactres.dynamic import dcsf as dcsf_of
    from contactres.viscoelastic import static_solid

    taken = dcsf_job.run(static_solid(lossy), dcsf_job.Settings(ka=np.array([0.5]), loss=0.02))
    want = dcsf_of(Material.crystal("fused-silica"), 0.5, loss=0.02)
    assert taken.table["im"].iloc[0] > 0
    assert complex(taken.table["re"].iloc[0], taken.table["im"].iloc[0]) == pytest.approx(
        complex(want), rel=1e-5
    )
    coating = ("fused-silica:250e-9",)
    assert len(contact.run(lossy, contact.Settings(R, F, f, coating=coating)).table) == 1
    s = dcsf_job.Settings(radius=R, force=F, frequency=f, coating=coating)
    assert len(dcsf_job.run(lossy, s).table) == 1


def test_a_frequency_dependent_bare_face_is_named_as_such_not_as_lossy():
    """A viscoelastic solid (is_lossy, but no constants C) as a bare face: the jobs say it is no
    Material (take its storage constants), neither crash on its missing C nor call it a lossy
    Material (review R32h)."""
    from contactres import pmma

    R, F, f = np.array([1e-3]), np.array([1e-2]), np.array([1e6])
    runs = [
        (contact.run, contact.Settings(R, F)),
        (dcsf_job.run, dcsf_job.Settings(ka=np.array([0.5]))),
        (dcsf_job.run, dcsf_job.Settings(radius=R, force=F, frequency=f)),
    ]
    for run, settings in runs:
        with pytest.raises(ContactresInputError, match=r"must be a contactres\.Material") as info:
            run(pmma(), settings)
        assert "lossy" not in str(info.value) and "\n" not in str(info.value)


def test_dcsf_on_a_coated_lossy_face_adds_the_loss_to_the_dynamic_columns_only():
    """Fused silica C (1 + i q) under 250 nm of (elastic) fused silica, a ~ 4.6 µm.

    Static columns (contact radius, K_sa, k a) and the face's constants: the elastic face's,
    bit for bit (the elastic part, static_solid). Dynamic: at 1 kHz (no radiation to speak of)
    the added Im K is q times the substrate's part of the static punch stiffness,
    C_s dK/dC_s (first order of K(C_s (1 + i q)) in q: the stiffness is analytic in the
    constants), that derivative taken here by central differences of the static layered punch
    with the substrate's constants scaled; at 15 MHz the added Im K is positive and below what
    the whole half-space lossy adds (the bare solver with loss=q, another algorithm): the film
    on top stays undamped."""
    from contactres import LayeredMaterial, dynamic_contact_stiffness, flat_punch_stiffness

    glass, q = Material.crystal("fused-silica"), 0.02
    R, F, f = np.array([1e-3]), np.array([1e-2]), np.array([1e3, 15e6])
    s = dcsf_job.Settings(radius=R, force=F, frequency=f, coating=("fused-silica:250e-9",))
    elastic, lossy = dcsf_job.run(glass, s), dcsf_job.run(glass.with_loss(q), s)
    for col in ("ka", "radius_m", "force_N", "frequency_Hz", "contact_radius_m",
                "stiffness_N_per_m", "coating"):  # fmt: skip
        np.testing.assert_array_equal(lossy.table[col], elastic.table[col], err_msg=col)
    assert lossy.face == elastic.face
    added = (lossy.table["K_im_N_per_m"] - elastic.table["K_im_N_per_m"]).to_numpy()
    a = float(elastic.table["contact_radius_m"].iloc[0])

    def static_punch(scale):
        substrate = Material(C=glass.C * scale, density=glass.density)
        return flat_punch_stiffness(LayeredMaterial(substrate, [(glass, 250e-9)]), a, 0.0).real

    eps = 1e-4
    share = (static_punch(1 + eps) - static_punch(1 - eps)) / (2 * eps)
    assert 0.5 * float(elastic.table["stiffness_N_per_m"].iloc[0]) < share  # a ≫ 250 nm
    assert added[0] == pytest.approx(q * share, rel=1e-4)
    whole = dynamic_contact_stiffness(glass, R, F, f[1:], loss=q).imag
    whole -= dynamic_contact_stiffness(glass, R, F, f[1:]).imag
    assert 0 < added[1] < whole[0]


@pytest.mark.parametrize(
    "coating, words",
    [
        (("pmma250e-9",), ["MATERIAL:THICKNESS"]),
        (("glass:1e-7",), ["unknown coating material", "pmma", "fused-silica"]),
        (("pmma:0",), ["positive finite"]),
        (("pmma:inf",), ["positive finite"]),
        (("pmma:250",), ["nm/µm"]),
        (("pmma:1e-8",) * 11, ["at most 10"]),
        ((42,), ["MATERIAL:THICKNESS"]),
    ],
)
def test_coating_bad_input(coating, words):
    with pytest.raises(ContactresInputError) as err:
        contact.parse_coating(coating)
    for w in words:
        assert w in str(err.value)
    assert "--coating" in str(err.value)


def test_coating_with_tangential_at_a_frequency_is_the_layered_punch():
    """The tangential columns at a frequency on a coated face: the layered tangential punch of
    the stack at the contact radius (its own tests), turned with --direction; no contact at
    F = 0 (0 and no loss tangent)."""
    from contactres import LayeredMaterial, flat_punch_stiffness, pmma

    glass = Material.crystal("fused-silica")
    t = _table(glass, ("pmma:250e-9",), np.array([15e6]), True)
    a = t["contact_radius_m"].to_numpy()
    stack = LayeredMaterial(glass, [(pmma(), 250e-9)])
    want = flat_punch_stiffness(stack, a[1:], 15e6, "tangential")
    np.testing.assert_allclose(t["tangential_stiffness_real_N_per_m"][1:], want.real, rtol=1e-12)
    np.testing.assert_allclose(t["tangential_stiffness_imag_N_per_m"][1:], want.imag, rtol=1e-12)
    np.testing.assert_allclose(t["tangential_loss_tangent"][1:], want.imag / want.real)
    assert t["tangential_stiffness_real_N_per_m"][0] == 0
    assert np.isnan(t["tangential_loss_tangent"][0])


def test_coating_materials_are_pmma_and_the_isotropic_solids():
    from contactres import crystal_table

    t = crystal_table()
    assert contact.coating_materials() == (
        "pmma",
        *t.loc[t["symmetry"] == "isotropic", "name"],
    )


def test_pmma_coating_dynamic_columns_are_its_moduli_at_the_frequency():
    """At 1 Hz the dynamic stiffness is the static one (the same 1 Hz constants; no inertia at
    k a ~ 1e-8, the loss enters Re K at second order, tan² δ ~ 0.005); Im K > 0 (a passive
    film); PMMA stiffens with frequency (its power laws), so Re K grows with f."""
    glass = Material.crystal("fused-silica")
    t = _table(glass, ("pmma:250e-9",), np.array([1.0, 1e3, 15e6]), force=(1e-3,))
    k, re, im = (t[c].to_numpy() for c in ("stiffness_N_per_m", "dynamic_stiffness_real_N_per_m",
                                          "dynamic_stiffness_imag_N_per_m"))  # fmt: skip
    assert re[0] == pytest.approx(k[0], rel=0.01)
    assert (im > 0).all()
    assert re[0] < re[1] < re[2]


def test_a_stiffer_film_has_a_negative_share():
    """Si3N4 (E = 300 GPa) on fused silica (73 GPa): the film stiffens the contact."""
    t = _table(Material.crystal("fused-silica"), ("Si3N4:1e-6",), force=(1e-3,))
    assert t["film_share"][0] < 0


@pytest.mark.parametrize(
    ("coating", "ratios"), [((), (0.09, 0.11, 0.6)), (("pmma:250e-9",), (0.05, 0.2, 2.0))]
)
def test_contacts_wider_than_hertz_allows_are_flagged(coating, ratios):
    """a/R above HERTZ_APPROXIMATE_RATIO is flagged with its values kept; above
    HERTZ_MAX_RATIO the values are left empty (issue 30: R = 20 nm, F = 1 N printed a/R = 24
    and p0 = 2 TPa). The radii are placed with Hertz's own a³ = 3FR/(4E*) on isotropic glass
    (Johnson, Ch. 4), R² = 3F/(4E* (a/R)³) at F = 1 N; on a 250 nm PMMA film (softer: a wider
    contact) bare ratios well inside, near and far outside the limits (inside: 0.05, a/R = 0.056
    on the film; not 0.01, whose 34 µm contact, 140 times the film, took 6 s of CPU)."""
    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    e_star = 70e9 / (1 - 0.22**2)
    ratios = np.asarray(ratios)
    radii = np.sqrt(3 * 1.0 / (4 * e_star * ratios**3))
    s = contact.Settings(radius=radii, force=np.array([1.0]), frequency=np.array([1e5]),
                         coating=coating)  # fmt: skip
    result = contact.run(glass, s)
    table = result.table
    small, approximate, wide = (table.iloc[i] for i in range(3))
    ratio = (table["contact_radius_m"] / table["radius_m"]).to_numpy()
    if not coating:
        assert ratio[:2] == pytest.approx(ratios[:2], rel=1e-9)
    assert small["flags"] == "" and np.isfinite(small["stiffness_N_per_m"])
    assert approximate["flags"].endswith("> 0.1: Hertz approximate")
    assert contact.HERTZ_APPROXIMATE_RATIO < ratio[1] < contact.HERTZ_MAX_RATIO
    assert np.isfinite(approximate["dynamic_stiffness_real_N_per_m"])
    assert wide["flags"].endswith("> 0.5: beyond Hertz, no value")
    computed = [c for c in table.columns if c not in ("radius_m", "force_N", "frequency_Hz",
                                                       "coating", "flags")]  # fmt: skip
    assert all(np.isnan(wide[c]) for c in computed)
    assert wide["force_N"] == 1.0 and wide["radius_m"] == radii[2]
    assert len(result.warnings) - (1 if coating else 0) == 2  # (a PMMA note first)
    assert "1 of 3 rows" in result.warnings[-2] and "check the sphere radius" in result.warnings[-2]
    assert "values are kept" in result.warnings[-1]


def test_contacts_within_hertz_validity_get_no_flags_column():
    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    result = contact.run(glass, contact.Settings(radius=np.array([1e-3]), force=np.array([1.0])))
    assert "flags" not in result.table and result.warnings == ()


@pytest.mark.parametrize(("ratio", "refused"), [(0.45, False), (0.55, True)])
def test_maps_predict_refuses_a_tip_load_beyond_hertz_before_reading(tmp_path, ratio, refused):
    """issue 30: maps predict printed moduli of contacts wider than the tip. On an isotropic
    solid (M = E/(1 − ν²) in every orientation) the force that puts a/R at ``ratio`` follows
    from Hertz's a³ = 3FR/(4E*) (Johnson, Ch. 4): above HERTZ_MAX_RATIO the job refuses in one
    line before it reads the map (a missing file here), below it goes on to read it."""
    from contactres.jobs import maps_predict
    from contactres.jobs.maps import TipLoad

    glass = Material.isotropic(70e9, 0.22, density=2500.0)
    e_star, radius = 70e9 / (1 - 0.22**2), 1e-6
    force = 4 * e_star * (ratio * radius) ** 3 / (3 * radius)
    settings = maps_predict.Settings(glass, "cubic", TipLoad(radius, force))
    missing = tmp_path / "no_such_map.ang"
    if refused:
        with pytest.raises(ContactresInputError, match=r"0\.55 times the tip radius"):
            maps_predict.run(missing, settings)
    else:
        with pytest.raises((FileNotFoundError, ContactresInputError), match="no_such_map"):
            maps_predict.run(missing, settings)
