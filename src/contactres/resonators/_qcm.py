"""The QCM as a probe of contact stiffness (paper 2, Eqs. 1-5, 11-12, 15).

Small-load approximation: n_P equal point contacts on the acoustically effective area A_eff of a
resonator (overtone n, fundamental f_F, shear-wave impedance of quartz Z_q) shift the resonance
frequency and half-bandwidth by

    Δf + iΔΓ = P (K′ + iK″),   P = n_P / (2nπ² A_eff Z_q)              (paper 2, Eqs. 1-2, 4)

where K′ + iK″ is the complex stiffness of one contact: κ + iωξ for a Voigt element, the first
Fourier component of the force (Eqs. 4-5) for a nonlinear loop. ΔΓ is the half width at half
maximum (dissipation D = 2Γ/f). All quantities SI; shifts in Hz.

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein
J. Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.

Accuracy of :func:`shifts_from_loop`: relative error below 1e-9 (of K′, and of K″ where K″ is not
zero) for every loop of :mod:`contactres.tangential` at any amplitude, including the amplitudes at
which full sliding begins: the quadrature splits at the kinks and maps every sub-interval so that
the square-root singularities at its ends (and those just beyond them) become analytic.
Measured (tests/resonators/test_qcm.py, benchmarks/bench_loops.py): worst relative error ~3e-11
against the same rule with doubled nodes and against scipy's adaptive quadrature of Eq. 4,
including amplitudes within 1e-12 of the onset of full sliding.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..numerics import gauss_legendre_unit
from ..tangential import CattaneoMindlinLoop, DashpotLoop, MasingLoop, SavkoorLoop
from ..units import SMALL_LOAD_LIMIT
from ..validation import amplitude, positive

__all__ = [
    "QCM",
    "cattaneo_mindlin_expansion",
    "friction_from_slopes",
    "loop_stiffness",
    "savkoor_expansion",
    "shifts_from_loop",
    "shifts_from_stiffness",
    "stiffness_from_shifts",
]


#: Gauss-Legendre nodes per half sub-interval (default of :func:`loop_stiffness`).
DEFAULT_NODES = 24

# The default rule as a constant table, built once at import like the series coefficients of the
# loops: numpy's construction costs ~0.8 ms for 24 nodes, more than a call of loop_stiffness on a
# few amplitudes. Other node counts are built per call (once, then passed down).
_DEFAULT_RULE = gauss_legendre_unit(DEFAULT_NODES)

# Smallest distance (relative to the half-interval) of a near-singular point that the node map
# resolves. Smaller values resolve closer points but stretch the map (worse for the far end of
# the half-interval); with 24 nodes the worst relative error over all amplitudes is ~3e-11.
_ETA_MIN = 1e-5


@dataclass(frozen=True)
class QCM:
    """A quartz crystal resonator probed on one overtone.

    Parameters
    ----------
    fundamental : fundamental resonance frequency f_F, Hz (e.g. 5e6)
    overtone : overtone order n (odd, >= 1)
    area : acoustically effective area A_eff, m²
    zq : shear-wave impedance of the quartz, kg m⁻² s⁻¹ (AT-cut: 8.8e6)

    Examples
    --------
    A 5 MHz crystal on its 3rd overtone, 10 mm² effective area:

    >>> from contactres import QCM
    >>> q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    >>> print(f"{q.frequency / 1e6:g} MHz, {q.sensitivity(n_contacts=1000):.4f} Hz per N/m")
    15 MHz, 0.1919 Hz per N/m
    """

    fundamental: float = 5e6
    overtone: int = 3
    area: float = 1e-5
    zq: float = 8.8e6

    def __post_init__(self):
        for name, unit in (("fundamental", "Hz"), ("area", "m^2"), ("zq", "kg m^-2 s^-1")):
            positive(f"QCM {name}", getattr(self, name), unit)
        n = self.overtone
        if not np.isfinite(n) or int(n) != n or n < 1 or int(n) % 2 == 0:
            raise ContactresInputError(f"QCM overtone must be an odd integer >= 1, got {n!r}")

    @property
    def frequency(self) -> float:
        """Resonance frequency of the overtone, n f_F, Hz."""
        return self.overtone * self.fundamental

    @property
    def omega(self) -> float:
        """Angular frequency ω = 2π n f_F, rad/s."""
        return 2.0 * np.pi * self.frequency

    def sensitivity(self, n_contacts: float = 1) -> float:
        """P = n_P / (2nπ² A_eff Z_q), Hz per (N/m) (paper 2, Eq. 1)."""
        if not np.isfinite(n_contacts) or n_contacts <= 0:
            raise ContactresInputError(f"n_contacts must be > 0, got {n_contacts!r}")
        return n_contacts / (2.0 * self.overtone * np.pi**2 * self.area * self.zq)


def _check_small(q: QCM, df) -> None:
    worst = float(np.max(np.abs(df), initial=0.0)) / q.frequency
    if worst > SMALL_LOAD_LIMIT:
        warnings.warn(
            f"|Δf|/f = {worst:.2g} exceeds {SMALL_LOAD_LIMIT:g}: the small-load approximation "
            "of paper 2, Eq. 1 may not hold",
            RuntimeWarning,
            stacklevel=3,
        )


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def shifts_from_stiffness(q: QCM, kappa, xi, n_contacts=1):
    """Δf, ΔΓ (Hz) of n_P Voigt contacts (κ in N/m, ξ in kg/s): paper 2, Eq. 1. Vectorised.

    Examples
    --------
    1000 contacts of stiffness 1 kN/m and damping 1e-7 kg/s each:

    >>> from contactres import QCM, shifts_from_stiffness
    >>> q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    >>> df, dgamma = shifts_from_stiffness(q, 1000.0, 1e-7, n_contacts=1000)
    >>> print(f"Δf = {df:.2f} Hz, ΔΓ = {dgamma:.3f} Hz")
    Δf = 191.90 Hz, ΔΓ = 1.809 Hz
    >>> round(df, 6) == round(q.sensitivity(1000) * 1000.0, 6)  # Δf = P κ
    True
    """
    P = q.sensitivity(n_contacts)
    df = P * np.asarray(kappa, dtype=float)
    dg = P * q.omega * np.asarray(xi, dtype=float)
    _check_small(q, df)
    return _out(df), _out(dg)


def stiffness_from_shifts(q: QCM, df, dgamma, n_contacts=1):
    """κ (N/m), ξ (kg/s) per contact from Δf, ΔΓ (Hz): paper 2, Eq. 2 (inverse of Eq. 1).

    Examples
    --------
    The inverse of :func:`shifts_from_stiffness` (a round trip):

    >>> from contactres import QCM, shifts_from_stiffness, stiffness_from_shifts
    >>> q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    >>> kappa, xi = stiffness_from_shifts(q, 191.9, 1.809, n_contacts=1000)
    >>> print(f"κ = {kappa:.1f} N/m, ξ = {xi:.3g} kg/s")
    κ = 1000.0 N/m, ξ = 1e-07 kg/s
    >>> df, dgamma = shifts_from_stiffness(q, kappa, xi, n_contacts=1000)
    >>> round(float(df), 6), round(float(dgamma), 6)
    (191.9, 1.809)
    """
    P = q.sensitivity(n_contacts)
    _check_small(q, df)
    return _out(np.asarray(df, dtype=float) / P), _out(
        np.asarray(dgamma, dtype=float) / (P * q.omega)
    )


# --------------------------------------------------------------------------------------------
# Quadrature of Eqs. 4-5
# --------------------------------------------------------------------------------------------


def _rule(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1] (the prepared default for n = DEFAULT_NODES)."""
    return _DEFAULT_RULE if n == DEFAULT_NODES else gauss_legendre_unit(n)


