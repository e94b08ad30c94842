"""Tests of the built-in crystal table (contactres.crystals) and Material.crystal."""

import ast
import inspect

import numpy as np
import pytest

import contactres.crystals
from contactres import Material, crystal_names, crystal_table
from contactres.crystals import CrystalRecord, crystal_record

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


def test_copper_anisotropy_ratios():
    # Cu: A = 2·75.4/(168.4 - 121.4) = 3.21, ν = 121.4/(168.4 + 121.4) = 0.419 (docs/validation.md)
    m = Material.crystal("cu")  # case-insensitive
    assert m.zener_ratio == pytest.approx(3.21, abs=0.005)
    assert m.cubic_poisson == pytest.approx(0.419, abs=0.0005)


def test_unknown_crystal_lists_known_ones():
    with pytest.raises(ValueError, match=r"unknown crystal 'Xx'.*Cu.*diamond"):
        Material.crystal("Xx")
    assert crystal_names()[0] == "Cu"


def test_record_is_in_si_units_and_builds_the_material():
    r = crystal_record(" CU ")  # case and surrounding blanks are ignored
    assert isinstance(r, CrystalRecord)
    assert (r.name, r.c11, r.c12, r.c44, r.density) == ("Cu", 168.4e9, 121.4e9, 75.4e9, 8960.0)
    assert "Simmons" in r.source
    m = Material.crystal("Cu")
    ref = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0)
    np.testing.assert_array_equal(m.C, ref.C)
    assert (m.density, m.name) == (8960.0, "Cu")
    with pytest.raises(ValueError, match="unknown crystal"):
        crystal_record("Xx")


def test_crystals_is_a_table_only_module():
    # Ground layer: the table must not import the materials (that was an import cycle).
    tree = ast.parse(inspect.getsource(contactres.crystals))
    imported = {node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    imported |= {
        a.name for node in ast.walk(tree) if isinstance(node, ast.Import) for a in node.names
    }
    assert imported, "the parse found no imports at all"
    assert not any("materials" in name for name in imported), imported
