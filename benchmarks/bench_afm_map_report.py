"""Benchmark: a 256 x 256 DART image from its file to the report (``contactres afm map``).

Target: under 5 s on the 2-core reference machine for the whole chain, as the command runs it:
read the Asylum ``.ibw`` (:func:`contactres.read_ibw`), reconstruct f0 and Q per pixel from the
two amplitudes and phases (:func:`contactres.analysis.dart_reconstruction`), invert mode 1 to
k* and σ with the tip position known, Hertz to E* and M, tan δ
(:func:`contactres.invert_cr_map`), then write the folder: ``afm_map.json``, the two figures and
the NetCDF Dataset (:func:`contactres.apps.afm_map.write_afm_map`). Each stage is printed.

The image is written first (not timed) with ``igorwriter`` (the test extra): the lever's
contact resonance on a Kelvin-Voigt contact varying across the map (k* from 30 to 300 N/m,
tan δ 0.02 to 0.08; the resonance by :func:`contactres.contact_frequencies` on 64 values,
tiled), driven at f0 + 150 Hz ∓ 3 kHz as DART does, the damped oscillator's response at each
drive stored as an Asylum image stores it (float32, phases in degrees, the frequency layer as
the offset from the note's DriveFrequency).

Run: ``.venv/bin/python benchmarks/bench_afm_map_report.py`` (exit status 1 if the target is
missed).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _verdict import exit_code, target

TARGET_S = 5.0
SIDE = 256
K_C, F_FREE, R_TIP, WIDTH, DRIVE = 3.0, 88e3, 0.95, 6e3, 270e3  # N/m, Hz, -, Hz, Hz


def _write_image(path: Path) -> None:
    import igorwriter

    from contactres import Cantilever, contact_frequencies

    lever = Cantilever((F_FREE,), K_C)
    k = np.geomspace(30.0, 300.0, 64)
    tan = np.linspace(0.02, 0.08, 64)
    fc = contact_frequencies(lever, k * (1 + 1j * tan) / K_C, R_TIP, modes=(1,))[:, 0]
    f0, q = fc.real, fc.real / (2 * fc.imag)
    reps = SIDE * SIDE // k.size
    f0 = np.tile(f0, reps).reshape(SIDE, SIDE)
    q = np.tile(q, reps).reshape(SIDE, SIDE)
    centre = f0 + 150.0
    layers = []
    for f in (centre - WIDTH / 2, centre + WIDTH / 2):
        amp = 2e-11 * f0**2 / np.sqrt((f0**2 - f**2) ** 2 + (f * f0 / q) ** 2)
        layers.append((amp, np.degrees(np.arctan2(f * f0 / q, f0**2 - f**2))))
    (a1, p1), (a2, p2) = layers
    data = np.stack([np.zeros_like(f0), a1, a2, p1, p2, centre - DRIVE], axis=-1)
    wave = igorwriter.IgorWave5(data.transpose(1, 0, 2).astype(np.float32), name="DART0001")
    for d in ("x", "y"):
        wave.set_dimscale(d, 0.0, 5e-6 / SIDE, "m")
    labels = ("Height", "Amplitude1", "Amplitude2", "Phase1", "Phase2", "Frequency")
    for i, label in enumerate(labels):
        wave.set_dimlabel(2, i, label + "Retrace")
    note = {
        "SpringConstant": K_C,
        "ThermalFrequency": F_FREE,
        "DriveFrequency": DRIVE,
        "DFRTFrequencyWidth": WIDTH,
        "ScanSize": 5e-6,
        "ScanPoints": SIDE,
        "ScanLines": SIDE,
    }
    wave.set_note("".join(f"{key}: {value:g}\r" for key, value in note.items()))
    wave.save(str(path))


def main() -> int:
    from contactres.analysis import ModulusModel
    from contactres.apps.afm_map import write_afm_map
    from contactres.jobs import afm_map as job

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "dart256.ibw"
        _write_image(path)
        settings = job.Settings(
            tip_position=R_TIP,
            modulus=ModulusModel(tip_radius=20e-9, load=50e-9, tip_modulus=165e9),
        )
        t0 = time.perf_counter()
        data = job.read_input(path)
        t_read = time.perf_counter() - t0
        result = job.run(data, settings)
        t_run = time.perf_counter() - t0 - t_read
        write_afm_map(result, Path(tmp) / "report")
        t_all = time.perf_counter() - t0
        t_write = t_all - t_read - t_run
    s = result.summary
    print(f"contact-resonance map from file to report: {SIDE} x {SIDE} DART image")
    print(f"  read .ibw:                          {t_read:.3f} s")
    print(f"  DART reconstruction + inversion:    {t_run:.3f} s")
    print(f"  report (json, 2 figures, NetCDF):   {t_write:.3f} s")
    print(f"  pixels with k*: {s['pixels_with_k_star']}, flagged: {s['pixels_flagged']}")
    results = [target(f"afm map, {SIDE}x{SIDE} DART file to report", t_all, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
