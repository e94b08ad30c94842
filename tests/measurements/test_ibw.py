"""Igor binary waves: the real Asylum files of ../shared and DART images written at test time.

The checks are independent of the reader: the note's values are those read by eye from the
files' bytes (``SpringConstant: 1.1841`` ...), the data are compared with the data block decoded
here with :mod:`struct` (PTN003's layout: a 64-byte binary header, a 320-byte wave header,
then the values in column-major order), and the DART fixture's layers with the arrays that
were written.
"""

from __future__ import annotations

import math
import struct
import sys

import numpy as np
import pytest
from afm_file_fixtures import (
    DART_LABELS,
    DRIVE_FREQUENCY,
    INVOLS,
    SCAN_SIZE,
    SPRING_CONSTANT,
    asylum_files,
    write_dart_ibw,
)

import contactres as cr
from contactres.errors import ContactresInputError
from contactres.measurements import IgorWave, parse_note

pytest.importorskip("igor2", reason="igor2 (the extra 'afm') reads .ibw files")

# Read by eye from the two files' notes (the bytes between carriage returns).
REAL_NOTES = {
    "fmt-igor-fd_SiN_FD_plot.ibw": {
        "SpringConstant": 1.1841,
        "InvOLS": 4.499e-08,
        "DriveFrequency": 23251.0,
        "MicroscopeModel": "MFP3D",
        "Version": "16.11.212",
        "DARTIGain": 5.5,
        "StartHeadTemp": "29.5625 \u00b0C",
        "ForceNote": "",
    },
    "fmt-igor-fd_U3_3_p10004.ibw": {
        "SpringConstant": 0.31451,
        "InvOLS": 2.0364e-07,
        "DriveFrequency": 75000.0,
        "MicroscopeModel": "MFP3D",
        "Version": "15.00.78",
        "DARTIGain": 5.5,
        "StartHeadTemp": "27.5 \u00b0C",
        "ForceNote": "",
    },
}
# The wave names in the files' headers.
WAVE_NAMES = {
    "fmt-igor-fd_SiN_FD_plot.ibw": "SiN_1240325",
    "fmt-igor-fd_U3_3_p10004.ibw": "U3_3_p10004",
}


def _data_block(raw: bytes) -> np.ndarray:
    """The values of a version-5 float32 wave decoded with struct alone (little-endian)."""
    version, _, wfm_size = struct.unpack_from("<hhi", raw, 0)
    assert version == 5
    n_dim = struct.unpack_from("<4i", raw, 64 + 68)  # nDim sits 68 bytes into WaveHeader5
    shape = tuple(n for n in n_dim if n)
    count = math.prod(shape)
    assert wfm_size == 320 + 4 * count  # a float32 wave
    values = struct.unpack_from(f"<{count}f", raw, 64 + 320)
    return np.array(values).reshape(shape, order="F")


@pytest.mark.parametrize("name", sorted(REAL_NOTES))
def test_real_asylum_notes(name):
    path = next((p for p in asylum_files() if p.name == name), None)
    if path is None:
        pytest.skip(f"{name} is not in ../shared")
    wave = cr.read_ibw(path)
    for key, value in REAL_NOTES[name].items():
        assert wave.note[key] == value, key
    # Hundreds of lines, as the README of the fixtures says, and the repeated keys keep the
    # last value (a folder, after a number).
    assert len(wave.note) > 500
    assert wave.note["SaveForce"].startswith("C:Users:")
    assert math.isnan(wave.note["OldScanSize"]) or wave.note["OldScanSize"] > 0
    assert wave.labels == ("Raw", "Defl", "ZSnsr")
    assert wave.scale is None  # a force record: no pixels
    assert wave.name == WAVE_NAMES[name]


@pytest.mark.parametrize("name", sorted(REAL_NOTES))
def test_real_asylum_data_match_the_bytes(name):
    path = next((p for p in asylum_files() if p.name == name), None)
    if path is None:
        pytest.skip(f"{name} is not in ../shared")
    wave = cr.read_ibw(path)
    expected = _data_block(path.read_bytes())
    assert wave.data.shape == expected.shape
    assert wave.data.dtype == np.float64
    np.testing.assert_array_equal(wave.data, expected)
    np.testing.assert_array_equal(wave.layer("Defl"), expected[:, 1])
    assert not wave.data.flags.writeable


def test_dart_fixture_256(tmp_path):
    path = tmp_path / "dart.ibw"
    written, _ = write_dart_ibw(path, 256, 256)
    wave = cr.read_ibw(path)
    assert isinstance(wave, IgorWave)
    assert wave.data.shape == (256, 256, 6)
    assert wave.labels == DART_LABELS
    np.testing.assert_array_equal(wave.data, written.astype(float))
    assert wave.note["SpringConstant"] == SPRING_CONSTANT
    assert wave.note["InvOLS"] == INVOLS
    assert wave.note["DriveFrequency"] == DRIVE_FREQUENCY
    assert wave.note["ImagingMode"] == "DART"
    assert wave.note["SaveImage"].startswith("C:Users")  # the last of the repeated key
    assert wave.scale == pytest.approx((SCAN_SIZE / 256, SCAN_SIZE / 256), rel=1e-15)
    assert wave.source == str(path)
    assert wave.name == "DART0001"


