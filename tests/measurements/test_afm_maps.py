"""Frequency and Q maps from instrument files: BGlib SHO fits (HDF5), NetCDF/Zarr grids, the
frequency layer of a DART image, the frequency check, and their recipes in the registry.

The BGlib files are built here with h5py in the layout BGlib's band-excitation fitter writes
(pycroscopy/BGlib, ``BGlib/be/analysis/be_sho_fitter.py``: the compound dtype ``sho32`` of
``Amplitude [V]``, ``Frequency [Hz]``, ``Quality Factor``, ``Phase [rad]``, ``R2 Criterion``;
datasets ``Guess`` and ``Fit`` of shape (positions, steps) in a group
``Raw_Data-SHO_Fit_000`` beside ``Raw_Data``; and ``BGlib/be/translators/be_odf.py``: position
dimensions ``X`` then ``Y`` (X varies fastest), in ``Position_Indices``/``Position_Values`` of
the channel group, linked to the main datasets by object-reference attributes; the scan size
as ``grid_scan_width_[m]``/``grid_scan_height_[m]`` attributes of the measurement group).
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from afm_file_fixtures import DRIVE_FREQUENCY, write_dart_ibw

import contactres as cr
from contactres.errors import ContactresInputError
from contactres.jobs.readers import ALL_READERS, read_afm_map_file
from contactres.measurements import (
    ResonanceMaps,
    check_frequency_map,
    dart_frequency_Hz,
    read_be_sho,
    read_resonance_grid,
)

h5py = pytest.importorskip("h5py", reason="h5py (the extra 'afm') reads BGlib files")

SHO_NAMES = ["Amplitude [V]", "Frequency [Hz]", "Quality Factor", "Phase [rad]", "R2 Criterion"]
SHO32 = np.dtype({"names": SHO_NAMES, "formats": [np.float32] * 5})


def _truth(rows, cols, steps=1):
    """Per pixel and step: f, Q, A, phase, r2 (distinct values, so a misplaced pixel shows)."""
    i, j, s = np.meshgrid(np.arange(rows), np.arange(cols), np.arange(steps), indexing="ij")
    return {
        "Frequency [Hz]": 3.1e5 + 37.0 * i + 5.0 * j + 1000.0 * s,
        "Quality Factor": 40.0 + i + 0.25 * j + s,
        "Amplitude [V]": 1e-3 * (1 + i + j),
        "Phase [rad]": 0.01 * (i - j),
        "R2 Criterion": 0.9 + 0.0001 * (i + j),
    }


def write_bglib(path, rows=5, cols=7, steps=1, *, guess_only=False, labels=(b"X", b"Y")):
    """A BE-line file in BGlib's layout; returns the truth, (rows, cols, steps) per field."""
    truth = _truth(rows, cols, steps)
    with h5py.File(path, "w") as f:
        meas = f.create_group("Measurement_000")
        meas.attrs["grid_scan_width_[m]"] = 2e-6
        meas.attrs["grid_scan_height_[m]"] = 1e-6
        meas.attrs["grid_num_cols"] = cols
        meas.attrs["grid_num_rows"] = rows
        chan = meas.create_group("Channel_000")
        # Positions: X varies fastest (BGlib's Dimension('X', ...), Dimension('Y', ...)).
        yy, xx = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
        inds = np.stack([xx.ravel(), yy.ravel()], axis=1).astype(np.uint32)
        pos_inds = chan.create_dataset("Position_Indices", data=inds)
        pos_vals = chan.create_dataset("Position_Values", data=inds.astype(np.float32))
        for d in (pos_inds, pos_vals):
            d.attrs["labels"] = np.array(labels)
            d.attrs["units"] = np.array([b"m", b"m"])
        raw = chan.create_dataset("Raw_Data", data=np.zeros((rows * cols, 4), np.complex64))
        raw.attrs["Position_Indices"] = pos_inds.ref
        sho = chan.create_group("Raw_Data-SHO_Fit_000")
        table = np.zeros((rows * cols, steps), SHO32)
        for name in SHO_NAMES:
            table[name] = truth[name].reshape(rows * cols, steps)
        names = ("Guess",) if guess_only else ("Guess", "Fit")
        for name in names:
            # The guess differs from the fit, so a test sees which one was read.
            data = table.copy()
            if name == "Guess":
                data["Frequency [Hz]"] += 500.0
            d = sho.create_dataset(name, data=data)
            d.attrs["Position_Indices"] = pos_inds.ref
            d.attrs["Position_Values"] = pos_vals.ref
    return truth


