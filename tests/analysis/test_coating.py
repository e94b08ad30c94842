"""E and γ on a coated plate (issue 26, point 4): :mod:`contactres.analysis._coating`.

The anchors: the compliance method on a plate whose film is the substrate is JKR (paper 2,
Eq. 9; :func:`contactres.jkr`); the table's interpolation against the layered solution between
its nodes; κ(F_N) made by an independent forward route (the public sphere solution and tangential
punch, the energy release rate by finite differences: no table, no interpolation, no code of the
module) gives back the E and γ it was made with; a film of the substrate's own material, or one
that thins away, gives the uncoated fit back; a soft film lowers the apparent E of paper 2's
model (the gallery's PMMA/SiO2 question).
"""

import numpy as np
import pytest

import contactres as cr
from contactres.analysis import AnalysisSettings
from contactres.analysis._coating import as_coating, build_law, fit_coated
from contactres.analysis._coating_bootstrap import resampled_coated
from contactres.analysis._coating_law import _corrections, _table_radii
from contactres.analysis._jkr import fit_jkr_mindlin
from contactres.errors import ContactresInputError
from contactres.normal import sphere_contact, sphere_contact_at, static_punch_stiffness
from contactres.tangential import kappa_jkr_mindlin
from contactres.viscoelastic import STATIC_FREQUENCY_HZ

NU = 0.17
R = 1.1e-3
FORCES = np.array([1.6, 3.3, 4.9, 6.5, 8.2, 9.8]) * 1e-3  # N per contact, paper 2's loads
FILM = cr.Material.isotropic(5e9, 0.35, name="soft film")  # PMMA-like, elastic
# The synthetic study's E and γ (SweepGroup of one_group_table).
TRUE_E, TRUE_GAMMA = 70e9, 0.1


def _layered_reference(E, nu, coating, f, a):
    """(C, P'R/a³, κ) of the sphere (E, ν) on the coated plate at contact radii ``a`` (m) and
    frequency ``f`` (Hz), from the layered solution's corrections at those radii
    (``_corrections``: no table, no interpolation), as the table's :meth:`normal` and
    :meth:`tangential` define them: the punch compliance C = 1/(2aE*) + q_C h/a² (m/N), the
    non-adhesive force factor 1/(3/(4E*) + q_P h/a) (Pa) and the storage part of the
    tangential stiffness, κ = Re 1/((2-ν)/(4Ga) + q_κ h/a²) (N/m)."""
    q = _corrections(E, nu, coating, f, a)
    h = coating.thickness
    e_star, G = E / (2 * (1 - nu**2)), E / (2 * (1 + nu))
    C = 1 / (2 * a * e_star) + q[:, 0] * h / a**2
    force = 1 / (3 / (4 * e_star) + q[:, 1] * h / a)
    kappa = np.real(1 / (2 * (2 - nu) / (8 * G * a) + (q[:, 2] + 1j * q[:, 3]) * h / a**2))
    return C, force, kappa


def _assert_interpolates(law, E, nu, coating, f, a, rtol=(1e-4, 3e-4, 2e-4)):
    """``law``'s C, P'R/a³ and κ at ``E`` and radii ``a`` against :func:`_layered_reference`,
    to the relative tolerances ``rtol`` (C, P', κ; by default build_law's tested ones)."""
    C, force, kappa = _layered_reference(E, nu, coating, f, a)
    C_i, _, force_i = law.normal(E, a)
    np.testing.assert_allclose(C_i, C, rtol=rtol[0])
    np.testing.assert_allclose(force_i, force, rtol=rtol[1])
    np.testing.assert_allclose(law.tangential(E, a), kappa, rtol=rtol[2])


def independent_kappa(E, gamma, film, h, nonadhesive_force, frequency_film=None):
    """(F, κ) of the adhesive sphere on the coated plate at the contact radii where the
    frictionless contact carries ``nonadhesive_force``: the compliance method written out
    with the public sphere solution (a, K = dF/dδ = the pair's punch stiffness) and dC/da by
    central differences in the force, and κ the tangential punch of sphere and coated plate
    sharing the traction (their compliances added: static_punch_stiffness with indenter)."""
    sphere = cr.Material.isotropic(E, NU, name="sphere")
    plate = cr.LayeredMaterial(sphere, [(film, h)])
    Fp = np.asarray(nonadhesive_force, dtype=float)
    eps = 1e-4
    c = sphere_contact(
        plate, R, np.concatenate([Fp, Fp * (1 - eps), Fp * (1 + eps)]), indenter=sphere
    )
    a3 = np.asarray(c.contact_radius).reshape(3, -1)
    C3 = 1 / np.asarray(c.stiffness).reshape(3, -1)
    a = a3[0]
    minus_dC = -(C3[2] - C3[1]) / (a3[2] - a3[1])
    F = Fp - np.sqrt(8 * np.pi * gamma * a / minus_dC)
    kappa = np.real(static_punch_stiffness(plate, a, "tangential", indenter=sphere))
    return F, kappa, a


def test_the_pair_punch_is_mindlin_and_below_the_series_of_the_two_punches():
    E, G = 70e9, 70e9 / (2 * (1 + NU))
    body = cr.Material.isotropic(E, NU)
    a = np.array([1e-6, 4e-6])
    same = cr.LayeredMaterial(body, [(body, 250e-9)])
    pair = static_punch_stiffness(same, a, "tangential", indenter=body)
    np.testing.assert_allclose(np.real(pair), 4 * G * a / (2 - NU), rtol=1e-10)
    # On a film the shared traction is softer than two separately optimal ones in series.
    coated = cr.LayeredMaterial(body, [(FILM, 250e-9)])
    pair = np.real(static_punch_stiffness(coated, a, "tangential", indenter=body))
    plate = np.real(static_punch_stiffness(coated, a, "tangential"))
    series = 1 / ((2 - NU) / (8 * G * a) + 1 / plate)
    assert np.all(pair < series) and np.all(series < 1.02 * pair)


