"""Tests of ``contactres contact`` and the indentation moduli of ``contactres crystals``."""

import io
import json
import re

import numpy as np
import pandas as pd
import pytest
from cli_checks import invoke, one_line_error, option_names, run

from contactres import Material, indentation_modulus, sphere_contact
from contactres.cli._crystal_face import parse_direction


def _json(r):
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def test_contact_crystal_json_matches_library():
    rows = _json(
        run("contact", "--crystal", "Cu", "--radius", 1e-3, "--force", 1, "--format", "json")
    )
    assert len(rows) == 1
    c = sphere_contact(Material.crystal("Cu"), 1e-3, 1.0)
    row = rows[0]
    assert row["contact_radius_m"] == pytest.approx(c.contact_radius, rel=1e-12)
    assert row["peak_pressure_Pa"] == pytest.approx(c.peak_pressure, rel=1e-12)
    assert row["depth_m"] == pytest.approx(c.depth, rel=1e-12)
    assert row["stiffness_N_per_m"] == pytest.approx(c.stiffness, rel=1e-12)
    # Sanity numbers for Cu (001) (docs/validation.md): M ≈ 134.0 GPa, a ≈ 17.75 µm.
    assert row["indentation_modulus_Pa"] == pytest.approx(134.0e9, rel=5e-4)
    assert row["contact_radius_m"] == pytest.approx(17.75e-6, rel=5e-4)


def test_three_ways_to_give_the_crystal_agree():
    common = ["--surface", "111", "--radius", 1e-6, "--force", 1e-6, "--format", "json"]
    a = _json(run("contact", "--crystal", "Cu", *common))[0]
    b = _json(run("contact", "--c11", 168.4e9, "--c12", 121.4e9, "--c44", 75.4e9, *common))[0]
    A = 2 * 75.4 / (168.4 - 121.4)
    nu = 121.4 / (168.4 + 121.4)
    c = _json(run("contact", "--zener", A, "--poisson", nu, "--c44", 75.4e9, *common))[0]
    for key in ("contact_radius_m", "stiffness_N_per_m", "indentation_modulus_Pa"):
        assert b[key] == pytest.approx(a[key], rel=1e-12)
        assert c[key] == pytest.approx(a[key], rel=1e-10)
    assert a["indentation_modulus_Pa"] == pytest.approx(
        indentation_modulus(Material.crystal("Cu").rotated((1, 1, 1))), rel=1e-12
    )


def test_csv_table_over_a_force_range_and_units_in_columns():
    r = run("contact", "--crystal", "Al", "--radius", 1e-3, "--force", "0:2:5", "--format", "csv")
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.stdout))
    assert list(t.columns) == [
        "radius_m",
        "force_N",
        "contact_radius_m",
        "semi_major_m",
        "semi_minor_m",
        "ellipticity",
        "orientation_deg",
        "peak_pressure_Pa",
        "depth_m",
        "stiffness_N_per_m",
        "indentation_modulus_Pa",
    ]
    np.testing.assert_allclose(t.force_N, np.linspace(0, 2, 5))
    # Al (001): a circle
    np.testing.assert_array_equal(t.semi_major_m, t.contact_radius_m)
    np.testing.assert_array_equal(t.semi_minor_m, t.contact_radius_m)
    assert (t.ellipticity == 1).all() and (t.orientation_deg == 0).all()
    # a ∝ F^(1/3): independent of the modulus.
    np.testing.assert_allclose(
        t.contact_radius_m[1:] / t.force_N[1:] ** (1 / 3), t.contact_radius_m[4] / 2 ** (1 / 3)
    )


def test_plain_output_and_note_on_low_symmetry_face():
    r = run("contact", "--crystal", "Cu", "--surface", "011", "--radius", 1e-3, "--force", 1)
    assert r.exit_code == 0
    assert "contact_radius_m" in r.stdout
    assert "elliptic" in r.stderr
    r = run("contact", "--crystal", "Cu", "--surface", "001", "--radius", 1e-3, "--force", 1)
    assert "elliptic" not in r.stderr


