"""``afm invert`` with numpy archives (.npz) in and out (issue 31, point 5), and the CSV reader's
numbers read whole (no Python strip per cell) with the cells it cannot read still named."""

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres.cli import main
from contactres.errors import ContactresInputError
from contactres.fileio import write_npz
from contactres.measurements import read_resonance_table
from contactres.measurements.schema import AFM_TABLE
from contactres.normal import hertz
from contactres.resonators import Cantilever, contact_frequencies


def _run(*args):
    return CliRunner().invoke(main, list(args))


def _map(n=40):
    """n pixels of a lever (k_c = 40 N/m, r = 0.95, two modes) on a Hertz contact of
    M_sample = 50 GPa under a 165 GPa tip, R = 50 nm, loads from 2 to 20 nN (a/R <= 0.06);
    a label column."""
    lever = Cantilever((160e3, 1003e3), 40.0)
    load = np.geomspace(2e-9, 2e-8, n)
    e_star = 1 / (1 / 50e9 + 1 / 165e9)
    k_star = 2 * hertz(e_star, 50e-9, load).contact_radius * e_star  # dF/dδ = 2aE*
    f = contact_frequencies(lever, k_star / 40.0, 0.95, modes=(1, 2))
    frame = pd.DataFrame(
        {
            "pixel": np.arange(1, n + 1),
            "label": [f"p{i}, row" for i in range(n)],  # a comma: quoted in the CSV
            "f1_free_Hz": 160e3,
            "f2_free_Hz": 1003e3,
            "k_c_N_per_m": 40.0,
            "tip_position": 0.95,
            "fc1_Hz": f[:, 0],
            "fc2_Hz": f[:, 1],
            "tip_radius_m": 50e-9,
            "load_N": load,
            "M_tip_Pa": 165e9,
        }
    )
    return frame, k_star


def test_npz_in_and_out_give_the_csv_results_as_exact_doubles(tmp_path):
    frame, k_star = _map()
    frame.to_csv(tmp_path / "map.csv", index=False)
    write_npz(tmp_path / "map.npz", frame)
    for source, out in (("map.csv", "a.csv"), ("map.npz", "b.npz"), ("map.npz", "c.csv")):
        r = _run("afm", "invert", str(tmp_path / source), "--out", str(tmp_path / out))
        assert r.exit_code == 0, r.output
    text = pd.read_csv(tmp_path / "a.csv", keep_default_na=False)
    with np.load(tmp_path / "b.npz", allow_pickle=False) as archive:
        binary = {name: archive[name] for name in archive.files}
    assert list(binary) == list(text.columns)
    np.testing.assert_allclose(binary["k_star_N_per_m"], k_star, rtol=1e-8)
    np.testing.assert_allclose(binary["M_sample_Pa"], 50e9, rtol=1e-7)
    for name, values in binary.items():
        if values.dtype.kind == "f":  # the CSV's computed columns hold 10 digits of these
            got = pd.to_numeric(text[name]).to_numpy(dtype=float)
            np.testing.assert_allclose(values, got, rtol=1e-9, atol=0, equal_nan=True)
        else:
            assert values.astype(str).tolist() == text[name].astype(str).tolist(), name
    # The CSV written from the archive is the one written from the CSV, to the byte.
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()


def test_an_npz_table_is_checked_and_its_rows_named(tmp_path):
    frame, _ = _map(5)
    frame.loc[3, "fc1_Hz"] = np.inf
    write_npz(tmp_path / "bad.npz", frame)
    with pytest.raises(ContactresInputError, match=r"row 4, column 'fc1_Hz'.*not a finite"):
        read_resonance_table(tmp_path / "bad.npz", AFM_TABLE)
    frame, _ = _map(5)
    frame["tip_position"] = np.nan  # not given: solved from the two modes
    write_npz(tmp_path / "gap.npz", frame)
    checked = read_resonance_table(tmp_path / "gap.npz", AFM_TABLE)
    assert checked["tip_position"].isna().all() and checked["fc2_Hz"].notna().all()


