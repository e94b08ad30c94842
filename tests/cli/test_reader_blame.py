"""Silent defaults and wrong blame in the table and TOML readers (issue 27, items 6 and 15),
each reproduced with the input that showed it on the example sweep table or a small table of
each other kind:

* a misspelt optional column (``poison``) was a note, its value silently replaced by the
  default: a name that looks like a misspelling of a column the table lacks is refused in one
  line, for every table the readers check against a schema;
* one extra field on the first data row made pandas take the first field for an index and shift
  every column, and the error blamed ``ramp``;
* a TOML constant beside a column of the same name was neither checked nor compared;
* a line of ``;`` in a comma file was read as one cell and blamed as an empty one.
"""

import warnings
from importlib import resources

import numpy as np
import pytest
from cli_checks import one_line_error, run

from contactres.errors import ContactresInputError
from contactres.measurements import read_sweeps
from contactres.measurements._resonances import read_resonance_table
from contactres.measurements._spectra_table import read_spectra
from contactres.measurements._sweeps import SweepWarning
from contactres.measurements.readers.exports import TIDY_READER
from contactres.measurements.schema import AFM_TABLE, RUM_TABLE, Column, TableSchema


@pytest.fixture
def example():
    """The first 60 lines of the package's example sweep table (header first): 15 columns, the
    constants among them (sphere_radius_m = 0.0011 m, poisson = 0.17)."""
    source = resources.files("contactres") / "data" / "example_sweeps.csv"
    return source.read_text(encoding="utf-8").splitlines()[:60]


def _write(path, lines):
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _renamed(lines, old, new):
    header = lines[0].split(",")
    header[header.index(old)] = new
    return [",".join(header), *lines[1:]]


def _one_line(info, *words):
    text = str(info.value)
    assert len(text.splitlines()) == 1, text
    for w in words:
        assert w in text, text
    return text


# --------------------------------------------------------------------------------------------
# A misspelt column


def test_the_near_miss_rule_on_a_schema_of_its_own():
    """The rule, on a schema made here: case, blanks, underscores, the unit suffix and a
    qualifying last word do not count; a different number is another column, not a typo; a name
    unlike every column stays a note."""
    schema = TableSchema(
        "test table",
        "",
        (
            Column("poisson", "-", "ν"),
            Column("sphere_radius_m", "m", "R"),
            Column("fc3_Hz", "Hz", "mode 3"),
        ),
    )
    absent = schema.names
    assert schema.near_miss("poison", absent) == "poisson"
    assert schema.near_miss("Poisson_ratio", absent) == "poisson"
    assert schema.near_miss("Sphere Radius", absent) == "sphere_radius_m"
    assert schema.near_miss("sphere-radius-m", absent) == "sphere_radius_m"
    assert schema.near_miss("fc3_hz", absent) == "fc3_Hz"
    assert schema.near_miss("fc4_Hz", absent) is None  # another mode
    assert schema.near_miss("operator", absent) is None
    assert schema.near_miss("poison", ("sphere_radius_m",)) is None  # poisson is given


@pytest.mark.parametrize(
    "old, new, meant",
    [
        ("poisson", "poison", "'poisson'"),
        ("poisson", "Poisson_ratio", "'poisson'"),
        ("sphere_radius_m", "Sphere radius", "'sphere_radius_m'"),
        ("overtone", "overtones", "'overtone'"),
        ("ramp", "Ramp", "'ramp'"),
    ],
)
def test_a_misspelt_sweep_column_is_refused_not_defaulted(tmp_path, example, old, new, meant):
    path = _write(tmp_path / "typo.csv", _renamed(example, old, new))
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(path)
    _one_line(info, "typo.csv", f"column {new!r}", "sweep table", f"did you mean {meant}")