@pytest.mark.parametrize(
    "crystal, surface, hkl",
    [("Cu", "011", (0, 1, 1)), ("Li", "011", (0, 1, 1)), ("Cu", "1 2 3", (1, 2, 3))],
)
def test_elliptic_contact_does_not_depend_on_the_inplane_axis(crystal, surface, hkl):
    """Issue 27, point 9: turning the face about its normal (--inplane) moved the stiffness of
    Cu(011) by 3.8 %; now only the orientation of the ellipse moves."""
    common = ["--crystal", crystal, "--surface", surface, "--radius", 1e-3, "--force", "0.5,2"]
    face = Material.crystal(crystal).rotated(hkl)
    lib = sphere_contact(face, 1e-3, np.array([0.5, 2.0]))
    for inplane in (None, (0, 1, -1), (1, -1, 1), (2, 1, -1), (-1, 0, 0)):
        extra = [] if inplane is None else ["--inplane", " ".join(map(str, inplane))]
        got = _json(run("contact", *common, *extra, "--format", "json"))
        turned = Material.crystal(crystal).rotated(hkl, inplane=inplane)
        phi = np.degrees(sphere_contact(turned, 1e-3, 1.0).orientation)
        for i, row in enumerate(got):
            for key, want in [
                ("contact_radius_m", lib.contact_radius[i]),
                ("semi_major_m", lib.semi_major[i]),
                ("semi_minor_m", lib.semi_minor[i]),
                ("depth_m", lib.depth[i]),
                ("stiffness_N_per_m", lib.stiffness[i]),
                ("peak_pressure_Pa", lib.peak_pressure[i]),
                ("ellipticity", lib.ellipticity),
            ]:
                assert row[key] == pytest.approx(want, rel=1e-8), (inplane, key)
            assert row["ellipticity"] < 0.99
            assert row["orientation_deg"] == pytest.approx(phi, abs=1e-8)


def test_contact_and_the_maps_route_agree_within_the_circular_approximation():
    """The maps compute Hertz with M (a circle: K = 2aM); on Cu(011) the ellipse's stiffness is
    within 0.1 % of it (5.0737e6 against 5.0702e6 N/m at R = 1 mm, F = 1 N), its radius √(ab)
    within 0.2 % (17.171 against 17.200 µm)."""
    from contactres import hertz

    row = _json(
        run(
            "contact",
            "--crystal",
            "Cu",
            "--surface",
            "011",
            "--radius",
            1e-3,
            "--force",
            1,
            "--format",
            "json",
        )
    )[0]
    h = hertz(indentation_modulus(Material.crystal("Cu").rotated((0, 1, 1))), 1e-3, 1.0)
    assert row["stiffness_N_per_m"] == pytest.approx(h.stiffness, rel=1e-3)
    assert row["contact_radius_m"] == pytest.approx(h.contact_radius, rel=2e-3)


@pytest.mark.parametrize(
    "args, match",
    [
        (["--radius", 1, "--force", 1], "exactly one"),
        (["--crystal", "Cu", "--c11", 1e9, "--radius", 1, "--force", 1], "exactly one"),
        (["--crystal", "Cu", "--c44", 1e9, "--radius", 1, "--force", 1], "--c44"),
        (["--c11", 2e9, "--c12", 1e9, "--radius", 1, "--force", 1], "missing --c44"),
        (["--crystal", "Unobtainium", "--radius", 1, "--force", 1], "unknown crystal"),
        (["--crystal", "Cu", "--surface", "1x1", "--radius", 1, "--force", 1], "--surface"),
        (["--crystal", "Cu", "--radius", -1, "--force", 1], "radius"),
        (["--crystal", "Cu", "--radius", 1, "--force", -1], "force"),
        (["--crystal", "Cu", "--radius", "1e-4:2e-4:3", "--force", "1:2:4"], "same number"),
        (["--zener", 1, "--poisson", 0.7, "--c44", 1e9, "--radius", 1, "--force", 1], "poisson"),
    ],
)
def test_bad_input_one_line_exit_2(args, match):
    r = run("contact", *args)
    assert r.exit_code == 2
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and match in lines[0]