@pytest.mark.parametrize(
    "arrays, message",
    [
        ({"fc1_Hz": np.ones(3), "k_c_N_per_m": np.ones(4)}, "one length"),
        ({"fc1_Hz": np.ones((3, 2))}, "one-dimensional"),
        ({"fc1_Hz": np.array([1.0, None], dtype=object)}, "numpy archive"),  # a pickle
        ({"fc1_Hz": np.ones(3, dtype=complex)}, "numbers or text"),
        ({}, "no arrays"),
    ],
)
def test_a_bad_archive_is_refused_in_one_line(tmp_path, arrays, message):
    path = tmp_path / "t.npz"
    np.savez(path, **arrays)  # (allow_pickle: numpy's default, to write the object array)
    with pytest.raises(ContactresInputError, match=message) as info:
        read_resonance_table(path, AFM_TABLE)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_numbers_with_white_space_read_as_written_and_text_is_named(tmp_path):
    """The reader parses each column whole and strips only the cells pandas' parser leaves
    (other white space than ASCII, blanks of spaces); the values are those of the same table
    written without the white space."""
    frame, _ = _map(4)
    clean = tmp_path / "clean.csv"
    frame.to_csv(clean, index=False)
    padded = frame.astype(object)
    padded["fc1_Hz"] = [f" {v!r} " for v in frame["fc1_Hz"]]
    padded["fc2_Hz"] = [f"\u00a0{v!r}\t" for v in frame["fc2_Hz"]]  # no-break space: Python's
    padded["tip_position"] = ["0.95", "   ", "", "\u00a00.95"]  # blanks: not given
    padded.to_csv(tmp_path / "padded.csv", index=False)
    want = read_resonance_table(clean, AFM_TABLE)
    got = read_resonance_table(tmp_path / "padded.csv", AFM_TABLE)
    for name in ("fc1_Hz", "fc2_Hz"):
        np.testing.assert_array_equal(got[name].to_numpy(), want[name].to_numpy())
    np.testing.assert_array_equal(got["tip_position"].to_numpy(), [0.95, np.nan, np.nan, 0.95])
    for cell in ("1_000", "12 kHz", "nan"):
        bad = frame.astype(object)
        bad.loc[2, "fc2_Hz"] = cell
        bad.to_csv(tmp_path / "bad.csv", index=False)
        with pytest.raises(ContactresInputError, match=r"line 4, column 'fc2_Hz'") as info:
            read_resonance_table(tmp_path / "bad.csv", AFM_TABLE)
        assert cell in str(info.value)


def test_the_flags_of_the_lever_and_of_the_modulus_are_joined_per_row(tmp_path):
    """The flags column joins the lever's flags and the modulus' flags of each row with ';'
    (joined once per distinct pair of masks): a row with both, rows with either, a clean row."""
    frame, _ = _map(4)
    frame.loc[[1, 3], "fc2_Hz"] *= 1.03  # the modes disagree on κ: inconsistent-modes
    frame.loc[[2, 3], "load_N"] = 1e-12  # E* = √(k*³/6RP) beyond the 165 GPa tip: tip-limit
    frame.to_csv(tmp_path / "map.csv", index=False)
    r = _run("afm", "invert", str(tmp_path / "map.csv"), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    flags = pd.read_csv(tmp_path / "o.csv", keep_default_na=False)["flags"].tolist()
    assert flags == [
        "",
        "inconsistent-modes",
        "tip-limit",
        "inconsistent-modes;tip-limit",
    ]


def _mixed(n=24):
    """A table of several levers and geometries (the rows are inverted group by group): two
    free frequencies, a lateral ratio with a tip height in some rows, the tip position given
    in some rows and solved from the two modes in others, Q factors in some cells, a reference
    sample in some rows, a label; the map of :func:`_map` underneath."""
    frame, _ = _map(n)
    i = np.arange(n)
    lever = Cantilever((150e3, 940e3), 40.0)
    f = contact_frequencies(lever, np.geomspace(5.0, 50.0, n), 0.9, modes=(1, 2))
    other = i % 3 == 1
    frame.loc[other, "f1_free_Hz"] = 150e3
    frame.loc[other, "f2_free_Hz"] = 940e3
    frame.loc[other, "fc1_Hz"] = f[other, 0]
    frame.loc[other, "fc2_Hz"] = f[other, 1]
    frame["lateral_ratio"] = np.where(i % 4 == 0, 0.8, np.nan)
    frame["tip_height_over_L"] = np.where(i % 4 == 0, 0.05, np.nan)
    frame["tip_position"] = np.where(i % 5 == 2, np.nan, frame["tip_position"])
    frame["Q1"] = np.where(i % 2 == 0, 300.0, np.nan)
    frame["fc1_ref_Hz"] = np.where(i % 6 == 3, frame["fc1_Hz"] * 1.01, np.nan)
    frame["M_ref_Pa"] = np.where(i % 6 == 3, 60e9, np.nan)
    frame.loc[i % 6 == 3, ["tip_radius_m", "load_N"]] = np.nan  # the reference method there
    return frame


@pytest.mark.parametrize("crystal", [None, "Si"])
def test_numpy_columns_give_the_dataframe_results_bit_for_bit(tmp_path, crystal):
    """issue 31, point 5: an archive inverted as numpy columns (no pandas) gives every column
    of the DataFrame path, to the bit, on a table of several lever groups (each group inverted
    at once), references, Q factors; with --crystal, the dynamic correction to 1e-12 (its kernel
    tables differ in the last bits from one run to the next, on either path)."""
    from contactres.jobs import afm_invert as job
    from contactres.materials import Material

    write_npz(tmp_path / "mixed.npz", _mixed())
    sample = None if crystal is None else Material.crystal(crystal).rotated((0, 0, 1))
    frame = job.run(tmp_path / "mixed.npz", job.Settings(sample=sample)).table
    arrays = job.run(tmp_path / "mixed.npz", job.Settings(sample=sample, arrays=True)).table
    assert not isinstance(arrays, pd.DataFrame) and list(arrays.columns) == list(frame.columns)
    assert len(set(frame["flags"])) > 1 and frame["modulus_method"].nunique() > 1
    for name in frame.columns:
        want, got = frame[name].to_numpy(), arrays[name]
        if want.dtype.kind == "f" and crystal is None:
            assert got.dtype == want.dtype and np.array_equal(got, want, equal_nan=True), name
        elif want.dtype.kind == "f":
            assert got.dtype == want.dtype, name
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=0, equal_nan=True)
        else:
            assert [str(v) for v in got] == [str(v) for v in want], name
    if crystal is not None:
        return
    write_npz(tmp_path / "a.npz", frame)
    write_npz(tmp_path / "b.npz", arrays)
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()


