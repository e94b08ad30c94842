"""Duplicate column names in a user's table: one line naming the file, the name, where it
repeats and the rule, exit code 2, for every command that reads a table and every reader
(delimited text, an Excel sheet, a numpy archive, an EBSD .ctf, an instrument export), and for
names that become one only once stripped of blanks or converted to SI (``amplitude_nm`` and
``amplitude_um`` are both ``amplitude_m``). pandas would rename a repeated name silently
(``df_Hz.1``) and read the first column only; here no such table reads as if it were fine.

The tables written (CSV, numpy archive, workbook, NetCDF) are another matter: a table of ours
with a name twice is a fault of contactres, raised as an internal error, never as the user's:
tests/test_written_columns.py.
"""

import csv
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_checks import one_line_error, run

import contactres
from contactres.errors import ContactresInputError
from contactres.measurements import read_sweeps
from contactres.measurements.readers.exports import read_export

DATA = Path(contactres.__file__).parent / "data"
RULE = "every column needs its own name"


def _rows(source: Path, count: int | None = None) -> list[list[str]]:
    rows = list(csv.reader(source.open(newline="", encoding="utf-8")))
    return rows if count is None else rows[: count + 1]


def _with_column(rows, copy_of: str, name: str | None = None) -> list[list[str]]:
    """``rows`` (header first) with the column ``copy_of`` repeated at the end as ``name``."""
    i = rows[0].index(copy_of)
    return [[*rows[0], copy_of if name is None else name], *([*r, r[i]] for r in rows[1:])]


def _write(path: Path, rows) -> Path:
    with path.open("w", newline="", encoding="utf-8") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)
    return path


def _message(r) -> str:
    """The one line of a user error (:func:`one_line_error`), after its ``PROG: error:``."""
    return one_line_error(r).split(": error: ", 1)[1]


def _letter(position: int) -> str:
    """Excel's letters of a column (1 -> A, 27 -> AA), written small here for the test."""
    text = ""
    while position:
        position, rest = divmod(position - 1, 26)
        text = chr(ord("A") + rest) + text
    return text


def test_excel_letters_written_here():
    assert [_letter(n) for n in (1, 8, 26, 27, 52, 53, 702, 703)] == [
        "A", "H", "Z", "AA", "AZ", "BA", "ZZ", "AAA",
    ]  # fmt: skip


# ---- every command that reads a delimited table ----------------------------------------------

SWEEPS = DATA / "example_sweeps.csv"
COMMANDS = {
    # command, the example table, the column repeated, the command's options
    "qcm analyze": (SWEEPS, "df_Hz", ["--no-figures", "--bootstrap", "0", "--out", "{o}"]),
    "qcm spectra": (DATA / "example_spectra.csv", "G_S", ["--out", "{o}.csv"]),
    "qcm particles": (
        DATA / "example_particles.csv",
        "dgamma_Hz",
        [
            *("--particle-radius", "5e-7", "--particle-density", "2200"),
            *("--fundamental", "5e6", "--medium", "water", "--out", "{o}"),
        ],
    ),
    "afm invert": (DATA / "example_afm.csv", "fc1_Hz", ["--out", "{o}.csv"]),
    "rum invert": (DATA / "example_rum.csv", "fc_Hz", ["--out", "{o}.csv"]),
}


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("spelling", ["same", "blanks"])
def test_a_column_named_twice_is_one_line_naming_both_places(tmp_path, command, spelling):
    source, column, options = COMMANDS[command]
    rows = _rows(source, 200)
    name = column if spelling == "same" else f"  {column} "  # the same name once stripped
    path = _write(tmp_path / "twice.csv", _with_column(rows, column, name))
    first, second = rows[0].index(column) + 1, len(rows[0]) + 1
    out = str(tmp_path / "o")
    r = run(*command.split(), path, *[o.replace("{o}", out) for o in options])
    line = _message(r)
    assert line == (
        f"{path}, line 1: duplicate column name(s) '{column}' (columns {first}, {second}); {RULE}"
    )
    assert not list(tmp_path.glob("o*"))  # nothing written