CRYSTAL = {"--crystal": "Cu", "--radius": "1e-3", "--force": "1"}
CONSTANTS = {"--c11": "168.4e9", "--c12": "121.4e9", "--c44": "75.4e9", "--radius": "1e-3",
             "--force": "1"}  # fmt: skip
RATIOS = {"--zener": "3.2", "--poisson": "0.42", "--c44": "75.4e9", "--radius": "1e-3",
          "--force": "1"}  # fmt: skip

# One bad input per option: a unit slip, a NaN, a sign, a value outside the plausible range or
# (for the options that only mean something together) an impossible combination.
BAD = [
    (CRYSTAL, "--crystal", "Unobtainium"),
    (CONSTANTS, "--c11", "165.7"),
    (CONSTANTS, "--c12", "nan"),
    (CONSTANTS, "--c44", "-75.4e9"),
    (RATIOS, "--zener", "0"),
    (RATIOS, "--poisson", "0.5"),
    (CRYSTAL, "--surface", "1x1"),
    (CRYSTAL, "--inplane", "001"),
    (CRYSTAL, "--radius", "100"),
    (CRYSTAL, "--force", "1e300"),
    (CRYSTAL, "--format", "xml"),
    (CRYSTAL, "--frequency", "15"),
    (CRYSTAL, "--direction", "east"),
    (CRYSTAL, "--coating", "pmma:250"),
]
# Flags take no value: their misuse is a combination (test_contact_tangential_bad_input).
FLAGS = {"--tangential"}


def test_every_option_has_a_bad_input_case():
    from contactres.cli.contact import contact

    assert option_names(contact) == {option for _, option, _ in BAD} | FLAGS


@pytest.mark.parametrize("base, option, value", BAD, ids=[f"{o}={v}" for _, o, v in BAD])
def test_each_option_refuses_bad_input_in_one_line(base, option, value):
    one_line_error(invoke(["contact"], base, option, value), option)


def test_issue_11_constants_in_gigapascals():
    r = run("contact", "--c11", 165.7, "--c12", 63.9, "--c44", 79.6, "--radius", 1e-3,
            "--force", 1)  # fmt: skip
    one_line_error(r, "--c11")
    assert (
        "--c11 165.7 is outside the plausible range: the elastic modulus lies in [1e5, 1e13] Pa; "
        "it looks like gigapascals (165.7 GPa = 1.657e11 Pa): check the unit of --c11"
    ) in r.stderr


@pytest.mark.parametrize(
    "args, option",
    [
        (["--radius", "1e300", "--force", "1e300"], "--radius"),
        (["--radius", "1e-3", "--force", "1e300"], "--force"),
        (["--radius", "1e300", "--force", "1"], "--radius"),
    ],
)
def test_issue_11_overflowing_input_is_refused_not_printed_as_inf(args, option):
    r = run("contact", "--crystal", "Cu", *args)
    one_line_error(r, option)
    assert "1e300 is outside the plausible range" in r.stderr and "inf" not in r.output


def test_c12_may_be_negative_or_zero_but_not_a_unit_slip():
    for c12 in ("-20e9", "0"):
        r = run("contact", "--c11", 100e9, "--c12", c12, "--c44", 50e9, "--radius", 1e-3,
                "--force", 1)  # fmt: skip
        assert r.exit_code == 0, r.output
    r = invoke(["contact"], CONSTANTS, "--c12", "121.4")
    assert "gigapascals (121.4 GPa = 1.214e11 Pa): check the unit of --c12" in r.stderr


def test_force_range_from_zero_is_checked_point_by_point():
    r = invoke(["contact"], CRYSTAL, "--force", "0:1e-11:101")  # its second point is 1e-13 N
    one_line_error(r, "--force")
    assert "--force 1e-13 (in 0:1e-11:101) is outside" in r.stderr


SOFTEST = ["--c11", "2e5", "--c12", "1e5", "--c44", "1e5"]


