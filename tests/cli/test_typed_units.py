"""Values typed with their unit (issue 30): options, TOML values and column names carry units,
converted to SI with pint at the input boundary only; plain numbers stay SI."""

from __future__ import annotations

import pandas as pd
import pytest
from cli_checks import run

from contactres import AnalysisSettings, analyze, read_sweeps
from contactres.errors import ContactresInputError
from contactres.examples import example_path
from contactres.typed_units import column_unit_factor, has_unit, to_si
from contactres.units import check_magnitude


@pytest.mark.parametrize(
    ("text", "unit", "si"),
    [
        # The factors are the SI prefixes' definitions (BIPM, The International System of
        # Units, 9th ed., 2019, Table 7) and 1 g/cm³ = 1000 kg/m³.
        ("1.1mm", "m", 1.1e-3),
        ("1.1 mm", "m", 1.1e-3),
        ("20 nm", "m", 2e-8),
        ("10 µm", "m", 1e-5),
        ("10 um", "m", 1e-5),
        ("2 mN", "N", 2e-3),
        ("5 MHz", "Hz", 5e6),
        ("70 GPa", "Pa", 7e10),
        ("2.2 g/cm^3", "kg/m^3", 2200.0),
        ("0.2 cm^2", "m^2", 2e-5),
        ("8.8e6 kg m^-2 s^-1", "kg m^-2 s^-1", 8.8e6),
    ],
)
def test_a_value_with_its_unit_is_converted_to_si(text, unit, si):
    assert has_unit(text)
    assert to_si(text, unit, "--x") == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize("text", ["1e-3", "1.1", "nan", "-2", " 3 "])
def test_plain_numbers_are_not_units(text):
    assert not has_unit(text)


@pytest.mark.parametrize(
    ("text", "unit", "words"),
    [
        ("2 N", "m", "a quantity of another kind than m"),
        ("1.1 mmm", "m", "unknown unit"),
        ("1,1 mm", "m", "decimal point"),
        ("3 mm", "", "plain number"),
        # expressions pint reads as unitless numbers: no empty unit in the message
        ("250e-9:3", "m", r"'250e-9:3' is not a number with a unit \(e.g. 1.1 mm\); give the"),
        ("1/2", "m", "is not a number with a unit"),
    ],
)
def test_a_wrong_unit_is_one_line(text, unit, words):
    with pytest.raises(ContactresInputError, match=words) as info:
        to_si(text, unit, "--x")
    assert "\n" not in str(info.value) and str(info.value).startswith("--x")


def test_column_suffixes_give_the_factor_of_their_unit():
    assert column_unit_factor("mm", "m") == pytest.approx(1e-3, rel=1e-15)
    assert column_unit_factor("cm2", "m^2") == pytest.approx(1e-4, rel=1e-15)
    assert column_unit_factor("mN", "N") == pytest.approx(1e-3, rel=1e-15)
    assert column_unit_factor("kHz", "Hz") == pytest.approx(1e3, rel=1e-15)
    assert column_unit_factor("N", "m") is None  # another dimension: not this quantity
    assert column_unit_factor("extra", "m") is None


def test_the_magnitude_check_takes_the_unit_and_suggests_no_slip():
    assert check_magnitude("sphere_radius", "1.1mm", "--sphere-radius") == pytest.approx(1.1e-3)
    with pytest.raises(ContactresInputError) as info:
        check_magnitude("sphere_radius", "2 km", "--sphere-radius")
    assert "2 km (= 2000 m) is outside" in str(info.value) and "looks like" not in str(info.value)


def test_an_option_with_its_unit_equals_the_option_in_si():
    """Done-when of issue 30: --sphere-radius 1.1mm equals --sphere-radius 1.1e-3 (here the
    contact's --radius and --force, ranges and lists included)."""
    for typed, si in (
        (("1.1mm", "2mN"), ("1.1e-3", "2e-3")),
        (("1mm:2mm:3", "2 mN"), ("1e-3:2e-3:3", "2e-3")),
        (("1mm,2mm", "2mN"), ("1e-3,2e-3", "2e-3")),
    ):
        a = run("contact", "--crystal", "Cu", "--radius", typed[0], "--force", typed[1])
        b = run("contact", "--crystal", "Cu", "--radius", si[0], "--force", si[1])
        assert a.exit_code == 0 and a.stdout == b.stdout, a.output


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("2 N", "another kind"),
        ("1,1 mm", "every value with its unit or none"),
        ("2 km", "= 2000 m"),
    ],
)
def test_a_bad_option_unit_is_one_line(value, words):
    r = run("contact", "--crystal", "Cu", "--radius", value, "--force", "1e-3")
    assert r.exit_code == 2 and words in r.stderr and "Traceback" not in r.output
    assert len(r.stderr.strip().splitlines()) == 1


def _table1(table):
    return analyze(table, settings=AnalysisSettings(bootstrap=0)).table1()


