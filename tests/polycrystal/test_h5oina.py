"""Oxford .h5oina files: fixtures written with h5py in the layout of the public specification
(github.com/oinanoanalysis/h5oina, H5OINAFile.md) are read back as the truth they were made of.

orix 0.15 has no .h5oina reader (its HDF5 readers are orix's own, EMsoft's and Bruker's), so the
truth here is the fixture's own arrays: Euler angles in radians (float32, as the format stores
them), phase 0 = not indexed, MAD in radians, X/Y in µm, NaN outside an irregular area.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres.errors import ContactresInputError
from contactres.jobs.maps import open_map
from contactres.jobs.readers import ALL_READERS
from contactres.polycrystal import indexed_pixels, read_ebsd, read_h5oina

h5py = pytest.importorskip("h5py", reason="h5py (the `afm` extra) writes the fixtures")

H, W, STEP_X, STEP_Y = 4, 5, 0.25, 0.5  # pixels, µm


def _truth(seed: int = 1):
    rng = np.random.default_rng(seed)
    euler = rng.uniform([0, 0, 0], [2 * np.pi, np.pi, 2 * np.pi], (H * W, 3)).astype(np.float32)
    phase = np.ones(H * W, dtype=np.uint8)
    phase[[3, 11]] = 0
    mad = np.radians(rng.uniform(0.2, 1.8, H * W)).astype(np.float32)
    return euler, phase, mad


def _write(path, euler, phase, mad=None, *, positions=True, order=None, columns=False):
    """``columns``: the (size, 1) and (1, 1) shapes the specification's tables give."""
    order = np.arange(H * W) if order is None else order
    i, j = np.divmod(np.arange(H * W), W)
    shape = (lambda a: np.asarray(a).reshape(-1, 1)) if columns else np.asarray
    with h5py.File(path, "w") as f:
        f["Format Version"] = "5.0"
        f["Manufacturer"] = "Oxford Instruments"
        data = f.create_group("1/EBSD/Data")
        data["Euler"] = euler[order]
        data["Phase"] = shape(phase[order])
        if positions:
            data["X"] = shape((j * STEP_X).astype(np.float32)[order])
            data["Y"] = shape((i * STEP_Y).astype(np.float32)[order])
        if mad is not None:
            data["Mean Angular Deviation"] = shape(mad[order])
        head = f.create_group("1/EBSD/Header")
        head["X Cells"], head["Y Cells"] = shape(np.int32(W)), shape(np.int32(H))
        head["X Step"], head["Y Step"] = shape(np.float32(STEP_X)), shape(np.float32(STEP_Y))
        ni = head.create_group("Phases/1")
        ni["Phase Name"] = "Nickel"
        ni["Lattice Dimensions"] = np.array([3.524, 3.524, 3.524], dtype=np.float32)
        ni["Lattice Angles"] = np.full(3, np.pi / 2, dtype=np.float32)
        ni["Laue Group"], ni["Space Group"] = np.int32(11), np.int32(225)
    return path


@pytest.mark.parametrize("columns", [False, True])
def test_a_written_fixture_is_read_as_its_truth(tmp_path, columns):
    euler, phase, mad = _truth()
    m = read_h5oina(_write(tmp_path / "map.h5oina", euler, phase, mad, columns=columns))
    assert m.shape == (H, W) and m.source == "map.h5oina"
    assert (m.step_x, m.step_y) == pytest.approx((0.25e-6, 0.5e-6), rel=1e-7)  # float32 steps
    assert np.array_equal(m.euler.reshape(-1, 3), euler.astype(float))  # radians, as stored
    assert np.array_equal(m.phase.ravel(), phase)
    assert m.confidence_name == "MAD (degrees)"
    assert np.allclose(m.confidence.ravel(), np.degrees(mad.astype(float)), rtol=1e-12, atol=0)
    used = indexed_pixels(m, max_mad=1.0)
    assert used.not_indexed == 2
    expected = (phase != 0) & (np.degrees(mad.astype(float)) <= 1.0)
    assert np.array_equal(used.mask.ravel(), expected)


def test_rows_placed_by_position_or_row_by_row(tmp_path):
    euler, phase, mad = _truth(2)
    shuffled = np.random.default_rng(0).permutation(H * W)
    a = read_h5oina(_write(tmp_path / "a.h5oina", euler, phase, mad, order=shuffled))
    b = read_h5oina(_write(tmp_path / "b.h5oina", euler, phase, positions=False))
    assert np.array_equal(a.euler, b.euler) and np.array_equal(a.phase, b.phase)
    assert np.all(b.confidence == 0.0)  # no MAD in the file: none made up


def test_nan_outside_an_irregular_area_is_not_indexed(tmp_path):
    euler, phase, mad = _truth(3)
    euler[7] = np.nan
    m = read_h5oina(_write(tmp_path / "irregular.h5oina", euler, phase, mad))
    assert m.phase.ravel()[7] == 0 and np.all(m.euler.reshape(-1, 3)[7] == 0.0)
    assert indexed_pixels(m).not_indexed == 3


def test_the_registry_and_read_ebsd_know_the_format(tmp_path):
    path = _write(tmp_path / "m.h5oina", *_truth())
    assert ALL_READERS.pick(path, "ebsd").name == "h5oina"
    assert np.array_equal(read_ebsd(path).euler, read_h5oina(path).euler)
    omap, store = open_map(path)  # what maps predict and maps fit open
    assert store is None and np.array_equal(omap.euler, read_h5oina(path).euler)


def test_bad_files_are_input_errors(tmp_path):
    text = tmp_path / "text.h5oina"
    text.write_text("not HDF5")
    with pytest.raises(ContactresInputError, match="not an HDF5 file"):
        read_h5oina(text)
    other = tmp_path / "other.h5oina"
    with h5py.File(other, "w") as f:
        f["x"] = 1
    with pytest.raises(ContactresInputError, match="no group /1/EBSD/Data"):
        read_h5oina(other)
    euler, phase, mad = _truth()
    short = _write(tmp_path / "short.h5oina", euler, phase, mad)
    with h5py.File(short, "a") as f:
        del f["1/EBSD/Data/Phase"]
        f["1/EBSD/Data/Phase"] = phase[:-1]
    with pytest.raises(ContactresInputError, match=r"Phase holds 19 rows.*4 x 5 = 20"):
        read_h5oina(short)