def test_plausible_extremes_print_finite_numbers():
    # the stiffest crystal under the largest load and sphere, and the softest extreme (its
    # smallest sphere with a contact within Hertz's validity: a/R ≈ 0.06 by a³ = 3FR/(4E*))
    for args in (
        ["--crystal", "diamond", "--radius", "1", "--force", "1e3"],
        [*SOFTEST, "--radius", "2e-7", "--force", "1e-12"],
    ):
        r = run("contact", *args, "--format", "csv")
        assert r.exit_code == 0, r.output
        t = pd.read_csv(io.StringIO(r.stdout))
        assert np.isfinite(t.to_numpy()).all()


def test_a_contact_wider_than_hertz_allows_is_flagged_not_printed():
    """R = 1 nm on the softest solid: a/R ≈ 2 (issue 30's a/R = 24 case in small): the row
    keeps R and F, its values are empty, and one stderr warning (wrapped at 100 columns) says
    which inputs to check."""
    r = run("contact", *SOFTEST, "--radius", "1e-9", "--force", "1e-12", "--format", "csv")
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.stdout))
    assert (
        t["flags"].iat[0].endswith("beyond Hertz, no value") and t["contact_radius_m"].isna().all()
    )
    assert "check the sphere radius (m) and the force (N)" in r.stderr
    assert r.stderr.startswith("contactres: warning: ")
    assert max(len(line) for line in r.stderr.splitlines()) <= 100  # issue 30: was 205


def test_help_states_units_and_shows_defaults_one_way():
    from contactres.cli.contact import contact

    unit = re.compile(r"(, N |, Pa|, m |, Hz |dimensionless|degrees)")
    for p in contact.params:
        if p.type.name in ("FLOAT", "START:STOP:NUM"):
            assert unit.search(p.help), p.opts
        if isinstance(p.default, (str, int, float)) and p.opts[0] != "--help":
            assert p.show_default is True, p.opts
    assert "[default: ([100] projected, or [010])]" in run("contact", "--help").output


@pytest.mark.parametrize(
    "text, expected",
    [("001", (0, 0, 1)), ("1-10", (1, -1, 0)), ("-1 1 1", (-1, 1, 1)), ("1,2,3", (1, 2, 3))],
)
def test_parse_direction(text, expected):
    assert parse_direction(text) == expected


@pytest.mark.parametrize("text", ["", "0000", "1,2", "000", "abc"])
def test_parse_direction_rejects(text):
    with pytest.raises(ValueError, match="surface"):
        parse_direction(text)


def test_crystals_lists_indentation_moduli():
    rows = _json(run("crystals", "--format", "json"))
    cu = next(row for row in rows if row["name"] == "Cu")
    assert cu["M001_GPa"] == pytest.approx(134.0, rel=5e-4)
    assert cu["M001_GPa"] < cu["M011_GPa"] < cu["M111_GPa"]
    # W is almost isotropic (A = 0.999): all faces give E/(1 - ν²) of the isotropic solid.
    w = next(row for row in rows if row["name"] == "W")
    assert max(w["M001_GPa"], w["M111_GPa"]) / min(w["M001_GPa"], w["M111_GPa"]) < 1.001