def test_an_instrument_export_naming_a_column_twice_is_one_line(tmp_path):
    rows = _rows(DATA / "example_qcmd.csv")
    column = "Delta_F/n_n=5_(Hz)"
    path = _write(tmp_path / "twice.csv", _with_column(rows, column))
    r = run("qcm", "stiffness", path, "--dissipation-scale", "1e-6", "--fundamental", "4.95e6",
            "--area", "2e-5", "--n-contacts", "3", "--out", tmp_path / "o")  # fmt: skip
    line = _message(r)
    assert line == (
        f"{path}: the header names the column '{column}' twice (columns 4 "
        "and 8): which one holds the data is not known; rename the wrong one (awsensors export)"
    )


def test_an_export_column_spelt_as_a_repeat_keeps_its_own_name(tmp_path):
    # The export reader numbers repeated names it does not read (QCM-I repeats its flow and
    # temperature columns per overtone) "Flow #2", ...: a column the file itself calls
    # "Flow #2" is neither merged with a repeat nor lost.
    rows = _rows(DATA / "example_qcmd.csv")
    tails = [["Flow", "Flow", "Flow #2"], *[["1", "2", "3"]] * (len(rows) - 1)]
    rows = [[*r, *t] for r, t in zip(rows, tails, strict=True)]
    path = _write(tmp_path / "flows.csv", rows)
    from contactres.measurements.readers.exports._base import read_rows

    raw = read_rows(path)
    assert raw.columns.is_unique
    assert list(raw.columns[-3:]) == ["Flow", "Flow #3", "Flow #2"]
    assert raw["Flow #2"].tolist() == ["3"] * (len(rows) - 1)  # the file's own column
    table = read_export(path, dissipation_scale=1e-6, fundamental=4.95e6)
    assert len(table.data) == 3 * (len(rows) - 1)  # read as the file without those columns


# ---- names that become one: stripped, or converted to SI ----------------------------------


def _sweeps(tmp_path, frame: pd.DataFrame) -> Path:
    path = tmp_path / "sweeps.csv"
    frame.to_csv(path, index=False)
    return path


@pytest.fixture(scope="module")
def sweeps() -> pd.DataFrame:
    table = pd.read_csv(SWEEPS)
    return table[table["sweep"].isin(table["sweep"].unique()[:6])].reset_index(drop=True)


