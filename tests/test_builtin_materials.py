"""Tests of the trigonal constructor, the built-in non-cubic solids and the AT-cut quartz plate."""

import json

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given
from hypothesis import strategies as st

import contactres
import contactres.crystals as crystals
from contactres import Material, at_cut_quartz, crystal_names, crystal_table
from contactres.cli import main
from contactres.crystals import crystal_record
from contactres.materials import AT_CUT_ANGLE, rotate_tensor, tensor_to_voigt, voigt_to_tensor

# McSkimin, Andreatch & Thurston (1965), 25 °C, in Pa: c11, c12, c13, c14, c33, c44.
QUARTZ = (86.80e9, 7.04e9, 11.91e9, -18.04e9, 105.75e9, 58.20e9)
CUBIC_NAMES = [
    "Cu", "Al", "Ni", "Au", "Ag", "Fe", "W", "Si", "Ge", "Pb", "Li", "Na", "NaCl", "KCl",
    "RbBr", "RbI", "GaAs", "diamond",
]  # fmt: skip
NEW_NAMES = ["quartz", "sapphire", "fused-silica", "soda-lime-glass", "Si3N4"]


def _rz(deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rotated_voigt(m: Material, R: np.ndarray) -> np.ndarray:
    return tensor_to_voigt(rotate_tensor(voigt_to_tensor(m.C), R))


# ----------------------------------------------------------------------------- Material.trigonal
def test_trigonal_layout_follows_the_convention():
    c11, c12, c13, c14, c33, c44 = QUARTZ
    C = Material.trigonal(*QUARTZ).C
    assert (C[0, 0], C[1, 1], C[2, 2]) == (c11, c11, c33)
    assert (C[0, 1], C[0, 2], C[1, 2]) == (c12, c13, c13)
    assert (C[3, 3], C[4, 4], C[5, 5]) == (c44, c44, (c11 - c12) / 2)
    assert (C[0, 3], C[1, 3], C[4, 5]) == (c14, -c14, c14)
    assert C[2, 3] == 0 and np.all(C[:4, 4:] == 0)
    np.testing.assert_array_equal(C, C.T)


@pytest.mark.parametrize(
    "constants", [QUARTZ, (496.8e9, 163.6e9, 110.9e9, -23.5e9, 498.1e9, 147.4e9)]
)
def test_trigonal_is_invariant_under_the_threefold_rotation(constants):
    m = Material.trigonal(*constants)
    scale = np.max(np.abs(m.C))
    for angle in (120.0, 240.0, -120.0):
        np.testing.assert_allclose(_rotated_voigt(m, _rz(angle)), m.C, rtol=0, atol=1e-12 * scale)
    # A two-fold axis along x (classes 32, -3m): a 180° turn about x leaves C unchanged too.
    np.testing.assert_allclose(
        _rotated_voigt(m, np.diag([1.0, -1.0, -1.0])), m.C, rtol=0, atol=1e-12 * scale
    )
    # But not a six-fold one: 60° (or 180°) about z flips the sign of C14 (hence the sign
    # convention matters), and leaves everything else as it was.
    flipped = _rotated_voigt(m, _rz(60.0))
    expected = Material.trigonal(*constants[:3], -constants[3], *constants[4:]).C
    np.testing.assert_allclose(flipped, expected, rtol=0, atol=1e-12 * scale)
    assert abs(flipped[0, 3] - m.C[0, 3]) > 0.1 * abs(m.C[0, 3])


def test_trigonal_with_zero_c14_is_hexagonal():
    c11, c12, c13, _, c33, c44 = QUARTZ
    hexagonal = Material.hexagonal(c11, c12, c13, c33, c44, name="hex")
    np.testing.assert_array_equal(Material.trigonal(c11, c12, c13, 0.0, c33, c44).C, hexagonal.C)
    assert hexagonal.name == "hex"


@pytest.mark.parametrize(
    "constants, rule",
    [
        ((86.8e9, 90e9, 11.9e9, -18e9, 105.8e9, 58.2e9), r"C11 > \|C12\|"),
        ((86.8e9, 7e9, 11.9e9, -18e9, 105.8e9, -1e9), "C44 > 0"),
        ((86.8e9, 7e9, 80e9, -18e9, 105.8e9, 58.2e9), r"C13² < C33 \(C11 \+ C12\)/2"),
        ((86.8e9, 7e9, 11.9e9, -50e9, 105.8e9, 58.2e9), r"C14² < C44 \(C11 - C12\)/2"),
    ],
)
def test_unstable_trigonal_constants_are_refused_by_name(constants, rule):
    with pytest.raises(ValueError, match=rf"trigonal constants .* unstable .*{rule}"):
        Material.trigonal(*constants)


def test_non_finite_trigonal_constant_is_refused():
    with pytest.raises(ValueError, match="c14 must be finite"):
        Material.trigonal(86.8e9, 7e9, 11.9e9, float("nan"), 105.8e9, 58.2e9)


_gpa = st.floats(-300.0, 300.0, allow_nan=False)


@given(_gpa, _gpa, _gpa, _gpa, _gpa, _gpa)
def test_stability_rule_is_exactly_positive_definiteness(c11, c12, c13, c14, c33, c44):
    # The block argument of the docstring, checked against the eigenvalues of the full matrix.
    C = np.zeros((6, 6))
    C[0, 0] = C[1, 1] = c11
    C[0, 1] = C[1, 0] = c12
    C[0, 2] = C[2, 0] = C[1, 2] = C[2, 1] = c13
    C[2, 2], C[3, 3], C[4, 4], C[5, 5] = c33, c44, c44, (c11 - c12) / 2
    C[0, 3] = C[3, 0] = C[4, 5] = C[5, 4] = c14
    C[1, 3] = C[3, 1] = -c14
    eig = np.linalg.eigvalsh(C)
    if abs(eig[0]) < 1e-6 * max(1.0, abs(eig[-1])):
        return  # on the boundary: round-off decides, not the rule
    try:
        Material.trigonal(c11 * 1e9, c12 * 1e9, c13 * 1e9, c14 * 1e9, c33 * 1e9, c44 * 1e9)
        stable = True
    except ValueError:
        stable = False
    assert stable == (eig[0] > 0)


# ----------------------------------------------------------------------------- built-in tables
def test_names_list_the_cubic_crystals_first_then_the_others():
    names = crystal_names()
    assert names[: len(CUBIC_NAMES)] == CUBIC_NAMES
    assert names[len(CUBIC_NAMES) :] == NEW_NAMES
    assert len({n.lower() for n in names}) == len(names), "names must be unique ignoring case"


@pytest.mark.parametrize("name", NEW_NAMES)
def test_every_new_solid_builds_from_any_case_of_its_name(name):
    m = Material.crystal(name.upper())
    r = crystal_record(f"  {name.lower()} ")
    assert m.name == r.name == name
    assert m.density == r.density > 1000
    assert len(r.source) > 20
    assert np.linalg.eigvalsh(m.C)[0] > 0


def test_trigonal_rows_build_the_trigonal_solid():
    q = Material.crystal("quartz")
    np.testing.assert_array_equal(q.C, Material.trigonal(*QUARTZ).C)
    assert q.density == 2648.0
    s = crystal_record("sapphire")
    assert (s.symmetry, s.c14, s.density) == ("trigonal", -23.5e9, 3980.0)
    assert "Wachtman" in s.source


@pytest.mark.parametrize(
    "name, E, nu, density",
    [
        ("fused-silica", 73.1e9, 0.17, 2203.0),
        ("soda-lime-glass", 72.0e9, 0.21, 2520.0),
        ("Si3N4", 285e9, 0.20, 3100.0),
    ],
)
def test_isotropic_rows_give_back_E_and_nu(name, E, nu, density):
    m = Material.crystal(name)
    E2, nu2 = m.isotropic_constants
    assert E2 == pytest.approx(E, rel=1e-12)
    assert nu2 == pytest.approx(nu, rel=1e-12)
    assert m.density == density
    r = crystal_record(name)
    assert (r.symmetry, r.E, r.nu) == ("isotropic", E, nu)
    assert (r.c11, r.c12, r.c44) == pytest.approx((m.C[0, 0], m.C[0, 1], m.C[3, 3]), rel=1e-12)


def test_table_gives_the_cubic_ratios_only_where_they_apply():
    t = crystal_table().set_index("name")
    assert t.loc["Cu", "symmetry"] == "cubic"
    assert t.loc["quartz", ["zener", "poisson", "E_GPa"]].isna().all()
    assert t.loc["quartz", "c14_GPa"] == pytest.approx(-18.04)
    assert t.loc["fused-silica", "zener"] == pytest.approx(1.0)
    assert t.loc["fused-silica", "poisson"] == pytest.approx(0.17)
    assert t.loc[CUBIC_NAMES, ["c13_GPa", "c14_GPa", "c33_GPa", "E_GPa", "nu"]].isna().all().all()
    assert (t["source"].str.len() > 5).all()


def test_a_malformed_row_is_refused():
    row = {c: "" for c in ("c11_GPa", "c12_GPa", "c13_GPa", "c14_GPa", "c33_GPa", "c44_GPa")}
    row |= {"name": "x", "symmetry": "isotropic", "E_GPa": "70", "nu": "", "density_kg_m3": "1"}
    row["source"] = "test"
    with pytest.raises(ValueError, match="must fill exactly E_GPa, nu; it fills E_GPa"):
        crystals._other_record(row)
    with pytest.raises(ValueError, match="unknown symmetry 'cubicish'"):
        crystals._other_record(row | {"symmetry": "cubicish"})


# ----------------------------------------------------------------------------- AT-cut quartz
def test_at_cut_frame_is_the_rotated_y_cut():
    m = at_cut_quartz()
    t = np.radians(AT_CUT_ANGLE)
    np.testing.assert_allclose(m.frame[0], [1, 0, 0], atol=1e-15)  # x' = X, the shear direction
    np.testing.assert_allclose(m.frame[2], [0, np.cos(t), np.sin(t)], atol=1e-15)  # z' = Y'
    np.testing.assert_allclose(m.frame[1], [0, np.sin(t), -np.cos(t)], atol=1e-15)
    assert np.linalg.det(m.frame) == pytest.approx(1.0)
    assert m.name == "quartz" and m.density == 2648.0


def test_at_cut_shear_stiffness_matches_the_closed_form():
    # c66' = C66 cos²θ + C44 sin²θ + 2 C14 sinθ cosθ, an independent formula of the same rotation.
    c11, c12, _, c14, _, c44 = QUARTZ
    t = np.radians(35.25)
    closed = (
        (c11 - c12) / 2 * np.cos(t) ** 2 + c44 * np.sin(t) ** 2 + 2 * c14 * np.sin(t) * np.cos(t)
    )
    assert at_cut_quartz().C[4, 4] == pytest.approx(closed, rel=1e-12)
    assert closed == pytest.approx(28.98e9, rel=2e-4)
    # The sign convention matters: the mirror cut at -35.25° is a much stiffer shear (~63 GPa).
    assert at_cut_quartz(-AT_CUT_ANGLE).C[4, 4] > 60e9


def test_at_cut_shear_stiffness_agrees_with_the_qcm_literature():
    """The unstiffened c66' against the QCM values.

    Published: μ_q = 2.947e10 Pa (the constant used with the Sauerbrey equation, ρ_q = 2648
    kg/m³), and Z_q = 8.8e6 kg m⁻² s⁻¹, G_q ≈ 29e9 Pa, e26 = 9.65e-2 C/m², ε_q = 4.54
    (D. Johannsmann et al., Sensors 21, 3490 (2021), Table A1). Those are piezoelectrically
    stiffened values; the model is purely elastic. The scatter among them (Z_q²/ρ_q =
    2.92e10 vs 2.947e10: 0.8 %) plus the stiffening (0.8 %) set the 2 % tolerance.
    """
    c66 = at_cut_quartz().C[4, 4]
    assert c66 == pytest.approx(2.947e10, rel=0.02)
    assert c66 < 2.947e10  # unstiffened: below the stiffened values
    # With the stiffening e26²/(ε_q ε0) of the same review: the shear-wave impedance of the QCM.
    eps0 = 8.8541878128e-12
    stiffened = c66 + 9.65e-2**2 / (4.54 * eps0)
    assert np.sqrt(2648.0 * stiffened) == pytest.approx(8.8e6, rel=0.006)  # 8.8e6 to 2 digits


def test_at_cut_angle_must_be_finite():
    with pytest.raises(ValueError, match="theta"):
        at_cut_quartz(float("inf"))


def test_at_cut_quartz_is_exported():
    assert "at_cut_quartz" in contactres.__all__


# ----------------------------------------------------------------------------- the CLI
def test_cli_lists_the_new_solids_with_their_symmetry():
    r = CliRunner().invoke(main, ["crystals", "--format", "json"])
    assert r.exit_code == 0, r.output
    rows = {row["name"]: row for row in json.loads(r.stdout)}
    assert set(NEW_NAMES) <= set(rows)
    quartz, silica = rows["quartz"], rows["fused-silica"]
    assert quartz["symmetry"] == "trigonal"
    assert quartz["zener"] is None and quartz["M011_GPa"] is None and quartz["M111_GPa"] is None
    assert quartz["c14_GPa"] == pytest.approx(-18.04)
    assert 50 < quartz["M001_GPa"] < 150
    assert silica["symmetry"] == "isotropic" and silica["zener"] == pytest.approx(1.0)
    # Isotropic: every face gives E/(1 - ν²).
    for key in ("M001_GPa", "M011_GPa", "M111_GPa"):
        assert silica[key] == pytest.approx(73.1 / (1 - 0.17**2), rel=1e-9)
    assert rows["Cu"]["symmetry"] == "cubic" and rows["Cu"]["c14_GPa"] is None