def test_the_compliance_method_with_the_substrate_as_film_is_jkr():
    E = 70e9
    same = cr.Material.isotropic(E, NU, name="substrate")
    law = build_law(as_coating((same, 200e-9)), NU, 0.0, (E / 2, 2 * E), (1e-6, 2e-5), n_E=3)
    assert law.E_nodes[1] == pytest.approx(E, rel=1e-14)  # the middle Chebyshev node
    gamma = 0.05
    a, clamped = law.contact_radius(FORCES, E, gamma, R)
    assert not clamped.any()
    e_star = E / (2 * (1 - NU**2))
    jkr = cr.jkr(e_star, R, FORCES, gamma)
    np.testing.assert_allclose(a, jkr.contact_radius, rtol=1e-8)
    np.testing.assert_allclose(
        law.kappa(FORCES, E, gamma, R), kappa_jkr_mindlin(FORCES, E, gamma, R, NU), rtol=1e-8
    )


def test_the_table_interpolates_the_layered_solution_to_3e_4():
    coating = as_coating((cr.pmma(), 250e-9))
    f = 15e6
    law = build_law(coating, NU, f, (30e9, 240e9), (1e-6, 1e-5))
    a = np.array([1.3e-6, 3.3e-6, 7.7e-6])  # between the radius nodes
    # Measured: P' 2.2e-4 at a/h = 5, κ 1.0e-4 (build_law's tested tolerances: the defaults).
    for E in (42e9, 95e9, 170e9):  # between the E nodes
        _assert_interpolates(law, E, NU, coating, f, a)


@pytest.fixture(scope="module")
def synthetic():
    E, gamma, h = 80e9, 0.06, 250e-9
    F, kappa, a = independent_kappa(E, gamma, FILM, h, FORCES + 3e-3)
    assert F.min() > 0  # paper 2's model (the comparison below) starts from positive loads
    law = build_law(as_coating((FILM, h)), NU, 0.0, (40e9, 320e9), (a.min() / 2, 2 * a.max()))
    return {"E": E, "gamma": gamma, "F": F, "kappa": kappa, "law": law}


def test_kappa_from_an_independent_route_gives_back_E_and_gamma(synthetic):
    s = synthetic
    res = fit_coated(s["law"], s["F"], s["kappa"], R, {"E": 60e9, "gamma": 0.02}, 1e3)
    assert res.values["E"] == pytest.approx(s["E"], rel=1e-3)
    assert res.values["gamma"] == pytest.approx(s["gamma"], rel=1e-2)
    # The bootstrap's estimator is the same: every resample of the exact data gives it back.
    W = np.random.default_rng(1).integers(1, 4, size=(5, s["F"].size)).astype(float)
    E_b, g_b = resampled_coated(s["law"], s["F"], s["kappa"], W, R, res, 1e3)
    np.testing.assert_allclose(E_b, res.values["E"], rtol=1e-4)
    np.testing.assert_allclose(g_b, res.values["gamma"], rtol=1e-2, atol=1e-4)


def test_the_grid_of_the_bootstrap_is_the_model_at_each_grid_point(synthetic):
    # kappa_grid (all E of a grid in one contact-radius solve) against the model called at
    # each E alone: the same numbers (each entry's arithmetic is that of its own call).
    law = synthetic["law"]
    E = np.array([45e9, 80e9, 80e9 * (1 + 1e-6), 300e9])
    gamma = np.array([0.0, 0.03, 0.06])
    grid = law.kappa_grid(FORCES[:, None, None], E[None, :, None], gamma[None, None, :], R)
    each = np.stack([law.kappa(FORCES[:, None], e, gamma[None, :], R) for e in E], axis=1)
    assert np.array_equal(grid, each)
    # The Gauss-Newton steps' form: rows of per-resample E stacked, against a call per row.
    rows = np.stack([E, E * (1 + 1e-6), E[::-1]])
    many = law.kappa(FORCES[None, None, :], rows[..., None], 0.05, R)
    ones = np.stack([law.kappa(FORCES[None, :], row[:, None], 0.05, R) for row in rows])
    assert np.array_equal(many, ones)


@pytest.mark.parametrize("per_value", [0, 10**9])
def test_a_grid_evaluated_value_by_value_or_all_at_once_is_the_model_at_each_E(
    synthetic, per_value, monkeypatch
):
    # CoatedLaw._by_value: each E's spline at its own entries (many entries per E) or all the
    # splines at every entry (few): the numbers of the model called at each E alone.
    import contactres.analysis._coating_law as coating

    monkeypatch.setattr(coating, "_PER_VALUE", per_value)
    law = synthetic["law"]
    E = np.linspace(50e9, 250e9, 15)
    gamma = np.linspace(0.0, 0.1, 15)
    grid = law.kappa_grid(FORCES[:, None, None], E[None, :, None], gamma[None, None, :], R)
    each = np.stack([law.kappa(FORCES[:, None], e, gamma[None, :], R) for e in E], axis=1)
    assert np.array_equal(grid, each)


def test_the_bootstrap_estimator_is_the_least_squares_fit(synthetic):
    # Noisy data (1 % on κ), resamples as whole-number weights: the grid estimator of the
    # bootstrap against least squares on the points repeated as often as they are drawn.
    s = synthetic
    rng = np.random.default_rng(3)
    F = np.tile(s["F"], 3)
    kappa = np.tile(s["kappa"], 3) * (1 + 0.01 * rng.standard_normal(F.size))
    res = fit_coated(s["law"], F, kappa, R, {"E": 60e9, "gamma": 0.02}, 1e3)
    W = rng.integers(0, 3, size=(4, F.size)).astype(float)
    E_b, g_b = resampled_coated(s["law"], F, kappa, W, R, res, 1e3)
    for w, E, g in zip(W, E_b, g_b, strict=True):
        take = np.repeat(np.arange(F.size), w.astype(int))
        ref = fit_coated(s["law"], F[take], kappa[take], R, {"E": 60e9, "gamma": 0.02}, 1e3)
        assert E == pytest.approx(ref.values["E"], rel=2e-4)
        assert g == pytest.approx(ref.values["gamma"], rel=5e-3, abs=1e-4)


