"""Tests of contactres.fileio: atomic writes leave whole files, never partial ones; a result set
appears whole or not at all and never replaces an input."""

import hashlib
import json
import os
import socket
import stat
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from matplotlib.figure import Figure

from contactres.fileio import (
    MANIFEST,
    OutputError,
    ResultSet,
    check_output,
    ensure_dir,
    save_figure,
    write_csv,
    write_text,
)


def _mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


def test_write_text_and_csv_round_trip(tmp_path):
    p = write_text(tmp_path / "a.txt", "héllo\n")
    assert p.read_text(encoding="utf-8") == "héllo\n"
    q = write_csv(tmp_path / "t.csv", pd.DataFrame({"x_m": [1.0, 2.0]}))
    assert q.read_text().splitlines() == ["x_m", "1.0", "2.0"]
    # no temporary files left behind
    assert sorted(f.name for f in tmp_path.iterdir()) == ["a.txt", "t.csv"]


def test_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = write_text(tmp_path / "keep.txt", "old")

    class Boom:
        def to_csv(self, path, **kwargs):
            with open(path, "w") as fh:
                fh.write("partial")
            raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        write_csv(target, Boom())
    assert target.read_text() == "old"
    assert [f.name for f in tmp_path.iterdir()] == ["keep.txt"]


def test_new_files_get_the_umask_mode_and_replaced_files_keep_theirs(tmp_path):
    # A plain open() gives 0o666 less the umask; the temporary file (0o600) must not leak through.
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    new = write_text(tmp_path / "new.txt", "x")
    assert _mode(new) == _mode(plain)
    os.chmod(new, 0o640)
    write_text(new, "y")
    assert _mode(new) == 0o640 and new.read_text() == "y"


def test_save_figure_and_ensure_dir(tmp_path):
    folder = ensure_dir(tmp_path / "a" / "b")
    fig = Figure()
    fig.subplots().plot([0, 1], [1, 0])
    p = save_figure(folder / "f.png", fig)
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    f = tmp_path / "file"
    f.write_text("keep me")
    with pytest.raises(ValueError, match="not a directory"):
        ensure_dir(f)
    assert f.read_text() == "keep me"


# ---- result sets: a folder written as a whole ------------------------------------------------

OWNED = ("a.csv", "b.csv", "c.png")


def _write_set(folder, contents, inputs=()):
    with ResultSet(folder, names=list(contents), inputs=inputs, owned=OWNED) as rs:
        for name, text in contents.items():
            rs.path(name).write_text(text)
    return folder


def _names(folder):
    return sorted(p.name for p in folder.iterdir())


def test_result_set_appears_whole_with_a_manifest_and_leaves_nothing_behind(tmp_path):
    out = _write_set(tmp_path / "out", {"a.csv": "1\n", "c.png": "png"})
    assert _names(out) == ["a.csv", "c.png", MANIFEST]
    record = json.loads((out / MANIFEST).read_text())
    for name in ("a.csv", "c.png"):
        data = (out / name).read_bytes()
        assert record["files"][name] == {
            "bytes": len(data),
            "sha256": hashlib.sha256(data).hexdigest(),
        }
    assert _names(tmp_path) == ["out"]  # no lock, no staging folder


def test_a_later_set_removes_the_files_of_an_earlier_one(tmp_path):
    out = _write_set(tmp_path / "out", {"a.csv": "old", "c.png": "old figure"})
    _write_set(out, {"a.csv": "new"})  # e.g. a run without figures
    assert _names(out) == ["a.csv", MANIFEST] and (out / "a.csv").read_text() == "new"
    assert set(json.loads((out / MANIFEST).read_text())["files"]) == {"a.csv"}


def test_a_folder_with_other_files_keeps_them(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "data.csv").write_text("the input")
    _write_set(out, {"a.csv": "old", "c.png": "old figure"}, inputs=[out / "data.csv"])
    _write_set(out, {"a.csv": "new", "b.csv": "new"}, inputs=[out / "data.csv"])
    assert _names(out) == ["a.csv", "b.csv", "data.csv", MANIFEST]
    assert (out / "data.csv").read_text() == "the input"
    assert _names(tmp_path) == ["out"]


