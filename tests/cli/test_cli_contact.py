"""Tests of ``contactres contact`` and the indentation moduli of ``contactres crystals``."""

import io
import json

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres import Material, indentation_modulus, sphere_contact
from contactres.cli import main
from contactres.cli._crystal_face import parse_direction


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


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
        "peak_pressure_Pa",
        "depth_m",
        "stiffness_N_per_m",
        "indentation_modulus_Pa",
    ]
    np.testing.assert_allclose(t.force_N, np.linspace(0, 2, 5))
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
        (["--crystal", "Cu", "--radius", "1:2:3", "--force", "1:2:4"], "same number"),
        (["--zener", 1, "--poisson", 0.7, "--c44", 1e9, "--radius", 1, "--force", 1], "poisson"),
    ],
)
def test_bad_input_one_line_exit_2(args, match):
    r = run("contact", *args)
    assert r.exit_code == 2
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and match in lines[0]


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