# ------------------------------------------------------------------ tangential and dynamic
def test_contact_tangential_and_frequency_match_library():
    """--tangential --frequency: the columns are the library's values at the Hertz contact
    radius; the static tangential column on an isotropic glass is Mindlin's 8Ga/(2 − ν)."""
    from contactres import at_cut_quartz, dcsf, tangential_contact_stiffness

    rows = _json(
        run(
            "contact",
            "--crystal",
            "quartz-AT",
            "--radius",
            5e-3,
            "--force",
            "1e-3,1e-2",
            "--tangential",
            "--frequency",
            15e6,
            "--format",
            "json",
        )
    )
    q = at_cut_quartz()
    for row, force in zip(rows, (1e-3, 1e-2), strict=True):
        c = sphere_contact(q, 5e-3, force)
        kt = tangential_contact_stiffness(q, c.contact_radius, 15e6)
        assert row["tangential_stiffness_real_N_per_m"] == pytest.approx(kt.real, rel=1e-9)
        assert row["tangential_stiffness_imag_N_per_m"] == pytest.approx(kt.imag, rel=1e-9)
        assert row["tangential_loss_tangent"] == pytest.approx(kt.imag / kt.real, rel=1e-9)
        kn = c.stiffness * dcsf(q, row["ks_a"], wavenumber="shear")
        assert row["dynamic_stiffness_imag_N_per_m"] == pytest.approx(kn.imag, rel=1e-9)
    glass = Material.crystal("soda-lime-glass")
    E, nu = glass.isotropic_constants
    row = _json(
        run(
            "contact",
            "--crystal",
            "soda-lime-glass",
            "--radius",
            5e-3,
            "--force",
            1e-3,
            "--tangential",
            "--format",
            "json",
        )
    )[0]
    G = E / (2 * (1 + nu))
    a = row["contact_radius_m"]
    assert row["tangential_stiffness_N_per_m"] == pytest.approx(8 * G * a / (2 - nu), rel=1e-9)


@pytest.mark.parametrize(
    "args, words",
    [
        (["--crystal", "quartz-AT", "--surface", "111"], ["already a cut"]),
        (["--crystal", "Cu", "--frequency", "15"], ["--frequency", "MHz"]),
        (["--c11", 168e9, "--c12", 121e9, "--c44", 75e9, "--frequency", 1e6], ["density"]),
        (["--crystal", "Cu", "--tangential", "--direction", "nan"], ["--direction"]),
        (["--crystal", "Cu", "--tangential", "--frequency", 1e9], ["k_s a", "beyond"]),
        (["--crystal", "Cu", "--direction", 30], ["--direction", "--tangential"]),
    ],
)
def test_contact_tangential_bad_input(args, words):
    r = run("contact", "--radius", 5e-3, "--force", 1e-3, *args)
    one_line_error(r, *words)


def test_contact_tangential_at_zero_force_is_zero_not_an_error():
    """F = 0 starts a load table: no contact, K_t = 0 and no loss tangent (empty)."""
    rows = _json(
        run(
            "contact",
            "--crystal",
            "quartz-AT",
            "--radius",
            5e-3,
            "--force",
            "0,1e-3",
            "--tangential",
            "--frequency",
            15e6,
            "--format",
            "json",
        )
    )
    assert rows[0]["tangential_stiffness_real_N_per_m"] == 0
    assert rows[0]["tangential_loss_tangent"] is None
    assert rows[1]["tangential_stiffness_real_N_per_m"] > 0


# ------------------------------------------------------------------------------ coated faces
def test_contact_coating_matches_the_job_and_notes_the_static_pmma():
    from contactres.jobs import contact as job

    r = run("contact", "--crystal", "fused-silica", "--radius", 1.1e-3, "--force", "1e-3,1e-2",
            "--coating", "pmma:250e-9", "--format", "json")  # fmt: skip
    rows = _json(r)
    s = job.Settings(np.array([1.1e-3]), np.array([1e-3, 1e-2]), coating=("pmma:250e-9",))
    t = job.run(Material.crystal("fused-silica"), s).table
    for row, (_, want) in zip(rows, t.iterrows(), strict=True):
        assert row["coating"] == "PMMA 250 nm"
        for key in ("contact_radius_m", "stiffness_N_per_m", "film_share"):
            assert row[key] == pytest.approx(want[key], rel=1e-12)
    warning = "contactres: warning: the static columns use the storage modulus at 1 Hz of PMMA"
    assert warning in r.stderr


def test_contact_two_coatings_top_first():
    r = run("contact", "--crystal", "Si3N4", "--radius", 1e-3, "--force", 1e-3, "--coating",
            "pmma:1e-7", "--coating", "fused-silica:2e-7", "--format", "json")  # fmt: skip
    row = _json(r)[0]
    assert row["coating"] == "PMMA 100 nm on fused-silica 200 nm"
    assert 0 < row["film_share"] < 1