def test_a_name_in_a_manifest_contactres_did_not_write_is_never_removed(tmp_path):
    """Issue 27: a manifest.json someone else wrote listing a file made the next set delete it."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "raw.dat").write_text("x")
    (out / MANIFEST).write_text('{"files": {"raw.dat": {}}}')
    with pytest.raises(OutputError, match=r"manifest\.json that contactres did not write"):
        _write_set(out, {"a.csv": "new"})
    assert (out / "raw.dat").read_text() == "x" and _names(out) == [MANIFEST, "raw.dat"]
    # Not JSON at all: refused the same way, nothing touched.
    (out / MANIFEST).write_text("my notes")
    with pytest.raises(OutputError, match="did not write"):
        _write_set(out, {"a.csv": "new"})
    assert _names(out) == [MANIFEST, "raw.dat"]


def test_another_kind_of_set_is_refused_not_removed(tmp_path):
    """Issue 27: qcm analyze into a folder of qcm stiffness results deleted them."""
    out = tmp_path / "out"
    with ResultSet(out, names=["k.csv"], owned=["k.csv"], kind="qcm_stiffness") as rs:
        rs.path("k.csv").write_text("stiffness")
    with pytest.raises(OutputError, match=r"another command \('qcm_stiffness' results"):
        with ResultSet(out, names=["a.csv"], owned=OWNED, kind="qcm_sweeps") as rs:
            rs.path("a.csv").write_text("new")
    assert _names(out) == ["k.csv", MANIFEST] and (out / "k.csv").read_text() == "stiffness"
    assert json.loads((out / MANIFEST).read_text())["kind"] == "qcm_stiffness"


def test_a_file_changed_since_the_earlier_set_wrote_it_stays(tmp_path):
    """Only files whose size and SHA-256 still match the earlier manifest are the set's own."""
    out = _write_set(tmp_path / "out", {"a.csv": "old", "c.png": "old figure"})
    (out / "c.png").write_text("the user's own figure now")
    _write_set(out, {"a.csv": "new"})
    assert _names(out) == ["a.csv", "c.png", MANIFEST]
    assert (out / "c.png").read_text() == "the user's own figure now"
    assert set(json.loads((out / MANIFEST).read_text())["files"]) == {"a.csv"}


def test_an_older_contactres_manifest_is_taken_over_by_its_own_names(tmp_path):
    """A manifest of contactres 0.2 (file records only, no writer or kind): its verified files
    are the earlier set's when every name it lists is one of this kind's; else refused."""
    out = _write_set(tmp_path / "out", {"a.csv": "old", "c.png": "old figure"})
    record = json.loads((out / MANIFEST).read_text())
    (out / MANIFEST).write_text(json.dumps({"files": record["files"]}))
    _write_set(out, {"a.csv": "new"})
    assert _names(out) == ["a.csv", MANIFEST]
    legacy = {"files": {"k.csv": {"bytes": 1, "sha256": "0" * 64}}}
    (out / MANIFEST).write_text(json.dumps(legacy))
    with pytest.raises(OutputError, match=r"lists 'k\.csv'"):
        _write_set(out, {"a.csv": "newer"})
    assert (out / "a.csv").read_text() == "new"


def test_the_manifest_records_its_writer_and_kind(tmp_path):
    from contactres import __version__

    with ResultSet(tmp_path / "o", names=["a.csv"], kind="demo") as rs:
        rs.path("a.csv").write_text("1")
    record = json.loads((tmp_path / "o" / MANIFEST).read_text())
    assert (record["generator"], record["version"], record["kind"]) == (
        "contactres",
        __version__,
        "demo",
    )


def test_without_an_atomic_exchange_the_two_renames_give_the_same_result(tmp_path, monkeypatch):
    import ctypes

    def no_libc(*args, **kwargs):
        raise OSError("no C library here")

    out = _write_set(tmp_path / "out", {"a.csv": "old", "c.png": "old"})
    monkeypatch.setattr(ctypes, "CDLL", no_libc)
    _write_set(out, {"a.csv": "new"})
    assert _names(out) == ["a.csv", MANIFEST] and (out / "a.csv").read_text() == "new"
    assert _names(tmp_path) == ["out"]


def test_a_kill_between_the_two_renames_is_undone_by_the_next_run(tmp_path):
    # What a kill after 'folder -> .old' and before 'staging -> folder' leaves behind.
    old = tmp_path / ".out.contactres-0123456789ab.old"
    _write_set(old, {"a.csv": "old"})
    with pytest.raises(RuntimeError, match="stop"):
        with ResultSet(tmp_path / "out", names=["a.csv"], owned=OWNED) as rs:
            rs.path("a.csv").write_text("new")
            raise RuntimeError("stop")
    assert (tmp_path / "out" / "a.csv").read_text() == "old"
    assert _names(tmp_path) == ["out"]