def test_a_note_column_and_a_near_name_beside_the_real_column_are_kept(tmp_path, example):
    """Columns of other names are notes, as before; so is a name near one the table has."""
    lines = [example[0] + ",operator,poison"] + [ln + ",AB,0.3" for ln in example[1:]]
    table = read_sweeps(_write(tmp_path / "notes.csv", lines)).data
    np.testing.assert_array_equal(table["poisson"], 0.17)  # the poisson column, not 'poison'


def test_the_cli_refuses_a_misspelt_column_in_one_line(tmp_path, example):
    path = _write(tmp_path / "typo.csv", _renamed(example, "poisson", "poison"))
    r = run("qcm", "analyze", path, "--out", tmp_path / "out", "--bootstrap", "0")
    one_line_error(r, "typo.csv", "'poison'", "did you mean 'poisson'")
    assert not (tmp_path / "out").exists()


def test_a_misspelt_column_of_an_afm_or_rum_table_is_refused(tmp_path):
    afm = _write(
        tmp_path / "afm.csv",
        ["f1_free_Hz,fc1_Hz,tip_radius,load_N", "60000,250000,3e-8,1e-6"],
    )
    with pytest.raises(ContactresInputError) as info:
        read_resonance_table(afm, AFM_TABLE)
    _one_line(info, "afm.csv", "'tip_radius'", "afm-table", "did you mean 'tip_radius_m'")
    rum = _write(tmp_path / "rum.csv", ["pixel,f0_Hz,fc_Hz,mass", "1,1e6,1.01e6,1e-3"])
    with pytest.raises(ContactresInputError) as info:
        read_resonance_table(rum, RUM_TABLE)
    _one_line(info, "rum.csv", "'mass'", "did you mean 'mass_kg'")


def test_a_misspelt_column_of_a_spectra_table_or_index_is_refused(tmp_path):
    rows = [f"s1,{f:.1f},1e-3,2e-4,5" for f in np.linspace(4.99e6, 5.01e6, 5)]
    table = _write(tmp_path / "spectra.csv", ["spectrum,frequency_Hz,G_S,B_S,overtones", *rows])
    with pytest.raises(ContactresInputError) as info:
        read_spectra(table)
    _one_line(info, "spectra.csv", "'overtones'", "spectra table", "did you mean 'overtone'")
    folder = tmp_path / "folder"
    folder.mkdir()
    _write(folder / "a.csv", ["frequency_Hz,G_S,B_S", "4.99e6,1e-3,2e-4", "5e6,2e-3,0"])
    _write(folder / "index.csv", ["file,reference,drive_voltge_V", "a.csv,true,0.1"])
    with pytest.raises(ContactresInputError) as info:
        read_spectra(folder)
    _one_line(info, "index.csv", "'drive_voltge_V'", "did you mean 'drive_voltage_V'")


def test_a_misspelt_column_of_a_qcmd_shift_table_is_refused(tmp_path):
    path = _write(
        tmp_path / "shifts.csv",
        ["time_s,overtone,df_Hz,dgamma", "0,3,-10,1", "0,5,-12,1.5"],
    )
    with pytest.raises(ContactresInputError) as info:
        TIDY_READER.load(path, fundamental=5e6)
    _one_line(info, "shifts.csv", "'dgamma'", "QCM-D shift table", "did you mean 'dgamma_Hz'")


# --------------------------------------------------------------------------------------------
# One extra field on the first data row


def test_an_extra_field_on_the_first_row_names_that_row_not_a_column(tmp_path, example):
    lines = list(example)
    lines[1] += ",x"
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(_write(tmp_path / "extra.csv", lines))
    text = _one_line(
        info, "extra.csv", "line 2 has 16 fields, the header 15", "1 field more than the header"
    )
    assert "column" not in text.split("(")[0]  # no column blamed: the row is at fault
    r = run("qcm", "analyze", tmp_path / "extra.csv", "--out", tmp_path / "out")
    one_line_error(r, "extra.csv", "line 2 has 16 fields")