def test_be_sho_maps_on_the_grid(tmp_path):
    path = tmp_path / "be_line.h5"
    truth = write_bglib(path, rows=5, cols=7)
    maps = read_be_sho(path)
    assert isinstance(maps, ResonanceMaps)
    assert maps.frequency_Hz.shape == (5, 7)
    for name, attribute in (
        ("Frequency [Hz]", "frequency_Hz"),
        ("Quality Factor", "q_factor"),
        ("Amplitude [V]", "amplitude"),
        ("Phase [rad]", "phase_rad"),
        ("R2 Criterion", "r2"),
    ):
        expected = truth[name][..., 0].astype(np.float32).astype(float)
        np.testing.assert_array_equal(getattr(maps, attribute), expected)
    assert maps.pixel_size == pytest.approx((2e-6 / 7, 1e-6 / 5), rel=1e-7)
    assert maps.source == f"{path}:/Measurement_000/Channel_000/Raw_Data-SHO_Fit_000/Fit"


def test_be_sho_guess_when_there_is_no_fit_and_a_step(tmp_path):
    path = tmp_path / "beps.h5"
    truth = write_bglib(path, rows=3, cols=4, steps=3, guess_only=True)
    maps = read_be_sho(path, step=2)
    expected = (truth["Frequency [Hz]"][..., 2] + 500.0).astype(np.float32)
    np.testing.assert_array_equal(maps.frequency_Hz, expected)
    assert maps.source.endswith("/Guess")
    assert maps.steps == 3
    with pytest.raises(ContactresInputError, match="step 3 is out of range"):
        read_be_sho(path, step=3)


def test_be_sho_positions_by_label(tmp_path):
    # Columns labelled Y then X: the reader follows the labels, not the column order.
    path = tmp_path / "swapped.h5"
    rows, cols = 3, 4
    truth = write_bglib(path, rows=rows, cols=cols)
    with h5py.File(path, "r+") as f:
        inds = f["Measurement_000/Channel_000/Position_Indices"]
        inds[...] = inds[()][:, ::-1]
        inds.attrs["labels"] = np.array([b"Y", b"X"])
    maps = read_be_sho(path)
    np.testing.assert_array_equal(
        maps.frequency_Hz, truth["Frequency [Hz]"][..., 0].astype(np.float32)
    )


def test_be_sho_bad_files(tmp_path):
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w") as f:
        f.create_dataset("x", data=np.zeros(3))
    with pytest.raises(ContactresInputError, match="no SHO fit in the file"):
        read_be_sho(empty)
    text = tmp_path / "text.h5"
    text.write_text("not hdf5\n")
    with pytest.raises(ContactresInputError, match="not an HDF5 file"):
        read_be_sho(text)


def _grid_dataset(rows=4, cols=5, *, q_name="q_factor", f_units="Hz"):
    xr = pytest.importorskip("xarray", reason="xarray (the extra 'maps') reads grids")
    y = np.arange(rows) * 20e-9
    x = np.arange(cols) * 10e-9
    f = 3e5 + np.arange(rows * cols, dtype=float).reshape(rows, cols)
    q = 50.0 + np.arange(rows * cols, dtype=float).reshape(rows, cols)
    ds = xr.Dataset(
        {
            "frequency_Hz": (("y", "x"), f, {"units": f_units}),
            q_name: (("y", "x"), q),
        },
        coords={"y": ("y", y, {"units": "m"}), "x": ("x", x, {"units": "m"})},
    )
    return ds, f, q


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_resonance_grid_netcdf_and_zarr(tmp_path, suffix):
    ds, f, q = _grid_dataset()
    path = tmp_path / f"grid{suffix}"
    if suffix == ".nc":
        ds.to_netcdf(path)
    else:
        pytest.importorskip("zarr", reason="zarr (the extra 'maps') writes Zarr stores")
        ds.to_zarr(path, consolidated=False)
    maps = read_resonance_grid(path)
    np.testing.assert_array_equal(maps.frequency_Hz, f)
    np.testing.assert_array_equal(maps.q_factor, q)
    assert maps.pixel_size == pytest.approx((10e-9, 20e-9), rel=1e-12)
    assert maps.amplitude is None


def test_resonance_grid_transposed_and_q(tmp_path):
    ds, f, q = _grid_dataset(q_name="Q")
    path = tmp_path / "xy.nc"
    ds.transpose("x", "y").to_netcdf(path)
    maps = read_resonance_grid(path)
    np.testing.assert_array_equal(maps.frequency_Hz, f)
    np.testing.assert_array_equal(maps.q_factor, q)


def test_resonance_grid_rules(tmp_path):
    ds, _, _ = _grid_dataset(f_units="kHz")
    path = tmp_path / "khz.nc"
    ds.to_netcdf(path)
    with pytest.raises(ContactresInputError, match="units 'kHz'; it must be in Hz"):
        read_resonance_grid(path)
    ds, _, _ = _grid_dataset()
    path = tmp_path / "no_q.nc"
    ds.drop_vars("q_factor").to_netcdf(path)
    with pytest.raises(ContactresInputError, match=r"no variable q_factor \(or Q\)"):
        read_resonance_grid(path)