def test_an_error_inside_leaves_the_earlier_set_and_no_new_folders(tmp_path):
    out = _write_set(tmp_path / "out", {"a.csv": "old"})
    with pytest.raises(KeyError):
        with ResultSet(out, names=["a.csv", "b.csv"], owned=OWNED) as rs:
            rs.path("a.csv").write_text("new")
            raise KeyError("analysis failed")
    assert _names(out) == ["a.csv", MANIFEST] and (out / "a.csv").read_text() == "old"
    with pytest.raises(KeyError):
        with ResultSet(tmp_path / "x" / "y" / "out", names=["a.csv"]):
            raise KeyError("analysis failed")
    assert _names(tmp_path) == ["out"]


def test_only_declared_names_can_be_written(tmp_path):
    with ResultSet(tmp_path / "out", names=["a.csv"]) as rs:
        for bad in ("b.csv", MANIFEST, "../a.csv"):
            with pytest.raises(KeyError, match="not one of the files declared"):
                rs.path(bad)
        rs.path("a.csv").write_text("x")


@pytest.mark.parametrize("how", ["same path", "symlinked folder", "hard link"])
def test_an_output_never_replaces_an_input(tmp_path, how):
    data = tmp_path / "data"
    data.mkdir()
    src = data / "a.csv"
    src.write_text("the input")
    out = data
    if how == "symlinked folder":
        out = tmp_path / "link"
        out.symlink_to(data, target_is_directory=True)
    elif how == "hard link":
        out = tmp_path / "out"
        out.mkdir()
        os.link(src, out / "a.csv")
    with pytest.raises(OutputError, match=r"'.*a\.csv' would overwrite the input '.*a\.csv'"):
        _write_set(out, {"a.csv": "result"}, inputs=[src])
    assert src.read_text() == "the input"
    # a file an earlier set wrote (and this one would remove) is protected too
    with pytest.raises(OutputError, match="would overwrite the input"):
        _write_set(out, {"b.csv": "result"}, inputs=[src])
    assert src.read_text() == "the input"


def test_folders_that_cannot_be_written_are_named_before_anything_happens(tmp_path, monkeypatch):
    f = tmp_path / "file"
    f.write_text("keep")
    with pytest.raises(OutputError, match="exists and is not a directory"):
        check_output(f)
    with pytest.raises(OutputError, match=r"cannot be created: '.*file' is not a directory"):
        check_output(f / "sub")
    real_access = os.access
    locked = tmp_path / "locked"
    locked.mkdir()
    monkeypatch.setattr(os, "access", lambda p, mode: Path(p) != locked and real_access(p, mode))
    with pytest.raises(OutputError, match=r"'.*locked' is not writable"):
        check_output(locked)
    with pytest.raises(OutputError, match=r"cannot be created: '.*locked' is not writable"):
        check_output(locked / "new" / "out")
    assert f.read_text() == "keep" and not (locked / "new").exists()
    (tmp_path / "out" / "a.csv").mkdir(parents=True)
    with pytest.raises(OutputError, match=r"output '.*a\.csv' is a directory, not a file"):
        check_output(tmp_path / "out", ["a.csv"])


def _dead_pid():
    p = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True)
    return int(p.stdout)


def test_a_second_run_into_the_same_folder_is_refused_and_a_stale_lock_taken_over(tmp_path):
    lock = tmp_path / ".out.contactres.lock"
    lock.write_text(f"{os.getpid()}\n{socket.gethostname()}\n")  # a live run: this process
    with pytest.raises(OutputError, match=rf"another contactres run \(process {os.getpid()} on"):
        _write_set(tmp_path / "out", {"a.csv": "x"})
    assert not (tmp_path / "out").exists() and lock.exists()
    lock.write_text(f"{_dead_pid()}\n{socket.gethostname()}\n")  # a killed run
    _write_set(tmp_path / "out", {"a.csv": "x"})
    assert _names(tmp_path) == ["out"]


def test_text_cells_a_spreadsheet_would_run_are_neutralised(tmp_path):
    """Issue 27 (CSV injection): labels starting with =, +, -, @ were written verbatim."""
    import pandas as pd

    from contactres.fileio import write_csv

    frame = pd.DataFrame(
        {"label": ["=1+1", "+x", "-y", "@SUM(A1)", "\tz", "plain", "a=b"], "value": [-1.5] * 7}
    )
    write_csv(tmp_path / "t.csv", frame)
    back = pd.read_csv(tmp_path / "t.csv", keep_default_na=False)
    assert back["label"].tolist() == ["'=1+1", "'+x", "'-y", "'@SUM(A1)", "'\tz", "plain", "a=b"]
    assert back["value"].tolist() == [-1.5] * 7  # numbers stay numbers
    assert frame["label"][0] == "=1+1"  # the caller's table is not changed


