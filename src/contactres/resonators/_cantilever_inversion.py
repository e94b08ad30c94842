"""Contact-resonance AFM: contact stiffness (and tip position, damping) from measured resonances.

The inverse of :mod:`contactres.resonators._cantilever`. For each measured mode n the frequency
gives β_n (the cantilever's normalisation, complex with a quality factor), and κ = k*/k_c follows

* normal spring only: explicitly, κ = 2β³(1 + cos β cosh β)/(3D) (U. Rabe, K. Janser,
  W. Arnold, "Vibrations of free and surface-coupled atomic force microscope cantilevers:
  theory and experiment", Rev. Sci. Instrum. 67, 3281 (1996), for k_c = 3EI/L³), divided by
  g_yy = cos²φ when the lever is tilted;
* with a lateral spring at a tip of height h: det M(β, κ) is a polynomial a κ² + b κ + c (its
  coefficients are determinants of the rows, exact by multilinearity); of its roots, the one on mode
  n's branch is chosen by counting (below).

Branch of mode n. Adding a positive stiffness raises every eigenvalue, so β_n(κ) increases from
β_n⁰ (free) to its κ → ∞ limit, and at a fixed β the roots κ > 0 of det M, taken in increasing
order, belong to the modes N₀, N₀ − 1, ... that cross β as κ grows (N₀ = number of free roots
below β: the smaller κ belongs to the higher mode). Mode n is root number N₀ − n (0-based) among
the positive roots; none when N₀ < n (frequency below the free one: κ < 0, returned as the
branch continued through zero, the root of largest non-positive real part) or when there are too
few positive roots (frequency at or above the κ → ∞ limit: κ = NaN).

No contact. A frequency equal to its mode's free one (β = β_n⁰: 1 + cos β cosh β = 0) is
κ = 0, where the closed form is 0/0 and rounding alone would decide between a tiny κ and
"below free" (f/f_free = 1 + 2e-16 from a whole-Hz free frequency is either). Within
:data:`FREE_TOLERANCE` of it either way, ``|f/f_free − 1|`` <= 1e-6 (the precision of a free
resonance), gives κ = 0 exactly with the flag ``no_contact`` (and σ = 0); further below stays
``below_free``. Further above, κ is small and positive, as the model says (flagged
``insensitive``).

Two modes, tip position unknown (D. C. Hurley and J. A. Turner, "Measurement of Poisson's ratio
with contact-resonance atomic force microscopy", J. Appl. Phys. 102, 033509 (2007), the
two-mode method): one contact, so κ_a(r) = κ_b(r). Δ(r) = κ_a − κ_b (the springs, below:
damping) is scanned on a grid of r in (0, 1] (:data:`R_GRID`, with one point past 1 so that
r = 1 is bracketed), every sign change between finite values is refined by bisection on whole
arrays of (pixel, interval) pairs, and a limit is kept only if ``|Δ| <= 1e-6 (|κ_a| + |κ_b|)``
there (a pole, where κ jumps through infinity, gives a huge ``|Δ|`` instead). A tip at r = 1
with noisy frequencies puts the crossing on either side of 1: a crossing in (1, 1.005] is
r = 1 when the two modes agree there within :data:`END_TOLERANCE` (a relative error of 1e-7
in f2 sent such a pixel to the far crossing near r = 0.62, κ off by a factor 2.6 to 4). The
physical crossing is the largest r in [0.5, 1] (the tip sits near the free end): the crossings
of modes 1 and 2 come in pairs placed nearly symmetrically about r ≈ 0.78 (normal spring: a tip
at r = 0.8, 0.9, 1 has its partner at 0.77, 0.69, 0.64), so for the tips of real levers,
r ≳ 0.8, the larger is the tip, and an independent beam's third mode confirms it and rejects
the partner (tests/resonators/test_cantilever_independent.py). Several crossings in the
window are information, not a failure: the pixel keeps the largest r and its κ, is flagged
``several_crossings``, and the next one is reported beside it (``tip_position_other``,
``kappa_other``); all crossings are returned as candidates. Two modes alone cannot tell a
tip at r < 0.78 from its partner above it (0.82 for r = 0.75), nor, with a lateral spring and
κ ≳ 300, the tip from a third crossing of the saturated modes just below r = 1: a third
measured mode decides (below).

Three or more modes (the consistency check). The crossing still comes from the first two
measured modes; every further measured mode gives its own κ at each candidate r. A candidate
is *consistent* where those agree with the crossing's κ within ``mode_tolerance`` (relative);
a further mode that no positive κ reproduces there (below its free or above its pinned
frequency) contradicts the candidate. The largest consistent r in [0.5, 1] is chosen (a
spurious crossing of the first two modes is rejected by the third), and the pixel is flagged
``inconsistent_modes`` when no candidate is consistent (then the largest r, as with two modes).
``mode_spread`` is the relative range (max κ_n − min κ_n)/κ over κ and the modes that check it:
the further modes with r solved, every usable mode with r given (κ their mean); inf where a
further mode contradicts r, NaN where no mode checks (one mode with r given, two with r
solved). The Euler-Bernoulli lever is the model being checked: a real lever (tip mass,
trapezoidal section, a tip not at a point) can disagree by a few per cent between modes,
which is why the default tolerance is 5 % and not the accuracy of the frequencies.

Damping. A quality factor Q makes the mode's frequency complex, ω_c = ω(1 + i/(2Q)), ω = 2πf,
and the root of the characteristic equation at ω_c is a complex κ_c = κ′ + iκ″. The contact
is a Kelvin-Voigt spring and dashpot, k* + iω_c σ at that complex frequency, so
k_c κ_c = k* − (ω/(2Q)) σ + iωσ exactly: σ = k_c κ″/ω (N s/m) and k* = k_c (κ′ + κ″/(2Q)).
Taking k* = k_c κ′ instead is off by κ″/(2Qκ′), ~1e-3 (8e-4 at Q = 30, 5e-4 at Q = 47; a
contact that sets Q gives κ″/κ′ ≈ 1/(sQ), s = d ln f/d ln κ), the difference independent
checks found against the exact complex root. The lever's own loss, with its free Q known,
enters as a complex bending stiffness (β = β_ref √(ω/ω_ref), ω_ref complex;
:class:`Cantilever`), so a lossless contact gives σ = 0. The two-mode crossing compares
the springs κ′ + κ″/(2Q).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, flagged, values
from ..errors import ContactresInputError
from ._cantilever import (
    FREE_ROOTS,
    Cantilever,
    beta_from_frequency,
    determinant_coefficients,
    normal_kappa,
    normal_log_slope,
    normal_trig,
    tip_coefficients,
)

__all__ = [
    "FLAG_ABOVE_PINNED",
    "FLAG_BELOW_FREE",
    "FLAG_INCONSISTENT_MODES",
    "FLAG_INSENSITIVE",
    "FLAG_NOT_MEASURED",
    "FLAG_NOT_POSITIVE",
    "FLAG_NO_CONTACT",
    "FLAG_NO_CROSSING",
    "FLAG_SEVERAL_CROSSINGS",
    "FREE_TOLERANCE",
    "MIN_SENSITIVITY",
    "MODE_TOLERANCE",
    "R_GRID",
    "ContactResonanceResult",
    "flag_names",
    "invert_contact_resonance",
    "kappa_on_branch",
]

#: κ is <= 0, NaN or infinite.
FLAG_NOT_POSITIVE = 1
#: f below the mode's free frequency: only a negative κ reproduces it.
FLAG_BELOW_FREE = 2
#: f at or above the κ → ∞ limit of the mode for this tip position and springs (κ = NaN).
FLAG_ABOVE_PINNED = 4
#: d ln f / d ln κ < MIN_SENSITIVITY: tip near a node of the mode, κ saturated, or κ → 0.
FLAG_INSENSITIVE = 8
#: two-mode inversion: no crossing κ_a(r) = κ_b(r) with r in [0.5, 1].
FLAG_NO_CROSSING = 16
#: two-mode inversion: more than one crossing with r in [0.5, 1]; information, not a failure:
#: the largest r was taken, the next is in ``tip_position_other`` and ``kappa_other``.
FLAG_SEVERAL_CROSSINGS = 32
#: a frequency is NaN (not measured).
FLAG_NOT_MEASURED = 64
#: the modes disagree on κ by more than ``mode_tolerance`` (module notes: three modes).
FLAG_INCONSISTENT_MODES = 128
#: f at the mode's free frequency within :data:`FREE_TOLERANCE` (relative, either way): κ = 0.
FLAG_NO_CONTACT = 256

_NAMES = (
    (FLAG_NOT_POSITIVE, "not_positive"),
    (FLAG_BELOW_FREE, "below_free"),
    (FLAG_ABOVE_PINNED, "above_pinned"),
    (FLAG_INSENSITIVE, "insensitive"),
    (FLAG_NO_CROSSING, "no_crossing"),
    (FLAG_SEVERAL_CROSSINGS, "several_crossings"),
    (FLAG_NOT_MEASURED, "not_measured"),
    (FLAG_INCONSISTENT_MODES, "inconsistent_modes"),
    (FLAG_NO_CONTACT, "no_contact"),
)

#: Line below which a mode is "insensitive": s = d ln f / d ln κ < 1e-3 means a relative
#: frequency error of 1e-5 (a few Hz at a few hundred kHz, typical of contact-resonance
#: tracking) becomes > 1 % in κ. Reached near a node of the mode, deep in saturation
#: (κ ≳ 1e3 for mode 1 at r = 1) and, trivially, as κ → 0 (the contact hardly shifts f).
MIN_SENSITIVITY = 1e-3

#: Relative distance from a mode's free frequency (f_n⁰ = f_ref (β_n⁰/β_ref)², the model's
#: free lever), either way, within which a contact resonance is the free lever itself: κ = 0,
#: flagged ``no_contact``, instead of ``below_free`` and a NaN (below) or a κ of rounding
#: (above). A free resonance is calibrated to about 1e-6 of f (a fraction of a Hz at a few
#: hundred kHz, from a thermal spectrum or a sweep) and drifts by as much either way; a contact
#: resonance that close to it, or equal to it, is no contact within that precision (the κ it
#: would give, ~1e-6, is far below the ``insensitive`` line anyway). The band is symmetric
#: because f/f_free is computed: a frequency equal to the free one comes out 1 ± 2e-16 as the
#: rounding of the model's f_n⁰ falls. Further below, no κ >= 0 explains f: ``below_free`` (a
#: wrong free frequency, a different mode or drift).
FREE_TOLERANCE = 1e-6

#: Flags of a mode that no positive κ reproduces at the tip position (it contradicts r).
_CONTRADICTS = FLAG_NOT_POSITIVE | FLAG_BELOW_FREE | FLAG_ABOVE_PINNED

#: Default relative disagreement of κ between modes beyond which a pixel is flagged
#: ``inconsistent_modes`` (module notes: the model error of a real lever, not the noise).
MODE_TOLERANCE = 0.05

#: Grid of tip positions scanned by the two-mode inversion (step 0.005, one point past 1).
#: A crossing in (1, 1.005], past the free end by less than one step, is the tip at the end
#: seen through the noise of the frequencies (a tip at r = 1 puts the crossing on either side
#: of 1 at random): it is taken as r = 1, its κ evaluated there, when the two modes agree
#: there within :data:`END_TOLERANCE`.
R_GRID = np.append(np.linspace(0.01, 1.0, 199), 1.005)
R_GRID.setflags(write=False)

#: Largest relative disagreement of the two modes' κ at r = 1 for a crossing past the free end
#: (:data:`R_GRID`) to count as the tip at the end. Frequency errors of ~1e-5 (tracking) move κ
#: by ~1e-5/s, below 1e-3 for sensitivities s >= 1e-2; a crossing that truly lies past the end
#: (the lever's saturated modes meeting there) disagrees by per cent at r = 1 and is rejected.
END_TOLERANCE = 1e-3


def flag_names(flags: int) -> list[str]:
    """Short names of the bits set in one ``flags`` value (e.g. ["above_pinned"])."""
    return [name for bit, name in _NAMES if int(flags) & bit]


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, repr=False)
class ContactResonanceResult(Summarised):
    """Result of :func:`invert_contact_resonance`; arrays have the pixel shape (...) unless noted.

    Attributes
    ----------
    kappa : κ = k*/k_c, the contact's spring (mean over the usable modes with r known; the
        crossing for two modes); with a Q the spring of the Kelvin-Voigt contact, Re κ_c +
        Im κ_c/(2Q) (module notes: damping); 0 where the pixel is flagged ``no_contact``
    k_star : κ k_c, N/m
    tip_position : r = L1/L (given, or the chosen crossing; NaN if none)
    sigma : contact damping k_c Im κ_c/ω, N s/m (mean over the usable modes); NaN without Q
    flags : int bit mask, OR over the modes used (FLAG_* constants, :func:`flag_names`)
    candidates, candidate_kappa : (..., K) every crossing r and its κ, NaN-padded (K = 0 when r
        was given)
    kappa_modes, sigma_modes, flags_modes : (..., n_modes) per measured column
    mode_spread : (max − min)/κ of the per-mode κ (and κ) over the modes that check it (module
        notes); inf where a further mode contradicts r; NaN where no mode checks
    averaged_modes : (..., n_modes) bool, the modes whose κ was averaged into ``kappa``
    modes : the mode number of each column
    normalisation : "global" or "modewise" (from the cantilever)
    method : what was done, in words
    tip_position_other, kappa_other : the crossing not taken, r and κ (the largest other r in
        [0.5, 1]; NaN when there is none or r was given): the alternative of a pixel flagged
        ``several_crossings``
    """

    kappa: np.ndarray
    k_star: np.ndarray
    tip_position: np.ndarray
    sigma: np.ndarray
    flags: np.ndarray
    candidates: np.ndarray
    candidate_kappa: np.ndarray
    kappa_modes: np.ndarray
    sigma_modes: np.ndarray
    flags_modes: np.ndarray
    mode_spread: np.ndarray
    averaged_modes: np.ndarray
    modes: tuple[int, ...]
    normalisation: str
    method: str
    tip_position_other: np.ndarray
    kappa_other: np.ndarray

    def _facts(self) -> list[tuple[str, str]]:
        """The method and modes, κ, k* (N/m), r, σ (N s/m, with Q) and the flagged pixels."""
        facts = [
            ("", self.method),
            ("modes", ", ".join(str(m) for m in self.modes)),
            ("κ", values(self.kappa)),
            ("k*", values(self.k_star, "N/m")),
            ("r", values(self.tip_position)),
        ]
        if np.any(np.isfinite(self.sigma)):
            facts.append(("σ", values(self.sigma, "N s/m")))
        return [*facts, ("flagged", flagged(self.flags))]


def _closed_form(g) -> bool:
    """Whether the tip springs (g_yy, g_yθ, g_θθ) are a normal spring only: κ in closed form."""
    return not (np.any(g[1]) or np.any(g[2]))


def _roots(beta, r, g, trig=None):
    """The (up to two) roots κ of det M(β, ·) = 0; the second is NaN where det M is linear,
    None for a normal spring only (one root, the closed form: no array of NaN to select from;
    ``trig``: its :func:`~contactres.resonators._cantilever.normal_trig`, if the caller has it)."""
    g_yy, g_yt, g_tt = g
    if _closed_form(g):
        return normal_kappa(beta, r, trig) / g_yy, None  # closed form; the tilt leaves k* cos²φ
    a, b, c = determinant_coefficients(beta, r, g)
    quad = (g_yy * g_tt - g_yt**2) > 0  # det of the tip stiffness: α η² (module notes)
    a = np.where(quad, a, 0.0)
    s = np.sqrt((b * b - 4.0 * a * c).astype(complex))
    s = np.where((np.conj(b) * s).real >= 0, s, -s)  # no cancellation in b + s
    qq = -0.5 * (b + s)
    k1 = np.where(quad, qq / np.where(quad, a, 1.0), -c / b)
    k2 = np.where(quad, c / qq, np.nan)
    if not (np.iscomplexobj(beta) and np.any(np.imag(beta))):
        k1, k2 = k1.real, k2.real  # real β: keep the real roots (complex pairs are unphysical)
    return k1, k2


def kappa_on_branch(beta, mode, tip_position, g, trig=None, n0=None):
    """κ of mode ``mode`` (1-based) at wavenumber β, and its flags (module notes: branch).

    Parameters
    ----------
    beta : real or complex β, broadcasts with mode, tip_position and the g's
    mode : int array, 1-based
    tip_position : r (not validated here; may exceed 1 slightly in the two-mode scan)
    g : (g_yy, g_yθ, g_θθ) of :func:`~contactres.resonators._cantilever.tip_coefficients`
    trig : :func:`~contactres.resonators._cantilever.normal_trig` of β and tip_position, or
        None (a normal spring only: the closed form then takes its functions from it)
    n0 : int array, optional
        ``np.searchsorted(FREE_ROOTS, np.real(beta))``, the free modes below β, if the caller
        has it (shared with :func:`_sensitivity_flags`); None: searched here.

    Returns
    -------
    (kappa, flags) : κ (dtype of β), int flags (FLAG_NOT_POSITIVE, FLAG_BELOW_FREE,
        FLAG_ABOVE_PINNED; FLAG_INSENSITIVE is added by the caller)
    """
    k1, k2 = _roots(beta, tip_position, g, trig)
    if n0 is None:
        n0 = np.searchsorted(FREE_ROOTS, np.real(beta))  # free modes below β (N₀)
    j = n0 - np.asarray(mode)
    if k2 is None:  # one root: the selection below with k2 = NaN, in a third of the passes
        re = np.real(k1)
        kappa = np.where(np.where(j < 0, re <= 0, (j == 0) & (re > 0)), k1, np.nan)
        flags = np.where(j < 0, FLAG_BELOW_FREE, 0) | np.where(
            (j >= 1) | ((j == 0) & ~(re > 0)), FLAG_ABOVE_PINNED, 0
        )
        ok = np.isfinite(kappa) & (np.real(kappa) > 0)
        return kappa, flags | np.where(ok, 0, FLAG_NOT_POSITIVE)
    p1, p2 = np.real(k1) > 0, np.real(k2) > 0
    first_small = ~p2 | (p1 & (np.real(k1) <= np.real(k2)))
    small = np.where(p1 & first_small, k1, np.where(p2, k2, np.nan))
    large = np.where(p1 & p2, np.where(first_small, k2, k1), np.nan)
    n_pos = p1.astype(int) + p2
    # Below the free frequency: continue the branch through κ = 0 (largest non-positive root).
    n1, n2 = np.real(k1) <= 0, np.real(k2) <= 0
    below = np.where(n1 & (~n2 | (np.real(k1) >= np.real(k2))), k1, np.where(n2, k2, np.nan))
    kappa = np.where(j < 0, below, np.where(j == 0, small, np.where(j == 1, large, np.nan)))
    flags = np.where(j < 0, FLAG_BELOW_FREE, 0) | np.where(
        (j >= 0) & (j >= n_pos), FLAG_ABOVE_PINNED, 0
    )
    ok = np.isfinite(kappa) & (np.real(kappa) > 0)
    return kappa, flags | np.where(ok, 0, FLAG_NOT_POSITIVE)


#: Relative step of the central difference in β, and the relative half-width of the band about
#: a free root in which a mode is flagged insensitive whatever its slope.
_EDGE = 1e-6


def _left_interval(n0: np.ndarray, *points: np.ndarray) -> np.ndarray:
    """Whether any of ``points`` lies in another interval between free roots than the one of
    index ``n0`` (``np.searchsorted(FREE_ROOTS, x) != n0`` for some x of ``points``).

    The index of x (the number of roots below it; NaN is above every root, numpy's order) is
    ``n0`` exactly when the root below, ``FREE_ROOTS[n0 - 1]``, is less than x and the root
    above, ``FREE_ROOTS[n0]``, is not (each where it exists): comparisons with the two roots
    about the interval, gathered once, in place of a binary search a point (the flags' three
    searches were ~4 % of the instructions of ``afm invert`` of a 512² map)."""
    below = np.concatenate(([np.nan], FREE_ROOTS)).take(n0)  # NaN: no root below (never >=)
    above = np.concatenate((FREE_ROOTS, [np.inf])).take(n0)
    last = n0 == FREE_ROOTS.size  # no root above: no point is beyond it
    out = np.zeros(np.shape(n0), dtype=bool)
    for x in points:  # a loop over the two ends of the band, not over pixels
        out |= (below >= x) | ~((above >= x) | last)
    return out


def _sensitivity_flags(beta, mode, r, g, kappa, trig=None, n0=None):
    """FLAG_INSENSITIVE where s = d ln f / d ln κ = 2κ/(β dκ/dβ) < MIN_SENSITIVITY.

    ``kappa`` is κ on mode ``mode``'s branch (NaN off it). A normal spring only: β dκ/dβ =
    κ L from the closed form's derivative (:func:`normal_log_slope`, one evaluation); with
    lateral springs a central difference of κ on the branch (two more roots of det M). Either
    way a mode with Re β within a relative ``_EDGE`` of a free root is flagged. ``trig`` and
    ``n0``: as for :func:`kappa_on_branch` (the closed form's functions and the free modes
    below β, shared with κ's).
    """
    if _closed_form(g):  # L of κ/g_yy is L of κ: the tilt's constant factor drops out
        slope = np.real(kappa * normal_log_slope(beta, r, trig))  # β dκ/dβ; NaN off the branch
        s = 2.0 * np.real(kappa) / slope
        weak = ~(np.abs(s) >= MIN_SENSITIVITY)  # NaN (at κ = 0 or ∞) counts as weak
        # A damped mode whose Re β sits within a relative 1e-6 of a free root carries no κ:
        # what is left of κ there is the damping's (a pixel of k* = 0.28 N/m read 31 N/m from
        # such a mode at Q = 22). The central difference flags it because a neighbour leaves
        # the branch; the closed-form slope does not see that edge, so it is flagged here.
        if n0 is None:
            n0 = np.searchsorted(FREE_ROOTS, np.real(beta))
        edge = _left_interval(n0, np.real(beta * (1.0 + _EDGE)), np.real(beta * (1.0 - _EDGE)))
        return np.where((weak | edge) & np.isfinite(kappa), FLAG_INSENSITIVE, 0)
    eps = _EDGE  # central difference: truncation ~eps², rounding ~1e-16/eps, both far below 1e-3
    k_hi, _ = kappa_on_branch(beta * (1.0 + eps), mode, r, g)
    k_lo, _ = kappa_on_branch(beta * (1.0 - eps), mode, r, g)
    slope = np.real(k_hi - k_lo) / (2.0 * eps)  # β dκ/dβ
    s = 2.0 * np.real(kappa) / slope
    weak = ~(np.abs(s) >= MIN_SENSITIVITY)  # NaN (no neighbour on the branch) counts as weak
    return np.where(weak & np.isfinite(kappa), FLAG_INSENSITIVE, 0)


def _sum_modes(a):
    """``a.sum(axis=-1)`` over the few modes (the last axis; bools: counts), a column at a
    time: numpy's reduction adds the columns in order onto a zero, so these are its numbers
    bit for bit, without its buffered iteration over rows of two or three elements (the
    inversion's reductions over the modes were ~7 % of an afm invert of a 512² map).
    From 8 modes on, numpy sums by pairs (eight partial sums), so its own reduction is used."""
    if a.shape[-1] >= 8:
        return a.sum(axis=-1)
    total = np.zeros(a.shape[:-1], dtype=int if a.dtype == bool else a.dtype)
    for j in range(a.shape[-1]):  # a loop over the modes (<= 8), not over pixels
        total += a[..., j]
    return total


def _reduce_modes(ufunc, a):
    """``ufunc.reduce(a, axis=-1)`` over the modes, a column at a time in their order (as
    :func:`_sum_modes`), for ``np.maximum``, ``np.minimum`` (NaN-free input: numpy's reduction
    returns any NaN as +NaN), ``np.bitwise_or`` and ``np.logical_or``."""
    out = a[..., 0].copy()
    for j in range(1, a.shape[-1]):
        ufunc(out, a[..., j], out=out)
    return out


def _mean_where(values, use):
    n = _sum_modes(use)
    total = _sum_modes(np.where(use, values, 0.0))
    return np.where(n > 0, total / np.maximum(n, 1), np.nan)


def _spring(kappa, half_q):
    """The contact's spring k*/k_c of a complex κ_c at ω_c = ω(1 + i/(2Q)) (module notes:
    damping): Re κ_c + Im κ_c/(2Q); ``half_q`` = 1/(2Q), 0 without a Q (then Re κ_c)."""
    return np.real(kappa) + np.imag(kappa) * half_q


def _crossings(beta_a, mode_a, beta_b, mode_b, g, half_q=(0.0, 0.0)):
    """Every crossing κ_a(r) = κ_b(r) of the springs (:func:`_spring`) on R_GRID, per pixel.

    Flat arrays of length N (``half_q``: 1/(2Q) of the two modes, scalars or length N).
    Returns (pixel index, r, κ) of the accepted crossings (flat, any order); r in (1, 1.005]
    is returned as 1 with its κ there (:data:`R_GRID`).
    """
    n = beta_a.shape[0]
    col = [x.reshape(-1, 1) if np.ndim(x) else x for x in (beta_a, mode_a, beta_b, mode_b)]
    col += [np.reshape(x, (-1, 1)) if np.ndim(x) else x for x in half_q]
    gc = tuple(x.reshape(-1, 1) if np.ndim(x) else x for x in g)

    def delta(rows, r):
        gg = tuple(x[rows] if np.ndim(x) else x for x in gc)
        c = [x[rows] if np.ndim(x) else x for x in col]
        ka = _spring(kappa_on_branch(c[0], c[1], r, gg)[0], c[4])
        kb = _spring(kappa_on_branch(c[2], c[3], r, gg)[0], c[5])
        return ka - kb, ka, kb

    pix, lo = [], []
    chunk = max(1, 1_000_000 // R_GRID.size)  # bounded memory: a loop over chunks of pixels
    for start in range(0, n, chunk):
        rows = np.arange(start, min(n, start + chunk))
        d, _, _ = delta(rows, R_GRID[None, :])
        s = np.sign(d)
        change = (s[:, :-1] * s[:, 1:] < 0) | (s[:, :-1] == 0)  # NaN ends never count
        p, i = np.nonzero(change)
        pix.append(rows[p])
        lo.append(R_GRID[i])
    pix = np.concatenate(pix).astype(int)
    lo = np.concatenate(lo)
    hi = lo + np.diff(R_GRID)[np.searchsorted(R_GRID, lo)]
    f_lo = delta(pix, lo[:, None])[0]
    lo, hi = lo[:, None], hi[:, None]
    for _ in range(55):  # 55 halvings of a 0.005 bracket: r to the last bit
        mid = 0.5 * (lo + hi)
        f_mid = delta(pix, mid)[0]
        same = np.sign(f_mid) == np.sign(f_lo)
        lo, f_lo = np.where(same, mid, lo), np.where(same, f_mid, f_lo)
        hi = np.where(same, hi, mid)
    r = 0.5 * (lo + hi)
    d, ka, kb = delta(pix, r)
    ok = (
        np.isfinite(d)
        & (ka > 0)
        & (kb > 0)
        & (np.abs(d) <= 1e-6 * (np.abs(ka) + np.abs(kb)))  # rejects poles (|Δ| → ∞)
    )[:, 0]
    past = r > 1.0  # past the free end by less than one step: the tip at the end (R_GRID)
    if np.any(past):
        d_1, ka_1, kb_1 = delta(pix, np.minimum(r, 1.0))
        ka, kb = np.where(past, ka_1, ka), np.where(past, kb_1, kb)
        at_end = np.abs(d_1) <= END_TOLERANCE * 0.5 * (np.abs(ka_1) + np.abs(kb_1))
        ok &= ~past[:, 0] | at_end[:, 0]
    kappa = 0.5 * (ka + kb)[:, 0]
    return pix[ok], np.minimum(r[ok, 0], 1.0), kappa[ok]


def invert_contact_resonance(
    cantilever: Cantilever,
    frequencies,
    tip_position=None,
    q_factors=None,
    lateral_ratio=0.0,
    tip_height=0.0,
    tilt=0.0,
    modes=None,
    mode_tolerance: float = MODE_TOLERANCE,
) -> ContactResonanceResult:
    """κ = k*/k_c (and r, σ) from contact-resonance frequencies, pixel by pixel, vectorised.

    Parameters
    ----------
    cantilever : the free lever (free frequencies, k_c = 3EI/L³, normalisation, free Q)
    frequencies : (..., n_modes) contact resonances, Hz (NaN = not measured)
    tip_position : r = L1/L in (0, 1], broadcasting with the pixels; None: from two modes
        (the first two measured columns of each pixel), module notes
    q_factors : (..., n_modes) contact-resonance quality factors, or None (σ = NaN); with
        them κ is the spring of a Kelvin-Voigt contact (module notes: damping)
    lateral_ratio, tip_height, tilt : α = k_lat/k*, η = h/L, φ (degrees from the sample's
        surface, > 0 with the free end nearer the sample), broadcasting with the pixels
        (:func:`~contactres.resonators._cantilever.tip_coefficients`)
    modes : mode number (1-based) of each column; default 1..n_modes
    mode_tolerance : relative disagreement of κ between modes beyond which a pixel is flagged
        ``inconsistent_modes``; with r unknown it also picks the crossing that a third mode
        confirms (module notes: three modes). Default :data:`MODE_TOLERANCE` (5 %).

    Returns
    -------
    ContactResonanceResult
        A frequency at its mode's free one within :data:`FREE_TOLERANCE` (relative, either
        way) gives κ = 0 flagged ``no_contact``; two modes with several crossings give the largest
        r in [0.5, 1], flagged ``several_crossings``, the next in ``tip_position_other``.
    """
    f = np.asarray(frequencies, dtype=float)
    f = f[None] if f.ndim == 0 else f
    n_cols = f.shape[-1]
    modes = tuple(range(1, n_cols + 1)) if modes is None else tuple(int(m) for m in modes)
    if len(modes) != n_cols or min(modes) < 1 or max(modes) > len(FREE_ROOTS) - 2:
        raise ContactresInputError(
            f"modes must give a mode (1..8) per column ({n_cols}), got {modes!r}"
        )
    if not 0 < mode_tolerance < np.inf:
        raise ContactresInputError(f"mode_tolerance must be > 0 (relative), got {mode_tolerance!r}")
    measured = ~np.isnan(f)
    if np.any(~np.isfinite(f[measured]) | (f[measured] <= 0)):
        raise ContactresInputError("frequencies must be > 0 and finite (Hz) or NaN (not measured)")
    q = None
    no_q = np.ones(f.shape, bool)
    if q_factors is not None:
        q = np.broadcast_to(np.asarray(q_factors, dtype=float), f.shape)
        no_q = np.isnan(q)  # a cell without a Q: real ω there, σ unknown
        if np.any(~(q[measured & ~no_q] > 0) | ~np.isfinite(q[measured & ~no_q])):
            raise ContactresInputError("q_factors must be finite and > 0 (dimensionless) or NaN")
        q = np.where(no_q, np.inf, q)
    g = tuple(np.asarray(x)[..., None] for x in tip_coefficients(lateral_ratio, tip_height, tilt))
    mode_arr = np.array(modes)
    k_c = cantilever.spring_constant
    half_q = 0.0 if q is None else 0.5 / q  # 1/(2Q); 0 where no Q (q = inf there)
    with np.errstate(all="ignore"):  # NaN pixels and poles are flagged, not warned about
        beta = beta_from_frequency(cantilever, f, mode_arr, q)
        if tip_position is not None:
            r = np.asarray(tip_position, dtype=float)
            bad = ~(r > 0) | ~(r <= 1)
            if np.any(bad):
                shown = float(r[bad].ravel()[0]) if r.ndim else float(r)
                raise ContactresInputError(f"tip_position must be in (0, 1] (L1/L), got {shown!r}")
            r = r[..., None]
            pix = np.broadcast_shapes(f.shape[:-1], r.shape[:-1])
            cand = np.full((*pix, 0), np.nan)
            cand_k = cand
            other = other_k = np.full(pix, np.nan)
            method = "tip position given"
        else:
            if n_cols < 2:
                raise ContactresInputError("tip_position=None needs two measured modes (columns)")
            r, cand, cand_k, n_win, other, other_k = _two_modes(
                beta, mode_arr, measured, g, mode_tolerance, half_q
            )
            method = (
                "two modes (first two measured columns), tip position from κ_a(r) = κ_b(r) "
                "(Hurley & Turner 2007): the largest crossing r in [0.5, 1] (that further "
                "modes confirm, where measured)"
            )
        # A normal spring only: κ's closed form and its slope share their 12 transcendental
        # functions a pixel (evaluated once: a fifth of a map's inversion; the same numbers).
        trig = normal_trig(beta, r) if _closed_form(g) else None
        n0 = np.searchsorted(FREE_ROOTS, np.real(beta))  # free modes below β, for both
        kappa_m, flags_m = kappa_on_branch(beta, mode_arr, r, g, trig, n0)
        flags_m = flags_m | _sensitivity_flags(beta, mode_arr, r, g, kappa_m, trig, n0)
        del trig  # 12 arrays of the pixels' size
        # At the free frequency within FREE_TOLERANCE either way (the ratio is 1 ± rounding
        # when f is the free one): no contact, κ = 0 exactly.
        # Compared in real frequencies: the model's free f_n = f_ref (β_n⁰/β_ref)², whatever Q.
        b_ref, w_ref = cantilever.reference(mode_arr)
        free = f / (np.real(w_ref) / (2.0 * np.pi) * (FREE_ROOTS[mode_arr - 1] / b_ref) ** 2)
        free = measured & (np.abs(free - 1.0) <= FREE_TOLERANCE)
        kappa_m = np.where(free, 0.0, kappa_m)
        flags_m = np.where(free, FLAG_NO_CONTACT, flags_m)
        flags_m = np.where(measured, flags_m, FLAG_NOT_MEASURED | FLAG_NOT_POSITIVE)
        spring_m = _spring(kappa_m, half_q)
        sigma_m = k_c * np.imag(kappa_m) / (2.0 * np.pi * f) if q is not None else None
        if sigma_m is not None:
            sigma_m = np.where(no_q, np.nan, sigma_m)
        usable = (flags_m & ~FLAG_NO_CONTACT) == 0  # κ = 0 of no contact is a value
        if tip_position is not None:
            kappa = _mean_where(spring_m, usable)
            averaged = usable
            used = measured
        else:
            used = _first_two(np.broadcast_to(measured, kappa_m.shape))[1]
            kappa = _mean_where(spring_m, used)
            averaged = used
        flags = _reduce_modes(np.bitwise_or, np.where(used, flags_m, 0))
        none = ~_reduce_modes(np.logical_or, used)
        flags = np.where(none, FLAG_NOT_MEASURED | FLAG_NOT_POSITIVE, flags)
        # The modes that check κ: the usable ones beyond the crossing's two (r solved), or all
        # usable ones when there are at least two (r given).
        # A further measured mode that no κ > 0 reproduces at r (below free, above pinned)
        # contradicts r: an infinite spread, not a missing check.
        wrong = measured & ~used & ((flags_m & _CONTRADICTS) != 0)
        if tip_position is None:
            check = (usable & ~used) | wrong
        else:
            check = usable & (_sum_modes(usable) > 1)[..., None]
        k_chk = np.where(wrong, np.inf, spring_m)  # NaN-free where checked: usable is κ finite
        hi = np.maximum(_reduce_modes(np.maximum, np.where(check, k_chk, -np.inf)), kappa)
        lo = np.minimum(_reduce_modes(np.minimum, np.where(check, k_chk, np.inf)), kappa)
        checked = _reduce_modes(np.logical_or, check)
        spread = np.where(checked & np.isfinite(kappa), (hi - lo) / kappa, np.nan)
        flags = flags | np.where(spread > mode_tolerance, FLAG_INCONSISTENT_MODES, 0)
        if tip_position is None:
            flags = flags | np.where(n_win == 0, FLAG_NO_CROSSING, 0)
            flags = flags | np.where(n_win > 1, FLAG_SEVERAL_CROSSINGS, 0)
            flags = flags | np.where(_sum_modes(measured) < 2, FLAG_NOT_MEASURED, 0)
        if sigma_m is None:
            sigma_m = np.full(kappa_m.shape, np.nan)
            sigma = np.full(kappa.shape, np.nan)
        else:
            sigma = _mean_where(sigma_m, usable if tip_position is not None else used)
    normal = "closed form" if _closed_form(g) else "4x4 determinant"
    if q is not None:
        method += "; with Q: Kelvin-Voigt contact, k* = k_c(Re κ + Im κ/(2Q)), σ = k_c Im κ/ω"
    return ContactResonanceResult(
        kappa=kappa,
        k_star=kappa * k_c,
        tip_position=np.broadcast_to(r[..., 0], kappa.shape).copy(),
        sigma=sigma,
        flags=flags.astype(int),
        candidates=cand,
        candidate_kappa=cand_k,
        kappa_modes=spring_m,
        sigma_modes=sigma_m,
        flags_modes=flags_m.astype(int),
        mode_spread=spread,
        averaged_modes=np.broadcast_to(averaged, kappa_m.shape).copy(),
        modes=modes,
        normalisation=cantilever.normalisation,
        method=f"{method}; κ per mode by the {normal}; normalisation {cantilever.normalisation}",
        tip_position_other=np.broadcast_to(other, kappa.shape).copy(),
        kappa_other=np.broadcast_to(other_k, kappa.shape).copy(),
    )


def _first_two(measured):
    """Indices (..., 2) of the first two measured columns of each pixel, and the mask of those
    that are measured (the two modes whose crossing gives r)."""
    first_two = np.argsort(~measured, axis=-1, kind="stable")[..., :2]
    mask = np.zeros(measured.shape, bool)
    np.put_along_axis(mask, first_two, True, axis=-1)
    return first_two, mask & measured


def _two_modes(beta, mode_arr, measured, g, tolerance, half_q):
    """(r[..., None], candidates, candidate κ, number of eligible crossings, the other r and its
    κ) of the two-mode inversion; further measured modes choose among the crossings (module
    notes). ``half_q``: 1/(2Q) per cell (or 0), for the Kelvin-Voigt spring of each mode."""
    shape = np.broadcast_shapes(beta.shape, *(np.shape(x) for x in g))
    pix_shape = shape[:-1]
    beta = np.broadcast_to(beta, shape)
    meas = np.broadcast_to(measured, shape)
    first_two, crossing = _first_two(meas)
    b2 = np.take_along_axis(beta, first_two, axis=-1).reshape(-1, 2)
    m2 = mode_arr[first_two].reshape(-1, 2)
    w = np.broadcast_to(half_q, shape)
    w2 = np.take_along_axis(w, first_two, axis=-1).reshape(-1, 2)
    gf = tuple(np.broadcast_to(x[..., 0], pix_shape).reshape(-1) for x in g)
    n = b2.shape[0]
    pix, r, kap = _crossings(b2[:, 0], m2[:, 0], b2[:, 1], m2[:, 1], gf, (w2[:, 0], w2[:, 1]))
    order = np.lexsort((r, pix))
    pix, r, kap = pix[order], r[order], kap[order]
    counts = np.bincount(pix, minlength=n)
    k_max = int(counts.max(initial=0))
    rank = np.arange(pix.size) - np.repeat(np.cumsum(counts) - counts, counts)
    cand = np.full((n, k_max), np.nan)
    cand_k = np.full((n, k_max), np.nan)
    cand[pix, rank] = r
    cand_k[pix, rank] = kap
    in_win = (cand >= 0.5) & (cand <= 1.0)
    # Further modes: κ of each at every candidate r, its largest deviation from the crossing's.
    extra = (meas & ~crossing).reshape(n, -1)
    dev = np.full((n, k_max), -np.inf)
    gk = tuple(x[:, None] for x in gf)
    w_all = w.reshape(n, -1)
    for c in np.flatnonzero(extra.any(axis=0)):  # a loop over modes (<= 8), not over pixels
        k_c, f_c = kappa_on_branch(beta.reshape(n, -1)[:, c, None], mode_arr[c], cand, gk)
        k_c = np.where((f_c & _CONTRADICTS) != 0, np.inf, _spring(k_c, w_all[:, c, None]))
        dev = np.where(extra[:, c, None], np.fmax(dev, np.abs(k_c / cand_k - 1.0)), dev)
    checked = in_win & np.isfinite(dev)
    consistent = checked & (dev <= tolerance)
    decide = consistent.any(axis=-1, keepdims=True)  # else: the two-mode rule, flagged later
    eligible = np.where(decide, consistent, in_win)
    chosen = np.max(np.where(eligible, cand, -np.inf), axis=-1, initial=-np.inf)
    # The crossing not taken: the largest other r in the window (the rejected one when a
    # further mode decided).
    rest = in_win & (cand != chosen[:, None])
    other = np.max(np.where(rest, cand, -np.inf), axis=-1, initial=-np.inf)
    at = np.argmax(np.where(rest, cand, -np.inf), axis=-1) if k_max else np.zeros(n, int)
    other_k = np.take_along_axis(cand_k, at[:, None], axis=-1)[:, 0] if k_max else other
    other_k = np.where(np.isfinite(other), other_k, np.nan)
    chosen = np.where(np.isfinite(chosen), chosen, np.nan)
    other = np.where(np.isfinite(other), other, np.nan)
    return (
        chosen.reshape((*pix_shape, 1)),
        cand.reshape((*pix_shape, k_max)),
        cand_k.reshape((*pix_shape, k_max)),
        eligible.sum(axis=-1).reshape(pix_shape),
        other.reshape(pix_shape),
        other_k.reshape(pix_shape),
    )