def _half_nodes(length, eta, rule):
    """Nodes t in [0, length] (distance from the end of a half-interval) and weights, for an
    integrand with square-root singularities at t = 0 and t = -eta (a point beyond the end).

    The map t = η sinh²φ makes √t and √(t + η) analytic in φ (both singular points move to
    ±iπ/2 away from the interval); Gauss-Legendre in φ (``rule``: nodes and weights on [0, 1])
    then converges exponentially whatever η.
    """
    x, w = rule
    eta = np.minimum(np.maximum(eta, _ETA_MIN * length), 4.0 * length)
    eta = np.where(length > 0, eta, 1.0)
    phi_max = np.arcsinh(np.sqrt(length / eta))
    e = np.exp(phi_max[..., None] * x)
    sh = 0.5 * (e - 1.0 / e)
    t = eta[..., None] * sh * sh
    # dt = η sinh 2φ dφ = η (e² - e⁻²)/2 dφ
    wt = (phi_max * eta)[..., None] * w * (sh * (e + 1.0 / e))
    return t, wt


def _distance_beyond(points, end, side):
    """Distance from ``end`` to the nearest point strictly beyond it (side -1: below, +1: above)."""
    d = side * (points - end[..., None])
    d = np.where(d > 0, d, np.inf)
    return d.min(axis=-1)