@pytest.mark.parametrize(
    "cells",
    [
        ["=a", "ok", None, float("nan"), 3, -2.5, "-b"],  # text among numbers and gaps
        [b"=bytes", "=text", "plain"],  # bytes: pandas' string methods refuse the column
        [1, 2, 3],  # an object column without any text
        # runs of one object (a curve table's sweep id on each of its rows), each tested once
        ["=a"] * 3 + ["ok"] * 2 + [None] * 2 + ["-b", "=a"] + [float("nan")] * 2 + ["@c"] * 4,
    ],
)
def test_neutralising_a_whole_column_follows_the_cell_rule(cells):
    """The column-at-once test of :func:`contactres.fileio.neutralised` (issue 31, point 5)
    gives what the rule says cell by cell: a string starting with = + - @, tab or CR gets an
    apostrophe; anything else (numbers, gaps, bytes) is left as it is."""
    import pandas as pd

    from contactres.fileio import neutralised

    frame = pd.DataFrame({"cell": pd.Series(cells, dtype=object)})
    expected = [
        "'" + v if isinstance(v, str) and v[:1] in ("=", "+", "-", "@", "\t", "\r") else v
        for v in cells
    ]
    got = neutralised(frame)["cell"].tolist()
    assert len(got) == len(expected)
    for g, e in zip(got, expected, strict=True):
        assert g is e or g == e or (g != g and e != e)


def test_floats_written_as_text_match_what_pandas_writes(tmp_path):
    """write_csv turns float64 columns into text before pandas writes them (issue 31, point 5:
    pandas 3 writes text ~5x faster than floats); the file is the one pandas writes itself."""
    import numpy as np
    import pandas as pd

    from contactres.fileio import write_csv

    rng = np.random.default_rng(7)
    bits = rng.integers(0, 2**63, 5000, dtype=np.uint64).view(np.float64)
    special = [np.nan, np.inf, -np.inf, -0.0, 0.0, 1e16, 1e15, 5e-324, 0.1, -2.5, 1e-5]
    values = np.concatenate([bits, special])
    frame = pd.DataFrame({"a": values, "b": values[::-1].copy(), "label": "x"})
    for kwargs in ({}, {"na_rep": "NA"}, {"index": True}):
        write_csv(tmp_path / "fast.csv", frame, **kwargs)
        frame.to_csv(tmp_path / "pandas.csv", **{"index": False, **kwargs})
        assert (tmp_path / "fast.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def test_a_signed_number_written_as_text_stays_a_number(tmp_path):
    """afm invert and rum invert write their computed columns as 10-digit text: a negative value
    ("-0.5") is a number to a spreadsheet and was written as "'-0.5", text that no longer sums."""
    import pandas as pd

    from contactres.fileio import write_csv

    cells = ["-0.5", "+1e-3", "-12.", "-.5E+2", "-inf", "-2+3", "-1-1", "-", "- 1", "+A1"]
    write_csv(tmp_path / "t.csv", pd.DataFrame({"x": cells}))
    back = pd.read_csv(tmp_path / "t.csv", dtype=str, keep_default_na=False)["x"].tolist()
    assert back == cells[:5] + ["'" + c for c in cells[5:]]


def _mixed_frame():
    """Columns of every kind the joined writer covers: floats (gaps, signs, extremes), integers,
    booleans, text with commas and quotes, object text with gaps, pandas' string dtype, and a
    header that needs quotes."""
    import numpy as np

    values = [0.1, np.nan, -0.0, 1e16, 5e-324, -np.inf, 123456789.123, 7.0]
    frame = pd.DataFrame(
        {
            "x": values,
            "n": np.arange(8, dtype=np.int64) - 3,
            "ok": [True, False] * 4,
            'a "quoted", name': ['he said "hi"', "a,b", "plain", "", "x", "y", "z", "w"],
            "gaps": pd.Series(["a", None, "b", np.nan, "c", "d", "e", "f"], dtype=object),
            "s": pd.Series(["u", "v", None, "w", "x", "y", "z", "q"], dtype="string"),
        }
    )
    frame.insert(1, "y", values[::-1])
    return frame


@pytest.mark.parametrize("na_rep", ["", "NA"])
def test_the_joined_csv_is_the_text_pandas_writes(tmp_path, monkeypatch, na_rep):
    """write_csv joins the text of a table with pandas' default options itself (issue 31,
    point 5): the bytes are those of pandas' own writer, and pandas' writer is not called."""
    frame = _mixed_frame()
    frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep=na_rep)

    def refuse(*args, **kwargs):
        raise AssertionError("pandas' writer was called")

    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_csv", refuse)
        write_csv(tmp_path / "joined.csv", frame, na_rep=na_rep)
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


