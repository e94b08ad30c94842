"""Tests of the built-in crystal table."""

import pytest

from contactres import Material, crystal_names, crystal_table

REQUIRED = [
    "Cu",
    "Al",
    "Ni",
    "Au",
    "Ag",
    "Fe",
    "W",
    "Si",
    "Ge",
    "Pb",
    "Li",
    "Na",
    "NaCl",
    "KCl",
    "RbBr",
    "RbI",
    "GaAs",
    "diamond",
]


def test_table_has_required_crystals_with_sources():
    t = crystal_table()
    assert set(REQUIRED) <= set(t["name"])
    assert t["source"].str.len().min() > 5
    assert (t[["c11_GPa", "c44_GPa", "density_kg_m3"]] > 0).all().all()


@pytest.mark.parametrize("name", REQUIRED)
def test_every_crystal_is_a_stable_material(name):
    m = Material.crystal(name)
    assert m.density > 0
    assert 0.1 < m.zener_ratio < 10


def test_copper_anisotropy_matches_physics_md():
    m = Material.crystal("cu")  # case-insensitive
    assert m.zener_ratio == pytest.approx(3.21, abs=0.005)
    assert m.cubic_poisson == pytest.approx(0.419, abs=0.0005)


def test_unknown_crystal_lists_known_ones():
    with pytest.raises(ValueError, match=r"unknown crystal 'Xx'.*Cu.*diamond"):
        Material.crystal("Xx")
    assert crystal_names()[0] == "Cu"