def test_a_soft_film_lowers_the_apparent_E_of_paper_2s_model(synthetic):
    # The gallery (paper2_coating.py) finds E(PMMA)/E(SiO2) ~ 0.7-0.9 for 250 nm of PMMA: the
    # uncoated model reads a soft film as a softer solid, never a stiffer one.
    s = synthetic
    apparent = fit_jkr_mindlin(s["F"], s["kappa"], R, NU).values["E"]
    assert apparent < 0.95 * s["E"]


def homogeneous_data(E=70e9, gamma=0.05, radius=R, forces=FORCES):
    return forces, kappa_jkr_mindlin(forces, E, gamma, radius, NU)


@pytest.mark.parametrize(("h", "rtol"), [(50e-9, 1e-5), (2e-6, 1e-5)])
def test_a_film_of_the_substrate_material_gives_the_uncoated_fit(h, rtol):
    # The table's interpolation in E is all the difference: a film as thick as the contact
    # (2 µm against a = 4-8 µm) makes the corrections vary most with E. The film is stiffer
    # than the substrate at the table's lowest E (35 GPa): seven E nodes, E measured to 9.6e-7
    # and 5.9e-7, γ to 2.3e-6 and 6.9e-8 (with five, the former default: 7.1e-5 and 4.4e-4 in
    # E, 2.2e-4 and 2.4e-4 in γ; this fails).
    # The table spans the radii the fit visits (a = 4-8 µm at the true E, up to 1.3 times that
    # at the lowest E of the table, as the analysis' own window of 0.7-1.5 times the uncoated
    # radii). The largest a/h sets the cost of the layered solutions: the table's former 1-20 µm
    # made the 50 nm case 28 s of CPU, 2-12 µm took 10 s with five E nodes.
    E, gamma = 70e9, 0.05
    F, kappa = homogeneous_data(E, gamma)
    same = cr.Material.isotropic(E, NU, name="substrate")
    law = build_law(as_coating((same, h)), NU, 0.0, (E / 2, 4 * E), (2e-6, 1.2e-5))
    res = fit_coated(law, F, kappa, R, {"E": 50e9, "gamma": 0.02}, 1e3)
    assert res.values["E"] == pytest.approx(E, rel=rtol)
    assert res.values["gamma"] == pytest.approx(gamma, rel=10 * rtol)


def test_a_film_thinning_away_gives_the_uncoated_fit():
    # Small contacts (R = 20 µm, 5-50 µN: a = 0.2-0.3 µm) so that a/h stays small enough for
    # the solver; a film stiffer than PMMA (20 GPa) whose shear compliance still moves E by
    # 8 % at h = 10 nm (a/h ~ 27): the approach to the uncoated fit is what is tested.
    radius, forces = 20e-6, np.linspace(5e-6, 50e-6, 5)
    E, gamma = 70e9, 0.02
    film = cr.Material.isotropic(20e9, 0.3, name="film")
    F, kappa = homogeneous_data(E, gamma, radius, forces)
    deviation = []
    for h in (40e-9, 20e-9, 10e-9):
        law = build_law(as_coating((film, h)), NU, 0.0, (E / 2, 4 * E), (1e-7, 8e-7))
        res = fit_coated(law, F, kappa, radius, {"E": E, "gamma": gamma}, 1e3)
        deviation.append(res.values["E"] / E - 1)
    # First order in h: halving h halves the gap, and the linear extrapolation to h = 0 (from
    # 20 and 10 nm) lands on the uncoated fit to 1 % (measured 0.6 %).
    assert 0.4 < deviation[1] / deviation[0] < 0.6
    assert 0.4 < deviation[2] / deviation[1] < 0.6
    assert abs(2 * deviation[2] - deviation[1]) < 0.01


@pytest.mark.parametrize(
    ("coating", "match"),
    [
        ((FILM, 0.0), "thickness"),
        ((FILM, -1e-9), "thickness"),
        ((FILM, 2.0), r"AnalysisSettings\(coating=\.\.\.\), layer 1\) 2.0 m is above 1 m"),
        ("pmma:250e-9", "pairs"),
        ((1.0, 250e-9), "pair"),
    ],
)
def test_bad_coatings_are_refused_in_one_line(coating, match):
    with pytest.raises(ContactresInputError, match=match) as err:
        AnalysisSettings(coating=coating)
    assert "\n" not in str(err.value)


def test_the_analysis_takes_films_up_to_the_one_thickness_limit():
    """The analysis's limit is that of every layered input (contactres.layered.MAX_THICKNESS_M,
    as LayeredMaterial and ``--coating``): a 2 mm film is taken, 1 m + 1 mm is not, and its
    thickness is printed in mm."""
    from contactres.layered import MAX_THICKNESS_M

    coating = AnalysisSettings(coating=(FILM, 2e-3)).coating
    assert coating.thickness == 2e-3
    assert coating.label.endswith(" 2 mm")
    with pytest.raises(ContactresInputError, match="is above 1 m"):
        AnalysisSettings(coating=(FILM, MAX_THICKNESS_M + 1e-3))
    with pytest.raises(ContactresInputError, match="is above 1 m"):
        cr.LayeredMaterial(cr.Material.isotropic(70e9, 0.17), [(FILM, MAX_THICKNESS_M + 1e-3)])


def test_the_radiation_step_is_accepted_on_a_coated_plate():
    # The radiation on the coated plate: tests/analysis/test_radiation_coated.py.
    settings = AnalysisSettings(
        coating=(FILM, 250e-9), sphere_material="glass", plate_material="quartz-AT"
    )
    assert settings.coating.layers == ((FILM, 250e-9),)
    with pytest.raises(ContactresInputError, match="unknown plate material"):
        AnalysisSettings(coating=(FILM, 250e-9), sphere_material="glass", plate_material="x")