@pytest.mark.parametrize(
    "frame",
    [
        pd.DataFrame({"a": [1.5], "b": ["line\nbreak"]}),  # a line break inside a cell
        pd.DataFrame({"a": [1.5, float("nan")]}),  # one column: pandas quotes an empty field
        pd.DataFrame({"a": [], "b": []}),  # no rows
        pd.DataFrame({"a": [1.5], "when": [pd.Timestamp("2026-01-01")]}),  # dates
        pd.DataFrame({"a": [1.5, 2.5], "mixed": pd.Series([1, "x"], dtype=object)}),
    ],
)
def test_tables_the_joined_writer_leaves_to_pandas_are_written_as_pandas_writes(tmp_path, frame):
    frame.to_csv(tmp_path / "pandas.csv", index=False)
    write_csv(tmp_path / "ours.csv", frame)
    assert (tmp_path / "ours.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def test_write_npz_keeps_doubles_and_text(tmp_path):
    """The archive holds every column under its name: floats bit for bit, integers, text
    (a gap as an empty string); numpy reads it without pickles."""
    import numpy as np

    from contactres.fileio import write_npz

    rng = np.random.default_rng(11)
    x = rng.integers(0, 2**63, 1000, dtype=np.uint64).view(np.float64)
    frame = pd.DataFrame(
        {"file": x, "allow_pickle": np.arange(1000), "t": ["a", None] * 500}
    )  # (numpy.savez's own keywords as column names)
    write_npz(tmp_path / "t.npz", frame)
    with np.load(tmp_path / "t.npz", allow_pickle=False) as archive:
        assert archive.files == ["file", "allow_pickle", "t"]
        assert archive["file"].view(np.uint64).tolist() == x.view(np.uint64).tolist()
        assert archive["allow_pickle"].tolist() == list(range(1000))
        assert archive["t"].tolist() == ["a", ""] * 500


@pytest.mark.parametrize("float_format", ["%.10g", "%.3e", "%.15g"])
def test_the_joined_csv_with_a_float_format_is_the_text_pandas_writes(
    tmp_path, monkeypatch, float_format
):
    """A float format (the reports' CSV_FLOAT_FORMAT) keeps the joined writer (issue 31, point
    3: pandas formats a float cell at ~2 µs): every double, gaps and signs included, is written
    as pandas' own writer writes it with that format."""
    import numpy as np

    from contactres.fileio import write_csv

    rng = np.random.default_rng(3)
    bits = rng.integers(0, 2**63, 3000, dtype=np.uint64).view(np.float64)
    special = [np.nan, np.inf, -np.inf, -0.0, 0.0, 1e16, 1e15, 5e-324, 0.1, -2.5, 1e-5]
    values = np.concatenate([bits, special, -bits[:50]])
    frame = pd.DataFrame({"a": values, "n": np.arange(values.size), "label": "x,y"})
    for na_rep in ("", "NA"):
        frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep=na_rep, float_format=float_format)
        with monkeypatch.context() as m:
            m.setattr(pd.DataFrame, "to_csv", lambda *a, **k: pytest.fail("pandas was called"))
            write_csv(tmp_path / "joined.csv", frame, na_rep=na_rep, float_format=float_format)
        assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