def test_check_frequency_map():
    checked = check_frequency_map([[3e5, 0.0], [np.nan, 3.1e5]], "map.ibw")
    assert np.isnan(checked[0, 1]) and np.isnan(checked[1, 0]) and checked[1, 1] == 3.1e5
    assert not checked.flags.writeable
    with pytest.raises(ContactresInputError) as info:
        check_frequency_map(np.zeros((3, 3)), "map.ibw (layer FrequencyRetrace)")
    assert str(info.value).startswith("map.ibw (layer FrequencyRetrace): no frequency measured")
    with pytest.raises(ContactresInputError, match="negative frequency -120 Hz at row 0"):
        check_frequency_map([[-120.0, 3e5]], "offsets")
    with pytest.raises(ContactresInputError, match="must be 2-D"):
        check_frequency_map([3e5, 3e5], "line")


def test_dart_frequency_adds_the_drive_frequency(tmp_path):
    pytest.importorskip("igor2", reason="igor2 (the extra 'afm') reads .ibw files")
    path = tmp_path / "dart.ibw"
    written, truth = write_dart_ibw(path, 6, 4)
    frequency = dart_frequency_Hz(cr.read_ibw(path))
    assert frequency.shape == (4, 6)  # (y, x): Igor's first index runs along x
    np.testing.assert_allclose(
        frequency, (written[..., 5].astype(float) + DRIVE_FREQUENCY).T, rtol=0, atol=0
    )
    np.testing.assert_allclose(frequency, truth["centre"].T, rtol=0, atol=0.02)


def test_dart_frequency_map_of_zeros(tmp_path):
    igorwriter = pytest.importorskip("igorwriter", reason="igorwriter writes the fixtures")
    pytest.importorskip("igor2", reason="igor2 (the extra 'afm') reads .ibw files")
    path = tmp_path / "off.ibw"
    wave = igorwriter.IgorWave5(np.zeros((4, 3, 2), np.float32), name="img", unicode=False)
    wave.set_dimlabel(2, 0, "HeightRetrace")
    wave.set_dimlabel(2, 1, "FrequencyRetrace")
    wave.set_note("DriveFrequency: 301250\r")
    wave.save(str(path))
    with pytest.raises(ContactresInputError) as info:
        dart_frequency_Hz(cr.read_ibw(path))
    assert str(info.value).startswith(f"{path} (layer FrequencyRetrace): no frequency measured")


def test_recipes_of_kind_afm_map(tmp_path):
    pytest.importorskip("igor2", reason="igor2 (the extra 'afm') reads .ibw files")
    xr = pytest.importorskip("xarray", reason="xarray (the extra 'maps') reads grids")
    ibw, h5, nc = tmp_path / "a.ibw", tmp_path / "b.h5", tmp_path / "c.nc"
    write_dart_ibw(ibw, 4, 4)
    write_bglib(h5)
    _grid_dataset()[0].to_netcdf(nc)
    assert [r.name for r in ALL_READERS.of_kind("afm_map")] == ["ibw", "be-sho", "grid"]
    for path, name in ((ibw, "ibw"), (h5, "be-sho"), (nc, "grid")):
        assert ALL_READERS.pick(path, "afm_map").name == name
        # Renamed, each file is still recognised by its first bytes.
        renamed = tmp_path / f"renamed_{name}.dat"
        renamed.write_bytes(path.read_bytes())
        assert ALL_READERS.pick(renamed, "afm_map").name == name
    assert isinstance(ALL_READERS.pick(h5, "afm_map").load(h5), ResonanceMaps)
    assert isinstance(read_afm_map_file(ibw), cr.measurements.IgorWave)
    assert read_afm_map_file(nc).frequency_Hz.shape == (4, 5)
    del xr


def test_read_afm_map_file_bad_files(tmp_path):
    text = tmp_path / "scan.ibw"
    text.write_text("x,y\n1,2\n")
    with pytest.raises(ContactresInputError) as info:
        read_afm_map_file(text)
    message = str(info.value)
    assert message.startswith(f"{text}: not a contact-resonance map file contactres reads")
    assert "ibw (.ibw), be-sho (.h5/.hdf5), grid (.nc/.zarr)" in message
    empty = tmp_path / "empty.h5"
    empty.write_bytes(b"")
    with pytest.raises(ContactresInputError, match="the file is empty"):
        read_afm_map_file(empty)
    with pytest.raises(ContactresInputError, match="no such file"):
        read_afm_map_file(tmp_path / "absent.ibw")


def test_without_h5py_one_line_names_the_extra(tmp_path, monkeypatch):
    from contactres.errors import MissingExtraError

    path = tmp_path / "be.h5"
    write_bglib(path)
    monkeypatch.setitem(sys.modules, "h5py", None)  # as if not installed
    with pytest.raises(MissingExtraError) as info:
        read_be_sho(path)
    assert str(info.value) == (
        "reading band-excitation .h5 files needs h5py: pip install 'contactres[afm]'"
    )