def test_without_a_coating_the_settings_record_has_no_coating(tmp_path):
    from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
    from contactres.resonators._qcm import QCM

    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.1, (1e-9, 2e-9, 3e-9, 4e-9), 2e4, 0.1),),
        normal_forces=(2e-3, 4e-3, 6e-3),
        n_experiments=3,
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    frame = synthetic_sweeps(study, 7)
    table = cr.validate_sweeps(frame, constants={"area_m2": 2.5e-5, "overtone": 3, "n_contacts": 3})
    plain = cr.analyze(table, settings=AnalysisSettings(bootstrap=0))
    assert "coating" not in plain.settings
    assert all("coating" not in g for g in plain.groups)
    coated = cr.analyze(table, settings=AnalysisSettings(bootstrap=0, coating=(FILM, 100e-9)))
    assert coated.settings["coating"]["layers"] == [
        {"material": "soft film", "thickness_m": 100e-9}
    ]
    (g,) = coated.groups
    assert g["coating"]["uncoated"]["E_Pa"] == plain.groups[0]["E_Pa"]
    assert g["E_Pa"] > plain.groups[0]["E_Pa"]  # the film explains part of the softness
    shares = [row["film_share"] for row in g["coating"]["loads"]]
    assert len(shares) == 3 and all(0 < s < 1 for s in shares)
    assert np.isfinite(coated.jkr["kappa_N_per_m"]).any()


class SoftAtTheOvertone:
    """A film as stiff as the substrate in the static (normal) contact and 15 times softer at
    the overtone (the tangential stiffness). Not a physical material (a passive film stiffens
    with frequency): made so that the coated fit needs contact radii 2.1-2.5 times the uncoated
    ones (measured at 2-6 mN) to give the measured κ, within the table's E range (a film soft
    at both frequencies drives E to the table's bound first). The physical film that needs
    larger radii, soft statically and stiff at the overtone: :class:`StiffeningFilm`."""

    name = "film"

    def at(self, frequency):
        E = 70e9 if frequency <= STATIC_FREQUENCY_HZ else 4.5e9
        return cr.Material.isotropic(E, 0.3, name="film")


def jkr_radius(P, E, gamma, radius):
    """Paper 2's Eq. 9 in closed form, a³ = (3R/4E*)[P + w + √(2wP + w²)], w = 6πγR, E* of the
    homogeneous pair."""
    e_star = E / (2 * (1 - NU**2))
    w = 6 * np.pi * gamma * radius
    return (3 * radius / (4 * e_star) * (P + w + np.sqrt(2 * w * P + w**2))) ** (1 / 3)


def adhesive_force_at(E, gamma, film, h, a):
    """P(a) of the adhesive sphere on the coated plate at contact radius a, by the compliance
    method written out with the public sphere solution: P'(a) and K(a) = 1/C(a) at a, and
    −dC/da by central differences."""
    sphere = cr.Material.isotropic(E, NU, name="sphere")
    plate = cr.LayeredMaterial(sphere, [(film, h)])
    eps = 1e-4
    c = sphere_contact_at(plate, R, a * np.array([1.0, 1 - eps, 1 + eps]), indenter=sphere)
    C = 1 / np.asarray(c.stiffness)
    minus_dC = -(C[2] - C[1]) / (2 * eps * a)
    return float(np.asarray(c.force)[0] - np.sqrt(8 * np.pi * gamma * a / minus_dC))


