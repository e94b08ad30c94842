"""Contact-resonance AFM: an Euler-Bernoulli cantilever coupled to the sample at its tip (forward).

The lever (length L, bending stiffness EI, mass per length ρA) is clamped at x = 0 and free at
x = L; the tip sits at L1 = r L (r = ``tip_position`` in (0, 1]). With ξ = x/L and
β⁴ = ρA ω² L⁴ / EI, the mode shape on each segment is A cos βξ + B sin βξ + C cosh βξ + D sinh βξ
(U. Rabe, K. Janser, W. Arnold, "Vibrations of free and surface-coupled atomic force microscope
cantilevers: theory and experiment", Rev. Sci. Instrum. 67, 3281 (1996)).

Tip springs (derived here, not taken from the paper). The beam frame: x along the lever from
the clamp to the free end, y normal to it pointing away from the sample; the tip hangs on the
sample's side, its apex a height h below the axis. A rotation θ = y′ of the cross-section
moves the apex along the axis by hθ, so its displacement in the beam frame is
(u_x, u_y) = (hθ, y). The tilt φ (``tilt``, degrees) is the angle from the sample's surface to
the lever's axis, **positive when the free end is nearer the sample than the clamp** (the
usual mounting, about 10-12°): then the sample's outward normal is n = (−sin φ, cos φ) and its
tangent t = (cos φ, sin φ) in the beam frame, and a rotation θ > 0 pushes the apex towards the
sample (u·n = y cos φ − hθ sin φ). A lever mounted the other way (free end farther from the
sample) is not modelled; reading one convention for the other changes κ by per cent where the
lateral spring differs from the normal one (α ≠ 1; at α = 1 the tilt drops out). A normal
spring k* and a lateral spring k_lat = α k* (α = ``lateral_ratio``) store
½ k* (u·n)² + ½ k_lat (u·t)², i.e. a 2 x 2 stiffness on (y, θ) at L1, written with
k_c = 3EI/L³ and η = h/L (``tip_height``) as

    K_yy = k* g_yy,  K_yθ = k* L g_yθ,  K_θθ = k* L² g_θθ,
    g_yy = cos²φ + α sin²φ,  g_yθ = −η sin φ cos φ (1 − α),  g_θθ = η² (sin²φ + α cos²φ).

Its determinant is η² α k*² L²: the model is quadratic in κ = k*/k_c only when α η² > 0.
The variation of ½∫EI y″² + ½ qᵀKq − ½ω²∫ρA y² gives at ξ = r (derivatives in ξ, κ = k*/k_c)

    [y] = [y′] = 0,   y″(r⁺) − y″(r⁻) = 3κ (g_yθ y + g_θθ y′),
    y‴(r⁺) − y‴(r⁻) = −3κ (g_yy y + g_yθ y′),

with y = y′ = 0 at ξ = 0 and y″ = y‴ = 0 at ξ = 1. Clamped and free-end functions on the two
segments leave a 4 x 4 determinant in (β, κ): :func:`characteristic_determinant`.

Normal spring only (α = 0, η = 0 or φ = 0, with k* cos²φ as the effective spring), eliminating
the unknowns by hand gives the closed form (Rabe et al. 1996, Eq. 8, rewritten for the *end*
stiffness k_c = 3EI/L³; the paper normalises by 3EI/L1³, which differs by r³)::

    κ = 2 β³ (1 + cos β cosh β) / (3 D),    p = βr,  q = β(1 − r),
    D = (sin q cosh q − cos q sinh q)(1 − cos p cosh p)
        − (sin p cosh p − cos p sinh p)(1 + cos q cosh q)

(:func:`normal_kappa`). κ = 0 gives the free lever, 1 + cos β cosh β = 0; D = 0 is the limit
κ → ∞ (at r = 1: tan β = tanh β, the pinned end).

Frequencies map to β through the free lever: ``global``, β = β₁⁰ √(ω/ω₁) with the first free
mode only (ideal beam, f_n/f₁ = (β_n⁰/β₁⁰)²); ``modewise``, β_n = β_n⁰ √(ω/ω_n) with the mode's
own free frequency (real levers whose ratios differ from 6.267, 17.55). A quality factor Q
enters as a complex ω = 2πf (1 + i/(2Q)) (the free lever's ω_ref likewise when its Q is known).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..validation import nonnegative, positive

__all__ = [
    "FREE_ROOTS",
    "PINNED_ROOTS",
    "Cantilever",
    "beta_from_frequency",
    "characteristic_determinant",
    "contact_frequencies",
    "determinant_coefficients",
    "determinant_from_coefficients",
    "frequency_from_beta",
    "normal_kappa",
    "normal_log_slope",
    "normal_trig",
    "tip_coefficients",
]

NORMALISATIONS = ("global", "modewise")


def _newton_roots(f, df, guesses):
    x = np.asarray(guesses, dtype=float)
    for _ in range(30):  # quadratic convergence from the asymptotic guesses: a handful suffices
        x = x - f(x) / df(x)
    x.setflags(write=False)
    return x


#: β_n⁰ of the free lever, 1 + cos β cosh β = 0, n = 1..10 (1.8751, 4.6941, 7.8548, ...).
#: Built once at import (a constant table, like the quadrature rules of qcm.py).
FREE_ROOTS = _newton_roots(
    lambda b: np.cos(b) + 1.0 / np.cosh(b),
    lambda b: -np.sin(b) - np.tanh(b) / np.cosh(b),
    (np.arange(1, 11) - 0.5) * np.pi,
)
#: β_n of the lever pinned at its free end (κ → ∞ at r = 1), tan β = tanh β: 3.9266, 7.0686, ...
PINNED_ROOTS = _newton_roots(
    lambda b: np.sin(b) - np.tanh(b) * np.cos(b),
    lambda b: np.cos(b) + np.tanh(b) * np.sin(b) - np.cos(b) / np.cosh(b) ** 2,
    (np.arange(1, 11) + 0.25) * np.pi,
)


@dataclass(frozen=True)
class Cantilever:
    """A free AFM cantilever, as calibrated before contact.

    Parameters
    ----------
    free_frequencies : free flexural resonances f_1.. (1 to 3 modes), Hz
    spring_constant : static spring constant at the free end k_c = 3EI/L³, N/m
    normalisation : "global" (β from f_1 only) or "modewise" (β_n from f_n): see module notes
    free_q_factors : quality factors of the free modes (same length), or None (no air/intrinsic
        damping subtracted from the contact damping)

    Examples
    --------
    >>> from contactres import Cantilever
    >>> lever = Cantilever(free_frequencies=(13e3,), spring_constant=0.2)  # Hz, N/m
    >>> lever.normalisation
    'global'
    """

    free_frequencies: tuple[float, ...]
    spring_constant: float
    normalisation: str = "global"
    free_q_factors: tuple[float, ...] | None = None

    def __post_init__(self):
        f = tuple(float(x) for x in np.atleast_1d(np.asarray(self.free_frequencies, float)))
        if not 1 <= len(f) <= 3:
            raise ContactresInputError(
                f"Cantilever needs 1 to 3 free frequencies (Hz), got {len(f)}"
            )
        positive("Cantilever free_frequencies", np.asarray(f), "Hz")
        if np.any(np.diff(f) <= 0):
            raise ContactresInputError(f"Cantilever free_frequencies must increase (Hz), got {f!r}")
        object.__setattr__(self, "free_frequencies", f)
        positive("Cantilever spring_constant", self.spring_constant, "N/m")
        if self.normalisation not in NORMALISATIONS:
            raise ContactresInputError(
                f"Cantilever normalisation must be one of {NORMALISATIONS}, "
                f"got {self.normalisation!r}"
            )
        if self.free_q_factors is not None:
            q = tuple(float(x) for x in np.atleast_1d(np.asarray(self.free_q_factors, float)))
            if len(q) != len(f):
                raise ContactresInputError(
                    f"Cantilever free_q_factors needs one Q per free frequency ({len(f)}), "
                    f"got {len(q)}"
                )
            positive("Cantilever free_q_factors", np.asarray(q), "dimensionless")
            object.__setattr__(self, "free_q_factors", q)

    def reference(self, mode) -> tuple[np.ndarray, np.ndarray]:
        """(β_ref, ω_ref) used for ``mode`` (int or int array, 1-based): ω_ref in rad/s, complex
        2πf (1 + i/(2Q)) when the free Q is known. Global: mode 1's; modewise: the mode's own."""
        mode = np.asarray(mode, dtype=int)
        if self.normalisation == "global":
            idx = np.zeros_like(mode)
        else:
            if np.any(mode > len(self.free_frequencies)) or np.any(mode < 1):
                raise ContactresInputError(
                    f"modewise normalisation needs the free frequency of every mode used; "
                    f"the cantilever has {len(self.free_frequencies)}, modes used "
                    f"{[int(x) for x in np.unique(mode)]}"
                )
            idx = mode - 1
        omega = 2.0 * np.pi * np.asarray(self.free_frequencies)[idx]
        if self.free_q_factors is not None:
            omega = omega * (1.0 + 0.5j / np.asarray(self.free_q_factors)[idx])
        return FREE_ROOTS[idx], omega


def beta_from_frequency(cantilever: Cantilever, frequency, mode, q_factor=None) -> np.ndarray:
    """Dimensionless wavenumber β = β_ref √(ω/ω_ref) of a resonance at ``frequency`` (Hz).

    ω = 2πf (1 + i/(2Q)) when ``q_factor`` is given; the result is complex when either this Q or
    the free lever's Q is known, real otherwise. ``mode`` (1-based) broadcasts with frequency.
    """
    b_ref, w_ref = cantilever.reference(mode)
    w: np.ndarray = 2.0 * np.pi * np.asarray(frequency, dtype=float)  # complex with a Q
    if q_factor is not None:
        w = w * (1.0 + 0.5j / np.asarray(q_factor, dtype=float))
    return b_ref * np.sqrt(w / w_ref)


def frequency_from_beta(cantilever: Cantilever, beta, mode) -> np.ndarray:
    """Inverse of :func:`beta_from_frequency`: ω/(2π) = f_ref (β/β_ref)² in Hz.

    Complex (f′ + i f″, with Q = f′/(2f″)) when β or the reference is complex.
    """
    b_ref, w_ref = cantilever.reference(mode)
    return w_ref * (np.asarray(beta) / b_ref) ** 2 / (2.0 * np.pi)


def tip_coefficients(lateral_ratio=0.0, tip_height=0.0, tilt=0.0):
    """(g_yy, g_yθ, g_θθ) of the tip stiffness per unit k* (module notes), dimensionless.

    Parameters
    ----------
    lateral_ratio : α = k_lat/k*, >= 0
    tip_height : η = h/L, tip height over lever length, >= 0
    tilt : φ, degrees in [0, 90): the angle from the sample's surface to the lever's axis,
        positive with the free end nearer the sample than the clamp (module notes)
    """
    a = nonnegative("lateral_ratio", lateral_ratio, "k_lat/k*, dimensionless")
    eta = nonnegative("tip_height", tip_height, "h/L, dimensionless")
    phi = nonnegative("tilt", tilt, "degrees")
    if np.any(np.asarray(phi) >= 90.0):
        raise ContactresInputError(f"tilt must be < 90 (degrees), got {tilt!r}")
    s, c = np.sin(np.radians(phi)), np.cos(np.radians(phi))
    g_yy = c * c + a * s * s
    g_yt = -eta * s * c * (1.0 - a)
    g_tt = eta * eta * (s * s + a * c * c)
    return g_yy, g_yt, g_tt


def _check_position(tip_position):
    r = positive("tip_position", tip_position, "L1/L, dimensionless")
    if np.any(np.asarray(r) > 1.0):
        raise ContactresInputError(f"tip_position must be in (0, 1] (L1/L), got {tip_position!r}")
    return r


def _trig(x):
    """(cos x, sin x, cosh x, sinh x), elementwise.

    Real x: numpy's functions. Complex x (a damped mode): from e^{ix} and e^{x}, two complex
    exponentials and their reciprocals instead of four complex trigonometric functions (each
    of which evaluates real sines and hyperbolic functions again): 2.5 times faster on a map,
    equal to within a few units of the last place of the O(1) entries it feeds (the rows and
    the closed form take their differences anyway, e.g. sin q − sinh q ≈ −q³/3).
    """
    if not np.iscomplexobj(x):
        return np.cos(x), np.sin(x), np.cosh(x), np.sinh(x)
    e, h = np.exp(1j * x), np.exp(x)
    ie, ih = 1.0 / e, 1.0 / h
    return 0.5 * (e + ie), -0.5j * (e - ie), 0.5 * (h + ih), 0.5 * (h - ih)


def _cos_cosh(x):
    """(cos x, cosh x) of :func:`_trig`, the same numbers, without the sines that
    :func:`normal_kappa` does not use of β (2 of its 12 transcendental functions a pixel)."""
    if not np.iscomplexobj(x):
        return np.cos(x), np.cosh(x)
    e, h = np.exp(1j * x), np.exp(x)
    return 0.5 * (e + 1.0 / e), 0.5 * (h + 1.0 / h)


def normal_trig(beta, tip_position) -> tuple:
    """(cos, sin, cosh, sinh) of p = βr, of q = β(1 − r) and of β (three tuples of arrays): the
    12 transcendental functions a pixel that :func:`normal_kappa` (10 of them) and
    :func:`normal_log_slope` (all 12) evaluate, for a caller that needs both at one β and r
    (the inversion's κ and its sensitivity): passed to them as ``trig``, they are evaluated
    once instead of twice, and both give the same numbers as without it, bit for bit."""
    b = np.asarray(beta)
    r = np.asarray(tip_position)
    return _trig(b * r), _trig(b * (1.0 - r)), _trig(b)


def normal_kappa(beta, tip_position, trig: tuple | None = None) -> np.ndarray:
    """κ = k*/k_c (k_c = 3EI/L³) of a normal tip spring that makes β a root (closed form).

    κ = 2β³(1 + cos β cosh β) / (3D), D as in the module notes: Rabe et al., Rev. Sci. Instrum.
    67, 3281 (1996), rewritten for the end stiffness. Real or complex β; vectorised. Not
    validated (an inner routine of the inversion: check ``tip_position`` in (0, 1] yourself).
    ``trig``: :func:`normal_trig` of the same β and r, when the caller has it.
    """
    b = np.asarray(beta)
    if trig is None:
        r = np.asarray(tip_position)
        (cp, sp, chp, shp), (cq, sq, chq, shq) = _trig(b * r), _trig(b * (1.0 - r))
    else:
        (cp, sp, chp, shp), (cq, sq, chq, shq), (cb, _, chb, _) = trig
    d = (sq * chq - cq * shq) * (1.0 - cp * chp) - (sp * chp - cp * shp) * (1.0 + cq * chq)
    with np.errstate(divide="ignore", invalid="ignore"):
        if trig is None:
            cb, chb = _cos_cosh(b)  # the sines of β are not used here
        return 2.0 * b**3 * (1.0 + cb * chb) / (3.0 * d)


def normal_log_slope(beta, tip_position, trig: tuple | None = None) -> np.ndarray:
    """L = d ln κ / d ln β = β κ′(β)/κ of :func:`normal_kappa`, differentiated by hand.

    With κ = 2β³N/(3D), N = 1 + cos β cosh β and D = AB − CE (A = sin q cosh q − cos q sinh q,
    B = 1 − cos p cosh p, C = sin p cosh p − cos p sinh p, E = 1 + cos q cosh q; p = βr,
    q = β(1 − r)): L = 3 + β N′/N − β D′/D, N′ = cos β sinh β − sin β cosh β and
    D′ = AC + 2[(1 − r) sin q sinh q B − r sin p sinh p E] (A′ = 2(1 − r) sin q sinh q,
    B′ = rC, C′ = 2r sin p sinh p, E′ = −(1 − r)A). Real or complex β (β κ′ = κL is then the
    complex derivative along β); vectorised; inf or NaN where N or D vanish (κ = 0 or ∞).
    One evaluation (12 transcendental functions a pixel) instead of the two of a central
    difference of κ (20), for the inversion's sensitivity flag. Not validated (an inner
    routine). ``trig``: :func:`normal_trig` of the same β and r, when the caller has it.
    """
    b = np.asarray(beta)
    r = np.asarray(tip_position)
    (cp, sp, chp, shp), (cq, sq, chq, shq), (cb, sb, chb, shb) = (
        normal_trig(b, r) if trig is None else trig
    )
    a_, b_ = sq * chq - cq * shq, 1.0 - cp * chp
    c_, e_ = sp * chp - cp * shp, 1.0 + cq * chq
    d_b = a_ * c_ + 2.0 * ((1.0 - r) * sq * shq * b_ - r * sp * shp * e_)
    with np.errstate(divide="ignore", invalid="ignore"):
        return 3.0 + b * ((cb * shb - sb * chb) / (1.0 + cb * chb) - d_b / (a_ * b_ - c_ * e_))


def _rows(beta, r, g):
    """Rows of the 4 x 4 matrix of the jump conditions at ξ = r (module notes): (R⁰, S₃, S₄).

    Unknowns: A, B of y = A(cos − cosh)(βξ) + B(sin − sinh)(βξ) (clamped end satisfied) and C, D
    of y = C(cos + cosh)(βs) + D(sin + sinh)(βs), s = 1 − ξ (free end satisfied). Row k holds the
    k-th ξ-derivative divided by β^k, so the entries stay O(e^β) at every order.
    """
    b = np.asarray(beta)
    p, q = b * r, b * (1.0 - r)
    return _assemble_rows(b, g, _trig(p), _trig(q))


def _assemble_rows(b, g, trig_p, trig_q):
    """:func:`_rows` from (cos, sin, cosh, sinh) of p = βr and of q = β(1 − r)."""
    g_yy, g_yt, g_tt = g
    cp, sp, chp, shp = trig_p
    cq, sq, chq, shq = trig_q
    left = (  # y, y′/β, y″/β², y‴/β³ of the two clamped-end functions
        (cp - chp, sp - shp),
        (-sp - shp, cp - chp),
        (-cp - chp, -sp - shp),
        (sp - shp, -cp - chp),
    )
    right = (  # the same of the two free-end functions, as derivatives in ξ = 1 − s
        (cq + chq, sq + shq),
        (sq - shq, -cq - chq),
        (chq - cq, shq - sq),
        (-sq - shq, cq - chq),
    )
    zero = 0.0  # the springs act on the clamped-side unknowns only
    # κ-coefficients of the moment and shear rows (the tip springs act through y and y′ only)
    s3 = tuple(-3.0 / b**2 * (g_yt * left[0][j] + g_tt * b * left[1][j]) for j in range(2))
    s4 = tuple(3.0 / b**3 * (g_yy * left[0][j] + g_yt * b * left[1][j]) for j in range(2))
    rows0 = [tuple(-e for e in left[k]) + right[k] for k in range(4)]
    return rows0, (*s3, zero, zero), (*s4, zero, zero)


def _stack(rows):
    shape = np.broadcast_shapes(*(np.shape(e) for row in rows for e in row))
    return np.stack([np.stack([np.broadcast_to(e, shape) for e in row], -1) for row in rows], -2)


def _matrix(beta, kappa, r, g):
    """M(β, κ) = M₀ + κ M₁ of :func:`_rows`, shape (..., 4, 4)."""
    rows0, s3, s4 = _rows(beta, r, g)
    k = np.asarray(kappa)
    rows = [*rows0[:2], tuple(u + k * v for u, v in zip(rows0[2], s3, strict=True))]
    rows.append(tuple(u + k * v for u, v in zip(rows0[3], s4, strict=True)))
    return _stack(rows)


#: Column pairs (j, k) of the first two rows, their complements (l, m) and the Laplace sign
#: (−1)^(j+k+1) (0-based; rows 0 and 1 fixed): det = Σ sign · T_jk · B_lm.
_LAPLACE = tuple(
    ((j, k), tuple(c for c in range(4) if c not in (j, k)), (-1) ** (j + k + 1))
    for j in range(4)
    for k in range(j + 1, 4)
)


def _is_zero(e):
    return isinstance(e, float) and e == 0.0


def _laplace(minors, x, y):
    """det of the 4 x 4 matrix with rows (R₁, R₂, x, y), elementwise over arrays.

    Laplace expansion along the first two rows: their six 2 x 2 ``minors`` (in the order of
    :data:`_LAPLACE`, :func:`_top_minors`) times the complementary minors of (x, y); entries
    that are the float 0.0 (the κ-rows' free-end columns) are skipped. Plain products on whole
    arrays, no stacked matrices: the inversion evaluates it on every pixel of a map, where
    np.linalg.det of (N, 4, 4) arrays was its cost.
    """
    total = 0.0
    for t, (_, (i, j), sign) in zip(minors, _LAPLACE, strict=True):
        cross = 0.0
        if not (_is_zero(x[i]) or _is_zero(y[j])):
            cross = x[i] * y[j]
        if not (_is_zero(x[j]) or _is_zero(y[i])):
            cross = cross - x[j] * y[i]
        if not _is_zero(cross):
            total = total + t * cross if sign > 0 else total - t * cross
    return total


def _top_minors(top):
    """The six 2 x 2 minors of the rows R₁, R₂ (continuity of y and y′), order of _LAPLACE."""
    return [top[0][j] * top[1][k] - top[0][k] * top[1][j] for (j, k), _, _ in _LAPLACE]


def determinant_coefficients(beta, tip_position, g):
    """(a, b, c) with det M(β, κ) = a κ² + b κ + c, from the rows' linearity in κ.

    Only the moment and shear rows depend on κ, linearly, so the determinant's multilinearity
    in its rows gives c = det(R₁, R₂, R₃⁰, R₄⁰), b = det(R₁, R₂, S₃, R₄⁰) + det(R₁, R₂, R₃⁰, S₄),
    a = det(R₁, R₂, S₃, S₄) (S: the κ-coefficients) without the cancellation of fitting a
    parabola through det M at three κ. Each determinant is a Laplace expansion along R₁, R₂
    (:func:`_laplace`). g as in :func:`determinant_from_coefficients`.
    """
    rows0, s3, s4 = _rows(beta, np.asarray(tip_position), g)
    minors = _top_minors(rows0[:2])
    a = _laplace(minors, s3, s4)
    b = _laplace(minors, s3, rows0[3]) + _laplace(minors, rows0[2], s4)
    return a, b, _laplace(minors, rows0[2], rows0[3])


def _expanded_determinant(beta, kappa, r, g):
    """det M(β, κ) by the Laplace expansion of :func:`_laplace` on the rows of :func:`_matrix`.

    The same rows (κ folded into the moment and shear rows as in :func:`_matrix`), elementwise
    products instead of stacked matrices and LU: ~10x cheaper per entry on the bracketing grid
    of :func:`contact_frequencies`, where only the sign is used (it agrees with
    ``np.linalg.det`` away from the roots; within a few ulps of one the two may disagree, and
    :func:`contact_frequencies` widens such a bracket before bisecting with LU).
    """
    b = np.asarray(beta)
    p, q = b * r, b * (1.0 - r)
    cp, sp, chp, shp = _trig(p)
    # cos q, sin q by angle addition from those of β (one per grid point, not per pixel):
    # half the sines and cosines, each the dearest function here; a few ulps off, only the
    # sign of the determinant is used
    cb, sb = np.cos(b), np.sin(b)
    trig_q = (cb * cp + sb * sp, sb * cp - cb * sp, np.cosh(q), np.sinh(q))
    rows0, s3, s4 = _assemble_rows(b, g, (cp, sp, chp, shp), trig_q)
    k = np.asarray(kappa)
    x = tuple(u + k * v for u, v in zip(rows0[2], s3, strict=True))
    y = tuple(u + k * v for u, v in zip(rows0[3], s4, strict=True))
    return _laplace(_top_minors(rows0[:2]), x, y)


def characteristic_determinant(
    beta, kappa, tip_position, lateral_ratio=0.0, tip_height=0.0, tilt=0.0
) -> np.ndarray:
    """det M(β, κ) of the tip-coupled lever (module notes); its zeros in β are the modes.

    Parameters
    ----------
    beta : dimensionless wavenumber β (real or complex), broadcasts with the others
    kappa : κ = k*/k_c, normal contact stiffness over the end spring constant 3EI/L³
    tip_position : r = L1/L in (0, 1]
    lateral_ratio, tip_height, tilt : α = k_lat/k*, η = h/L, φ in degrees (:func:`tip_coefficients`)

    Returns
    -------
    det M, same dtype as β·κ; a polynomial of degree <= 2 in κ (degree 2 only if α η² > 0).
    """
    r = _check_position(tip_position)
    g = tip_coefficients(lateral_ratio, tip_height, tilt)
    return np.linalg.det(_matrix(beta, kappa, r, g))


def determinant_from_coefficients(beta, kappa, tip_position, g) -> np.ndarray:
    """det M(β, κ) for tip coefficients g = (g_yy, g_yθ, g_θθ) of :func:`tip_coefficients`.

    The inner form of :func:`characteristic_determinant` for the inversion, which evaluates it
    many times with the same springs: nothing is validated, and r may exceed 1 (det M is analytic
    in r, which lets a scan bracket r = 1).
    """
    return np.linalg.det(_matrix(beta, kappa, np.asarray(tip_position), g))


def _bisect_roots(fun, lo, hi, f_lo, iterations=60):
    """Vectorised bisection of fun (elementwise) on brackets [lo, hi] with a sign change,
    ``f_lo`` = fun(lo) (the caller has it already).

    Stops early once a halving leaves every bracket as it was (each at adjacent floats, ~47
    halvings of a 0.01-wide bracket): the state is then fixed, so the remaining halvings would
    repeat the same evaluation and the result equals that of all ``iterations``.
    """
    for _ in range(iterations):  # 60 halvings of a 0.01-wide bracket reach the last bit of β
        mid = 0.5 * (lo + hi)
        f_mid = fun(mid)
        left = np.sign(f_mid) == np.sign(f_lo)
        new_lo, new_hi = np.where(left, mid, lo), np.where(left, hi, mid)
        f_lo = np.where(left, f_mid, f_lo)  # unchanged where lo is: fun(lo) again
        if np.array_equal(new_lo, lo) and np.array_equal(new_hi, hi):
            break
        lo, hi = new_lo, new_hi
    return 0.5 * (lo + hi)


def _grid_brackets(grid, n_max, kappa, r, g):
    """Left ends on ``grid`` of the cells holding the first ``n_max`` sign changes of det M in
    β, shape (pixels, n_max), NaN where fewer; κ, r and g hold one row per pixel.

    Pixels are taken in chunks (a (pixels x grid) table of ~5e4 determinants stays in cache; a
    loop over chunks, not over pixels). The grid is evaluated in three blocks, each only for
    the pixels with fewer than n_max changes so far: up to midway between β⁰_{n_max} and
    β⁰_{n_max+1} (soft contacts stop there), up to β⁰_{n_max+1} + 1/2 (the n-th root of a
    normal spring lies below β⁰_{n+1}), and the rest (lateral springs). The brackets are those
    of the whole grid: a pixel's later cells cannot change its first n_max changes.
    """
    lo = np.full((kappa.shape[0], n_max), np.nan)
    # block ends: midway between β⁰_{n_max} and β⁰_{n_max+1}, then β⁰_{n_max+1} + 1/2, the end
    ends = np.searchsorted(
        grid, [FREE_ROOTS[n_max - 1 : n_max + 1].mean(), FREE_ROOTS[n_max] + 0.5]
    )
    chunk = max(1, 50_000 // grid.size)
    for start in range(0, kappa.shape[0], chunk):
        rows = slice(start, start + chunk)
        k, rr, gg = kappa[rows], r[rows], tuple(x[rows] for x in g)
        s = np.empty((k.shape[0], grid.size))
        todo = np.ones(k.shape[0], dtype=bool)
        begin = 0
        for end in (*ends.tolist(), grid.size - 1):
            cols = slice(begin, end + 1)
            gm = tuple(x[todo] for x in gg)
            block = np.sign(_expanded_determinant(grid[None, cols], k[todo], rr[todo], gm))
            if (block == 0).any():
                # A determinant exactly 0 at a grid point (a root on it) takes the sign to its
                # left, so that root counts once, not twice (review R22b)
                left = s[todo, begin - 1] if begin else np.ones(block.shape[0])
                ext = np.concatenate([left[:, None], block], axis=1)
                at = np.where(ext != 0, np.arange(ext.shape[1]), 0)
                np.maximum.accumulate(at, axis=1, out=at)
                block = np.take_along_axis(ext, at, axis=1)[:, 1:]
            s[todo, cols] = block
            if begin:  # no further change where not evaluated: pixels done keep their last sign
                s[~todo, cols] = s[~todo, begin - 1 : begin]
            todo &= np.sum(s[:, :end] * s[:, 1 : end + 1] <= 0, axis=1) < n_max
            begin = end + 1
            if not todo.any():
                s[:, begin:] = s[:, begin - 1 : begin]
                break
        count = np.cumsum(s[:, :-1] * s[:, 1:] <= 0, axis=1)
        for m in range(n_max):
            hit = count == m + 1
            idx = np.argmax(hit, axis=1)
            lo[rows, m] = np.where(hit.any(axis=1), grid[idx], np.nan)
    return lo


#: Step of the β grid on which contact_frequencies brackets the roots; two modes closer than
#: this would be missed (the modes of one lever are > 1 apart in β for the springs modelled).
BETA_STEP = 0.01


def contact_frequencies(
    cantilever: Cantilever,
    kappa,
    tip_position,
    lateral_ratio=0.0,
    tip_height=0.0,
    tilt=0.0,
    modes=(1, 2, 3),
) -> np.ndarray:
    """Contact-resonance frequencies (Hz) of the lever with tip springs (:func:`tip_coefficients`).

    The roots of det M(β, κ) = 0 (:func:`characteristic_determinant`) are bracketed on a grid of
    step :data:`BETA_STEP` in β (the n-th root lies below β⁰_{n+2}: a rank-2 stiffness moves each
    eigenvalue by at most two places) and refined by bisection on whole arrays; for complex κ
    they are continued from Re κ to κ by Newton steps in complex β. β maps back to frequency by
    the cantilever's normalisation (:func:`frequency_from_beta`).

    Parameters
    ----------
    cantilever : the free lever (its k_c defines κ)
    kappa : κ = k*/k_c, >= 0 (complex κ′ + iκ″ for a damped contact, κ″ >= 0)
    tip_position : r = L1/L in (0, 1]
    lateral_ratio, tip_height, tilt : α = k_lat/k*, η = h/L, φ (degrees from the sample's
        surface, > 0 with the free end nearer the sample); all arguments broadcast
    modes : 1-based mode numbers to return

    Returns
    -------
    ndarray of shape broadcast(...) + (len(modes),), Hz: real, or complex f′ + i f″ (Q = f′/2f″)
    when κ is complex or the cantilever's free Q factors are known.

    Examples
    --------
    With no contact (κ = 0) the modes are the free ones, f₂/f₁ = (β₂⁰/β₁⁰)² = 6.267; a contact
    spring raises every mode:

    >>> import numpy as np
    >>> from contactres import Cantilever, contact_frequencies
    >>> lever = Cantilever(free_frequencies=(13e3,), spring_constant=0.2)  # Hz, N/m
    >>> f = contact_frequencies(lever, [0.0, 1e3], 1.0, modes=(1, 2))  # κ = k*/k_c, tip at r = 1
    >>> print(np.round(f / 1e3, 2))  # kHz, one row per κ
    [[ 13.    81.47]
     [ 56.73 181.57]]
    """
    kap = np.asarray(kappa)
    nonnegative("kappa (real part)", kap.real, "k*/k_c, dimensionless")
    r = _check_position(tip_position)
    g = tip_coefficients(lateral_ratio, tip_height, tilt)
    modes = tuple(int(m) for m in np.atleast_1d(modes))
    if min(modes) < 1 or max(modes) > len(FREE_ROOTS) - 2:
        raise ContactresInputError(f"modes must be in 1..{len(FREE_ROOTS) - 2}, got {modes!r}")
    shape = np.broadcast_shapes(kap.shape, np.shape(r), *(np.shape(x) for x in g))
    flat = [np.broadcast_to(x, shape).reshape(-1, 1) for x in (kap, r, *g)]
    kap_c, r_f, g_f = flat[0], flat[1], tuple(flat[2:])
    n_max = max(modes)
    grid = np.arange(0.5, FREE_ROOTS[n_max + 1] + 0.5, BETA_STEP)

    def det(b, k=kap_c.real, rows=slice(None)):
        gg = tuple(x[rows] for x in g_f)
        return np.linalg.det(_matrix(b, k[rows], r_f[rows], gg))

    lo = _grid_brackets(grid, n_max, kap_c.real, r_f, g_f)
    good = np.isfinite(lo)
    lo_g = np.where(good, lo, 1.0)
    hi_g = lo_g + BETA_STEP
    # The scan's signs come from the expanded determinant, the bisection's from LU: for a root
    # within a few ulps of a grid point the two may disagree on that point's sign, and the cell
    # then holds no LU sign change. Such a bracket takes a cell more on each side, where LU
    # changes sign (review R22b: otherwise β lands a whole step, 0.01, off).
    f_lo = det(lo_g)
    same = np.sign(f_lo) == np.sign(det(hi_g))
    if same.any():
        lo_g, hi_g = np.where(same, lo_g - BETA_STEP, lo_g), np.where(same, hi_g + BETA_STEP, hi_g)
        f_lo = det(lo_g)
    beta = _bisect_roots(det, lo_g, hi_g, f_lo)
    if np.iscomplexobj(kap) and np.any(kap_c.imag != 0):
        beta = beta.astype(complex)
        steps = 8  # continuation in Im κ keeps each Newton start inside its basin
        for t in np.linspace(1.0 / steps, 1.0, steps):
            k_t = kap_c.real + 1j * t * kap_c.imag
            for _ in range(8):
                h = 1e-7 * np.abs(beta)
                d0 = det(beta, k_t)
                slope = (det(beta + h, k_t) - det(beta - h, k_t)) / (2.0 * h)
                beta = beta - d0 / slope
    beta = np.where(good, beta, np.nan)
    cols = np.array(modes) - 1
    freq = frequency_from_beta(cantilever, beta[:, cols], np.array(modes)[None, :])
    return freq.reshape((*shape, len(modes)))
