"""A rerun replaces only what contactres can show it wrote (issue 27, point 1): a file of a
result set's names that no manifest of contactres vouches for, and a Zarr store that contactres
did not write or that holds files added since, are refused in one line and left byte for byte
as they were (contactres.fileio.ResultSet, contactres.polycrystal.write_map)."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from contactres._ownership import STORE_MARKER, refusal, unvouched
from contactres.fileio import OutputError, ResultSet

OWNED = ["a.csv", "b.csv", "c.png"]


def _tree(folder: Path) -> dict:
    """Every file and folder under ``folder`` with the SHA-256 of each file's bytes."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        if p.is_file()
        else ""
        for p in sorted(folder.rglob("*"))
    }


def _write_set(folder, contents):
    with ResultSet(folder, names=list(contents), owned=OWNED, kind="test") as rs:
        for name, text in contents.items():
            rs.path(name).write_text(text)


def test_a_file_no_manifest_vouches_for_is_never_overwritten(tmp_path):
    """Issue 27: qcm stiffness overwrote a stiffness.csv of the user's in a folder without a
    manifest. Refused on entering (before any work), naming the file; nothing changes."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.csv").write_text("the user's table")
    before = _tree(tmp_path)
    with pytest.raises(OutputError, match=r"'a\.csv'|\(a\.csv\)") as info:
        with ResultSet(out, names=["a.csv", "b.csv"], owned=OWNED, kind="test"):
            pytest.fail("the work started")
    assert "contactres did not write" in str(info.value) and "\n" not in str(info.value)
    assert _tree(tmp_path) == before  # no manifest, no lock, no staging folder left


def test_a_results_file_edited_since_is_not_overwritten_but_the_others_are(tmp_path):
    out = tmp_path / "out"
    _write_set(out, {"a.csv": "old", "b.csv": "old"})
    (out / "a.csv").write_text("edited by hand")
    before = _tree(tmp_path)
    with pytest.raises(OutputError, match=r"\(a\.csv\)"):
        _write_set(out, {"a.csv": "new", "b.csv": "new"})
    assert _tree(tmp_path) == before
    _write_set(out, {"b.csv": "new"})  # a set that does not write a.csv: a.csv stays
    assert (out / "a.csv").read_text() == "edited by hand" and (out / "b.csv").read_text() == "new"


def test_a_file_put_there_during_the_work_is_refused_at_the_commit(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(OutputError, match=r"\(b\.csv\)"):
        with ResultSet(out, names=["a.csv", "b.csv"], owned=OWNED, kind="test") as rs:
            rs.path("a.csv").write_text("new")
            rs.path("b.csv").write_text("new")
            (out / "b.csv").write_text("written meanwhile by someone else")
    assert sorted(p.name for p in out.iterdir()) == ["b.csv"]
    assert (out / "b.csv").read_text() == "written meanwhile by someone else"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_check_makes_the_checks_of_entering_and_writes_nothing(tmp_path):
    ResultSet(tmp_path / "new" / "deeper", names=["a.csv"], owned=OWNED).check()
    assert list(tmp_path.iterdir()) == []  # no folder made, no lock left
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.csv").write_text("mine")
    with pytest.raises(OutputError, match="did not write"):
        ResultSet(out, names=["a.csv"], owned=OWNED).check()
    assert _tree(tmp_path) == {"out": "", "out/a.csv": hashlib.sha256(b"mine").hexdigest()}


def test_the_refusal_is_one_line_naming_the_first_files():
    line = refusal("output folder", "F", ["a", "b", "c", "d"])
    assert line == (
        "output folder 'F' holds files contactres did not write (a, b, c, …); "
        "choose another path (nothing was changed)"
    )
    assert "…" not in refusal("output store", "S.zarr", ["notes.txt"])


def test_unvouched_names_what_exists_without_a_record(tmp_path):
    (tmp_path / "a").write_text("x")
    (tmp_path / "d").mkdir()
    os.symlink(tmp_path / "missing", tmp_path / "link")  # a broken link exists too
    assert unvouched(tmp_path, ["a", "b", "d", "link"], vouched=["a"]) == ["d", "link"]


# ------------------------------------------------------------------------------- map stores


@pytest.fixture
def maps():
    pytest.importorskip("zarr", reason="the maps extra (xarray, zarr) is not installed")
    from contactres import polycrystal

    return polycrystal


def _small(maps, seed=1):
    return maps.synthetic_polycrystal((6, 5), n_grains=2, seed=seed)


def test_a_store_is_signed_with_the_digest_of_its_keys(maps, tmp_path):
    """The marker holds the SHA-256 of the store's keys (files and folders by their path inside
    it, sorted; folders end in '/'), recomputed here by another walk; a read map does not carry
    it on."""
    store = maps.write_map(tmp_path / "m.zarr", _small(maps))
    keys = sorted(
        p.relative_to(store).as_posix() + ("/" if p.is_dir() else "") for p in store.rglob("*")
    )
    root = json.loads((store / "zarr.json").read_text())["attributes"][STORE_MARKER]
    record = json.loads(root)
    assert record["generator"] == "contactres" and record["keys"] == len(keys)
    assert record["keys_sha256"] == hashlib.sha256("\n".join(keys).encode()).hexdigest()
    assert STORE_MARKER not in maps.read_map(store).attrs


@pytest.mark.parametrize("added", ["notes.txt", "euler/notes.txt", "mine/zarr.json"])
def test_a_store_holding_a_file_contactres_did_not_write_is_not_replaced(maps, tmp_path, added):
    store = maps.write_map(tmp_path / "m.zarr", _small(maps))
    (store / added).parent.mkdir(exist_ok=True)
    (store / added).write_text("{}")
    before = _tree(tmp_path)
    name = added.rsplit("/zarr.json", 1)[0]  # a group is named, not its metadata
    for attempt in (
        lambda: maps.check_map_output(store),
        lambda: maps.write_map(store, _small(maps, 2)),
    ):
        with pytest.raises(OutputError) as info:
            attempt()
        assert f"({name})" in str(info.value) and "nothing was changed" in str(info.value)
        assert _tree(tmp_path) == before  # byte for byte, and nothing left beside


def test_a_store_another_program_wrote_is_not_replaced(maps, tmp_path):
    xr = pytest.importorskip("xarray")
    store = tmp_path / "theirs.zarr"
    xr.Dataset({"t": ("x", np.arange(3.0))}).to_zarr(store, consolidated=False)
    before = _tree(tmp_path)
    with pytest.raises(OutputError, match=r"contactres did not write \(t, zarr\.json\)"):
        maps.write_map(store, _small(maps))
    with pytest.raises(OutputError, match="did not write"):
        maps.check_map_output(store)
    assert _tree(tmp_path) == before


def test_a_store_of_contactres_is_replaced_and_a_copy_of_it_too(maps, tmp_path):
    first = maps.write_map(tmp_path / "m.zarr", _small(maps))
    copy = tmp_path / "copy.zarr"
    shutil.copytree(first, copy)  # the marker names the keys, not the folder
    other = _small(maps, seed=2)
    for store in (first, copy):
        maps.check_map_output(store)
        maps.write_map(store, other)
        assert np.array_equal(maps.map_from_dataset(maps.read_map(store)).euler, other.euler)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["copy.zarr", "m.zarr"]