def one_group_table(loads, negate_last=False, kappa_law=None, monkeypatch=None):
    """The validated sweeps of one experiment at ``loads`` (glass in air, the synthetic
    study's E 70 GPa and γ 0.1 J/m²), the last load's Δf negated if asked (κ < 0: left out
    of the fits). ``kappa_law``: {load: κ} of the sweeps in place of the bare plate's."""
    from contactres.measurements import _synthetic
    from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
    from contactres.resonators._qcm import QCM

    if kappa_law is not None:
        monkeypatch.setattr(
            _synthetic,
            "kappa_jkr_mindlin",
            lambda force, *args: np.vectorize(lambda f: kappa_law[float(f)])(force),
        )
    group = SweepGroup("glass", "air", R, TRUE_E, TRUE_GAMMA, (1e-9, 2e-9, 3e-9, 4e-9), 2e4, 0.1)
    study = SweepStudy(
        groups=(group,),
        normal_forces=loads,
        n_experiments=1,
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    frame = synthetic_sweeps(study, 7)
    if negate_last:
        frame.loc[frame["normal_force_N"] == loads[-1], "df_Hz"] *= -1
    return cr.validate_sweeps(frame, constants={"area_m2": 2.5e-5, "overtone": 3, "n_contacts": 3})


def test_a_load_left_out_of_the_fit_does_not_withhold_it():
    # One experiment at 2, 4 and 6 mN, and at 30 mN with Δf of the wrong sign (κ < 0): that
    # load is left out of both fits. It sets the table's largest radius (1.5 times the
    # uncoated fit's radius there) and the coated fit's radius at it lies beyond the table
    # (P at the table's largest radius, measured 13.3 mN, is below 30 mN), but the fit did
    # not use it: E and γ are given, and that load's row has no radius, κ or share.
    loads = (2e-3, 4e-3, 6e-3, 30e-3)
    table = one_group_table(loads, negate_last=True)
    film, h = SoftAtTheOvertone(), 2e-6
    (g,) = cr.analyze(table, settings=AnalysisSettings(bootstrap=0, coating=(film, h))).groups
    assert g["poisson"] == NU
    uncoated = g["coating"]["uncoated"]
    E0, gamma0 = uncoated["E_Pa"], uncoated["gamma_J_m2"]
    lo, hi = g["coating"]["table_contact_radius_range_m"]
    assert lo == pytest.approx(0.7 * jkr_radius(loads[0], E0, gamma0, R), rel=1e-12)
    assert hi == pytest.approx(1.5 * jkr_radius(loads[-1], E0, gamma0, R), rel=1e-12)
    assert "fit-at-bound" not in g["checks"] and "rejected_fit" not in g
    E, gamma = g["E_Pa"], g["gamma_J_m2"]
    assert np.isfinite([E, gamma, g["E_err_Pa"], g["gamma_err_J_m2"]]).all()
    assert g["n_points_fitted"] == 3
    # Where the radii are, independently of the table: on the stable branch P(a) rises, so a
    # load above P at the table's largest radius has its radius beyond it, one below inside.
    at_hi = adhesive_force_at(E, gamma, film.at(STATIC_FREQUENCY_HZ), h, hi)
    assert loads[2] < at_hi < loads[-1]
    rows = g["coating"]["loads"]
    assert [r["normal_force_N"] for r in rows] == list(loads)
    for r in rows[:3]:  # measured 3.2-5.1 % below the table's top
        assert lo < r["contact_radius_m"] < hi and 0 < r["film_share"] < 1
    last = rows[-1]
    assert np.isnan([last["contact_radius_m"], last["kappa_N_per_m"], last["film_share"]]).all()
    assert last["kappa_bare_N_per_m"] == pytest.approx(
        kappa_jkr_mindlin(loads[-1], E, gamma, R, NU), rel=1e-12
    )


def test_a_used_load_outside_the_table_withholds_the_coated_fit():
    # The withholding itself (apply_coating's last step, after any re-tabulation): a 250 nm
    # PMMA film, a table of radii 3-9 µm and a fit (E 70 GPa, γ 0.1 J/m²) whose radius at
    # 30 mN is beyond it (P at 9 µm, measured 13.0 mN, is below 30 mN: independent of the
    # table). Used (κ > 0): E and γ are withheld and the note says why; left out (κ <= 0):
    # kept. The radii at 2 and 4 mN are inside either way.
    import pandas as pd

    from contactres.analysis._coating import _outside_the_table, _radii

    film, h = cr.pmma(), 250e-9
    law = build_law(as_coating((film, h)), NU, 15e6, (40e9, 160e9), (3e-6, 9e-6))
    at_hi = adhesive_force_at(TRUE_E, TRUE_GAMMA, film.storage(STATIC_FREQUENCY_HZ), h, 9e-6)
    assert 4e-3 < at_hi < 30e-3
    for kappa_last, withheld in ((5e5, True), (-5e5, False)):
        part = pd.DataFrame(
            {"normal_force_N": [2e-3, 4e-3, 30e-3], "kappa_N_per_m": [3e5, 4e5, kappa_last]}
        )
        out = {
            "E_Pa": TRUE_E,
            "E_err_Pa": 1e8,
            "gamma_J_m2": TRUE_GAMMA,
            "gamma_err_J_m2": 1e-3,
            "sphere_radius_m": R,
            "checks": [],
            "note": "",
        }
        radii = _radii(law, out, part)
        assert radii[2].tolist() == [False, False, True]
        _outside_the_table(law, out, radii)
        assert ("fit-at-bound" in out["checks"]) == withheld
        assert np.isnan(out["E_Pa"]) == withheld and np.isnan(out["gamma_J_m2"]) == withheld
        if withheld:
            assert out["rejected_fit"] == {"E_Pa": TRUE_E, "gamma_J_m2": TRUE_GAMMA}
            assert out["note"] == (
                "the coated fit needs contact radii outside its table (3e-06-9e-06 m) at 1 "
                "load(s): E and γ withheld"
            )


class StiffeningFilm:
    """A polymer-like film that stiffens with frequency (a Prony arm: passive, causal):
    storage E 2 GPa at STATIC_FREQUENCY_HZ, 8 GPa at the overtone (15 MHz, ωτ = 3 there),
    ν 0.3."""

    def __new__(cls):
        nu, f, wt = 0.3, 15e6, 3.0
        g_inf = 2e9 / (2 * (1 + nu))
        g1 = 6e9 / (2 * (1 + nu)) * (1 + wt**2) / wt**2
        law = cr.Prony(g_inf, [(g1, wt / (2 * np.pi * f))])
        return cr.ViscoelasticMaterial.isotropic(law, poisson=nu, name="stiffening film")


def coated_kappa(F, E, gamma, film, h, frequency):
    """(κ, a) on the coated plate at the loads F, independently of the table: a from
    :func:`adhesive_force_at` = F (Brent), κ the tangential punch of sphere and coated plate
    at the film's constants at ``frequency`` (static_punch_stiffness with indenter)."""
    from scipy.optimize import brentq

    static = film.storage(STATIC_FREQUENCY_HZ)
    a = np.array(
        [
            brentq(
                lambda r, f=f: adhesive_force_at(E, gamma, static, h, r) - f, 1e-6, 1e-4, rtol=1e-10
            )
            for f in F
        ]
    )
    sphere = cr.Material.isotropic(E, NU, name="sphere")
    plate = cr.LayeredMaterial(sphere, [(film.at(frequency), h)])
    return np.real(static_punch_stiffness(plate, a, "tangential", indenter=sphere)), a


def test_a_film_soft_statically_and_stiff_at_the_overtone_is_fitted_not_withheld(monkeypatch):
    # Review R31a: 2 µm of a film of 2 GPa (static) and 8 GPa (15 MHz), κ(F_N) made on the
    # coated plate (E 70 GPa, γ 0.1 J/m²) by the independent route: the coated radii are
    # 1.5-1.8 times the uncoated fit's, beyond the first table (1.5x at the largest load).
    # The table is rebuilt over the radii the film can give, and the fit gives back E and γ
    # within its stated errors (measured 0.24 and 0.14 of them), at the true radii.
    loads = (2e-3, 4e-3, 6e-3, 30e-3)
    film, h = StiffeningFilm(), 2e-6
    kappa, a_true = coated_kappa(loads, TRUE_E, TRUE_GAMMA, film, h, 15e6)
    table = one_group_table(
        loads, kappa_law=dict(zip(loads, kappa, strict=True)), monkeypatch=monkeypatch
    )
    (g,) = cr.analyze(table, settings=AnalysisSettings(bootstrap=0, coating=(film, h))).groups
    assert "fit-at-bound" not in g["checks"] and "rejected_fit" not in g
    uncoated = g["coating"]["uncoated"]
    a0 = jkr_radius(loads[-1], uncoated["E_Pa"], uncoated["gamma_J_m2"], R)
    assert a_true[-1] > 1.5 * a0  # beyond the first table
    assert g["coating"]["table_contact_radius_range_m"][1] > a_true[-1]
    assert abs(g["E_Pa"] - TRUE_E) < 2 * g["E_err_Pa"]
    assert abs(g["gamma_J_m2"] - TRUE_GAMMA) < 2 * g["gamma_err_J_m2"]
    radii = [r["contact_radius_m"] for r in g["coating"]["loads"]]
    np.testing.assert_allclose(radii, a_true, rtol=2e-3)


def test_the_wider_table_holds_the_radii_the_film_gives_over_the_fits_bounds():
    # _wider_law's bound, checked against the layered solution (adhesive_force_at, no table):
    # at either end of the table's E range, the radius at the largest used load (30 mN) with
    # the fit's γ is below the new table's top (P there above the load, P rising on the
    # stable branch), and the Hertz radius at the smallest (2 mN) above its bottom; a left-out
    # load (100 mN, κ < 0) does not widen it (used, it would). A table that spans the bound
    # already: None (no rebuild; the fit is then withheld as it is).
    import pandas as pd

    from contactres.analysis._coating import _radii, _wider_law

    film, h = StiffeningFilm(), 2e-6
    coating = as_coating((film, h))
    law = build_law(coating, NU, 15e6, (40e9, 160e9), (3e-6, 1.2e-5))
    part = pd.DataFrame(
        {"normal_force_N": [2e-3, 30e-3, 100e-3], "kappa_N_per_m": [3e5, 6e5, -6e5]}
    )
    out = {"E_Pa": TRUE_E, "gamma_J_m2": TRUE_GAMMA, "sphere_radius_m": R}
    radii = _radii(law, out, part)
    assert radii[2].tolist() == [False, True, True] and radii[3].tolist() == [True, True, False]
    wide = _wider_law(law, out, {"gamma_J_m2": 0.05}, radii)
    lo, hi = wide.radius_range
    assert lo <= 3e-6 and hi > 1.2e-5
    static = film.storage(STATIC_FREQUENCY_HZ)
    for E in law.bounds:
        assert adhesive_force_at(E, TRUE_GAMMA, static, h, hi) > 30e-3
        assert adhesive_force_at(E, 0.0, static, h, lo) < 2e-3
    _, clamped = wide.contact_radius(np.array([2e-3, 30e-3]), TRUE_E, TRUE_GAMMA, R)
    assert not clamped.any()
    assert _wider_law(wide, out, {"gamma_J_m2": 0.05}, _radii(wide, out, part)) is None
    # The left-out load, were it used, would widen the table further.
    part["kappa_N_per_m"] = 6e5
    more = _wider_law(law, out, {"gamma_J_m2": 0.05}, _radii(law, out, part))
    assert more.radius_range[0] == lo and more.radius_range[1] > hi


def test_the_wider_table_interpolates_the_layered_solution_where_the_refit_works():
    # The widened table of the test above (2 µm of the stiffening film: radii 2.7-25.8 µm, a/h
    # 1.4-13, 11 radii: 15 a decade below 4 thicknesses, 5 above, build_law) against the
    # layered solution (_corrections at the radius, no table) at the refit's radii of 2-30 mN
    # (10 and 15.7 µm, test_a_film_soft_statically_...) and midway between the nodes around
    # them, E midway between the E nodes. Measured <= 4.9e-5 (P'; C 1.5e-5, κ 3.0e-5); the
    # bottom interval (2.92 µm, a/h 1.5, below any radius of the fit) 1.2e-5 in κ. Built with
    # the first table's film, ν, frequency and E nodes (a wrong ν, frequency or number of E
    # nodes: this fails).
    import pandas as pd

    from contactres.analysis._coating import _radii, _wider_law

    film, h, f = StiffeningFilm(), 2e-6, 15e6
    coating = as_coating((film, h))
    law = build_law(coating, NU, f, (40e9, 160e9), (3e-6, 1.2e-5))
    part = pd.DataFrame({"normal_force_N": [2e-3, 30e-3], "kappa_N_per_m": [3e5, 6e5]})
    out = {"E_Pa": TRUE_E, "gamma_J_m2": TRUE_GAMMA, "sphere_radius_m": R}
    wide = _wider_law(law, out, {"gamma_J_m2": 0.05}, _radii(law, out, part))
    mid = np.exp((wide.log_a[1:] + wide.log_a[:-1]) / 2)
    a = np.concatenate([[1.0e-5, 1.57e-5], mid[(mid > 8e-6) & (mid < 2.2e-5)]])
    assert a.size == 5  # three midpoints: 9.01, 13.31 and 20.69 µm
    x = np.log(wide.E_nodes)
    for E in np.exp((x[1:] + x[:-1]) / 2):
        _assert_interpolates(wide, E, NU, coating, f, a, rtol=(5e-5, 1e-4, 1e-4))


@pytest.mark.parametrize(
    ("layers", "radii", "E_range"),
    [
        # The contact inside a thick soft film (a/h 0.02-0.26), a lossy film across the knee
        # of the spacing (a/h 0.5-5), and the same film inside it on a wide range of E (a/h
        # 0.2-2, 30-240 GPa: the case of build_law's map that 10 radii a decade fail).
        (
            [(cr.Material.isotropic(2e9, 0.3, name="soft film"), 50e-6)],
            (1e-6, 1.3e-5),
            (40e9, 160e9),
        ),
        ([(cr.pmma(), 1e-6)], (0.5e-6, 5e-6), (40e9, 160e9)),
        ([(cr.pmma(), 1e-6)], (0.2e-6, 2e-6), (30e9, 240e9)),
    ],
)
def test_the_table_interpolates_the_layered_solution_where_the_contact_is_in_the_film(
    layers, radii, E_range
):
    # Midway between the radius nodes (in ln a), at E nodes (the spline in a alone) and midway
    # between them (both interpolations), against the layered solution at the radius
    # (_corrections, no table); the tolerances are build_law's stated ones. Measured: the
    # spline <= 2.4e-5 (C, P', κ; P' 2.3e-5 at a/h 0.54), with the E part <= 2.6e-5 on
    # 40-160 GPa and 6.7e-5 in κ (C 4.3e-5) on 30-240 GPa. With 5 radii a decade throughout
    # (_DENSER = 1, the old spacing) every case fails: C up to 6.5e-4 and P' 1.04e-3 in the
    # thick film (C 6.0e-4 at the first E, where the assertion stops), 9.8e-4 and 1.1e-3 in C
    # in the others. With 10 (_DENSER = 2) only the last fails, C up to 1.16e-4 midway in E
    # (1.06e-4 where the assertion stops; the spline alone 9.4e-5; the others <= 1.0e-4 in P',
    # 7.2e-5 in C): the tests show 5 a decade too few and 10 short for PMMA on a wide range;
    # 15 was chosen from build_law's map.
    coating, f = as_coating(layers), 15e6
    law = build_law(coating, NU, f, E_range, radii)
    a = np.exp((law.log_a[1:] + law.log_a[:-1]) / 2)
    x = np.log(law.E_nodes)
    for E in (*law.E_nodes[[0, 2, 4]], *np.exp((x[1:] + x[:-1]) / 2)):
        _assert_interpolates(law, E, NU, coating, f, a)


@pytest.mark.parametrize(
    ("E_film", "E_range"),
    [
        # The analysis' own width of range (0.6-2.5 times the uncoated E: 4.2) and a wider one
        # (several groups), each under a film far stiffer than the substrate.
        (300e9, (10e9, 40e9)),
        (200e9, (30e9, 240e9)),
    ],
)
def test_the_table_of_a_stiff_film_interpolates_the_layered_solution_in_E(E_film, E_range):
    # Midway between the E nodes (in ln E), at radii of the table (the E interpolation alone),
    # against the layered solution there (_corrections, no table); the tolerances are
    # build_law's stated ones. A film stiffer than the substrate gets seven E nodes (measured
    # here, a/h 0.02-0.2: <= 3.5e-7 in C, P', κ on 10-40 GPa, κ's 3.45e-7 the largest, and
    # <= 4.4e-6 on 30-240 GPa; build_law's <= 6.1e-6 is over a/h 0.02-20); with five (n_E=5,
    # the former default) this fails: C 1.1e-4 and 6.1e-4 (P' 6.7e-4, κ 7.3e-4 on the wider
    # range).
    coating, f, nu = (
        as_coating((cr.Material.isotropic(E_film, 0.25, name="stiff"), 1e-6)),
        15e6,
        0.3,
    )
    law = build_law(coating, nu, f, E_range, (0.02e-6, 0.2e-6))
    a = np.exp(law.log_a[::5])
    x = np.log(law.E_nodes)
    for E in np.exp((x[1:] + x[:-1]) / 2):
        _assert_interpolates(law, E, nu, coating, f, a)


def test_the_table_radii_are_log_spaced_and_denser_inside_the_film():
    # Wholly above the knee (4 thicknesses): the plain log spacing, 5 a decade (the table of
    # the bundled example's 250 nm PMMA, unchanged); across it: steps of 1/15 decade below,
    # 1/5 above (within one step's rounding to a whole number of steps), ends as given.
    h = 250e-9
    np.testing.assert_array_equal(_table_radii(1e-6, 1e-5, h, 5), np.geomspace(1e-6, 1e-5, 6))
    a = _table_radii(1e-7, 1e-5, h, 5)
    assert (a[0], a[-1]) == (1e-7, 1e-5)
    step = np.diff(np.log10(a))
    below, above = a[1:] <= 4 * h * (1 + 1e-9), a[:-1] >= 4 * h * (1 - 1e-9)
    assert below.sum() >= 15 and above.sum() >= 2
    np.testing.assert_allclose(step[below], step[below][0], rtol=1e-9)
    assert 1 / 15 * 0.9 < step[below][0] <= 1 / 15 * (1 + 1e-9)
    assert 1 / 5 * 0.9 < step[above][-1] <= 1 / 5 * (1 + 1e-9)


def test_the_wider_table_of_a_thick_soft_film_is_a_tight_bound():
    # Where the bound is tight (50 µm of a 2 GPa film, loads 0.1-1 mN: the contact sits in
    # the film, whose half-space the bound takes), the force at the table's top radius on the
    # layered solution is within ~1 % above the largest load (review R31f: P/F 1.009-1.012).
    # A bound with the smaller γ of the two fits, γ = 0, or the softest pair's sphere at the
    # range's stiff end falls below the load there; each is a wrong bound, and this fails.
    # So does a table widened at the top only (where the radii clamped): P' at its bottom
    # (5 µm) is 3.2e-4 N, above the smallest load, so a refit with γ below ~0.004 J/m² would
    # need a radius below the table (the table of both ends costs one radius more here).
    import pandas as pd

    from contactres.analysis._coating import _radii, _wider_law

    film, h = cr.Material.isotropic(2e9, 0.3, name="soft film"), 50e-6
    law = build_law(as_coating((film, h)), NU, 15e6, (40e9, 160e9), (5e-6, 6e-6))
    part = pd.DataFrame({"normal_force_N": [1e-4, 1e-3], "kappa_N_per_m": [1e5, 2e5]})
    out = {"E_Pa": 70e9, "gamma_J_m2": 0.1, "sphere_radius_m": R}
    wide = _wider_law(law, out, {"gamma_J_m2": 0.05}, _radii(law, out, part))
    lo, hi = wide.radius_range
    force = adhesive_force_at(law.bounds[0], 0.1, film, h, hi)
    assert 1e-3 <= force <= 1.05e-3
    for E in law.bounds:
        assert adhesive_force_at(E, 0.1, film, h, hi) >= 1e-3
        assert adhesive_force_at(E, 0.0, film, h, lo) <= 1e-4


def test_the_wider_table_of_a_thin_soft_film_stops_at_its_reach():
    # A film of 20 MPa (static) and 150 nm: the bound by its softest layer reaches ~850
    # thicknesses, beyond what the layered solver takes (~525: it raised, and the whole
    # analysis was lost as if the user's input were wrong, review R31f). The widened table
    # stops at _WIDE_REACH thicknesses (then the fit is withheld, as before the widening); the
    # bound is checked against the film's own half-space with Eq. 9, independently of it.
    import pandas as pd

    from contactres.analysis import _coating
    from contactres.analysis._coating import _radii, _wider_law

    nu, f, wt = 0.3, 15e6, 3.0
    g1 = (8e9 - 20e6) / (2 * (1 + nu)) * (1 + wt**2) / wt**2
    law_ = cr.Prony(20e6 / (2 * (1 + nu)), [(g1, wt / (2 * np.pi * f))])
    film, h = cr.ViscoelasticMaterial.isotropic(law_, poisson=nu), 150e-9
    law = build_law(as_coating((film, h)), NU, f, (42e9, 175e9), (3.2e-6, 1.0e-5))
    part = pd.DataFrame({"normal_force_N": [2e-3, 30e-3], "kappa_N_per_m": [3e5, 8e5]})
    out = {"E_Pa": 70e9, "gamma_J_m2": 0.1, "sphere_radius_m": R}
    radii = _radii(law, out, part)
    assert radii[2].any()
    # The unbounded top: JKR on the film's own half-space at 30 mN (E* of the film in
    # series with the sphere's at the table's lowest E), far beyond the reach.
    film_E = 20e6 / (1 - nu**2)
    E_star = 1 / (1 / film_E + (1 - NU**2) / 42e9)
    assert jkr_radius(30e-3, 2 * E_star * (1 - NU**2), 0.1, R) > 525 * h
    wide = _wider_law(law, out, {"gamma_J_m2": 0.1}, radii)
    assert wide is not None
    hi = wide.radius_range[1]
    assert hi == pytest.approx(_coating._WIDE_REACH * h, rel=1e-9)


@pytest.mark.parametrize("shape", [(24,), (3, 200, 6), (7, 3)])
def test_the_sum_over_the_E_nodes_is_lagrange_interpolation_and_numpys_sum(shape):
    # _node_sum is the interpolation in ln E of CoatedLaw (weights (..., n_E, 1), the nodes'
    # values (..., n_E, k)): a quartic in ln E is reproduced by the five nodes (an independent
    # check), and the sums are numpy's (w * q).sum(axis=-2), bit for bit (the law's values
    # before the sum was written out).
    from contactres.analysis._coating_law import CoatedLaw, _node_sum

    rng = np.random.default_rng(11)
    E_nodes = np.geomspace(3e10, 2e11, 5)
    law = CoatedLaw.__new__(CoatedLaw)  # only its E nodes are used (_weights)
    object.__setattr__(law, "E_nodes", E_nodes)
    E = rng.uniform(3e10, 2e11, shape)
    w = law._weights(E)[..., None]
    coef = rng.standard_normal((5, 2))  # two columns, each a quartic in ln E
    at_nodes = np.stack([np.polyval(c, np.log(E_nodes)) for c in coef.T], axis=-1)
    got = _node_sum(w, np.broadcast_to(at_nodes, (*shape, 5, 2)))
    exact = np.stack([np.polyval(c, np.log(E)) for c in coef.T], axis=-1)
    np.testing.assert_allclose(got, exact, rtol=0, atol=1e-9 * np.abs(coef).sum())
    q = rng.standard_normal((*shape, 5, 2)) * 10.0 ** rng.integers(-6, 6, (*shape, 5, 2))
    np.testing.assert_array_equal(_node_sum(w, q), (w * q).sum(axis=-2))
    # weights of more E than q has rows broadcast as numpy's product does (review R30b)
    wide = np.stack([w, w[::-1]])
    np.testing.assert_array_equal(_node_sum(wide, q), (wide * q).sum(axis=-2))


def test_a_spline_with_its_derivative_in_one_call_gives_both_as_apart():
    # _with_derivative: the contact-radius steps evaluate the spline and its slope in one
    # call; the values are those of the spline and of scipy's derivative evaluated apart (bit
    # for bit, inside and beyond the breakpoints), and the slope of a cubic is its derivative.
    from scipy.interpolate import CubicSpline

    from contactres.analysis._coating_law import _with_derivative

    rng = np.random.default_rng(5)
    knots = np.sort(rng.uniform(-3.0, 2.0, 9))
    cubic = np.array([[0.7, -1.1, 0.4, 2.0], [-0.2, 0.5, 1.3, -0.6]])  # two columns
    values = np.stack([np.polyval(c, knots) for c in cubic], axis=-1)
    spline = CubicSpline(knots, values, axis=0)
    both = _with_derivative(spline)
    x = np.concatenate([rng.uniform(-4.0, 3.0, 500), knots])
    got = both(x)
    np.testing.assert_array_equal(got[:, :2], spline(x))
    np.testing.assert_array_equal(got[:, 2:], spline.derivative()(x))
    slope = np.stack([np.polyval(np.polyder(c), x) for c in cubic], axis=-1)
    np.testing.assert_allclose(got[:, 2:], slope, rtol=1e-9, atol=1e-9)


def test_the_weights_of_one_E_are_those_of_an_array_of_E():
    # CoatedLaw._weights of one E (Python floats) and of many (numpy): the same bits; Lagrange
    # weights: one at their node, zero at the others, summing to one anywhere.
    from contactres.analysis._coating import CoatedLaw

    law = CoatedLaw.__new__(CoatedLaw)  # only its E nodes are used
    object.__setattr__(law, "E_nodes", np.geomspace(3e10, 2e11, 5))
    E = np.random.default_rng(2).uniform(2e10, 3e11, 300)
    one_by_one = np.stack([law._weights(float(e)) for e in E])
    np.testing.assert_array_equal(one_by_one, law._weights(E))
    np.testing.assert_allclose(one_by_one.sum(axis=-1), 1.0, rtol=0, atol=1e-12)
    at_nodes = np.stack([law._weights(float(e)) for e in law.E_nodes])
    np.testing.assert_allclose(at_nodes, np.eye(5), rtol=0, atol=1e-12)