@pytest.mark.parametrize(
    ("renamed", "added", "places"),
    [
        # a column in SI beside one in another unit
        ({}, ("amplitude_nm", 1e9), "'amplitude_m' (column 7) and 'amplitude_nm' (column 16)"),
        # two columns in other units than SI, the same quantity (a silent rename before)
        (
            {"amplitude_m": "amplitude_nm"},
            ("amplitude_um", 1e6),
            "'amplitude_nm' (column 7) and 'amplitude_um' (column 16)",
        ),
        (
            {"sphere_radius_m": "sphere_radius_mm"},
            ("sphere_radius_um", 1e6),
            "'sphere_radius_mm' (column 10) and 'sphere_radius_um' (column 16)",
        ),
    ],
)
def test_two_columns_of_one_quantity_in_two_units_name_both(
    tmp_path, sweeps, renamed, added, places
):
    name, factor = added
    quantity = name.rsplit("_", 1)[0]
    frame = sweeps.rename(columns=renamed).assign(**{name: sweeps[f"{quantity}_m"] * factor})
    path = _sweeps(tmp_path, frame)
    r = run("qcm", "analyze", path, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    line = _message(r)
    assert line == (
        f"{path}: columns {places} hold the same quantity, {quantity}_m in SI; keep one"
    )


def test_in_memory_names_that_differ_by_blanks_are_named_with_their_places(sweeps):
    frame = sweeps.rename(columns={"medium": "experiment "})
    with pytest.raises(ContactresInputError) as caught:
        contactres.validate_sweeps(frame)
    assert str(caught.value) == (
        "<table>: duplicate column name(s) 'experiment' (columns 2, 4) once stripped of "
        "blanks; one name each"
    )


# ---- the reader's own column: 'line' -------------------------------------------------------


def test_a_column_called_line_is_refused_not_overwritten(tmp_path):
    rows = _rows(DATA / "example_afm.csv")
    path = _write(tmp_path / "scan.csv", _with_column(rows, "pixel", "line"))
    r = run("afm", "invert", path, "--out", tmp_path / "o.csv")
    line = _message(r)
    assert line == (
        f"{path}, line 1: column 'line' (column 11) is the name contactres "
        "gives the line numbers of the file; rename it (e.g. scan_line)"
    )


# ---- an Excel sheet: the columns by their letters ----------------------------------------


openpyxl = pytest.importorskip("openpyxl")


def _book(path: Path, rows, sheet="sweeps", top=0) -> Path:
    book = openpyxl.Workbook()
    ws = book.active
    ws.title = sheet
    for _ in range(top):
        ws.append([])
    for row in rows:  # text cells: the reader takes a number's text as a CSV holds it
        ws.append(row)
    book.save(path)
    return path


def test_a_sheet_naming_columns_twice_names_every_repeat_by_its_letters(tmp_path):
    rows = _rows(SWEEPS, 40)
    rows = _with_column(_with_column(rows, "df_Hz"), "experiment", " experiment")
    rows = _with_column(rows, "df_Hz")
    path = _book(tmp_path / "twice.xlsx", rows, top=2)  # the header on row 3
    r = run("qcm", "analyze", path, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    line = _message(r)
    assert line == (
        f"{path}, sheet 'sweeps', row 3: duplicate column name(s) 'df_Hz' "
        f"(columns {_letter(8)}, {_letter(16)}, {_letter(18)}); 'experiment' (columns "
        f"{_letter(2)}, {_letter(17)}); {RULE}"
    )
    assert (_letter(8), _letter(16), _letter(17), _letter(18)) == ("H", "P", "Q", "R")


def test_a_sheet_with_a_column_called_line_is_refused(tmp_path):
    rows = _rows(DATA / "example_afm.csv")
    path = _book(tmp_path / "scan.xlsx", _with_column(rows, "pixel", "line"), "resonances")
    r = run("afm", "invert", path, "--out", tmp_path / "o.csv")
    line = _message(r)
    assert line == (
        f"{path}, sheet 'resonances', row 1: column 'line' (column K) is the "
        "name contactres gives the row numbers of the sheet; rename it (e.g. scan_line)"
    )


def test_two_units_of_one_quantity_on_a_sheet_are_named_by_letters(tmp_path, sweeps):
    frame = sweeps.assign(amplitude_nm=sweeps["amplitude_m"] * 1e9).astype(str)
    rows = [list(frame.columns), *frame.to_numpy().tolist()]
    path = _book(tmp_path / "units.xlsx", rows)
    with pytest.raises(ContactresInputError) as caught:
        read_sweeps(path)
    assert str(caught.value) == (
        f"{path}, sheet 'sweeps': columns 'amplitude_m' (column G) and 'amplitude_nm' (column "
        "P) hold the same quantity, amplitude_m in SI; keep one"
    )


def _with_empty_cells(rows, empty) -> list[list[str]]:
    """``rows`` with an empty header cell at each 0-based place of ``empty`` (its data cells
    ``1``), the rows' own cells in the other places."""
    width = len(rows[0]) + len(empty)
    table = []
    for row in rows:
        cells = iter(row)
        table.append(["" if i in empty else next(cells) for i in range(width)])
    return [table[0], *([c or "1" for c in r] for r in table[1:])]


@pytest.mark.parametrize(
    ("empty", "letters", "numbers"),
    [
        ([2], "column C of the header is empty", None),  # one: a column pandas names in a CSV
        ([1, 3], "columns B, D of the header are empty", "columns 2, 4 of the header are empty"),
        (
            list(range(1, 8)),
            "columns B, C, D, E, F, ... 7 in all of the header are empty",
            "columns 2, 3, 4, 5, 6, ... 7 in all of the header are empty",
        ),
    ],
)
def test_every_empty_header_cell_of_a_sheet_is_named_by_its_letters(
    tmp_path, empty, letters, numbers
):
    table = _with_empty_cells(_rows(DATA / "example_rum.csv"), empty)
    path = _book(tmp_path / "t.xlsx", table, "resonances", top=1)  # the header on row 2
    r = run("rum", "invert", path, "--out", tmp_path / "o.csv")
    assert _message(r) == f"{path}, sheet 'resonances', row 2: {letters}; every column needs a name"
    assert not (tmp_path / "o.csv").exists()
    if numbers is not None:  # the CSV reader says the same of the same header, by numbers
        csv_path = _write(tmp_path / "t.csv", table)
        r = run("rum", "invert", csv_path, "--out", tmp_path / "o.csv")
        assert _message(r) == f"{csv_path}, line 1: {numbers}; every column needs a name"


def test_a_sheet_naming_a_column_twice_beside_empty_cells_reads_as_a_csv_file(tmp_path):
    # Both faults in one header: both readers name the repeat first (its places by letters
    # and by numbers), the empty cells being no repeat of a name.
    rows = _with_column(_rows(DATA / "example_rum.csv"), "pixel")
    table = _with_empty_cells(rows, [1, 3])
    r = run("rum", "invert", _book(tmp_path / "t.xlsx", table, "resonances"), "--out",
            tmp_path / "o.csv")  # fmt: skip
    last = len(table[0])
    assert _message(r) == (
        f"{tmp_path / 't.xlsx'}, sheet 'resonances', row 1: duplicate column name(s) 'pixel' "
        f"(columns {_letter(1)}, {_letter(last)}); {RULE}"
    )
    r = run("rum", "invert", _write(tmp_path / "t.csv", table), "--out", tmp_path / "o.csv")
    assert _message(r) == (
        f"{tmp_path / 't.csv'}, line 1: duplicate column name(s) 'pixel' (columns 1, {last}); "
        f"{RULE}"
    )


# ---- a numpy archive: one array per column ---------------------------------------------------


def test_an_archive_holding_two_arrays_of_one_name_is_refused(tmp_path):
    table = pd.read_csv(DATA / "example_afm.csv")
    path = tmp_path / "twice.npz"
    np.savez(path, **{c: table[c].to_numpy() for c in table.columns})
    # zipfile warns of the name written twice, and writes it: numpy would read one of the two
    with zipfile.ZipFile(path, "a") as zf, pytest.warns(UserWarning, match="Duplicate name"):
        with zf.open("fc1_Hz.npy", "w") as member:
            np.lib.format.write_array(member, table["fc1_Hz"].to_numpy() * 2)
    with np.load(path) as archive:  # what numpy makes of it: one key, listed twice
        assert archive.files.count("fc1_Hz") == 2
    r = run("afm", "invert", path, "--out", tmp_path / "o.csv")
    line = _message(r)
    assert line == (
        f"{path}: duplicate array name(s) 'fc1_Hz' (arrays 6, 11 of the archive); {RULE}"
    )


def test_an_array_with_and_without_the_npy_suffix_is_one_name_twice(tmp_path):
    path = tmp_path / "both.npz"
    with zipfile.ZipFile(path, "w") as zf:
        for member in ("fc1_Hz.npy", "pixel.npy", "fc1_Hz"):
            with zf.open(member, "w") as fh:
                np.lib.format.write_array(fh, np.arange(3.0))
    r = run("afm", "invert", path, "--out", tmp_path / "o.csv")
    assert _message(r) == (
        f"{path}: duplicate array name(s) 'fc1_Hz' (arrays 1, 3 of the archive); {RULE}"
    )


def test_an_archive_with_an_array_called_line_names_its_place(tmp_path):
    table = pd.read_csv(DATA / "example_afm.csv")
    path = tmp_path / "scan.npz"
    np.savez(path, **{c: table[c].to_numpy() for c in table.columns[:3]}, line=np.arange(3))
    r = run("afm", "invert", path, "--out", tmp_path / "o.csv")
    assert _message(r) == (
        f"{path}: array 'line' (array 4 of the archive) is the name contactres gives the row "
        "numbers of the table; rename it (e.g. scan_line)"
    )


# ---- an EBSD .ctf: pandas would have read 'Euler1' and renamed the other 'Euler1.1' -----------


def test_a_ctf_naming_a_column_twice_is_refused(tmp_path):
    from contactres.polycrystal import synthetic_polycrystal, write_ctf

    good = write_ctf(tmp_path / "good.ctf", synthetic_polycrystal((6, 6), 3, seed=2))
    lines = good.read_text().splitlines()
    at = next(i for i, ln in enumerate(lines) if ln.startswith("Phase\t"))
    lines[at] += "\tEuler1"
    lines[at + 1 :] = [ln + "\t1.5" for ln in lines[at + 1 :]]
    path = tmp_path / "twice.ctf"
    path.write_text("\n".join(lines) + "\n")
    # pandas alone: the repeat renamed, the first read, nothing said
    assert "Euler1.1" in pd.read_csv(path, sep="\t", skiprows=at).columns
    r = run("maps", "predict", path, "--crystal", "Cu", "--tip-radius", "2e-8", "--force",
            "1e-6", "--out", tmp_path / "o.zarr")  # fmt: skip
    line = _message(r)
    assert line == (
        f"twice.ctf, line {at + 1}: duplicate column name(s) 'Euler1' (columns 6, 12); {RULE}"
    )


# ---- the constants of a sweep table's TOML file: one constant, two keys -----------------------


@pytest.mark.parametrize(
    ("toml", "keys"),
    [
        (
            "sphere_radius_m = 1.1e-3\nsphere_radius_mm = 1.2\n",
            "sphere_radius_mm and sphere_radius_m",
        ),
        (
            "sphere_radius_mm = 1.2\nsphere_radius_m = 1.1e-3\n",
            "sphere_radius_m and sphere_radius_mm",
        ),
        (
            'sphere_radius = "1.1 mm"\nsphere_radius_um = 1100\n',
            "sphere_radius_um and sphere_radius",
        ),
        ('sphere_radius = "1.1 mm"\nsphere_radius_m = 1e-3\n', "sphere_radius and sphere_radius_m"),
    ],
)
def test_two_keys_of_one_constant_are_named_as_the_file_writes_them(tmp_path, sweeps, toml, keys):
    path = _sweeps(tmp_path, sweeps.drop(columns="sphere_radius_m"))
    (tmp_path / "sweeps.toml").write_text(toml)
    r = run("qcm", "analyze", path, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    assert _message(r) == (
        f"{tmp_path / 'sweeps.toml'}: {keys} are the same constant; give one of them"
    )


AGAIN = (
    "clashes with a key or table defined above (itself or one on its dotted path); a TOML file "
    "defines each key and table once"
)


@pytest.mark.parametrize(
    ("toml", "said"),
    [
        ("area_m2 = 2.5e-5\nsphere_radius_m = 1e-3\narea_m2 = 3e-5\n", "line 3: key area_m2"),
        ("'sphere_radius_m' = 1e-3\n\"sphere_radius_m\" = 2e-3\n", 'line 2: key "sphere_radius_m"'),
        ("[lab]\nroom = 1\n\n[lab]\n", "line 4: table [lab]"),
        ("[lab]\nroom = 1\nroom.door = 2\n", "line 3: key room.door of table [lab]"),
        ("[[run]]\nby = 1\n[[run]]\nby = 2\n  by = 3\n", "line 5: key by of table [[run]]"),
        # the value tomllib places the fault after takes three lines; the key-like line inside
        # the string is no statement
        ('note = 1\nnote = """\nsphere_radius_m = 1\n"""\n', "line 2: key note"),
        ("area_m2 = 2.5e-5\r\narea_m2 = 3e-5\r\n", "line 2: key area_m2"),  # CRLF line breaks
        ("area_m2 = 2.5e-5\narea_m2 = 3e-5", "line 2: key area_m2"),  # tomllib: "end of document"
        # a key-like line below the statement that only parses with the string's end after it:
        # the text above line 4 is no TOML of its own (an open string), so line 4 is no statement
        ('a = 1\na = """\nb = 1\nc = 2 # """\n', "line 2: key a"),
        # a table name that needs quotes is shown quoted, its backslash escaped
        ('["a\\\\b".c]\nx = 1\nx = 2\n', 'line 3: key x of table ["a\\\\b".c]'),
    ],
)
def test_a_toml_key_given_twice_is_named_with_its_line(tmp_path, sweeps, toml, said):
    path = _sweeps(tmp_path, sweeps.drop(columns="sphere_radius_m"))
    (tmp_path / "sweeps.toml").write_bytes(toml.encode())
    r = run("qcm", "analyze", path, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    assert _message(r) == f"{tmp_path / 'sweeps.toml'}, {said} {AGAIN}"


def test_a_toml_fault_without_a_statement_to_name_keeps_tomllibs_text(tmp_path, sweeps):
    # A clash inside one inline table: tomllib's "Cannot overwrite a value" sends it to the
    # finder, and the statement's own text (one line) is no TOML of its own: nothing to name
    path = _sweeps(tmp_path, sweeps.drop(columns="sphere_radius_m"))
    (tmp_path / "sweeps.toml").write_text("x = 0\nlab = {room = 1, room.door = 2}\n")
    r = run("qcm", "analyze", path, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    assert _message(r).startswith(
        f"{tmp_path / 'sweeps.toml'}: not valid TOML (Cannot overwrite a value"
    )


def test_a_header_pandas_reads_otherwise_is_never_taken_as_read_right(tmp_path, monkeypatch):
    # The header check (the csv module's names) stood aside: pandas renames the repeat
    # (fc1_Hz.1), and the reader says so as its own fault instead of reading on.
    from contactres.measurements.readers import _delimited

    rows = _rows(DATA / "example_afm.csv")
    path = _write(tmp_path / "twice.csv", _with_column(rows, "fc1_Hz"))
    monkeypatch.setattr(_delimited, "repeats_text", lambda names, **_: None)
    with pytest.raises(RuntimeError, match=r"pandas read the header as \[.*'fc1_Hz\.1'\]"):
        _delimited.load(path)


def test_the_internal_message_shows_long_headers_short(tmp_path, monkeypatch):
    # A header of 30 names of 100 characters each, one repeated: 20 names shown, each cut to
    # 60 characters, the rest counted (not 20 names of 100 characters in one line).
    from contactres.measurements.readers import _delimited

    names = [f"{i:02d}" + "x" * 98 for i in range(30)]
    path = _write(tmp_path / "wide.csv", [[*names, names[0]], ["1"] * 31])
    monkeypatch.setattr(_delimited, "repeats_text", lambda names, **_: None)
    with pytest.raises(RuntimeError) as caught:
        _delimited.load(path)
    shown = ", ".join(repr(n[:59] + "…") for n in names[:20])
    assert str(caught.value) == (
        f"{path}: pandas read the header as [{shown}, ... 31 in all], the csv module as "
        f"[{shown}, ... 31 in all]"
    )


# ---- a table pandas saved twice: an empty header cell beside a written-out 'Unnamed: 0' ------


def test_a_table_pandas_saved_twice_reads_as_the_table_it_holds(tmp_path):
    # pd.read_csv(f).to_csv(g), twice, writes ",Unnamed: 0,pixel,...": pandas names the empty
    # cell "Unnamed: 0.1" (the other name is taken). A valid table, read as before: its two
    # index columns kept, the inversion's columns the same as the table's own.
    source = DATA / "example_rum.csv"
    once, twice = tmp_path / "once.csv", tmp_path / "twice.csv"
    pd.read_csv(source).to_csv(once)
    pd.read_csv(once).to_csv(twice)
    assert twice.read_text().startswith(",Unnamed: 0,pixel,")
    for path in (source, twice):
        r = run("rum", "invert", path, "--out", tmp_path / f"{path.stem}.out.csv")
        assert r.exit_code == 0, r.output
    plain = pd.read_csv(tmp_path / "example_rum.out.csv", dtype=str)
    saved = pd.read_csv(tmp_path / "twice.out.csv", dtype=str)
    assert list(saved.columns[1:]) == ["Unnamed: 0", *plain.columns]
    rows = [str(i) for i in range(len(plain))]  # the index pandas wrote, twice
    assert saved.iloc[:, 0].tolist() == rows and saved.iloc[:, 1].tolist() == rows
    pd.testing.assert_frame_equal(saved.iloc[:, 2:], plain)


# ---- empty header cells --------------------------------------------------------------------


@pytest.mark.parametrize(
    ("empty", "places"),
    [
        ([1, 3], "columns 2, 4"),  # among the names
        ([4, 5], "columns 5, 6"),  # right of them: "a,b,c,," (no columns dropped, as one is not)
        (list(range(4, 11)), "columns 5, 6, 7, 8, 9, ... 7 in all"),
    ],
)
def test_two_or_more_empty_header_cells_are_named_as_empty(tmp_path, empty, places):
    rows = _rows(DATA / "example_rum.csv")
    width = len(rows[0]) + sum(i >= len(rows[0]) for i in empty)
    table = []
    for row in rows:
        cells = iter(row)
        table.append(["" if i in empty else next(cells) for i in range(width)])
    path = _write(tmp_path / "t.csv", [[*table[0]], *([c or "1" for c in r] for r in table[1:])])
    r = run("rum", "invert", path, "--out", tmp_path / "o.csv")
    assert _message(r) == (
        f"{path}, line 1: {places} of the header are empty; every column needs a name"
    )


def test_one_empty_header_cell_is_a_column_pandas_names(tmp_path):
    # (as before: its values are kept in the output, under pandas' name)
    rows = _rows(DATA / "example_rum.csv")
    path = _write(tmp_path / "t.csv", [[*rows[0], ""], *([*r, "7"] for r in rows[1:])])
    r = run("rum", "invert", path, "--out", tmp_path / "o.csv")
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "o.csv", dtype=str)
    assert out[f"Unnamed: {len(rows[0])}"].tolist() == ["7"] * (len(rows) - 1)


def test_in_memory_names_the_same_as_given_are_not_said_stripped(sweeps):
    frame = pd.concat([sweeps, sweeps[["experiment"]]], axis=1)
    with pytest.raises(ContactresInputError) as caught:
        contactres.validate_sweeps(frame)
    assert str(caught.value) == (
        f"<table>: duplicate column name(s) 'experiment' (columns 2, {len(frame.columns)}); "
        "one name each"
    )


# ---- an input column named as one the inversion computes (one name, two columns) -----------


@pytest.mark.parametrize(
    ("command", "source", "column", "place"),
    [
        ("afm invert", "example_afm.csv", "kappa", 11),
        ("afm invert", "example_afm.csv", "flags", 11),
        ("rum invert", "example_rum.csv", "k_star_N_per_m", 5),
        ("rum invert", "example_rum.csv", "rum_model", 5),
    ],
)
def test_an_input_column_named_as_a_computed_one_is_refused(
    tmp_path, command, source, column, place
):
    rows = _rows(DATA / source)
    path = _write(tmp_path / "t.csv", _with_column(rows, "pixel", column))
    r = run(*command.split(), path, "--out", tmp_path / "o.csv")
    assert _message(r) == (
        f"{path}: column {column!r} (column {place}) is a column the inversion computes: the "
        "result would replace its values; rename it (a table an inversion wrote: drop its "
        "computed columns first)"
    )
    assert not (tmp_path / "o.csv").exists()


COMPUTED_WITH = {
    # command, the example, the columns an option adds, that option (with what it needs)
    "afm dynamic": (
        "afm invert",
        "example_afm.csv",
        ["k_static_N_per_m", "k_a", "dcsf_real", "dcsf_imag"],
        ["--crystal", "Si"],
    ),
    "afm film": (
        "afm invert",
        "example_afm.csv",
        ["coating", "M_film_Pa", "film_contact_radius_m", "film_weight", "film_verdict"],
        ["--coating", "pmma:250e-9", "--substrate", "fused-silica"],
    ),
    "rum film": (
        "rum invert",
        "example_rum.csv",
        ["coating", "M_film_Pa", "film_contact_radius_m", "film_weight", "film_verdict"],
        [
            *("--coating", "pmma:200e-9", "--substrate", "fused-silica"),
            *("--tip-radius", "2e-6", "--force", "1e-3"),
        ],
    ),
}


@pytest.mark.parametrize("case", list(COMPUTED_WITH))
def test_the_columns_an_option_adds_are_the_users_without_it(tmp_path, case):
    command, source, columns, options = COMPUTED_WITH[case]
    # The option's run writes these columns after the input's (read from its output, not
    # from a list of the code's)
    written = tmp_path / "written.csv"
    r = run(*command.split(), DATA / source, "--out", written, *options)
    assert r.exit_code == 0, r.output
    header = _rows(written)[0]
    assert [c for c in header if c in columns] == columns
    # The example with those columns of the user's (text, as a coating's label): read and kept
    # as given by a run without the option, refused by one with it.
    rows = _rows(DATA / source)
    values = [f"v{j}" for j in range(len(columns))]
    table = [[*rows[0], *columns], *([*r, *values] for r in rows[1:])]
    path = _write(tmp_path / "t.csv", table)
    out = tmp_path / "o.csv"
    r = run(*command.split(), path, "--out", out)
    assert r.exit_code == 0, r.output
    kept = pd.read_csv(out, dtype=str)
    for j, c in enumerate(columns):
        assert kept[c].tolist() == [f"v{j}"] * (len(rows) - 1)
    out.unlink()
    r = run(*command.split(), path, "--out", out, *options)
    first = len(rows[0]) + 1
    shown = ", ".join(f"{c!r} (column {first + j})" for j, c in enumerate(columns[:5]))
    assert _message(r) == (
        f"{path}: columns {shown} are columns the inversion computes: the result would replace "
        "their values; rename them (a table an inversion wrote: drop its computed columns first)"
    )
    assert not out.exists()


@pytest.mark.parametrize(("case", "always"), [("afm film", "kappa"), ("rum film", "rum_model")])
def test_a_computed_and_a_film_column_are_refused_in_one_line(tmp_path, case, always):
    # One column every run writes and two a coated run adds: the one message names all three
    # (named one at a time, the user would fix the first, run again and be refused again).
    command, source, film, options = COMPUTED_WITH[case]
    rows = _rows(DATA / source)
    added = [film[1], always, film[0]]
    table = [[*rows[0], *added], *([*r, "1", "2", "3"] for r in rows[1:])]
    path = _write(tmp_path / "t.csv", table)
    out = tmp_path / "o.csv"
    r = run(*command.split(), path, "--out", out, *options)
    first = len(rows[0]) + 1
    shown = ", ".join(f"{c!r} (column {first + j})" for j, c in enumerate(added))
    assert _message(r) == (
        f"{path}: columns {shown} are columns the inversion computes: the result would replace "
        "their values; rename them (a table an inversion wrote: drop its computed columns first)"
    )
    assert not out.exists()


def test_a_table_an_earlier_inversion_wrote_is_refused_in_one_line(tmp_path):
    first = tmp_path / "first.csv"
    assert run("afm", "invert", DATA / "example_afm.csv", "--out", first).exit_code == 0
    r = run("afm", "invert", first, "--out", tmp_path / "again.csv")
    line = _message(r)
    assert line.startswith(
        f"{first}: columns 'kappa' (column 11), 'k_star_N_per_m' (column 12), "
        "'tip_position_used' (column 13), 'sigma_N_s_per_m' (column 14), 'mode_spread' "
        "(column 15), ... 13 in all are columns the inversion computes"
    )


@pytest.mark.parametrize(
    ("command", "source", "options"),
    [
        ("afm invert", "example_afm.csv", []),
        ("afm invert", "example_afm.csv", ["--crystal", "Si"]),
        ("rum invert", "example_rum.csv", []),
    ],
)
def test_the_names_refused_are_every_column_the_run_adds(tmp_path, command, source, options):
    # The lists the refusal reads against what the run writes after the input's columns (a
    # column added to the output but not to the list would be overwritten without a word:
    # review R31g).
    from contactres.analysis._resonance_tables import _AFM_COMPUTED, _AFM_DYNAMIC, _RUM_COMPUTED

    out = tmp_path / "o.csv"
    r = run(*command.split(), DATA / source, "--out", out, *options)
    assert r.exit_code == 0, r.output
    added = set(_rows(out)[0]) - set(_rows(DATA / source)[0])
    if command == "rum invert":
        assert added == set(_RUM_COMPUTED)
    else:
        assert added == set(_AFM_COMPUTED) | (set(_AFM_DYNAMIC) if options else set())