def masing_stiffness(loop: MasingLoop, u0: np.ndarray, n: int):
    """K′, K″ of a Masing loop from its slope deficit (paper 2, Eqs. 4-5 after Masing's rule).

    With s = d/u0 on the virgin curve (Eq. 4 integrated by parts; Eq. 5 with the loop area
    4∫F'(d)(u0 - 2d) dd) and, for K″, ∫(1 - 2s) ds = 0::

        K′ = (8/π) ∫₀¹ F'(u0 s) √(s(1 - s)) ds,    K″ = -(4/π) ∫₀¹ L(u0 s) (1 - 2s) ds,

    L = κ - F'. Using F' for K′ and L for K″ avoids cancellation at large and small u0.
    """
    # Beyond the last break the contact slides (F' = 0, L = κ): integrate only up to
    # m = min(1, d_last/u0) and add the tail of K″, -(4/π) κ ∫_m^1 (1 - 2s) ds, in closed form.
    b = np.asarray(loop.breaks, dtype=float)
    sp = np.asarray(loop.singular_points, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inv = np.where(u0 > 0, 1.0 / u0, np.inf)[..., None]
        sb = np.where(np.isinf(inv), np.inf, b * inv)
        ss = np.where(np.isinf(inv), np.sign(sp) * np.inf, sp * inv)
    # A break within rounding of s = 1 is at s = 1 (u0 = d* exactly): no sliver pieces.
    sb = np.where(np.abs(sb - 1.0) < 1e-13, 1.0, sb)
    m = np.minimum(sb[..., -1], 1.0)
    edges = np.concatenate(
        [np.zeros((*u0.shape, 1)), np.minimum(sb[..., :-1], m[..., None]), m[..., None]], axis=-1
    )
    # square-root singular points: the weights' s = 0 and s = 1, and the virgin curve's
    special = np.concatenate([np.zeros((*u0.shape, 1)), np.ones((*u0.shape, 1)), ss], axis=-1)
    k1 = np.zeros(u0.shape)
    k2 = loop.kappa * (m * m - m)
    rule = _rule(n)
    for i in range(edges.shape[-1] - 1):
        lo, hi = edges[..., i], edges[..., i + 1]
        half = 0.5 * (hi - lo)
        for end, side in ((lo, -1.0), (hi, 1.0)):
            eta = _distance_beyond(special, end, side)
            t, wt = _half_nodes(half, eta, rule)
            # s and 1 - s from the end point, to keep √(1 - s) accurate near s = 1
            s = end[..., None] - side * t
            one_minus_s = (1.0 - end)[..., None] + side * t
            d = u0[..., None] * s
            root = np.sqrt(np.maximum(s * one_minus_s, 0.0))
            slope, loss = loop.slopes(d)
            k1 += np.einsum("...i,...i->...", wt * root, slope)
            k2 += np.einsum("...i,...i->...", wt * (one_minus_s - s), loss)
    return (8.0 / np.pi) * k1, -(4.0 / np.pi) * k2


def _generic_stiffness(loop, u0: np.ndarray, n: int):
    """K′, K″ straight from the branches (paper 2, Eqs. 4-5) for any loop.

    x = u/u0 in [-1, 1] is split at ``loop.kinks(u0)``; every piece [c - h, c + h] is mapped by
    x = c - h cos θ (θ in [0, π]), which absorbs the 1/√(1 - x²) of Eq. 4 and one-sided
    square-root singularities at the kinks. Near-singular points just outside a piece are not
    treated, so this path is exact only for loops that are smooth between their kinks.
    """
    u0e = np.where(u0 > 0, u0, 1e-100)  # the u0 -> 0 limit; 1e-100² is still a normal float
    kinks = np.asarray(loop.kinks(u0e), dtype=float).reshape((*u0.shape, -1))
    kinks = np.sort(np.where(np.isnan(kinks), 1.0, np.clip(kinks, -1.0, 1.0)), axis=-1)
    edges = np.concatenate([-np.ones((*u0.shape, 1)), kinks, np.ones((*u0.shape, 1))], axis=-1)
    x, w = _rule(n)
    theta = np.pi * x
    sin2, cos2 = np.sin(theta / 2.0), np.cos(theta / 2.0)
    k1 = np.zeros(u0.shape)
    k2 = np.zeros(u0.shape)
    for i in range(edges.shape[-1] - 1):
        lo, hi = edges[..., i, None], edges[..., i + 1, None]
        h = 0.5 * (hi - lo)
        xs = lo + 2.0 * h * sin2**2
        one_plus, one_minus = (1.0 + lo) + 2.0 * h * sin2**2, (1.0 - hi) + 2.0 * h * cos2**2
        dx = np.pi * w * 2.0 * h * sin2 * cos2
        u = u0e[..., None] * np.clip(xs, -1.0, 1.0)
        up, down = loop.branches(u, np.broadcast_to(u0e[..., None], u.shape))
        with np.errstate(divide="ignore", invalid="ignore"):
            wt = np.where(h > 0, dx * xs / np.sqrt(one_plus * one_minus), 0.0)
        k1 += np.sum(wt * (up + down), axis=-1)
        k2 += np.sum(dx * (up - down), axis=-1)
    return k1 / (np.pi * u0e), k2 / (np.pi * u0e)


def loop_stiffness(loop, u0, nodes: int = DEFAULT_NODES):
    """Complex stiffness K′ + iK″ (N/m) of one contact following ``loop`` at amplitude u0 (m).

    Paper 2, Eqs. 4-5: K′ = (1/πu0) ∫ [F₊ + F₋](u0x) x/√(1 - x²) dx, K″ = area/(πu0²).
    Masing loops are integrated in their virgin-curve form (exact splitting at full sliding and
    at the plateau edge); a :class:`~contactres.DashpotLoop` adds exactly iωξ; any other loop is
    integrated from its branches. ``nodes`` Gauss points per half sub-interval; the default meets
    1e-9 relative (see the module docstring and the convergence tests). u0 = 0 gives the limit.
    """
    u0 = amplitude(u0)
    n = int(nodes)
    if n < 2:
        raise ContactresInputError(f"nodes must be >= 2, got {nodes!r}")
    if isinstance(loop, DashpotLoop):
        return loop_stiffness(loop.loop, u0, n) + 1j * loop.omega * loop.xi
    if isinstance(loop, MasingLoop):
        k1, k2 = masing_stiffness(loop, u0, n)
    elif all(hasattr(loop, m) for m in ("branches", "kinks")):
        k1, k2 = _generic_stiffness(loop, u0, n)
    else:
        raise ContactresInputError(
            f"{type(loop).__name__} is not a loop (needs branches(u, u0), kinks(u0))"
        )
    k = k1 + 1j * k2
    return complex(k) if k.ndim == 0 else k


def shifts_from_loop(q: QCM, loop, u0, n_contacts=1, nodes: int = DEFAULT_NODES):
    """Δf(u0), ΔΓ(u0) in Hz of n_P contacts following ``loop`` (paper 2, Eqs. 4-5).

    Vectorised over the amplitude array ``u0`` (m); returns two arrays of its shape (floats for
    a scalar). Relative accuracy 1e-9 (:func:`loop_stiffness`).

    Examples
    --------
    Cattaneo-Mindlin contacts: at small amplitude the shifts are those of the linear spring κ, at
    larger amplitude partial slip lowers Δf and raises ΔΓ:

    >>> import numpy as np
    >>> from contactres import CattaneoMindlinLoop, QCM, shifts_from_loop, shifts_from_stiffness
    >>> q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    >>> loop = CattaneoMindlinLoop(kappa=1000.0, mu=0.5, normal_force=1e-3)  # N/m, -, N
    >>> u0 = np.array([1e-10, 1e-7])  # amplitudes, m
    >>> df, dgamma = shifts_from_loop(q, loop, u0, n_contacts=1000)
    >>> [round(float(x), 2) for x in df], [round(float(x), 4) for x in dgamma]
    ([191.89, 185.36], [0.0027, 2.8111])
    >>> df_spring, _ = shifts_from_stiffness(q, 1000.0, 0.0, n_contacts=1000)
    >>> bool(np.isclose(df[0], df_spring, rtol=1e-4, atol=0))
    True
    """
    k = np.asarray(loop_stiffness(loop, u0, nodes))
    P = q.sensitivity(n_contacts)
    df, dg = P * k.real, P * k.imag
    _check_small(q, df)
    return _out(df), _out(dg)


# --------------------------------------------------------------------------------------------
# Closed-form expansions (paper 2, Eqs. 11-12, 15) and the friction coefficient
# --------------------------------------------------------------------------------------------


def cattaneo_mindlin_expansion(loop: CattaneoMindlinLoop, u0, omega_xi: float = 0.0, order=2):
    """K′ + iK″ of a Cattaneo-Mindlin loop expanded in u0 (paper 2, Eqs. 11-12), N/m.

    K′ = κ[1 - κu0/(6μF_N) - (5/288)(κu0/μF_N)²],
    K″ = ωξ + (2/(9π)) κ²u0/(μF_N) + κ³u0²/(27π μ²F_N²)
    (``order`` 1 drops the squares). Valid for u0 ≪ d* = 3μF_N/(2κ). ``omega_xi`` = ωξ in N/m.
    The coefficients follow from Eqs. 4-6 with Masing's rule and are checked against the
    quadrature in tests/resonators/test_qcm.py (docs/validation.md); the OCR of the paper's
    Eq. 11 shows 1/3 and 4/(9π), twice these.
    """
    if order not in (1, 2):
        raise ContactresInputError(f"order must be 1 or 2, got {order!r}")
    u0 = amplitude(u0)
    k = loop.kappa
    e = k * u0 / loop.sliding_force
    k1 = k * (1.0 - e / 6.0 - (order == 2) * (5.0 / 288.0) * e**2)
    k2 = omega_xi + k * (2.0 / (9.0 * np.pi) * e + (order == 2) * e**2 / (27.0 * np.pi))
    return k1 + 1j * k2


def savkoor_expansion(loop: SavkoorLoop, u0, omega_xi: float = 0.0):
    """K′ + iK″ of a Savkoor loop to second order in u0 (paper 2, Eq. 15), N/m.

    K′ = κ[1 - (5/512)(κu0/(a²τ0))²],  K″ = ωξ + κ³u0²/(48π a⁴τ0²). Valid for u0 ≪ 4a²τ0/κ.
    """
    u0 = amplitude(u0)
    k = loop.kappa
    e = k * u0 / (loop.a**2 * loop.tau)
    return k * (1.0 - 5.0 / 512.0 * e**2) + 1j * (omega_xi + k * e**2 / (48.0 * np.pi))


def friction_from_slopes(
    q: QCM, kappa, normal_force, df_slope=None, dgamma_slope=None, n_contacts=1
):
    """Friction coefficient μ from the amplitude slopes of a Cattaneo-Mindlin sweep (Eq. 12).

    μ = -κ²/(6F_N dK′/du0) from the Δf slope and μ = 2κ²/(9πF_N dK″/du0) from the ΔΓ slope,
    with dK/du0 = (slope in Hz/m)/P, the slopes of :func:`cattaneo_mindlin_expansion` (whose
    coefficients are half those of the OCR'd paper). ``kappa`` N/m (from Δf0 via Eq. 2),
    ``normal_force`` N per contact. Returns (μ_from_df, μ_from_dgamma); nan where a slope is
    missing, nan or has the wrong sign for partial slip (nan inputs give nan).
    """
    P = q.sensitivity(n_contacts)
    kappa = np.asarray(kappa, dtype=float)
    F = np.asarray(normal_force, dtype=float)
    if np.any(kappa <= 0) or np.any(F <= 0):
        raise ContactresInputError(
            "friction_from_slopes needs kappa > 0 (N/m) and normal_force > 0 (N), got "
            f"kappa={_out(kappa)!r}, normal_force={_out(F)!r}"
        )
    mu1, mu2 = mu_from_slopes(P, kappa, F, df_slope, dgamma_slope)
    return _out(mu1), _out(mu2)


def mu_from_slopes(P, kappa, normal_force, df_slope, dgamma_slope):
    """μ from the Δf and ΔΓ slopes (Hz/m) with the sensitivity P (Hz per N/m) given, arrays.

    The formulas of :func:`friction_from_slopes` without its checks; ``P`` may be an array
    (one value per sweep), a slope may be None (then μ is nan).
    """
    shape = np.broadcast(P, kappa, normal_force).shape
    with np.errstate(divide="ignore", invalid="ignore"):
        if df_slope is None:
            mu1 = np.full(shape, np.nan)
        else:
            s = np.asarray(df_slope, dtype=float) / P
            mu1 = np.where(s < 0, -(kappa**2) / (6.0 * normal_force * s), np.nan)
        if dgamma_slope is None:
            mu2 = np.full(shape, np.nan)
        else:
            s = np.asarray(dgamma_slope, dtype=float) / P
            mu2 = np.where(s > 0, 2.0 * kappa**2 / (9.0 * np.pi * normal_force * s), np.nan)
    return mu1, mu2