@pytest.mark.parametrize("float_format", [None, "%.10g", "%.3e"])
def test_a_column_of_few_values_is_written_as_pandas_writes_it(tmp_path, monkeypatch, float_format):
    """A float column that repeats a few values (a curve table's amplitude grid, a gap per
    sweep) has each value's text made once: the bytes are still pandas' own, -0.0 apart from
    0.0, gaps, infinities and a NaN of another bit pattern included."""
    import numpy as np

    from contactres.fileio import write_csv

    odd_nan = np.array([0x7FF8000000000001], dtype=np.uint64).view(np.float64)[0]
    few = np.array([-0.0, 0.0, np.nan, odd_nan, np.inf, -np.inf, 0.1, 1e-10, 3.3e-10, -2.5])
    rng = np.random.default_rng(5)
    values = few[rng.integers(0, few.size, 5000)]
    frame = pd.DataFrame({"grid": values, "other": rng.normal(size=values.size)})
    frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep="NA", float_format=float_format)
    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_csv", lambda *a, **k: pytest.fail("pandas was called"))
        write_csv(tmp_path / "joined.csv", frame, na_rep="NA", float_format=float_format)
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def test_a_table_is_joined_chunk_by_chunk_and_left_to_pandas_where_a_later_chunk_needs_it(
    tmp_path, monkeypatch
):
    """The joined writer holds the text of the rows of CHUNK_CELLS cells at a time (10^5
    sweeps' curve table held ~0.9 GB of text at once): lines across chunk boundaries are
    pandas' own; a chunk that it does not cover (here a mixed cell after the first chunk) hands
    the whole table to pandas, which writes the file anew."""
    import numpy as np

    from contactres import _csvcells
    from contactres.fileio import write_csv

    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 14)  # 7 rows of 2 cells
    n = 40
    frame = pd.DataFrame(
        {"x": np.linspace(-1.0, 1.0, n), "s": pd.Series([f"s{i}" for i in range(n)], dtype=object)}
    )
    assert len(list(_csvcells.csv_chunks(frame))) == 1 + 6  # the header, then 6 chunks
    frame.to_csv(tmp_path / "pandas.csv", index=False, float_format="%.10g")
    write_csv(tmp_path / "joined.csv", frame, float_format="%.10g")
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()
    frame.loc[30, "s"] = 5  # a number among text: pandas' writer, for the whole file
    frame.to_csv(tmp_path / "pandas.csv", index=False, float_format="%.10g")
    write_csv(tmp_path / "mixed.csv", frame, float_format="%.10g")
    assert (tmp_path / "mixed.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


@pytest.mark.parametrize("float_format", ["%.10g", "%.3e", "%+.4f", "%10.2g", "%#.5g", "%.3f mm"])
def test_doubles_formatted_a_chunk_at_a_time_are_pandas_text(tmp_path, monkeypatch, float_format):
    """A column of doubles without gaps is formatted by one ``%`` of a format made for the
    whole chunk (issue 31, point 3), or with "%.Ng" in numpy (``_lines_bytes``), a chunk at a
    time: flags, widths, signs, -0.0, a subnormal and extremes give the text of pandas' own
    writer, which formats cell by cell (a chunk with an infinity goes cell by cell too); beside
    a column with gaps and text that needs quotes. A format with more
    than one conversion's text ("%.3f mm") is applied cell by cell, as before. A column with
    gaps joins the chunk's ``%`` where its NaN formats as "nan" (then written as ``na_rep``)."""

    import numpy as np

    from contactres import _csvcells
    from contactres.fileio import write_csv

    rng = np.random.default_rng(17)
    bits = rng.integers(0, 2**63, 4000, dtype=np.uint64).view(np.float64)
    bits = bits[np.isfinite(bits)]
    # The finite specials open the first chunk, the infinities close the last one.
    special = [-0.0, 0.0, 5e-324, 1e16, 1e-5, -2.5, 1.7976931348623157e308]
    values = np.concatenate([special, bits, -bits[:100], rng.normal(size=500), [np.inf, -np.inf]])
    gaps = rng.normal(size=values.size)
    gaps[::7] = np.nan
    text = [f'a,"{i}"' if i % 3 == 0 else f"s{i}" for i in range(values.size)]
    frame = pd.DataFrame({"x": values, "gaps": gaps, "label": text})
    calls = []
    # "%.10g" is assembled in numpy (_lines_bytes), the other formats by Python's %.
    joiner = "_lines_bytes" if float_format == "%.10g" else "_formatted_lines"
    joined = getattr(_csvcells, joiner)
    monkeypatch.setattr(_csvcells, joiner, lambda *a: calls.append(1) or joined(*a))
    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 3 * 1000)  # several chunks
    frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep="NA", float_format=float_format)
    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_csv", lambda *a, **k: pytest.fail("pandas was called"))
        write_csv(tmp_path / "joined.csv", frame, na_rep="NA", float_format=float_format)
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()
    chunks = -(-values.size // 1000)
    # Every chunk by one % each, the first with the specials in it, the last with infinities.
    assert len(calls) == (0 if float_format == "%.3f mm" else chunks)


@pytest.mark.parametrize("float_format", ["%.10g", "%.14g"])
@pytest.mark.parametrize("na_rep", ["", "NA", "nan"])
def test_gaps_formatted_with_their_chunk_are_pandas_text(
    tmp_path, monkeypatch, na_rep, float_format
):
    """A column of doubles with gaps is formatted within its chunk's ``%`` and each "nan" then
    written as ``na_rep``; a chunk where a text cell holds "nan" (a label "banana", "nan"
    itself) writes its gaps cell by cell: the bytes are pandas' own either way. "%.10g" is
    assembled in numpy (``_lines_bytes``, its gaps as ``na_rep`` there), "%.14g" (past
    ``MAX_PRECISION``) by the chunk's ``%``, where the gaps and "nan" text meet."""
    import numpy as np

    from contactres import _csvcells
    from contactres.fileio import write_csv

    rng = np.random.default_rng(23)
    n = 3000
    x = rng.normal(size=n) * 10.0 ** rng.integers(-12, 12, n)
    x[rng.random(n) < 0.2] = np.nan
    x[5], x[7] = np.inf, -np.inf
    odd_nan = np.array([0xFFF8000000000001], dtype=np.uint64).view(np.float64)[0]  # -NaN
    x[11] = odd_nan
    labels = [f"s{i}" for i in range(n)]
    labels[2500], labels[2600] = "banana", "nan"  # in the third chunk only
    frame = pd.DataFrame({"x": x, "y": x[::-1].copy(), "label": labels})
    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 3 * 1000)
    frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep=na_rep, float_format=float_format)
    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_csv", lambda *a, **k: pytest.fail("pandas was called"))
        write_csv(tmp_path / "joined.csv", frame, na_rep=na_rep, float_format=float_format)
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


