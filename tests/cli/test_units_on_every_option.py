"""Options and TOML keys that used to refuse a value typed with its unit (issue 30, second
review M5): ``--coating pmma:250nm``, ``qcm spectra --d26 3.1pm/V``, ``--calibration``,
``--reference-impedance``, and a TOML key ``sphere_radius_mm = 1.1``. A plain number stays SI;
the value with its unit equals the value in SI."""

from __future__ import annotations

from importlib.resources import files

import pandas as pd
import pytest
from cli_checks import one_line_error, run

from contactres import read_sweeps
from contactres.errors import ContactresInputError
from contactres.examples import example_path

SPECTRA = str(files("contactres") / "data" / "example_spectra.csv")


@pytest.fixture(scope="module")
def si_table():
    """The CSV table a command prints for a command line in SI (``run``'s arguments), read;
    each line is run once for every case that compares a typed value with it."""
    tables: dict[tuple[str, ...], pd.DataFrame] = {}

    def table(*args: str) -> pd.DataFrame:
        if args not in tables:
            r = run(*args)
            assert r.exit_code == 0, r.output
            tables[args] = pd.read_csv(pd.io.common.StringIO(r.stdout))
        return tables[args].copy()

    return table


@pytest.mark.parametrize("typed", ["pmma:250nm", "pmma:250 nm", "pmma:0.25µm"])
def test_a_coating_thickness_with_its_unit_equals_the_thickness_in_m(typed, si_table):
    args = ["contact", "--crystal", "fused-silica", "--radius", "1.1e-3", "--force", "1e-3"]
    a = si_table(*args, "--coating", "pmma:250e-9", "--format", "csv")
    with_unit = run(*args, "--coating", typed, "--format", "csv")
    assert with_unit.exit_code == 0, with_unit.output
    b = pd.read_csv(pd.io.common.StringIO(with_unit.stdout))
    pd.testing.assert_frame_equal(a, b, rtol=1e-12)
    assert (b["coating"] == "PMMA 250 nm").all()


def test_a_coating_thickness_in_another_kind_of_unit_is_one_line():
    r = run("contact", "--crystal", "Cu", "--radius", "1e-6", "--force", "1e-6",
            "--coating", "pmma:250mN")  # fmt: skip
    one_line_error(r, "--coating pmma:250mN", "another kind")


def test_a_coating_with_a_second_colon_is_one_clear_line():
    """pint reads '250e-9:3' as a number without a unit: the line says so (it used to read
    "is in , a quantity of another kind than m")."""
    r = run("contact", "--crystal", "Cu", "--radius", "1e-6", "--force", "1e-6",
            "--coating", "pmma:250e-9:3")  # fmt: skip
    one_line_error(r, "--coating pmma:250e-9:3", "is not a number with a unit")
    assert "is in ," not in r.stderr


@pytest.mark.parametrize(
    ("option", "si", "typed"),
    [
        ("--d26", "3.1e-12", "3.1pm/V"),
        ("--calibration", "2e-9", "2 nm/V"),
        ("--reference-impedance", "50", "50ohm"),
    ],
)
def test_spectra_options_take_their_unit(tmp_path, option, si, typed):
    outs = []
    for name, value in (("si", si), ("typed", typed)):
        out = tmp_path / f"{name}.csv"
        r = run("qcm", "spectra", SPECTRA, "--out", out, option, value)
        assert r.exit_code == 0, r.output
        outs.append(pd.read_csv(out, comment="#"))
    pd.testing.assert_frame_equal(outs[0], outs[1], rtol=1e-12)


def test_a_d26_in_pm_per_v_typed_as_m_per_v_names_the_slip(tmp_path):
    r = run("qcm", "spectra", SPECTRA, "--out", tmp_path / "s.csv", "--d26", "3.1")
    one_line_error(r, "--d26 3.1", "pm/V")


def _sweeps_without_radius(tmp_path):
    frame = pd.read_csv(example_path("example_sweeps.csv"), comment="#")
    frame = frame[frame["configuration"] == "SiO2_2.2mm"].drop(columns=["sphere_radius_m"])
    path = tmp_path / "s.csv"
    frame.to_csv(path, index=False)
    return path


@pytest.mark.parametrize(
    "toml", ["sphere_radius_mm = 1.1\n", "sphere_radius_um = 1100\n", 'sphere_radius = "1.1 mm"\n']
)
def test_a_toml_key_named_with_its_unit_is_read_as_the_column_is(tmp_path, toml):
    path = _sweeps_without_radius(tmp_path)
    (tmp_path / "s.toml").write_text(toml)
    radius = read_sweeps(path).data["sphere_radius_m"]
    assert radius.to_numpy() == pytest.approx(1.1e-3, rel=1e-12)


def test_a_toml_key_with_its_unit_is_checked_and_the_unknown_key_names_the_forms(tmp_path):
    path = _sweeps_without_radius(tmp_path)
    (tmp_path / "s.toml").write_text("sphere_radius_mm = 1100\n")  # 1.1 m: µm meant
    with pytest.raises(ContactresInputError, match="sphere_radius_m"):
        read_sweeps(path)
    (tmp_path / "s.toml").write_text('sphere_radius_mm = "1.1"\n')
    with pytest.raises(ContactresInputError, match="plain number"):
        read_sweeps(path)
    (tmp_path / "s.toml").write_text("sphere_radius_mm = 1.1\nsphere_radius_m = 1.1e-3\n")
    with pytest.raises(ContactresInputError, match="the same constant"):
        read_sweeps(path)
    (tmp_path / "s.toml").write_text("sphere_radios = 1.1e-3\n")
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(path)
    assert 'sphere_radius = "1.1 mm"' in str(info.value) and "sphere_radius_mm = 1.1" in str(
        info.value
    )


@pytest.mark.parametrize("typed", ["30deg", "30 deg", "0.5235987755982988rad"])
def test_a_direction_with_its_unit_equals_the_direction_in_degrees(typed, si_table):
    """`contact --direction` took only a number of degrees ('30deg' was "not a valid float",
    issue 30's last review); an angle with its unit is converted, 30 degrees = π/6 rad."""
    args = ["contact", "--crystal", "quartz-AT", "--radius", "5e-3", "--force", "1e-3"]
    args += ["--tangential", "--frequency", "15e6", "--format", "csv"]
    a = si_table(*args, "--direction", "30")  # the plain number: degrees
    with_unit = run(*args, "--direction", typed)
    assert with_unit.exit_code == 0, with_unit.output
    b = pd.read_csv(pd.io.common.StringIO(with_unit.stdout))
    pd.testing.assert_frame_equal(a, b, rtol=1e-12)


@pytest.mark.parametrize(("typed", "said"), [("30m", "another kind"), ("abc", "not an angle")])
def test_a_direction_of_another_kind_is_refused_in_one_line(typed, said):
    args = ["contact", "--crystal", "Cu", "--radius", "1e-3", "--force", "1", "--tangential"]
    r = run(*args, "--direction", typed)
    assert r.exit_code == 2 and said in one_line_error(r), r.output
