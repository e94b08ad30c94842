"""DART (dual AC resonance tracking): the damped oscillator's f0, Q and drive from two drives.

A contact resonance tracked by DART is driven at two frequencies f1 < f2 on either side of it;
per pixel the lock-ins give the amplitudes A1, A2 and the phases φ1, φ2 of the response. The
resonance is modelled as a damped harmonic oscillator driven with amplitude A_d,

    A(ω) = A_d ω0² / √((ω0² − ω²)² + (ω ω0/Q)²),    tan φ = (ω ω0/Q) / (ω0² − ω²),

φ the lag of the response behind the drive (0 well below ω0, π/2 at ω0, π well above). Its
three unknowns (ω0, Q, A_d) follow in closed form (A. Gannepalli et al., "Mapping nanoscale
elasticity and dissipation using dual frequency contact resonance AFM", Nanotechnology 22,
355705 (2011), and its corrigendum, Nanotechnology 24, 159501 (2013), whose corrected X1, X2
are the ones below).

Derivation (written again here). The complex response is H(ω) = A e^{iφ} with
1/H = (ω0² − ω² − i ω ω0/Q)/(A_d ω0²), so for each drive i

    (a) cos φ_i / A_i = (ω0² − ω_i²)/(A_d ω0²),     (b) sin φ_i / A_i = ω_i/(Q A_d ω0).

Their ratio gives X_i ≡ cot φ_i = (ω0² − ω_i²)/(g ω_i) with g = ω0/Q; (b) alone gives
A_i ω_i / sin φ_i = A_d ω0 Q, the same for both drives, so the amplitude ratio fixes the ratio
of the sines: Ω ≡ ω1 A1/(ω2 A2) = sin φ1 / sin φ2. With Δ = φ2 − φ1 (sin φ1 = Ω sin(φ1 + Δ)),

    X1 = cot φ1 = (1/Ω − cos Δ)/sin Δ,    X2 = cot φ2 = (cos Δ − Ω)/sin Δ,

the corrigendum's X1 = −(1 − sgn(Φ)√(1 + Φ²)/Ω)/Φ and X2 = (1 − sgn(Φ) Ω √(1 + Φ²))/Φ,
Φ = tan Δ, for 0 < Δ < π (where sgn(Φ)√(1 + Φ²)/Φ = 1/sin Δ). Only the phase *difference* and
the amplitude *ratio* enter: a constant phase offset of the detection and the unknown gain of
the drive cancel. Then ω_i X_i g = ω0² − ω_i² for both drives gives

    g = ω0/Q = (ω2² − ω1²)/(ω1 X1 − ω2 X2),    ω0² = ω1² + g ω1 X1
        = ω1 ω2 (ω2 X1 − ω1 X2)/(ω1 X1 − ω2 X2),

Q = ω0/g (Gannepalli's f0 = √(f1 f2 (f2 X1 − f1 X2)/(f1 X1 − f2 X2)) and
Q = √(f1 f2 (f2 X1 − f1 X2)(f1 X1 − f2 X2))/(f2² − f1²), the signs kept rather than squared
away), and from (b) A_d = A1 ω1 g/(ω0² sin φ1), sin φ1 = 1/√(1 + X1²) (φ1 in (0, π)), equal to
A1 √((ω0² − ω1²)² + (ω1 ω0/Q)²)/ω0². Exact oscillator data give ω0 and Q to round-off (the
tests: 1e-10 relative).

Noise (first order). Each input error moves X1, X2 and through them ω0 and Q. With the drives
placed symmetrically (φ1 + φ2 = π, i.e. f0² = f1 f2, so Ω = 1 and X1 = −X2) and independent
errors — a relative amplitude noise σ_A on each A_i and a phase noise σ_φ (rad) on each φ_i —
the amplitude ratio shifts X1 and X2 together (∂X1/∂Ω = ∂X2/∂Ω = −1/sin Δ), which moves ω0
alone, and the phase difference moves them apart (∂X1/∂Δ = −∂X2/∂Δ = 1/(1 + cos Δ)), which
moves Q alone:

    σ_f0 / f0 = √2 σ_A f0 / (Q (f1 + f2) sin Δ) ≈ √2 σ_A / (2 Q sin Δ),
    σ_Q / Q = √2 σ_φ / sin Δ

(the exact first-order terms of the symmetric placement; the approximation f1 + f2 ≈ 2 f0 is
good to O(1/Q²)). Phase noise leaves f0, and amplitude noise Q, unchanged to first order; off
the symmetric placement both mix. The noise is smallest at Δ = π/2 (drives near
f0 (1 ∓ 1/(2Q))) and grows as 1/sin Δ when the drives are close together (Δ → 0) or far apart
(Δ → π). The tests compare the scatter of f0 and Q over 40,000 noisy draws with these lines.

Flags (bit mask, :data:`DART_FLAGS`, :func:`dart_flag_names`):

* ``not_straddling``: both drives on one side of the resonance (φ1 and φ2 both below or both
  above π/2; f0 outside [f1, f2]). The equations stay exact and solvable there — an oscillator
  off to one side still gives a finite ω0 and Q — but the drives sit on the same flank, Δ is
  small, and the noise above grows as 1/sin Δ: the tracking lost the resonance, the value is a
  far extrapolation;
* ``degenerate_phase``: sin Δ below ``min_sin`` (φ1 ≈ φ2, or differing by π): X1, X2 are
  undetermined, f0, Q and A_d are NaN;
* ``not_physical``: no oscillator reproduces the data: ω0² ≤ 0, g ≤ 0 (Q ≤ 0, including
  Δ < 0, i.e. a lag that falls with frequency), a non-finite result, or A_d ≤ 0; values NaN;
* ``not_measured``: an input is NaN, an amplitude ≤ 0 or the two frequencies are equal;
  values NaN.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from .._summary import Summarised, flagged, values

__all__ = [
    "DART_FLAGS",
    "DART_FLAG_DEGENERATE_PHASE",
    "DART_FLAG_NOT_MEASURED",
    "DART_FLAG_NOT_PHYSICAL",
    "DART_FLAG_NOT_STRADDLING",
    "MIN_SIN_DELTA",
    "DartReconstruction",
    "dart_flag_names",
    "dart_reconstruct",
    "dart_reconstruction",
]

#: Both drives on one side of the resonance (still solved; module notes).
DART_FLAG_NOT_STRADDLING = 1
#: ``|sin(φ2 − φ1)|`` < min_sin: the phase difference is 0 or π; values NaN.
DART_FLAG_DEGENERATE_PHASE = 2
#: No damped oscillator reproduces the data (ω0² ≤ 0, Q ≤ 0, A_d ≤ 0); values NaN.
DART_FLAG_NOT_PHYSICAL = 4
#: An input is NaN, an amplitude ≤ 0, or f1 = f2; values NaN.
DART_FLAG_NOT_MEASURED = 8

#: Bit -> (short name, meaning).
DART_FLAGS = MappingProxyType(
    {
        DART_FLAG_NOT_STRADDLING: (
            "not_straddling",
            "both drive frequencies on one side of the resonance: solved, but extrapolated",
        ),
        DART_FLAG_DEGENERATE_PHASE: (
            "degenerate_phase",
            "the two phases are equal or differ by pi: f0, Q and the drive are undetermined",
        ),
        DART_FLAG_NOT_PHYSICAL: (
            "not_physical",
            "no damped oscillator reproduces the amplitudes and phases (f0^2 <= 0 or Q <= 0)",
        ),
        DART_FLAG_NOT_MEASURED: (
            "not_measured",
            "an input is missing (NaN), an amplitude is <= 0, or the two frequencies are equal",
        ),
    }
)

#: Default smallest |sin Δ| solved: below it a phase error of 1e-4 rad (a good lock-in) moves
#: X1 − X2, hence Q, by more than 10 % (∂X/∂Δ ~ 1/sin²Δ near Δ = 0).
MIN_SIN_DELTA = 1e-3


def dart_flag_names(flags: int) -> list[str]:
    """Short names of the bits set in one DART ``flags`` value (e.g. ["not_straddling"])."""
    return [name for bit, (name, _) in DART_FLAGS.items() if int(flags) & bit]


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, repr=False)
class DartReconstruction(Summarised):
    """The oscillator per pixel (arrays of the broadcast input shape).

    Attributes
    ----------
    f0 : resonance frequency, Hz (NaN where flagged degenerate, not physical or not measured)
    Q : quality factor, dimensionless
    A_drive : drive amplitude A_d, in the unit of A1, A2 (the response at ω → 0)
    phase_offset : φ1 − (the model's lag at f1), rad: the detection's phase offset where the
        phases carry one (0 for phases of the oscillator alone)
    flags : int bit mask (:data:`DART_FLAGS`)
    """

    f0: np.ndarray
    Q: np.ndarray
    A_drive: np.ndarray
    phase_offset: np.ndarray
    flags: np.ndarray

    def _facts(self) -> list[tuple[str, str]]:
        """f0 (kHz), Q, the drive amplitude (unit of A1, A2) and the flagged pixels."""
        return [
            ("f0", values(self.f0, "kHz", 1e3)),
            ("Q", values(self.Q)),
            ("A_drive", values(self.A_drive)),
            ("flagged", flagged(self.flags)),
        ]


def dart_reconstruction(
    f1_Hz, f2_Hz, A1, A2, phase1_rad, phase2_rad, *, min_sin: float = MIN_SIN_DELTA
) -> DartReconstruction:
    """f0, Q, drive amplitude, phase offset and flags of the damped oscillator (module notes).

    Parameters
    ----------
    f1_Hz, f2_Hz : drive frequencies, Hz (any order; numpy-broadcasting with the rest)
    A1, A2 : response amplitudes at f1, f2 (any one unit: V, m)
    phase1_rad, phase2_rad : phases of the response at f1, f2, rad, lag positive (a constant
        offset common to both cancels)
    min_sin : smallest ``|sin(φ2 − φ1)|`` solved (default :data:`MIN_SIN_DELTA`)

    Returns
    -------
    DartReconstruction
    """
    arrays = [np.asarray(x, dtype=float) for x in (f1_Hz, f2_Hz, A1, A2, phase1_rad, phase2_rad)]
    f1, f2, a1, a2, p1, p2 = np.broadcast_arrays(*arrays)
    w1, w2 = 2.0 * np.pi * f1, 2.0 * np.pi * f2
    with np.errstate(all="ignore"):  # bad pixels are flagged, not warned about
        missing = ~np.isfinite(f1 + f2 + a1 + a2 + p1 + p2) | ~(a1 > 0) | ~(a2 > 0) | (f1 == f2)
        missing |= ~(f1 > 0) | ~(f2 > 0)
        delta = p2 - p1
        s, c = np.sin(delta), np.cos(delta)
        degenerate = ~missing & ~(np.abs(s) >= min_sin)
        omega = (w1 * a1) / (w2 * a2)
        x1 = (1.0 / omega - c) / s
        x2 = (c - omega) / s
        g = (w2 * w2 - w1 * w1) / (w1 * x1 - w2 * x2)
        w0_sq = w1 * w1 + g * w1 * x1
        w0 = np.sqrt(w0_sq)
        q = w0 / g
        a_d = a1 * w1 * g * np.sqrt(1.0 + x1 * x1) / w0_sq
        # The model's lag at f1 (in (0, π) for g > 0): the rest of φ1 is the detection's offset.
        offset = p1 - np.arctan2(w1 * g, w0_sq - w1 * w1)
        bad = ~(w0_sq > 0) | ~(g > 0) | ~np.isfinite(q) | ~(a_d > 0) | ~np.isfinite(a_d)
        not_physical = ~missing & ~degenerate & bad
        # Straddling: f0 between the drives, X1 and X2 of opposite signs (φ1 < π/2 < φ2).
        lo, hi = np.minimum(f1, f2), np.maximum(f1, f2)
        f0 = w0 / (2.0 * np.pi)
        one_side = ~(missing | degenerate | not_physical) & ~((f0 >= lo) & (f0 <= hi))
    flags = (
        np.where(one_side, DART_FLAG_NOT_STRADDLING, 0)
        | np.where(degenerate, DART_FLAG_DEGENERATE_PHASE, 0)
        | np.where(not_physical, DART_FLAG_NOT_PHYSICAL, 0)
        | np.where(missing, DART_FLAG_NOT_MEASURED, 0)
    ).astype(int)
    void = (flags & ~DART_FLAG_NOT_STRADDLING) != 0
    nan = np.nan
    return DartReconstruction(
        f0=np.where(void, nan, f0),
        Q=np.where(void, nan, q),
        A_drive=np.where(void, nan, a_d),
        phase_offset=np.where(void, nan, offset),
        flags=flags,
    )


def dart_reconstruct(f1_Hz, f2_Hz, A1, A2, phase1_rad, phase2_rad):
    """Resonance frequency, Q and drive amplitude of a damped oscillator from DART data.

    The closed form of Gannepalli et al., Nanotechnology 22, 355705 (2011), with the corrected
    X1, X2 of its corrigendum, Nanotechnology 24, 159501 (2013); derived again, with its noise
    propagation and flags, in :mod:`contactres.analysis._dart` (see
    :func:`dart_reconstruction` for the flags and the phase offset).

    Parameters
    ----------
    f1_Hz, f2_Hz : drive frequencies, Hz
    A1, A2 : amplitudes of the response at f1, f2 (one unit, e.g. V or m)
    phase1_rad, phase2_rad : phases of the response, rad, lag positive (the oscillator's lag
        behind its drive; a common offset cancels)

    All numpy-broadcasting.

    Returns
    -------
    (f0_Hz, Q, A_drive) : arrays of the broadcast shape; NaN where the data admit no oscillator
        (degenerate phases, Q ≤ 0, missing data)

    Examples
    --------
    An oscillator at 300 kHz with Q = 80, driven 2 kHz either side:

    >>> import numpy as np
    >>> from contactres import dart_reconstruct
    >>> f0, Q, Ad = 300e3, 80.0, 1e-10  # Hz, dimensionless, m
    >>> f = np.array([298e3, 302e3])
    >>> A = Ad * f0**2 / np.sqrt((f0**2 - f**2) ** 2 + (f * f0 / Q) ** 2)
    >>> phi = np.arctan2(f * f0 / Q, f0**2 - f**2)  # lag, rad
    >>> out = dart_reconstruct(f[0], f[1], A[0], A[1], phi[0], phi[1])
    >>> print(f"{float(out[0]):.6g} Hz, Q = {float(out[1]):.6g}")
    300000 Hz, Q = 80
    """
    r = dart_reconstruction(f1_Hz, f2_Hz, A1, A2, phase1_rad, phase2_rad)
    return r.f0, r.Q, r.A_drive