@pytest.mark.parametrize("float_format", ["%.10g", "%g", "%.3g"])
@pytest.mark.parametrize("na_rep", ["", "NA"])
def test_lines_assembled_in_numpy_are_the_text_pandas_writes(
    tmp_path, monkeypatch, float_format, na_rep
):
    """With a "%.Ng" format the lines are assembled as bytes in numpy (issue 31, point 3):
    each chunk's text is that of pandas' own writer for tables of every kind it covers
    (doubles of random bits and gaps, integers, booleans, text with quotes and commas, gaps,
    non-ASCII text, a sweep id repeated over its rows as one object, an all-gap column, a
    column of a few values), with "\\n" and "\\r\\n" line ends; a chunk with a NUL in a text
    cell is joined as text, with the same bytes."""
    import numpy as np

    from contactres import _csvcells
    from contactres.fileio import write_csv

    rng = np.random.default_rng(41)
    n = 2400
    bits = rng.integers(0, 2**64, n, dtype=np.uint64).view(np.float64)
    sweep_ids = [f"µ-sweep/{i // 30}" if i % 90 else f'id, "{i // 30}"' for i in range(0, n, 30)]
    ids = pd.Series(np.repeat(np.array(sweep_ids, dtype=object), 30), dtype=object)
    labels = [["plain", "a,b", 'say "x"', "é", "", None][i % 6] for i in range(n)]
    labels[2000] = "nul\0inside"  # in the last chunk only
    frame = pd.DataFrame(
        {
            "sweep": ids,
            "x": bits,
            "amp": np.tile(np.linspace(0.0, 1e-8, 30), n // 30),
            "n": rng.integers(-(2**62), 2**62, n),
            "ok": rng.random(n) < 0.5,
            "label": pd.Series(labels, dtype=object),
            "s": pd.Series(labels, dtype="str"),
            "gap": np.full(n, np.nan),
            "y": rng.normal(size=n) * 10.0 ** rng.integers(-8, 12, n),
        }
    )
    frame.loc[::7, "y"] = np.nan
    calls = []
    joined = _csvcells._lines_bytes
    monkeypatch.setattr(_csvcells, "_lines_bytes", lambda *a: calls.append(1) or joined(*a))
    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 9 * 500)  # 5 chunks of 500 rows
    for end in ("\n", "\r\n"):
        want = frame.to_csv(
            index=False, na_rep=na_rep, float_format=float_format, lineterminator=end
        )
        got = "".join(_csvcells.csv_chunks(frame, na_rep, end, float_format))
        assert got == want
    assert len(calls) == 2 * 5
    frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep=na_rep, float_format=float_format)
    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_csv", lambda *a, **k: pytest.fail("pandas was called"))
        write_csv(tmp_path / "joined.csv", frame, na_rep=na_rep, float_format=float_format)
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def test_the_mixed_table_with_a_g_format_is_the_text_pandas_writes(tmp_path):
    """The table of every column kind (_mixed_frame: a header that needs quotes, -0.0, a
    subnormal, -inf, gaps in object and string text) with the reports' format."""
    from contactres.fileio import CSV_FLOAT_FORMAT

    frame = _mixed_frame()
    for na_rep in ("", "NA", "nan"):
        frame.to_csv(tmp_path / "pandas.csv", index=False, na_rep=na_rep, float_format="%.10g")
        write_csv(tmp_path / "joined.csv", frame, na_rep=na_rep, float_format=CSV_FLOAT_FORMAT)
        assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def _spy_on_lines_bytes(monkeypatch) -> list:
    """The kinds of what ``_csvcells._lines_bytes`` returns, call by call, in a list filled as
    it is called ("bytearray": a chunk assembled in numpy; "NoneType": joined as text)."""
    from contactres import _csvcells

    kinds: list = []
    joined = _csvcells._lines_bytes
    monkeypatch.setattr(
        _csvcells,
        "_lines_bytes",
        lambda *a: kinds.append(type(lines := joined(*a)).__name__) or lines,
    )
    return kinds


