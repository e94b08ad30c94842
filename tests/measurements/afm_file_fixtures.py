"""Instrument files for the CR-AFM reader tests, written at test time in the real layouts.

* An Asylum Research DART image (``.ibw``, Igor binary wave version 5) written with
  ``igorwriter`` (a test-only dependency, not contactres's writer): points × lines × 6 layers
  labelled as an Asylum instrument labels them, the wave scaled in metres, and a note of
  ``key: value`` lines separated by carriage returns in the style of the real notes of
  ``../shared/fixtures/asylum-ibw`` (keys and number formats as they write them).
* The layers hold a damped harmonic oscillator driven at f ± Δf/2 (the DART scheme: Gannepalli
  et al., Nanotechnology 22, 355705 (2011)), computed here from the textbook response
  A(f) = A_d f0² / √((f0² − f²)² + (f f0/Q)²), tan φ = (f f0/Q) / (f0² − f²) (lag positive),
  so a test can check what it reads against the truth it wrote.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
#: The real Asylum files (force records with real notes), outside the repository.
ASYLUM_DIR = REPO.parent / "shared" / "fixtures" / "asylum-ibw"

DART_LABELS = (
    "HeightRetrace",
    "Amplitude1Retrace",
    "Amplitude2Retrace",
    "Phase1Retrace",
    "Phase2Retrace",
    "FrequencyRetrace",
)

#: The lever and scan of the fixture (SI units, as the note gives them).
SPRING_CONSTANT = 2.8312
INVOLS = 6.1907e-08
DRIVE_FREQUENCY = 301250.0
FREQUENCY_WIDTH = 10000.0
SCAN_SIZE = 5e-06


def asylum_files() -> list[Path]:
    """The real ``.ibw`` files of ../shared, or a skip naming where they were looked for."""
    files = sorted(ASYLUM_DIR.glob("*.ibw"))
    if not files:
        pytest.skip(f"the real Asylum files are not here: {ASYLUM_DIR} (../shared is absent)")
    return files


def dart_note(points: int, lines: int, **changes) -> str:
    """A DART image's note as an Asylum instrument writes it (a subset of its keys); ``changes``
    replace values (a value None drops the key)."""
    entries = [
        ("VerDate", "160212"),
        ("Version", "16.11.212"),
        ("IgorFileVersion", "6.3.8.1"),
        ("ScanSize", f"{SCAN_SIZE:g}"),
        ("FastScanSize", f"{SCAN_SIZE:g}"),
        ("SlowScanSize", f"{SCAN_SIZE:g}"),
        ("ScanRate", "0.50069"),
        ("ScanPoints", f"{points}"),
        ("ScanLines", f"{lines}"),
        ("ScanAngle", "0"),
        ("ImagingMode", "DART"),
        ("SpringConstant", f"{SPRING_CONSTANT:g}"),
        ("InvOLS", f"{INVOLS:g}"),
        ("AmpInvOLS", "6.4203e-08"),
        ("DriveAmplitude", "0.5"),
        ("DriveFrequency", f"{DRIVE_FREQUENCY:g}"),
        ("DFRTFrequencyCenter", f"{DRIVE_FREQUENCY:g}"),
        ("DFRTFrequencyWidth", f"{FREQUENCY_WIDTH:g}"),
        ("DFRTOn", "1"),
        ("DARTIGain", "5.5"),
        ("DARTPGain", "0"),
        ("TipVoltage", "0"),
        ("MicroscopeModel", "MFP3D"),
        ("StartHeadTemp", "29.5625 \u00b0C"),
        # Asylum notes repeat a few keys, first with a number, then with a folder.
        ("SaveImage", "2"),
        ("Frequency", "$DDSFrequencyOffset0"),
        ("SaveImage", "C:Users:USER:Documents:Asylum Research Data:261128:"),
        ("Date", "2026-11-28"),
        ("Time", "21:44:03"),
    ]
    for key, value in changes.items():
        present = any(k == key for k, _ in entries)
        entries = [
            (k, v if k != key else value) for k, v in entries if k != key or value is not None
        ]
        if value is not None and not present:
            entries.append((key, value))
    # Asylum writes "Key: value" for numbers and "Key:value" for most text, with a final \r.
    return "".join(f"{k}:{' ' if _numeric(v) else ''}{v}\r" for k, v in entries)


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def oscillator(f, f0, q, a_drive):
    """Amplitude and phase (rad, lag positive, in (0, π)) of a damped harmonic oscillator
    driven at ``f``."""
    amplitude = a_drive * f0**2 / np.sqrt((f0**2 - f**2) ** 2 + (f * f0 / q) ** 2)
    phase = np.arctan2(f * f0 / q, f0**2 - f**2)
    return amplitude, phase


def dart_layers(points: int, lines: int, seed: int = 7):
    """(data (points, lines, 6), truth dict): a film with a round stiffer inclusion. The
    frequency layer holds the tracked frequency's offset from DriveFrequency, Hz; phases in
    degrees, amplitudes and height in m, as an Asylum image stores them."""
    rng = np.random.default_rng(seed)
    x = (np.arange(points) + 0.5) / points - 0.5
    y = (np.arange(lines) + 0.5) / lines - 0.5
    inside = np.hypot(*np.meshgrid(x, y, indexing="ij")) < 0.25
    f0 = np.where(inside, DRIVE_FREQUENCY + 2500.0, DRIVE_FREQUENCY - 1500.0)
    q = np.where(inside, 80.0, 45.0)
    a_drive = 1e-10
    # DART tracks the centre close to, not at, the resonance: a small offset per pixel.
    centre = f0 + rng.normal(0.0, 150.0, f0.shape)
    a1, p1 = oscillator(centre - FREQUENCY_WIDTH / 2, f0, q, a_drive)
    a2, p2 = oscillator(centre + FREQUENCY_WIDTH / 2, f0, q, a_drive)
    height = np.where(inside, 12e-9, 0.0) + rng.normal(0.0, 0.3e-9, f0.shape)
    data = np.stack(
        [height, a1, a2, np.degrees(p1), np.degrees(p2), centre - DRIVE_FREQUENCY], axis=-1
    )
    return data, {"f0": f0, "q": q, "centre": centre, "inside": inside}


def write_dart_ibw(path: Path, points: int = 256, lines: int = 256, labels=DART_LABELS, **note):
    """Write a DART image to ``path`` with igorwriter (skips without it); returns the data
    written (float32, as the instrument stores it) and the truth."""
    igorwriter = pytest.importorskip(
        "igorwriter", reason="igorwriter (test extra) writes the .ibw fixtures"
    )
    data, truth = dart_layers(points, lines)
    data = data.astype(np.float32)
    wave = igorwriter.IgorWave5(data, name="DART0001", unicode=False)
    wave.set_dimscale("x", 0.0, SCAN_SIZE / points, "m")
    wave.set_dimscale("y", 0.0, SCAN_SIZE / lines, "m")
    for k, label in enumerate(labels):
        wave.set_dimlabel(2, k, label)
    wave.set_note(dart_note(points, lines, **note))
    wave.save(str(path))
    return data, truth