def test_an_archive_read_as_numpy_columns_names_its_bad_cells_as_the_dataframe_does(tmp_path):
    frame, _ = _map(5)
    frame["fc1_Hz"] = frame["fc1_Hz"].astype(object)
    frame.loc[3, "fc1_Hz"] = "12 kHz"  # text where a number belongs
    np.savez(tmp_path / "text.npz", **{c: frame[c].to_numpy(dtype=str) for c in frame})
    frame, _ = _map(5)
    frame.loc[2, "k_c_N_per_m"] = -1.0  # a rule of the schema
    write_npz(tmp_path / "rule.npz", frame)
    for name in ("text.npz", "rule.npz"):
        messages = []
        for arrays in (False, True):
            with pytest.raises(ContactresInputError) as info:
                read_resonance_table(tmp_path / name, AFM_TABLE, arrays=arrays)
            messages.append(str(info.value))
        assert messages[0] == messages[1] and "row " in messages[0], messages


def test_absent_columns_of_numpy_columns_are_nan_and_each_its_own(tmp_path):
    """The schema's columns an archive lacks are NaN in the checked numpy columns, each its own
    writable array (as a DataFrame's): a change to one reaches no other."""
    frame, _ = _map(5)
    write_npz(tmp_path / "map.npz", frame)
    checked = read_resonance_table(tmp_path / "map.npz", AFM_TABLE, arrays=True)
    absent = [c.name for c in AFM_TABLE.columns if c.name not in frame.columns]
    assert len(absent) > 1
    for name in absent:
        assert checked[name].shape == (5,) and np.isnan(checked[name]).all()
    checked[absent[0]][0] = 1.0
    assert all(np.isnan(checked[name]).all() for name in absent[1:])
    checked["fc1_Hz"][0] = 1.0  # a column of the file is the reading's own