def test_columns_named_with_their_unit_are_read_in_si(tmp_path):
    """A sweep table whose columns are in mm, mN, nm and cm² gives the same Table 1 as the SI
    table it was made from (and, read, the same validated table: what the analysis sees)."""
    frame = pd.read_csv(example_path("example_sweeps.csv"), comment="#")
    frame = frame[frame["configuration"] == "SiO2_2.2mm"]
    si_path = tmp_path / "si.csv"
    frame.to_csv(si_path, index=False)
    typed = frame.rename(
        columns={"sphere_radius_m": "sphere_radius_mm", "normal_force_N": "normal_force_mN",
                 "amplitude_m": "amplitude_nm", "area_m2": "area_cm2"}
    )  # fmt: skip
    for col, factor in (("sphere_radius_mm", 1e3), ("normal_force_mN", 1e3),
                        ("amplitude_nm", 1e9), ("area_cm2", 1e4)):  # fmt: skip
        typed[col] = typed[col] * factor
    typed_path = tmp_path / "typed.csv"
    typed.to_csv(typed_path, index=False)
    # The converted cells differ from the SI ones in their last digits: equal to the fits'
    # convergence, not to the bit. The plateau fits that end at d_c = 0 are refitted with d_c
    # held there, to the LM's tolerance; μ of their blocks moves by ~1e-9 and E's error (a
    # Jacobian error of the JKR fit over those μ) by up to 2.5e-7 (measured). A unit slip
    # would move everything by 1e3 or more.
    typed_table, si_table = read_sweeps(typed_path), read_sweeps(si_path)
    pd.testing.assert_frame_equal(typed_table.data, si_table.data, check_exact=False, rtol=1e-15)
    pd.testing.assert_frame_equal(_table1(typed_table), _table1(si_table), rtol=1e-6)


def test_a_column_in_two_units_is_refused(tmp_path):
    frame = pd.read_csv(example_path("example_sweeps.csv"), comment="#").head(40)
    frame["sphere_radius_mm"] = frame["sphere_radius_m"] * 1e3
    path = tmp_path / "both.csv"
    frame.to_csv(path, index=False)
    with pytest.raises(
        ContactresInputError,
        match=r"columns 'sphere_radius_m' \(column 10\) and 'sphere_radius_mm' \(column 16\)",
    ):
        read_sweeps(path)


def test_a_toml_value_with_its_unit_equals_the_si_value(tmp_path):
    frame = pd.read_csv(example_path("example_sweeps.csv"), comment="#")
    frame = frame[frame["configuration"] == "SiO2_2.2mm"].drop(columns=["sphere_radius_m"])
    for name, text in (
        ("typed", 'sphere_radius = "1.1 mm"\n'),
        ("si", "sphere_radius_m = 1.1e-3\n"),
    ):
        frame.to_csv(tmp_path / f"{name}.csv", index=False)
        (tmp_path / f"{name}.toml").write_text(text)
    # The analysis is a function of the validated table's data alone (the column names and
    # constants are those of the schema, in SI), so a bit-identical table is an identical
    # analysis: comparing the tables checks the conversion at the bit, which Table 1 (the
    # analysis of both, ~2 s of CPU) only checked through the fits.
    typed, si = read_sweeps(tmp_path / "typed.csv"), read_sweeps(tmp_path / "si.csv")
    pd.testing.assert_frame_equal(typed.data, si.data, check_exact=True)
    (tmp_path / "typed.toml").write_text('sphere_radius = "1.1 N"\n')
    with pytest.raises(ContactresInputError, match="another kind"):
        read_sweeps(tmp_path / "typed.csv")
    (tmp_path / "typed.toml").write_text('sphere_radius = "1.1 mm"\nsphere_radius_m = 1e-3\n')
    with pytest.raises(ContactresInputError, match="the same constant"):
        read_sweeps(tmp_path / "typed.csv")


def test_several_values_typed_with_units_build_no_registry_each(monkeypatch):
    # A fresh registry cost ~0.2 s of CPU per value typed with a unit (issue 31): a command with
    # three such values paid 0.6 s. pint's application registry is built once per process.
    import pint

    to_si("1 mm", "m", "warm-up")  # pint's application registry may be built here, once
    built = []
    monkeypatch.setattr(pint.UnitRegistry, "__init__", lambda self, *a, **k: built.append(1))
    values = [to_si("1.1 mm", "m", "a"), to_si("2 mN", "N", "b"), to_si("5 MHz", "Hz", "c")]
    assert values == pytest.approx([1.1e-3, 2e-3, 5e6], rel=1e-15)
    assert column_unit_factor("mm", "m") == pytest.approx(1e-3, rel=1e-15)
    assert built == []


_FIRST_USE_FROM_THREADS = """
import threading
from contactres.typed_units import column_unit_factor, to_si

start = threading.Barrier(6)
got = []

def convert(k):
    start.wait()
    try:
        got.append(to_si("1.1 mm", "m", "a") if k % 2 else column_unit_factor("mm", "m"))
    except Exception as exc:
        got.append(repr(exc))

threads = [threading.Thread(target=convert, args=(k,)) for k in range(6)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(repr(sorted(map(str, got))))
"""


def test_the_first_values_typed_with_units_convert_alike_from_several_threads(tmp_path):
    # pint builds its application registry on first use without a lock (pint issue #2039): a
    # second thread could read it half-built and call "mm" an unknown unit. Run in a fresh
    # process, where no registry is built yet; each thread converts 1.1 mm or 1 mm by hand.
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-c", _FIRST_USE_FROM_THREADS], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == repr(sorted(["0.001"] * 3 + ["0.0011"] * 3))