def test_contact_prints_each_thickness_in_a_unit_that_reads():
    """A film at the one limit (1 m) and one of 1.5 µm print as such, not as "1e+09 nm"; just
    above the limit is one line naming the option and the limit."""
    r = run("contact", "--crystal", "fused-silica", "--radius", 1.1e-3, "--force", 1e-3,
            "--coating", "pmma:1", "--coating", "fused-silica:1.5e-6",
            "--format", "json")  # fmt: skip
    assert _json(r)[0]["coating"] == "PMMA 1 m on fused-silica 1.5 µm"
    r = run("contact", "--crystal", "fused-silica", "--radius", 1.1e-3, "--force", 1e-3,
            "--coating", "pmma:1.01")  # fmt: skip
    one_line_error(r, "--coating pmma:1.01", "above 1 m")


@pytest.mark.parametrize(
    "coating, words",
    [
        (["pmma250e-9"], ["--coating", "MATERIAL:THICKNESS"]),
        (["SiO2:1e-7"], ["--coating", "unknown coating material", "pmma", "fused-silica"]),
        (["pmma:-1e-9"], ["--coating", "positive finite", " m"]),
        (["pmma:nan"], ["--coating", "positive finite"]),
        (["pmma:250"], ["--coating", "nm/µm"]),
        (["pmma:1e-8"] * 11, ["--coating", "at most 10"]),
    ],
)
def test_contact_coating_bad_input_one_line(coating, words):
    args = [x for c in coating for x in ("--coating", c)]
    r = run("contact", "--crystal", "fused-silica", "--radius", 1e-3, "--force", 1e-3, *args)
    one_line_error(r, *words)


def test_contact_coating_tangential_at_a_frequency_has_the_bare_columns():
    """The coated face at a frequency prints the bare face's columns (plus coating and
    film_share), the tangential ones from the layered tangential punch at the contact radius."""
    from contactres import LayeredMaterial, flat_punch_stiffness, pmma

    common = ("contact", "--crystal", "fused-silica", "--radius", 1e-3, "--force", 1e-3,
              "--tangential", "--frequency", 15e6, "--format", "json")  # fmt: skip
    bare = _json(run(*common))[0]
    row = _json(run(*common, "--coating", "pmma:250e-9"))[0]
    # the contact ellipse's columns belong to a bare face only (a coated contact is axisymmetric)
    ellipse = ("semi_major_m", "semi_minor_m", "ellipticity", "orientation_deg")
    shared = [c for c in bare if c not in ellipse]
    assert list(row) == [*shared[:7], "coating", "film_share", *shared[7:]]
    glass = Material.crystal("fused-silica")
    stack = LayeredMaterial(glass, [(pmma(), 250e-9)])
    want = flat_punch_stiffness(stack, row["contact_radius_m"], 15e6, "tangential")
    assert row["tangential_stiffness_real_N_per_m"] == pytest.approx(want.real, rel=1e-12)
    assert row["tangential_stiffness_imag_N_per_m"] == pytest.approx(want.imag, rel=1e-12)
    assert row["tangential_loss_tangent"] == pytest.approx(want.imag / want.real, rel=1e-12)


def test_contact_coating_tangential_beyond_its_range_is_one_line():
    r = run("contact", "--crystal", "fused-silica", "--radius", 1e-3, "--force", 1e-3,
            "--coating", "pmma:250e-9", "--tangential", "--frequency", 5e8)  # fmt: skip
    one_line_error(r, "k_s a", "frequency")


def test_contact_coating_help_states_format_and_units():
    from contactres.cli.contact import contact

    (p,) = (p for p in contact.params if p.opts[0] == "--coating")
    assert p.metavar == "MATERIAL:THICKNESS" and p.multiple
    assert "thickness in m" in p.help and "top first" in p.help
    assert "1 Hz storage modulus" in p.help
    assert "MATERIAL:THICKNESS" in run("contact", "--help").output