def test_layers_by_label_not_position(tmp_path):
    path = tmp_path / "shuffled.ibw"
    order = (5, 0, 3, 1, 4, 2)
    labels = tuple(DART_LABELS[k] for k in order)
    written, _ = write_dart_ibw(path, 8, 6, labels=labels)
    wave = cr.read_ibw(path)
    for k, label in enumerate(labels):
        np.testing.assert_array_equal(wave.layer(label), written[..., k])
    # The channel without its scan direction, and any case, name the Retrace layer.
    np.testing.assert_array_equal(wave.layer("frequency"), written[..., 0])
    assert wave.layer_index("Phase2") == labels.index("Phase2Retrace")


def test_trace_layer_when_there_is_no_retrace(tmp_path):
    path = tmp_path / "trace.ibw"
    labels = tuple(label.replace("Retrace", "Trace") for label in DART_LABELS)
    written, _ = write_dart_ibw(path, 4, 4, labels=labels)
    np.testing.assert_array_equal(cr.read_ibw(path).layer("Frequency"), written[..., 5])


def test_missing_layer_names_the_layers_present(tmp_path):
    path = tmp_path / "no_frequency.ibw"
    write_dart_ibw(path, 4, 4, labels=DART_LABELS[:5])
    wave = cr.read_ibw(path)
    with pytest.raises(ContactresInputError) as info:
        wave.layer("Frequency")
    message = str(info.value)
    assert "\n" not in message
    assert str(path) in message and "'Frequency'" in message
    assert "HeightRetrace, Amplitude1Retrace, Amplitude2Retrace" in message


def test_scale_from_the_note_when_the_wave_is_not_in_metres(tmp_path):
    igorwriter = pytest.importorskip("igorwriter", reason="igorwriter writes the fixtures")
    path = tmp_path / "unscaled.ibw"
    wave = igorwriter.IgorWave5(np.zeros((4, 2, 2), np.float32), name="img", unicode=False)
    wave.set_note("ScanSize: 1e-06\rFastScanSize: 2e-06\rScanPoints: 4\rScanLines: 2\r")
    wave.save(str(path))
    assert cr.read_ibw(path).scale == (2e-06 / 4, 1e-06 / 2)


def test_note_without_spring_constant_is_read_as_it_is(tmp_path):
    path = tmp_path / "no_k.ibw"
    write_dart_ibw(path, 4, 4, SpringConstant=None)
    wave = cr.read_ibw(path)
    assert "SpringConstant" not in wave.note
    assert wave.note["InvOLS"] == INVOLS


@pytest.mark.parametrize("keep", [0, 1, 10, 63, 64, 200, 384, 1000, -50])
def test_truncated_wave_is_one_line(tmp_path, keep):
    source = tmp_path / "whole.ibw"
    write_dart_ibw(source, 16, 16)
    raw = source.read_bytes()
    path = tmp_path / "cut.ibw"
    path.write_bytes(raw[:keep] if keep >= 0 else raw[: len(raw) + keep])
    with pytest.raises(ContactresInputError) as info:
        cr.read_ibw(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: truncated or not an Igor binary wave")


def test_a_text_file_is_not_a_wave(tmp_path):
    path = tmp_path / "table.ibw"
    path.write_text("x,y\n1,2\n")
    with pytest.raises(ContactresInputError, match="truncated or not an Igor binary wave"):
        cr.read_ibw(path)


def test_missing_file(tmp_path):
    with pytest.raises(ContactresInputError, match="no such file"):
        cr.read_ibw(tmp_path / "absent.ibw")


def test_parse_note_numbers_and_text():
    note = parse_note(
        "A: 1e-06\rB:NaN\rC: -inf\rD:16.11.212\rE: 1_000\rF:\rno colon here\r: empty key\r"
        "G: 2\rG: folder:sub:\r\nH: .5\n"
    )
    assert note["A"] == 1e-06 and math.isnan(note["B"]) and note["C"] == -math.inf
    assert note["D"] == "16.11.212" and note["E"] == "1_000" and note["F"] == ""
    assert note["G"] == "folder:sub:"  # the last of a repeated key; colons after the first kept
    assert note["H"] == 0.5
    assert set(note) == set("ABCDEFGH")


def test_without_igor2_one_line_names_the_extra(tmp_path, monkeypatch):
    from contactres.errors import MissingExtraError

    path = tmp_path / "dart.ibw"
    write_dart_ibw(path, 4, 4)
    # A None entry in sys.modules makes the import fail as if igor2 were not installed.
    monkeypatch.setitem(sys.modules, "igor2", None)
    monkeypatch.setitem(sys.modules, "igor2.binarywave", None)
    with pytest.raises(MissingExtraError) as info:
        cr.read_ibw(path)
    assert str(info.value) == "reading .ibw files needs igor2: pip install 'contactres[afm]'"