def test_a_trailing_separator_on_every_row_is_not_read_shifted(tmp_path, example):
    """Every data row one field longer (a trailing comma): pandas took the sweep ids for an
    index and read each column one to the left."""
    lines = [example[0], *(ln + "," for ln in example[1:])]
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(_write(tmp_path / "trailing.csv", lines))
    _one_line(info, "trailing.csv", f"{len(example) - 1} rows have more fields", "header's 15")


# --------------------------------------------------------------------------------------------
# A TOML constant beside its column


def test_a_toml_constant_beside_its_column_is_checked(tmp_path, example):
    path = _write(tmp_path / "s.csv", example)
    path.with_suffix(".toml").write_text("sphere_radius_m = 1.1\n")  # mm in a metre key
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(path)
    _one_line(info, "s.toml", "key 'sphere_radius_m'", "sphere_radius_m = 1.1", "millimetres")
    r = run("qcm", "analyze", path, "--out", tmp_path / "out")
    one_line_error(r, "s.toml", "sphere_radius_m = 1.1")


def test_a_toml_constant_that_differs_from_its_column_is_said_and_the_column_wins(
    tmp_path, example
):
    path = _write(tmp_path / "s.csv", example)
    toml = path.with_suffix(".toml")
    toml.write_text('sphere_radius = "1.2 mm"\n')
    with pytest.warns(SweepWarning) as caught:
        table = read_sweeps(path).data
    said = [str(w.message) for w in caught if "s.toml" in str(w.message)]
    assert len(said) == 1 and len(said[0].splitlines()) == 1, said
    for words in ("'1.2 mm'", "column 'sphere_radius_m'", "0.0011", "the column's value is used"):
        assert words in said[0], said[0]
    np.testing.assert_array_equal(table["sphere_radius_m"], 1.1e-3)  # as written in the column
    toml.write_text('sphere_radius = "1.1 mm"\n')  # the same radius: nothing to say
    with warnings.catch_warnings():
        warnings.simplefilter("error", SweepWarning)
        read_sweeps(path)


def test_an_argument_beside_its_column_is_checked(tmp_path, example):
    path = _write(tmp_path / "s.csv", example)
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(path, sphere_radius_m=1.1)
    _one_line(info, "argument sphere_radius_m", "1.1", "millimetres")


# --------------------------------------------------------------------------------------------
# A row with another separator


def test_a_semicolon_row_in_a_comma_file_is_named_as_such(tmp_path, example):
    lines = list(example)
    lines[5] = lines[5].replace(",", ";")
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(_write(tmp_path / "semi.csv", lines))
    text = _one_line(info, "semi.csv, line 6", "1 field", "has 15", "';' as separator")
    assert "empty" not in text
    r = run("qcm", "analyze", tmp_path / "semi.csv", "--out", tmp_path / "out")
    one_line_error(r, "semi.csv, line 6", "';' as separator")


def test_a_semicolon_row_after_an_empty_last_cell_is_named_as_such(tmp_path, example):
    # The last cells are compared per run of equal cells (one column of 10^6 rows, issue 31):
    # here the row before the ';' row ends in an empty cell too, so the ';' row's empty last
    # cell is inside a run, not at its start (a test the single ';' row above leaves open).
    lines = list(example)
    lines[4] = lines[4][: lines[4].rindex(",") + 1]
    lines[5] = lines[5].replace(",", ";")
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(_write(tmp_path / "semi.csv", lines))
    _one_line(info, "semi.csv, line 6", "1 field", "has 15", "';' as separator")


def test_a_comma_row_in_a_semicolon_file_is_named_as_such(tmp_path, example):
    lines = [ln.replace(",", ";") for ln in example]
    lines[3] = example[3]
    with pytest.raises(ContactresInputError) as info:
        read_sweeps(_write(tmp_path / "semi.csv", lines))
    _one_line(info, "semi.csv, line 4", "1 field", "has 15", "',' as separator")
