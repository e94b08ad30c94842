"""The bundled DART image ``example_dart.ibw``: the script makes it again byte for byte, and it
reads as an Asylum DART image whose layers are the oscillator the script describes.

The physical checks use the textbook damped harmonic oscillator written out here, not the
script's code: at the two drives f_c ∓ Δf/2 the phase lags straddle 90° (the drives sit on
either side of the resonance), and the amplitude ratio A2/A1 and both phases agree with
A(f) ∝ 1/√((f0² − f²)² + (f f0/Q)²), tan φ = (f f0/Q)/(f0² − f²) at the f0 and Q the
script's docstring states for the film and the inclusion, within the noise it states.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import contactres as cr
from contactres.examples import EXAMPLES, example_path
from contactres.measurements import dart_frequency_Hz

pytest.importorskip("igor2", reason="igor2 (the extra 'afm') reads .ibw files")

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "make_example_dart.py"
# The film and the inclusion, as the script's docstring states them (f0 in Hz, Q).
FILM, INCLUSION = (266.349e3, 29.41), (305.300e3, 79.78)
DRIVE_AMPLITUDE = 20e-12  # m
DRIVE_FREQUENCY, WIDTH = 270e3, 6e3


def _script():
    spec = importlib.util.spec_from_file_location("make_example_dart", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_script_makes_the_bundled_file(tmp_path):
    pytest.importorskip("igorwriter", reason="igorwriter (test extra) writes .ibw files")
    made = _script().write(tmp_path / "example_dart.ibw")
    assert made.read_bytes() == example_path("example_dart.ibw").read_bytes()


def test_example_is_listed_with_its_command():
    # The command gives the tip position, tip and load the file was made with (the script's
    # constants; the default r = 1 put tan δ 19 % off), as afm map's --help example does.
    example = EXAMPLES["example_dart.ibw"]
    script = _script()
    words = example.command.split()
    assert words[:4] == ["contactres", "afm", "map", "example_dart.ibw"]
    options = dict(zip(words[4::2], words[5::2], strict=True))
    assert float(options["--tip-position"]) == script.TIP_POSITION
    assert float(options["--tip-radius"]) == script.TIP_RADIUS
    assert float(options["--force"]) == script.LOAD
    assert float(options["--tip-modulus"]) == script.TIP_MODULUS
    assert f"r = L1/L = {script.TIP_POSITION}" in example.description
    from contactres.cli.afm_map import afm_map

    assert example.command in " ".join(afm_map.help.replace("\\", " ").split())
    assert example_path("example_dart.ibw").stat().st_size < 300_000


def test_example_reads_as_a_dart_image():
    wave = cr.read_ibw(example_path("example_dart.ibw"))
    assert wave.data.shape == (64, 64, 6)
    assert wave.labels == (
        "HeightRetrace",
        "Amplitude1Retrace",
        "Amplitude2Retrace",
        "Phase1Retrace",
        "Phase2Retrace",
        "FrequencyRetrace",
    )
    assert wave.note["ImagingMode"] == "DART"
    assert wave.note["SpringConstant"] == 3.0
    assert wave.note["DriveFrequency"] == DRIVE_FREQUENCY
    assert wave.note["DFRTFrequencyWidth"] == WIDTH
    assert wave.scale == pytest.approx((2e-6 / 64, 2e-6 / 64), rel=1e-12)


def _oscillator(f, f0, q):
    amplitude = DRIVE_AMPLITUDE * f0**2 / np.sqrt((f0**2 - f**2) ** 2 + (f * f0 / q) ** 2)
    return amplitude, np.degrees(np.arctan2(f * f0 / q, f0**2 - f**2))


def test_example_layers_are_the_stated_oscillator():
    wave = cr.read_ibw(example_path("example_dart.ibw"))
    centre = dart_frequency_Hz(wave)  # (y, x), Hz
    p1, p2 = wave.layer("Phase1").T, wave.layer("Phase2").T
    a1, a2 = wave.layer("Amplitude1").T, wave.layer("Amplitude2").T
    assert (p1 < 90).all() and (p2 > 90).all()  # the drives straddle the resonance
    # Each pixel is the film or the inclusion: its centre lies within 7 tracking errors
    # (100 Hz) of one of the two resonances.
    inclusion = np.abs(centre - INCLUSION[0]) < 700
    film = np.abs(centre - FILM[0]) < 700
    assert (inclusion ^ film).all()
    assert 0.1 < inclusion.mean() < 0.25  # a disc of radius 0.45 µm in 2 µm × 2 µm: 16 %
    for mask, (f0, q) in ((film, FILM), (inclusion, INCLUSION)):
        low, phase1 = _oscillator(centre[mask] - WIDTH / 2, f0, q)
        high, phase2 = _oscillator(centre[mask] + WIDTH / 2, f0, q)
        # The stated noise: 0.2° on each phase, 2 pm on each amplitude; 6 standard deviations.
        np.testing.assert_allclose(p1[mask], phase1, rtol=0, atol=1.2)
        np.testing.assert_allclose(p2[mask], phase2, rtol=0, atol=1.2)
        np.testing.assert_allclose(a1[mask], low, rtol=0, atol=12e-12)
        np.testing.assert_allclose(a2[mask], high, rtol=0, atol=12e-12)


def test_the_drive_amplitude_comes_back_in_metres():
    # Asylum's amplitude layers are in m: the reconstructed drive amplitude has their unit and
    # the script's 20 pm drive (within its 2 pm amplitude noise per pixel, median over 4096).
    from contactres.jobs import afm_map as job

    result = job.run(example_path("example_dart.ibw"), job.Settings(tip_position=0.95))
    drive = result.dataset["drive_amplitude"]
    assert drive.attrs["units"] == "m"
    assert np.nanmedian(drive.values) == pytest.approx(DRIVE_AMPLITUDE, rel=0.01)