def test_a_chunk_with_a_long_text_cell_is_joined_as_text(tmp_path, monkeypatch):
    """A text column's records are as wide as its longest text, and every line of the chunk
    as wide as its records: one 4 kB note would make each of the chunk's rows 4 kB in numpy.
    A chunk with a cell past 256 bytes is joined as text (its bytes still pandas' own); the
    chunks without it are assembled in numpy."""
    import numpy as np

    from contactres import _csvcells

    n = 1500
    notes = [f"n{i}" for i in range(n)]
    notes[700] = "long, " + "é" * 2000  # in the second chunk only; quoted, non-ASCII
    rng = np.random.default_rng(5)
    frame = pd.DataFrame({"x": rng.normal(size=n), "note": pd.Series(notes, dtype=object)})
    kinds = _spy_on_lines_bytes(monkeypatch)
    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 2 * 500)  # 3 chunks of 500 rows
    want = frame.to_csv(index=False, na_rep="NA", float_format="%.10g")
    assert "".join(_csvcells.csv_chunks(frame, "NA", "\n", "%.10g")) == want
    assert kinds == ["bytearray", "NoneType", "bytearray"]
    frame.to_csv(tmp_path / "pandas.csv", index=False, float_format="%.10g")
    write_csv(tmp_path / "joined.csv", frame, float_format="%.10g")
    assert (tmp_path / "joined.csv").read_bytes() == (tmp_path / "pandas.csv").read_bytes()


def test_a_lone_surrogate_in_text_is_kept_in_text_and_refused_in_a_file(tmp_path, monkeypatch):
    """A text cell holding a lone surrogate ("\\udcff": bytes of a file name decoded with
    surrogateescape) is in csv_chunks' text as pandas' to_csv() to a string keeps it, also
    where the chunk is assembled as bytes in numpy; written to a file it raises the
    UnicodeEncodeError pandas' writer raises (UTF-8 has no surrogates), at the same cell."""
    import numpy as np

    from contactres import _csvcells

    n = 900
    labels = [f"s{i}" for i in range(n)]
    labels[400], labels[401], labels[850] = "a\udcffb", "\ud83d\ude00", "µ\udc80"
    rng = np.random.default_rng(3)
    frame = pd.DataFrame({"x": rng.normal(size=n), "label": pd.Series(labels, dtype=object)})
    kinds = _spy_on_lines_bytes(monkeypatch)
    monkeypatch.setattr(_csvcells, "CHUNK_CELLS", 2 * 300)  # 3 chunks of 300 rows
    for float_format in ("%.10g", "%.14g", None):
        want = frame.to_csv(index=False, na_rep="NA", float_format=float_format)
        assert _csvcells.csv_text(frame, "NA", "\n", float_format) == want
    assert kinds == ["bytearray"] * 3  # "%.10g": in numpy
    with pytest.raises(UnicodeEncodeError) as pandas_error:
        frame.to_csv(tmp_path / "pandas.csv", index=False, float_format="%.10g")
    with pytest.raises(UnicodeEncodeError) as error:
        write_csv(tmp_path / "joined.csv", frame, float_format="%.10g")
    cause = ("surrogates not allowed", "\udcff")
    for e in (error.value, pandas_error.value):  # (the position: within each writer's chunk)
        assert (e.encoding, e.reason, e.object[e.start : e.end]) == ("utf-8", *cause)
    assert not (tmp_path / "joined.csv").exists()
