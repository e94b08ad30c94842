"""Carlson's symmetric elliptic integrals R_F and R_D on arrays (the plateau loop's tails).

Why. The closed form of the plateau loop's slopes
(:func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`) needs, at each of some 10⁶ points
of a large table's fits, the tails K(m) - F(φ|m) and E(m) - E(φ|m) of Legendre's incomplete
elliptic integrals. Through scipy's ``ellipk``, ``ellipkinc``, ``ellipe`` and ``ellipeinc``
(cephes, a scalar loop per element) they cost ~2400 instructions a point with the rest of the
closed form, and the differences lose digits to cancellation as φ nears π/2 (to ~1e-10
relative where the tail is 1e-6 rad long). Here both tails come from one sequence of
Carlson's duplication steps in numpy, each as a sum of positive terms.

How. With s = cos φ and m' = 1 - m, the substitution θ -> π/2 - θ, then t = sin θ, turns
each tail into an integral over t from 0 to s of 1/√((1 - t²)(m' + m t²)) (and of its product
with m' + m t²), which Carlson's reduction of such integrals (B. C. Carlson, "Numerical
computation of real or complex elliptic integrals", Numer. Algorithms 10 (1995) 13-26, Eqs.
4.5-4.6 for Legendre's forms; DLMF 19.25.5, 19.25.7) and the homogeneity of R_F and R_D give as

    K - F(φ|m) = s R_F(m' sin²φ, m' + m s², m'),
    E - E(φ|m) = m' s [R_F(...) + (m s²/3) R_D(...)]      (the same arguments).

Both functions are homogeneous and symmetric; the duplication (x, y, z) -> ((x + λ)/4, ...),
λ = √x√y + √y√z + √z√x, leaves R_F unchanged and R_D up to the sum 3 Σ 4⁻ⁿ/(√zₙ(zₙ + λₙ)),
and each step divides the spread of the arguments about their mean by ~4 (by more while they
differ by orders of magnitude). Once every relative deviation of a point's arguments from
their mean is below :data:`DEVIATION` (R_F's mean (x + y + z)/3, R_D's (x + y + 3z)/5), the
fifth-order Taylor series of Carlson (1995), Eqs. 2.2-2.3 and 2.17-2.18, gives both to
~δ⁶/10 relative (δ the deviation): below the rounding of the sums. A point stops at the first
check (after :data:`MIN_STEPS` steps, then every :data:`CHECK_EVERY`) at which its own
deviations are small enough: its numbers depend on its arguments alone, never on the points
evaluated with it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "BLOCK",
    "CHECK_EVERY",
    "DEVIATION",
    "MAX_STEPS",
    "MIN_STEPS",
    "carlson_rf_rd",
    "legendre_tails",
]

#: Points per block of the duplication (its ~8 arrays, 32 kB each, stay in the core's cache).
BLOCK = 4096

#: Largest relative deviation of a point's arguments from their mean at which the series
#: stops: the truncation, ~δ⁶/10 relative (the next terms' coefficients are below 1/10),
#: is then ~2e-17, under the rounding of the series' sum.
DEVIATION = 2.5e-3

#: Duplication steps taken by every point before its deviations are first checked: on the
#: plateau fits of the 10⁴-sweep benchmark table 85 % of the points need 5, 99.6 % at most 6,
#: and a check with its series on the points it stops costs ~60 numpy calls (more than a step's
#: ~17 on the fits' calls of a few hundred points): 6 steps, then a check every 2, took 13 %
#: fewer instructions than 5 and a check every step.
MIN_STEPS = 6

#: Steps between the later checks of the points not yet converged at :data:`MIN_STEPS`.
CHECK_EVERY = 2

#: Steps after which a point still not converged gets NaN. Each step divides the differences
#: of the arguments by exactly 4 while their mean tends to R_F⁻² > 0, so a point of the
#: domain needs ~log₄(spread/(DEVIATION R_F⁻²)) steps: 13 at (1e-300, 1e-300, 1), under 40 at
#: any finite arguments of the domain. The cap only keeps a point outside it from stepping
#: for ever.
MAX_STEPS = 100


def carlson_rf_rd(x: ArrayLike, y: ArrayLike, z: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """R_F(x, y, z) and R_D(x, y, z) at each point (Carlson 1995; module docstring).

    Parameters
    ----------
    x, y, z : 1-d arrays of the same size, dimensionless (any one unit: R_F scales as its
        -1/2 power, R_D as the -3/2), x, y >= 0 with x + y > 0, z > 0

    Returns
    -------
    R_F, R_D at each point, to a few units of rounding relative; NaN at a point outside the
    domain (a NaN or infinite argument, a negative one, x = y = 0 or z <= 0), as scipy's
    ``elliprf``/``elliprd`` give there.

    In blocks of :data:`BLOCK` points (the step's ~8 arrays stay in the core's cache); each
    point's steps are its own, the same numbers in any block.
    """
    x, y, z = (np.asarray(a, dtype=float) for a in (x, y, z))
    rf, rd = np.full_like(x, np.nan), np.full_like(x, np.nan)
    inside = np.isfinite(x) & np.isfinite(y) & np.isfinite(z)
    inside &= (x >= 0.0) & (y >= 0.0) & (x + y > 0.0) & (z > 0.0)
    if not inside.all():  # the duplication would never converge there
        good = np.flatnonzero(inside)
        rf[good], rd[good] = carlson_rf_rd(x[good], y[good], z[good])
        return rf, rd
    for start in range(0, x.size, BLOCK):
        block = slice(start, start + BLOCK)
        rf[block], rd[block] = _duplicate(x[block], y[block], z[block])
    return rf, rd


def legendre_tails(
    sin2: np.ndarray, cos2: np.ndarray, m: np.ndarray, m1: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """K(m) - F(φ|m) and E(m) - E(φ|m), the integrals of (1 - m sin²θ)^∓½ from φ to π/2.

    Parameters
    ----------
    sin2, cos2 : sin²φ and cos²φ (both passed: the caller forms each without cancellation)
    m, m1 : the parameter m and m' = 1 - m (likewise), m1 > 0

    Returns
    -------
    The two tails, dimensionless, by :func:`carlson_rf_rd` (module docstring: with s = cos φ,
    s R_F and m' s [R_F + (m s²/3) R_D] at (m' sin²φ, 1 - m sin²φ, m')).
    """
    rf, rd = carlson_rf_rd(m1 * sin2, m1 + m * cos2, m1)
    s = np.sqrt(cos2)
    return s * rf, m1 * s * (rf + (m * cos2 / 3.0) * rd)


def _duplicate(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`carlson_rf_rd` at one block of points of its domain (NaN where a point has not
    converged after :data:`MAX_STEPS` steps)."""
    # The three arguments as the rows of one array: each of a step's square roots and updates
    # is one numpy call on all three (the same numbers as one call each).
    n = x.size
    xyz = np.array([x, y, z])
    tail = np.zeros_like(x)  # Σ 4⁻ⁿ/(√zₙ(zₙ + λₙ)) of R_D
    scale = 1.0  # 4⁻ⁿ, the same for every point still stepping
    active = np.arange(x.size)
    steps = 0
    # The points that stop, check by check: where, their arguments, means, sums and 4⁻ⁿ; the
    # series then runs once on all of them (each point's numbers its own: those of a series
    # at each check, without its ~50 numpy calls a check on a few points each).
    stopped: list[tuple[np.ndarray, ...]] = []
    while active.size and steps < MAX_STEPS:
        sx, sy, sz = np.sqrt(xyz)
        lam = sx * sy
        sx += sy
        sx *= sz
        lam += sx  # λ = √x√y + √z(√x + √y)
        t = np.add(xyz[2], lam, out=sy)
        t *= sz
        np.divide(scale, t, out=t)
        tail += t
        scale *= 0.25
        xyz += lam
        xyz *= 0.25
        steps += 1
        if steps < MIN_STEPS or (steps - MIN_STEPS) % CHECK_EVERY:
            continue
        # Converged where the spread of the three about their mean is below DEVIATION of it.
        x, y, z = xyz
        hi = np.maximum(x, y)
        np.maximum(hi, z, out=hi)
        lo = np.minimum(x, y)
        np.minimum(lo, z, out=lo)
        hi -= lo
        mean_f = x + y
        mean_f += z
        mean_f /= 3.0
        done = hi < DEVIATION * mean_f
        if not done.any():
            continue
        if done.all():  # (every point left stops here: no gathers)
            stopped.append((active, xyz, mean_f, np.full(active.size, scale), tail))
            break
        at = np.flatnonzero(done)
        stopped.append((active[at], xyz[:, at], mean_f[at], np.full(at.size, scale), tail[at]))
        left = np.flatnonzero(~done)
        active = active[left]
        xyz, tail = xyz[:, left], tail[left]
    rf, rd = np.full(n, np.nan), np.full(n, np.nan)  # (NaN: not converged)
    if stopped:
        here, xyz, mean_f, scales, tails = (
            parts[0] if len(stopped) == 1 else np.concatenate(parts, axis=-1)
            for parts in zip(*stopped, strict=True)
        )
        f, d = _series(xyz[0], xyz[1], xyz[2], mean_f)
        d *= scales
        d += 3.0 * tails
        rf[here], rd[here] = f, d
    return rf, rd


def _series(
    x: np.ndarray, y: np.ndarray, z: np.ndarray, mean_f: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """R_F and R_D (the latter without its duplication sum and factor 4⁻ⁿ) from the Taylor
    series at arguments close to their means (Carlson 1995, Eqs. 2.3 and 2.18)."""
    # R_F: X + Y + Z = 0, E2 = XY - Z², E3 = XYZ.
    dx, dy = 1.0 - x / mean_f, 1.0 - y / mean_f
    dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    rf = (1.0 + e2 * (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) + e3 / 14.0) / np.sqrt(mean_f)
    # R_D: mean (x + y + 3z)/5, X + Y + 3Z = 0; E2 = XY - 6Z², E3 = (3XY - 8Z²)Z,
    # E4 = 3(XY - Z²)Z², E5 = XYZ³.
    mean_d = (x + y + 3.0 * z) / 5.0
    dx, dy = 1.0 - x / mean_d, 1.0 - y / mean_d
    dz = -(dx + dy) / 3.0
    xy, zz = dx * dy, dz * dz
    e2 = xy - 6.0 * zz
    e3 = (3.0 * xy - 8.0 * zz) * dz
    e4 = 3.0 * (xy - zz) * zz
    e5 = xy * zz * dz
    series = (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
    )
    return rf, series / (mean_d * np.sqrt(mean_d))
