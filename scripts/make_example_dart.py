"""Make ``src/contactres/data/example_dart.ibw``: a synthetic Asylum Research DART image (an Igor
binary wave, version 5) of a polymer film with a round stiffer inclusion, in the layout an Asylum
instrument writes.

Run ``python scripts/make_example_dart.py`` (seeded: the same file every time; it needs
igorwriter, the test extra). The recipe, per pixel (64 × 64 pixels over 2 µm):

* the sample: a film (E = 2.5 GPa, ν = 0.35, tan δ = 0.04) with a round inclusion of radius
  0.45 µm at the centre (E = 5 GPa, ν = 0.30, tan δ = 0.01); an Si tip (M = 165 GPa) of radius
  R = 20 nm at the load P = 50 nN: 1/E* = (1 − ν²)/E + 1/M_tip, Hertz a = (3PR/4E*)^(1/3),
  k* = 2aE* (K. L. Johnson, Contact Mechanics, 1985, Eqs. 4.22-4.23), and the damped contact
  k*(1 + i tan δ);
* the lever: k_c = 3 N/m, free first mode 88 kHz with Q = 150, tip at r = 0.95; the first
  contact resonance f0 and its Q from :func:`contactres.contact_frequencies` with the complex
  κ = k*(1 + i tan δ)/k_c (Q = f′/2f″): 266.349 kHz, Q = 29.41 on the film and 305.300 kHz,
  Q = 79.78 on the inclusion;
* DART (Gannepalli, Cearley, Nikiforov, Kalinin & Proksch, Nanotechnology 22, 355705 (2011)):
  the tracked centre f_c = f0 + 100 Hz of Gaussian tracking error, the two drives at
  f_c ∓ Δf/2 with Δf = 6 kHz, and the damped harmonic oscillator's response at each,
  A(f) = A_d f0² / √((f0² − f²)² + (f f0/Q)²), tan φ = (f f0/Q)/(f0² − f²) (phase lag, 90° at
  resonance), A_d = 20 pm; noise of 2 pm on each amplitude and 0.2° on each phase;
* the layers as an Asylum image stores them: ``HeightRetrace`` (m: the inclusion 3 nm proud,
  a slight tilt, 0.2 nm noise), ``Amplitude1Retrace``/``Amplitude2Retrace`` (m),
  ``Phase1Retrace``/``Phase2Retrace`` (degrees), ``FrequencyRetrace`` (Hz: f_c minus the
  drive frequency set, 270 kHz, as Asylum's note maps the channel to ``$DDSFrequencyOffset0``);
  Igor's first index runs along x (the fast scan axis), float32;
* a note of ``key: value`` lines separated by carriage returns in the style of real Asylum notes
  (``SpringConstant``, ``InvOLS``, ``DriveFrequency``, ``DFRTFrequencyWidth``, ``DARTIGain``,
  ``ScanSize``, ``ScanPoints``, ``ScanLines``, ``ImagingMode``, ``ThermalFrequency``,
  ``ThermalQ`` ...).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contactres import Cantilever, contact_frequencies

SHAPE = (64, 64)  # (lines y, points x)
SCAN_SIZE = 2e-6  # m
SEED = 29
TIP_MODULUS, TIP_RADIUS, LOAD = 165e9, 20e-9, 50e-9  # Pa, m, N
SPRING_CONSTANT, FREE_FREQUENCY, FREE_Q, TIP_POSITION = 3.0, 88e3, 150.0, 0.95
FILM = {"E": 2.5e9, "nu": 0.35, "tan_delta": 0.04}
INCLUSION = {"E": 5e9, "nu": 0.30, "tan_delta": 0.01, "radius": 0.45e-6}
DRIVE_FREQUENCY, FREQUENCY_WIDTH, DRIVE_AMPLITUDE = 270e3, 6e3, 20e-12  # Hz, Hz, m
TRACKING, AMPLITUDE_NOISE, PHASE_NOISE = 100.0, 2e-12, 0.2  # Hz, m, degrees
INVOLS = 5.87e-08  # m/V
LABELS = (
    "HeightRetrace",
    "Amplitude1Retrace",
    "Amplitude2Retrace",
    "Phase1Retrace",
    "Phase2Retrace",
    "FrequencyRetrace",
)


def contact_resonance(phase: dict) -> tuple[float, float]:
    """(f0 in Hz, Q) of the first contact mode on a phase of the sample."""
    m_sample = phase["E"] / (1 - phase["nu"] ** 2)
    e_star = 1 / (1 / m_sample + 1 / TIP_MODULUS)
    a = (3 * LOAD * TIP_RADIUS / (4 * e_star)) ** (1 / 3)
    kappa = 2 * a * e_star * (1 + 1j * phase["tan_delta"]) / SPRING_CONSTANT
    lever = Cantilever((FREE_FREQUENCY,), SPRING_CONSTANT, free_q_factors=(FREE_Q,))
    f = complex(contact_frequencies(lever, kappa, TIP_POSITION, modes=(1,))[0])
    return f.real, f.real / (2 * f.imag)


def oscillator(f, f0, q):
    """Amplitude (m) and phase lag (degrees) of the damped harmonic oscillator driven at f."""
    amplitude = DRIVE_AMPLITUDE * f0**2 / np.sqrt((f0**2 - f**2) ** 2 + (f * f0 / q) ** 2)
    return amplitude, np.degrees(np.arctan2(f * f0 / q, f0**2 - f**2))


def layers(rng) -> np.ndarray:
    """The six layers, shape (points x, lines y, 6), float32."""
    lines, points = SHAPE
    x = (np.arange(points) + 0.5) * SCAN_SIZE / points
    y = (np.arange(lines) + 0.5) * SCAN_SIZE / lines
    xx, yy = np.meshgrid(x, y)  # (y, x)
    inside = np.hypot(xx - SCAN_SIZE / 2, yy - SCAN_SIZE / 2) < INCLUSION["radius"]
    (f_film, q_film), (f_inc, q_inc) = contact_resonance(FILM), contact_resonance(INCLUSION)
    f0 = np.where(inside, f_inc, f_film)
    q = np.where(inside, q_inc, q_film)
    centre = f0 + rng.normal(0.0, TRACKING, SHAPE)
    a1, p1 = oscillator(centre - FREQUENCY_WIDTH / 2, f0, q)
    a2, p2 = oscillator(centre + FREQUENCY_WIDTH / 2, f0, q)
    a1, a2 = (a + rng.normal(0.0, AMPLITUDE_NOISE, SHAPE) for a in (a1, a2))
    p1, p2 = (p + rng.normal(0.0, PHASE_NOISE, SHAPE) for p in (p1, p2))
    height = np.where(inside, 3e-9, 0.0) + 1e-3 * xx + rng.normal(0.0, 0.2e-9, SHAPE)
    stack = np.stack([height, a1, a2, p1, p2, centre - DRIVE_FREQUENCY], axis=-1)
    return np.transpose(stack, (1, 0, 2)).astype(np.float32)  # Igor: x first


def note() -> str:
    """The wave note: Asylum's keys and number formats, lines ended by carriage returns."""
    lines, points = SHAPE
    entries = [
        ("VerDate", "160212"),
        ("Version", "16.11.212"),
        ("IgorFileVersion", "6.3.8.1"),
        ("ImagingMode", "DART"),
        ("ScanSize", f"{SCAN_SIZE:g}"),
        ("FastScanSize", f"{SCAN_SIZE:g}"),
        ("SlowScanSize", f"{SCAN_SIZE:g}"),
        ("ScanRate", "0.50069"),
        ("ScanPoints", f"{points}"),
        ("ScanLines", f"{lines}"),
        ("ScanAngle", "0"),
        ("SpringConstant", f"{SPRING_CONSTANT:g}"),
        ("InvOLS", f"{INVOLS:g}"),
        ("AmpInvOLS", f"{INVOLS:g}"),
        ("ThermalFrequency", f"{FREE_FREQUENCY:g}"),
        ("ThermalQ", f"{FREE_Q:g}"),
        ("DriveAmplitude", "0.8"),
        ("DriveFrequency", f"{DRIVE_FREQUENCY:g}"),
        ("DFRTFrequencyCenter", f"{DRIVE_FREQUENCY:g}"),
        ("DFRTFrequencyWidth", f"{FREQUENCY_WIDTH:g}"),
        ("DFRTOn", "1"),
        ("DARTIGain", "5.5"),
        ("DARTPGain", "0"),
        ("Setpoint", "0.5"),
        ("TipVoltage", "0"),
        ("Amplitude1", "$Lockin.1.r"),
        ("Phase1", "$Lockin.1.theta"),
        ("Frequency", "$DDSFrequencyOffset0"),
        ("MicroscopeModel", "MFP3D"),
        ("Date", "2026-11-28"),
        ("Time", "21:44:03"),
    ]
    return "".join(f"{k}:{v}\r" if v[:1].isalpha() else f"{k}: {v}\r" for k, v in entries)


def write(path: Path) -> Path:
    """Write the example DART image to ``path`` (deterministic: seeded, no time stamp)."""
    import igorwriter

    wave = igorwriter.IgorWave5(layers(np.random.default_rng(SEED)), name="DART0001", unicode=False)
    lines, points = SHAPE
    wave.set_dimscale("x", 0.0, SCAN_SIZE / points, "m")
    wave.set_dimscale("y", 0.0, SCAN_SIZE / lines, "m")
    for k, label in enumerate(LABELS):
        wave.set_dimlabel(2, k, label)
    wave.set_note(note())
    wave.save(str(path))
    return path


def main() -> None:
    data = Path(__file__).resolve().parents[1] / "src" / "contactres" / "data"
    path = data / "example_dart.ibw"
    path.unlink(missing_ok=True)  # igorwriter saves into an empty file only
    write(path)
    print(f"wrote {path}: {path.stat().st_size} bytes")


if __name__ == "__main__":
    main()
