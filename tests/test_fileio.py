"""Tests of contactres.fileio: atomic writes leave whole files, never partial ones."""

import os
import stat

import pandas as pd
import pytest
from matplotlib.figure import Figure

from contactres.fileio import ensure_dir, save_figure, write_csv, write_text


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