def test_an_array_table_holds_columns_of_one_length():
    from contactres.measurements import ArrayTable

    t = ArrayTable({"a": [1.0, 2.0, 3.0], "b": np.array(["x", "y", "z"], dtype=object)})
    t["c"] = "global"  # one value: every row, as text objects
    t["d"] = np.nan
    assert len(t) == 3 and t.columns == ["a", "b", "c", "d"]
    assert t["c"].dtype == object and list(t["c"]) == ["global"] * 3 and np.isnan(t["d"]).all()
    with pytest.raises(ContactresInputError, match="3 rows"):
        t["e"] = [1.0, 2.0]
    with pytest.raises(ContactresInputError, match="one dimension"):
        t["e"] = np.ones((3, 2))
    part = t[["b", "a"]]
    assert part.columns == ["b", "a"] and part["a"] is t["a"]
    deep, shallow = t.copy(), t.copy(deep=False)
    assert deep["a"] is not t["a"] and np.array_equal(deep["a"], t["a"])
    assert shallow["a"] is t["a"]
    shallow["a"] = [7.0, 8.0, 9.0]  # a new column in the copy: the table keeps its own
    assert list(t["a"]) == [1.0, 2.0, 3.0]
    t.attrs["line_word"] = "row"
    frame = t.to_frame()
    assert frame.attrs["line_word"] == "row" and list(frame.columns) == t.columns
    back = ArrayTable.from_frame(frame)
    assert back.columns == t.columns and np.array_equal(back["a"], t["a"])


def test_text_of_numpy_columns_is_written_as_pandas_writes_it(tmp_path):
    """The archive of numpy columns holds the text pandas' ``fillna("").astype(str)`` gives:
    None and NaN empty, numbers as their text, one width for the column (a column of empty
    cells, the flags of a table without one, included)."""
    from contactres.measurements import ArrayTable

    cells = np.array(["hertz", None, np.nan, 3, "", "hertz + dynamic"], dtype=object)
    columns = {"m": cells, "x": np.arange(6.0), "e": np.array([""] * 6, dtype=object)}
    write_npz(tmp_path / "a.npz", pd.DataFrame(columns))
    write_npz(tmp_path / "b.npz", ArrayTable(columns))
    with np.load(tmp_path / "a.npz") as a, np.load(tmp_path / "b.npz") as b:
        assert a["m"].dtype == b["m"].dtype == np.dtype("<U15") and a["e"].dtype == b["e"].dtype
        assert a["m"].tolist() == b["m"].tolist() == ["hertz", "", "", "3", "", "hertz + dynamic"]
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()


@pytest.mark.parametrize("pool", [["global"], ["", "hertz"], ["a", "bb", "", "c;d"], list("abcde")])
def test_columns_of_a_few_texts_are_written_as_pandas_writes_them(tmp_path, pool):
    """Columns of up to four distinct texts (compared as text, a pass each) and of more (one
    text per distinct object), each text held by many equal objects: pandas' archive, byte for
    byte; with a None or a number among them, too. Also as a map's columns are built, a few
    objects repeated (grouped by object), with equal texts in other objects among them, a text
    that is equal to a str but not one, and a column that is a strided view."""
    from contactres.measurements import ArrayTable

    rng = np.random.default_rng(5)
    picks = rng.integers(len(pool), size=300)
    cells = np.array(["".join(list(pool[i])) for i in picks], object)
    other = cells.copy()
    other[[7, 100]] = [None, 2.5]
    repeated = np.array(pool, dtype=object)[picks]
    mixed = repeated.copy()
    mixed[::7] = cells[::7]
    typed = repeated.copy()
    typed[[3, 50]] = np.str_(pool[0])
    columns = {
        "t": cells,
        "u": other,
        "v": repeated,
        "w": mixed,
        "x": typed,
        "y": np.repeat(repeated, 2)[::2],
    }
    write_npz(tmp_path / "a.npz", pd.DataFrame(columns))
    write_npz(tmp_path / "b.npz", ArrayTable(columns))
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()


def test_rows_are_grouped_as_pandas_groups_them():
    """The lever groups of the inversion are pandas' ``groupby(sort=False, dropna=False)``
    groups (NaN a value of its own, -0.0 equal to 0.0), in the order of their first row."""
    from contactres.analysis._resonance_tables import _row_groups

    rng = np.random.default_rng(7)
    values = np.array([0.0, -0.0, np.nan, 1.5, 2.0])
    for trial in range(60):
        n, m = int(rng.integers(1, 40)), int(rng.integers(1, 4))
        high = 1 if trial % 4 == 0 else len(values)  # every fourth table: one group
        keys = [values[rng.integers(0, high, n)] for _ in range(m)]
        frame = pd.DataFrame({f"c{j}": k for j, k in enumerate(keys)})
        want = frame.groupby(list(frame.columns), sort=False, dropna=False).indices.values()
        got = _row_groups(keys)
        assert [r.tolist() for r in got] == [r.tolist() for r in want]
