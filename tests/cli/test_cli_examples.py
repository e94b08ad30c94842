"""``contactres examples`` and :mod:`contactres.examples`: the installed example files, listed,
located and copied, and the commands listed for them run from a folder holding the copies."""

from __future__ import annotations

import shlex
import sys
from importlib.resources import files

import pytest
from cli_checks import LISTED_COMMANDS_RUN, one_line_error, run

from contactres.examples import EXAMPLES, copy_examples, example_path

DATA = files("contactres").joinpath("data")


def test_every_example_file_of_the_package_is_listed_and_found():
    shipped = sorted(p.name for p in DATA.iterdir() if p.name.startswith("example_"))
    assert sorted(EXAMPLES) == shipped
    for name in EXAMPLES:
        path = example_path(name)
        assert path.is_file() and path.read_bytes() == DATA.joinpath(name).read_bytes()
        assert name in EXAMPLES[name].command  # the command reads this very file


def test_copies_are_byte_identical_and_existing_files_are_kept(tmp_path):
    copied = copy_examples(tmp_path / "new", ["example_rum.csv", "example_afm.csv"])
    assert [p.name for p in copied] == ["example_rum.csv", "example_afm.csv"]
    for p in copied:
        assert p.read_bytes() == example_path(p.name).read_bytes()
    mine = tmp_path / "new" / "example_rum.csv"
    mine.write_text("my edits")
    with pytest.raises(ValueError, match=r"already holds example_rum\.csv; nothing copied"):
        copy_examples(tmp_path / "new", ["example_qcmd.csv", "example_rum.csv"])
    assert mine.read_text() == "my edits"  # nothing touched, nothing copied
    assert not (tmp_path / "new" / "example_qcmd.csv").exists()
    copy_examples(tmp_path / "new", "example_rum.csv", overwrite=True)  # one name as a string
    assert mine.read_bytes() == example_path("example_rum.csv").read_bytes()
    with pytest.raises(ValueError, match=r"no example named 'crystals\.csv'"):
        example_path("crystals.csv")  # library data, not an example


def test_listing_names_and_paths():
    r = run("examples")
    assert r.exit_code == 0, r.output
    for name, ex in EXAMPLES.items():
        assert name in r.output and f"$ {ex.command}" in r.output
    r = run("examples", "example_rum.csv", "example_afm.csv")
    assert r.exit_code == 0
    assert r.output.splitlines() == [
        str(example_path("example_rum.csv")),
        str(example_path("example_afm.csv")),
    ]


#: The packages of the optional extras (maps, afm, excel): blocked, the base install is left.
EXTRA_PACKAGES = ("xarray", "zarr", "dask", "distributed", "igor2", "h5py", "openpyxl")


def test_the_examples_that_need_an_extra_say_which():
    """issue 30: the listing marks the commands the base install cannot run."""
    assert {n: ex.extra for n, ex in EXAMPLES.items() if ex.extra} == {
        "example_dart.ibw": "afm,maps",  # igor2 reads .ibw, xarray holds the maps
        "example_cu_map.ang": "maps",  # the Zarr store
    }
    lines = [*run("examples").output.splitlines(), ""]
    for name, ex in EXAMPLES.items():
        after = lines[lines.index(f"  $ {ex.command}") + 1]
        marked = after == f"    (needs an optional extra: pip install 'contactres[{ex.extra}]')"
        assert marked == bool(ex.extra), (name, after)


@pytest.mark.parametrize("name", LISTED_COMMANDS_RUN)
def test_the_listed_command_runs_in_the_folder_of_the_copies(name, tmp_path, monkeypatch):
    """... and without any extra where none is marked."""
    assert not EXAMPLES[name].extra
    r = run("examples", "--copy", tmp_path, name)
    assert r.exit_code == 0, r.output
    assert f"copied 1 example file(s) into {tmp_path}" in r.output
    copy_examples(tmp_path, "example_cu_map.ang")  # the map that example_cu_kstar.csv is of
    for package in EXTRA_PACKAGES:
        monkeypatch.setitem(sys.modules, package, None)  # import it -> ImportError
    monkeypatch.chdir(tmp_path)
    words = shlex.split(EXAMPLES[name].command)
    assert words[0] == "contactres"
    r = run(*words[1:])
    assert r.exit_code == 0, r.output


def test_bad_input_is_one_line(tmp_path):
    one_line_error(run("examples", "nosuch.csv"), "no example named 'nosuch.csv'")
    one_line_error(run("examples", "--overwrite"), "--overwrite goes with --copy")
    one_line_error(run("examples", "--copy", ""), "--copy", "folder name")
    one_line_error(run("examples", "--format", "xml"), "--format")
    (tmp_path / "example_rum.csv").write_text("mine")
    one_line_error(
        run("examples", "--copy", tmp_path, "example_rum.csv"), "already holds example_rum.csv"
    )
    a_file = tmp_path / "file"
    a_file.write_text("x")
    one_line_error(run("examples", "--copy", a_file, "example_rum.csv"), str(a_file))
