"""The map jobs read EBSD exports and value grids through the one registry of reader recipes,
with the errors the direct readers give."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from contactres.errors import ContactresInputError
from contactres.jobs.maps import open_map
from contactres.jobs.readers import ALL_READERS, read_ebsd_file, read_grid_file, read_value_grid
from contactres.measurements.readers import Reader
from contactres.polycrystal._ebsd import read_ebsd

DATA = Path(__file__).resolve().parents[2] / "src" / "contactres" / "data"


def test_an_ebsd_export_is_read_as_the_ebsd_reader_reads_it():
    omap, ds = open_map(DATA / "example_cu_map.ang")
    direct = read_ebsd(DATA / "example_cu_map.ang")
    assert ds is None
    np.testing.assert_array_equal(omap.euler, direct.euler)
    assert (omap.step_x, omap.step_y) == (direct.step_x, direct.step_y)


def test_an_unknown_suffix_gives_the_ebsd_readers_message(tmp_path):
    scan = tmp_path / "scan.txt"
    scan.write_text("1,2\n")
    with pytest.raises(ContactresInputError) as direct:
        read_ebsd(scan)
    with pytest.raises(ContactresInputError) as through:
        open_map(scan)
    assert str(through.value) == str(direct.value)
    assert str(through.value) == (
        "scan.txt: unknown EBSD export '.txt' (expected .ang or .ctf or .h5oina)"
    )


def test_an_added_ebsd_recipe_is_used_and_the_registry_is_unchanged(tmp_path):
    scan = tmp_path / "scan.osc"
    scan.write_text("binary, say\n")
    seen = []
    osc = Reader(
        "osc", (".osc",), lambda path, head: True, lambda p: seen.append(p) or "map", "ebsd"
    )
    mine = ALL_READERS.with_reader(osc)
    assert read_ebsd_file(scan, mine) == "map" and seen == [scan]
    assert open_map(scan, mine) == ("map", None)
    assert ALL_READERS.for_suffix(scan, "ebsd") is None  # the shared registry has no osc
    assert mine.for_suffix(scan, "ebsd") is osc


def test_value_grids_of_any_suffix_are_read_by_the_grid_recipe(tmp_path):
    grid = np.array([[1.0, 2.0], [np.nan, 4.0]])
    np.savetxt(tmp_path / "k.csv", grid, delimiter=",")
    np.savetxt(tmp_path / "k.dat", grid)  # whitespace-separated, a suffix no recipe names
    np.save(tmp_path / "k.npy", grid)
    for name in ("k.csv", "k.dat", "k.npy"):
        np.testing.assert_array_equal(read_grid_file(tmp_path / name), grid)
    bad = tmp_path / "bad.txt"
    bad.write_text("1,2\n3,x\n")
    with pytest.raises(ContactresInputError) as direct:
        read_value_grid(bad)
    with pytest.raises(ContactresInputError) as through:
        read_grid_file(bad)
    assert (
        str(through.value) == str(direct.value) == "bad.txt: row 2, column 2: 'x' is not a number"
    )
