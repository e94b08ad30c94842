"""Quadrature of the oscillating-pressure displacement N(r̄, φ) (paper 1, Eqs. 21-22).

The numerics behind :mod:`contactres.dynamic`: the kernel table of a material, the closed-form
static parts, and the six linear functionals of N that the displacement conditions need.

Numerical method (all exact rearrangements; the accuracy is set by :class:`Resolution`)
------------------------------------------------------------------------------------------
* s = κ·(k_s a) turns ∫ds g(s/ka) F(s) into ka ∫dκ g(κ) F(κ ka): one table of g per material
  serves every frequency and every model (:class:`KernelTable`, cached).
* The static part g∞(θ) is integrated in closed form: the flat-punch pressure displaces the contact
  uniformly, N_st = (π/2) ∫ g∞ dθ; the Hertz shape gives (π/4)(1 − r̄²/2) per unit ĝ₀ plus a
  second-harmonic term ∝ r̄² (Weber-Schafheitlin integrals). Only g − g∞ (~1/κ²) is integrated.
* Near field 0 < κ < T₁ (T₁ beyond every bulk and Rayleigh slowness): the path is moved into the
  upper half κ plane, where g is analytic (the branch points and the Rayleigh near-pole lie on or
  below the real axis), so no narrow feature is left on the path and ``loss=0`` (Q⁻¹ -> 0⁺) works
  as well as Q⁻¹ = 0.02. A uniform loss C(1 + iQ⁻¹) is exactly a rescaling of the wave number:
  g_lossy(κ) = g_elastic(κ √(1 + iQ⁻¹)) / (1 + iQ⁻¹), so only the elastic kernel is tabulated.
* A smooth partition of unity χ(κ) hands the real axis over from the near field (Gauss-Legendre
  in κ on [T₁, T₂]) to the far field κ > T₁, where g − g∞ is a Chebyshev series in w = (T₁/κ)²,
  split into the angular harmonics e^{2imθ} (only cos 4mθ on a cubic (001) face), and integrated
  against the analytic Bessel weights of each harmonic on a fixed s grid.
* The θ integral of the near field is the trapezoidal rule (spectrally accurate for the smooth
  periodic integrand), with g upsampled by FFT so the rule also resolves cos(s r̄ cos θ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy import special

from ..halfspace import dynamic_kernel, shear_reference, static_kernel
from ..materials import Material, require_material, rotate_tensor, voigt_to_tensor
from .weights import _bessel_even, _j1s, _sinc, _wa_harmonic_weights, _wa_line_weight

__all__ = [
    "KernelTable",
    "Resolution",
    "functionals",
    "kernel_table",
    "point_values",
    "resolution_for",
]

# T1 = _T1_FACTOR x the largest in-plane bulk slowness (units of 1/c_s); the Rayleigh slowness
# is below 1/0.69 of it for any isotropic Poisson ratio, so T1 clears every singularity.
_T1_FACTOR = 1.75
# Height of the near-field contour over the real κ axis, relative to the largest slowness.
_CONTOUR_HEIGHT = 0.3
# Width parameter of the erfc hand-over on [T1, 2 T1]: χ(T1) = 1 - 1e-17, χ(2 T1) = 1e-17.
_CHI_STEPS = 12.0
# The non-axisymmetric harmonics of the WA weight are integrated up to this s (see _far_weights).
_WA_HARMONIC_CUT = 120.0
# Upper bound of the adaptive number of θ nodes on [0, π).
_N_THETA_MAX = 1024


# ----------------------------------------------------------------------------------- resolution
@dataclass(frozen=True)
class Resolution:
    """Discretisation of the N(r̄, φ) integrals; :meth:`doubled` refines every one of them.

    Attributes
    ----------
    n_theta : θ nodes of the kernel table on [0, π) (period of g)
    n_contour : Gauss-Legendre nodes on the complex near-field contour 0 -> T₁
    n_segment : Gauss-Legendre nodes on the real hand-over segment [T₁, 2T₁]
    n_fit : Chebyshev nodes of the far field in w = (T₁/κ)²
    s_ratio : ratio of the geometric far-field s panels (below s = 8)
    s_panel : width of the uniform far-field s panels above s = 8
    s_far : end of the far-field s grid; beyond it the leading asymptotic term (~ s_far^-2.5) is
        added in closed form (:func:`_far_remainder`) and the rest (~ s_far^-3.5) neglected
    n_gauss : Gauss-Legendre nodes per far-field s panel
    theta_tol : n_theta is doubled until the angular harmonics of g in the upper half of the
        resolved band are below theta_tol times the axisymmetric part (strong anisotropy needs
        more: A = 0.2 takes 128 nodes)
    """

    n_theta: int = 32
    n_contour: int = 48
    n_segment: int = 40
    n_fit: int = 20
    s_ratio: float = 1.25
    s_panel: float = 2.0
    s_far: float = 600.0
    n_gauss: int = 12
    theta_tol: float = 1e-11

    def doubled(self) -> Resolution:
        """Every resolution doubled (the convergence check of the tests)."""
        return replace(
            self,
            n_theta=2 * self.n_theta,
            n_contour=2 * self.n_contour,
            n_segment=2 * self.n_segment,
            n_fit=2 * self.n_fit,
            s_ratio=math.sqrt(self.s_ratio),
            s_panel=self.s_panel / 2,
            s_far=2 * self.s_far,
            n_gauss=2 * self.n_gauss,
            theta_tol=self.theta_tol * 1e-2,
        )


def resolution_for(rtol: float) -> Resolution:
    """The :class:`Resolution` that reaches relative accuracy ``rtol`` of the DCSF.

    Measured (tests and benchmarks/bench_dcsf.py, k_l a <= 2, A in [0.2, 10]): the default
    (rtol in [1e-8, 1e-4)) moves by < 1e-6 when every resolution is doubled, and by ~1e-8
    typically; rtol >= 1e-4 takes a coarser grid (still ~1e-6); rtol < 1e-8 doubles everything.
    """
    r = float(rtol)
    if not (np.isfinite(r) and 1e-10 <= r < 1):
        raise ValueError(f"rtol must lie in [1e-10, 1), got {rtol!r}")
    if r >= 1e-4:
        return Resolution(
            n_contour=32, n_segment=28, n_fit=14, s_far=150.0, n_gauss=10, theta_tol=1e-8
        )
    if r < 1e-8:
        return Resolution().doubled()
    return Resolution()


# ----------------------------------------------------------------------------------- materials
def _check_loss(loss) -> float:
    q = float(loss)
    if not (np.isfinite(q) and 0 <= q < 1):
        raise ValueError(f"loss (Q^-1) must lie in [0, 1), got {loss!r}")
    return q


def _max_slowness(m: Material) -> float:
    """Largest slowness of bulk waves travelling along the surface, in units of 1/c_s."""
    c = voigt_to_tensor(np.asarray(m.C).real) / shear_reference(m)
    th = np.linspace(0.0, np.pi, 181)
    n = np.stack([np.cos(th), np.sin(th), np.zeros_like(th)], axis=-1)
    gamma = np.einsum("ijkl,tj,tl->tik", c, n, n)
    lam = np.linalg.eigvalsh(gamma)[:, 0]
    return float(np.max(1.0 / np.sqrt(lam)))


# ----------------------------------------------------------------------------------- the table
def _gauss(a: float, b: float, n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


@dataclass(frozen=True, eq=False)
class KernelTable:
    """g(κ, θ) − g∞(θ) of one material and loss on the nodes every frequency and model reuse.

    Built by :func:`kernel_table` (cached). Dimensionless; θ on [0, π) (g has period π).
    """

    resolution: Resolution
    loss: float
    t1: float
    theta: np.ndarray  # (nθ,)
    ginf: np.ndarray  # (nθ,) lossy g∞(θ) = C44 Ĝ(θ)/(1 + iQ⁻¹)
    n_static: float  # N_st of the undamped constants = (π/2) ∫ g∞ dθ
    near_kappa: np.ndarray  # (nk,) complex nodes of the near field (contour + segment)
    near_weight: np.ndarray  # (nk,) quadrature weights dκ × χ(κ)
    near_values: np.ndarray  # (nk, nθ) g − g∞ at the near nodes
    far_harmonics: np.ndarray  # (n_m,) harmonic indices m of e^{2imθ} kept in the far field
    far_coeffs: np.ndarray  # (n_m, n_fit) Chebyshev coefficients of (g − g∞)/w per harmonic
    fourfold: bool = False  # g(θ + π/2) = g(θ): only harmonics e^{4ijθ}


_TABLES: dict = {}
_TABLES_MAX = 32


def _elastic_kernel(m: Material, kappa, theta, loss: float):
    """g of the lossy solid C(1 + iQ⁻¹) from the elastic one: g(κ√(1 + iQ⁻¹))/(1 + iQ⁻¹)."""
    f = 1 + 1j * loss
    k = np.asarray(kappa, dtype=complex) * np.sqrt(f)
    return dynamic_kernel(m, k, theta) / f


def kernel_table(m: Material, loss: float = 0.02, resolution: Resolution | None = None):
    """The :class:`KernelTable` of the undamped material ``m`` (surface frame) with loss Q⁻¹."""
    m = require_material(m, lossless=True)
    q = _check_loss(loss)
    res = resolution or Resolution()
    key = (np.asarray(m.C).tobytes(), q, res)
    table = _TABLES.get(key)
    if table is None:
        if len(_TABLES) >= _TABLES_MAX:
            _TABLES.pop(next(iter(_TABLES)))
        table = _build_table(m, q, res)
        _TABLES[key] = table
    return table


def _symmetry(m: Material) -> tuple[bool, bool]:
    """(mirror, fourfold): g(−θ) = g(θ) (mirror plane y -> −y) and g(θ + π/2) = g(θ) (4-fold
    axis along z) of the surface-frame stiffness; a cubic (001) face has both."""
    c = voigt_to_tensor(np.asarray(m.C).real)
    scale = np.max(np.abs(c))

    def same(rot):
        cr = rotate_tensor(c, np.asarray(rot, dtype=float))
        return bool(np.max(np.abs(cr - c)) <= 1e-12 * scale)

    return same([[1, 0, 0], [0, -1, 0], [0, 0, 1]]), same([[0, -1, 0], [1, 0, 0], [0, 0, 1]])


def _theta_values(m, kappa, q, ginf_fn, nth, symmetry, old=None):
    """g − g∞ on κ × (θ_j = πj/nth); reuses ``old`` (the values at nth/2) and the symmetry."""
    mirror, fourfold = symmetry
    j = np.arange(nth)
    base = j % (nth // 2) if fourfold else j
    if mirror:
        period = nth // 2 if fourfold else nth
        base = np.minimum(base, period - base)
    need = np.unique(base)
    values = np.empty((kappa.size, nth), dtype=complex)
    if old is not None:
        have = need[need % 2 == 0]
        values[:, have] = old[:, have // 2]
        need = need[need % 2 == 1]
    theta = np.pi * need / nth
    values[:, need] = _elastic_kernel(m, kappa[:, None], theta[None, :], q) - ginf_fn(theta)
    return values[:, base]


def _build_table(m: Material, q: float, res: Resolution) -> KernelTable:
    c44 = shear_reference(m)
    kb = _max_slowness(m)
    t1 = _T1_FACTOR * kb
    height = _CONTOUR_HEIGHT * kb

    # Near field: κ(t) = t + i h sin(π t/T1) on [0, T1], then the real segment [T1, 2 T1].
    t, wt = _gauss(0.0, t1, res.n_contour)
    kc = t + 1j * height * np.sin(np.pi * t / t1)
    wc = wt * (1 + 1j * height * np.pi / t1 * np.cos(np.pi * t / t1))
    ks, ws = _gauss(t1, 2 * t1, res.n_segment)
    ws = ws * _chi(ks, t1)
    near_kappa = np.concatenate([kc, ks.astype(complex)])
    near_weight = np.concatenate([wc, ws])
    # Far field: (g − g∞)/w as a Chebyshev series in x = 2w − 1, w = (T1/κ)² in (0, 1).
    nf = res.n_fit
    x = np.cos(np.pi * (np.arange(nf) + 0.5) / nf)
    w = 0.5 * (x + 1)
    kappa = np.concatenate([near_kappa, t1 / np.sqrt(w)])

    def ginf_fn(theta):
        return c44 * static_kernel(m, theta) / (1 + 1j * q)

    symmetry = _symmetry(m)
    nth = res.n_theta
    values = None
    while True:
        values = _theta_values(m, kappa, q, ginf_fn, nth, symmetry, values)
        harm = np.abs(np.fft.fft(values, axis=1))
        tail = np.max(harm[:, nth // 4 : nth - nth // 4 + 1])
        if tail <= res.theta_tol * np.max(harm[:, 0]) or nth >= _N_THETA_MAX:
            break
        nth *= 2
    theta = np.pi * np.arange(nth) / nth
    ginf0 = c44 * static_kernel(m, theta)  # undamped
    ginf = ginf0 / (1 + 1j * q)
    n_static = 0.5 * np.pi * (2 * np.pi) * float(np.mean(ginf0))
    near_values = values[: near_kappa.size]
    vals = values[near_kappa.size :] / w[:, None]
    tk = np.polynomial.chebyshev.chebvander(x, nf - 1)  # (nf, nf)
    coeffs = (2.0 / nf) * (tk.T @ vals)  # (nf, nθ)
    coeffs[0] *= 0.5
    harm = np.fft.fft(coeffs, axis=1) / nth  # (nf, nθ) harmonic m at index m mod nθ
    mm = np.fft.fftfreq(nth, 1.0 / nth).astype(int)
    keep = np.max(np.abs(harm), axis=0) > 1e-13 * np.max(np.abs(harm))
    keep &= np.abs(mm) < nth // 2
    return KernelTable(
        resolution=res,
        loss=q,
        t1=t1,
        theta=theta,
        ginf=ginf,
        n_static=n_static,
        near_kappa=near_kappa,
        near_weight=near_weight,
        near_values=near_values,
        far_harmonics=mm[keep],
        far_coeffs=harm[:, keep].T,
        fourfold=symmetry[1],
    )


def _chi(kappa, t1: float):
    """Smooth hand-over: 1 below T1, 0 above 2 T1 (to 1e-17), erfc-shaped between."""
    width = t1 / _CHI_STEPS
    return 0.5 * special.erfc((np.real(kappa) - 1.5 * t1) / width)


# ----------------------------------------------------------------------------------- far grid
_GRIDS: dict = {}


def _far_grid(res: Resolution, s_low: float):
    """Nodes and weights of the far-field s integral on [s_low, s_far] (geometric, then uniform)."""
    top = 8.0
    edges = [top]
    while edges[-1] > s_low:
        edges.append(edges[-1] / res.s_ratio)
    edges = edges[::-1]
    n_uni = max(1, math.ceil((res.s_far - top) / res.s_panel))
    edges.extend(top + res.s_panel * np.arange(1, n_uni + 1))
    edges = np.asarray(edges)
    x, w = np.polynomial.legendre.leggauss(res.n_gauss)
    a, b = edges[:-1, None], edges[1:, None]
    s = (0.5 * (b - a) * x + 0.5 * (b + a)).ravel()
    ws = (0.5 * (b - a) * w).ravel()
    return s, ws, float(edges[-1])


_FAR_CACHE: dict = {}


def _far_basis(table: KernelTable, ka: np.ndarray):
    """The far-field s grid for k_s a values ``ka`` (1-D, > 0) and the Chebyshev basis on it.

    Returns the grid's cache key, s, the end S of the grid and ``basis`` (na, ns, nf): T_f(2w − 1)
    × w × (1 − χ(s/ka)) × ds with w = (T1 ka/s)² (zero where w > 1), so that ``basis @
    far_coeffs[m]`` is harmonic m of g − g∞ at κ = s/ka times the hand-over and ds. The grid is
    shared (cached) by all ka whose smallest value falls in the same geometric bin.
    """
    res = table.resolution
    # Quantise s_low so that curves with nearby smallest ka share a grid.
    s_low = table.t1 * float(np.min(ka))
    level = math.floor(math.log(max(s_low, 1e-8)) / math.log(res.s_ratio))
    gkey = (res, level)
    grid = _GRIDS.get(gkey)
    if grid is None:
        if len(_GRIDS) > 16:
            old = next(iter(_GRIDS))
            del _GRIDS[old]
            # ...and the weights on it, which would otherwise pile up in a long session.
            for key in [k for k in _FAR_CACHE if k[0] == old]:
                del _FAR_CACHE[key]
        grid = _GRIDS[gkey] = _far_grid(res, res.s_ratio**level)
    sg, ds, s_end = grid
    w = (table.t1 * ka[:, None] / sg[None, :]) ** 2  # (na, ns)
    inside = w <= 1
    x = np.where(inside, 2 * w - 1, 1.0)
    nf = table.far_coeffs.shape[1]
    hand = (1 - _chi(sg[None, :] / ka[:, None], table.t1)) * inside * w * ds[None, :]
    basis = np.polynomial.chebyshev.chebvander(x, nf - 1) * hand[:, :, None]  # (na, ns, nf)
    return gkey, sg, s_end, basis


def _far_weights(gkey, s: np.ndarray, harmonics: np.ndarray) -> np.ndarray:
    """Analytic weights of the far field on the grid ``gkey`` (nodes ``s``; from
    :func:`_far_basis`), cached per grid and harmonic.

    Returns a (6, n_m, n_s) array: for the functionals F0, F1, FW, F2D, H0, H1 (see
    :func:`functionals`) and harmonic e^{inθ}, n = 2m, the factor 2π iⁿ × (shape transform) ×
    (J_n(s r̄) at the point, or its WA average W_n).
    """
    res = gkey[0]
    sinc = _sinc(s)
    j1s = _j1s(s)
    nabs = [int(n) for n in 2 * np.abs(harmonics)]
    missing = sorted({n for n in nabs if (gkey, n) not in _FAR_CACHE})
    if missing:
        # WA weights of the non-axisymmetric harmonics: their share of N is ~1e-3, so stopping
        # them at s = _WA_HARMONIC_CUT costs < 1e-8 relative (their tail ~ s^-2.5).
        cut = s <= min(_WA_HARMONIC_CUT, res.s_far)
        wtab = _wa_harmonic_weights(s[cut], max(missing))
        jtab = _bessel_even(missing, s)
        for n in missing:
            wn = np.zeros_like(s)
            wn[cut] = wtab[n // 2]
            if n == 0:
                wn = sinc
            _FAR_CACHE[(gkey, n)] = (jtab[n], wn)
    two_pi = 2 * np.pi
    out = np.zeros((6, len(nabs), s.size))
    for i, n in enumerate(nabs):
        jn, wn = _FAR_CACHE[(gkey, n)]
        sign = two_pi * (1 if n % 4 == 0 else -1)  # 2π iⁿ
        out[1, i] = sign * sinc * jn
        out[2, i] = sign * sinc * wn
        out[5, i] = sign * j1s * jn
        if n == 0:
            out[0, i] = two_pi * sinc
            out[3, i] = two_pi * sinc**2
            out[4, i] = two_pi * j1s
    return out


# ----------------------------------------------------------------------------------- functionals
def _resampled(values: np.ndarray, n_out: int) -> np.ndarray:
    """Rows sampled on n equispaced θ in [0, π), trigonometrically resampled to n_out points
    (harmonics |m| < min(n, n_out)/2 kept: the weights they multiply vanish beyond)."""
    n = values.shape[-1]
    if n_out == n:
        return values
    h = np.fft.fft(values, axis=-1)
    out = np.zeros((*values.shape[:-1], n_out), dtype=complex)
    half = min(n, n_out) // 2
    out[..., :half] = h[..., :half]
    out[..., n_out - half + 1 :] = h[..., n - half + 1 :]
    return np.fft.ifft(out, axis=-1) * (n_out / n)


def _n_theta_near(smax: float) -> int:
    """θ nodes on [0, π) that resolve cos(s cos θ), |s| <= smax: its harmonics e^{2imθ} are
    J_2m(s), negligible beyond 2|m| ~ |s| + 12."""
    return int(8 * math.ceil((1.1 * smax + 24) / 8))


def _static_values(table: KernelTable) -> dict:
    """Closed-form static parts (lossy g∞) of the six functionals (see module docstring)."""
    g0 = np.mean(table.ginf)
    g2 = 2 * np.mean(table.ginf * np.cos(2 * table.theta))  # ĝ₂ + ĝ₋₂
    flat = np.pi**2 * g0
    return {
        "F0": flat,
        "F1": flat,
        "FW": flat,
        "F2D": flat,
        "H0": 2 * np.pi * (np.pi / 4) * g0,
        "H1": 2 * np.pi * ((np.pi / 8) * g0 - (np.pi / 16) * g2),
    }


_FUNCTIONALS = ("F0", "F1", "FW", "F2D", "H0", "H1")


def functionals(table: KernelTable, ksa: np.ndarray) -> dict:
    """N of the six functionals at k_s a values ``ksa`` (1-D, >= 0).

    F0 = N_F(0), F1 = N_F(1, 0), FW = WA average of N_F along φ = 0 (Eq. 27), F2D = WA average
    over the whole contact, H0 = N_H(0), H1 = N_H(1, 0) (Hertz-shaped pressure, for TP).
    """
    static = _static_values(table)
    out = {k: np.full(ksa.shape, v, dtype=complex) for k, v in static.items()}
    pos = ksa > 0
    if not np.any(pos):
        return out
    ka = ksa[pos]

    # Near field: θ-direct trapezoidal rule on a resampled grid, folded onto [0, π/2].
    s = ka[:, None] * table.near_kappa[None, :]  # (na, nk)
    nt = _n_theta_near(float(np.max(np.abs(s))))
    vals = _resampled(table.near_values, nt)  # (nk, nt)
    half = nt // 2
    fold = vals[:, : half + 1].copy()
    fold[:, 1:half] += vals[:, nt - 1 : half : -1]
    cth = np.cos(np.pi * np.arange(half + 1) / nt)
    dth = 2 * np.pi / nt
    mean0 = np.mean(vals, axis=1) * 2 * np.pi  # ∫ (g − g∞) dθ
    wk = table.near_weight[None, :] * ka[:, None]  # ka dκ χ
    sinc = _sinc(s)
    j1s = _j1s(s)
    z = s[:, :, None] * cth[None, None, :]
    c1 = np.sum(np.cos(z) * fold, axis=2) * dth
    cw = np.sum(_wa_line_weight(z) * fold, axis=2) * dth
    near = [
        np.sum(wk * sinc * mean0, axis=1),
        np.sum(wk * sinc * c1, axis=1),
        np.sum(wk * sinc * cw, axis=1),
        np.sum(wk * sinc**2 * mean0, axis=1),
        np.sum(wk * j1s * mean0, axis=1),
        np.sum(wk * j1s * c1, axis=1),
    ]

    # Far field: Chebyshev series in w = (T1 ka/s)² against the harmonic weights on a fixed grid.
    gkey, sg, s_end, basis = _far_basis(table, ka)
    weights = _far_weights(gkey, sg, table.far_harmonics)
    # v[f, s, j] = Σ_m c_{m f} weight_j[m, s]  for the six functionals j.
    v = np.einsum("mf,jms->sfj", table.far_coeffs, weights, optimize=True)
    basis = basis.reshape(ka.size, -1)
    v = v.reshape(-1, 6)
    far = basis @ v.real + 1j * (basis @ v.imag)  # (na, 6)
    far += _far_remainder(table, ka, s_end)
    for j, name in enumerate(_FUNCTIONALS):
        out[name][pos] += near[j] + far[:, j]
    return out


def _far_limit(table: KernelTable) -> np.ndarray:
    """C₁ per far-field harmonic: the limit of (g − g∞)/w as w = (T1/κ)² -> 0, Σ_k c_k T_k(−1)."""
    nf = table.far_coeffs.shape[1]
    return table.far_coeffs @ np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)


def _far_remainder(table: KernelTable, ka: np.ndarray, s_end: float) -> np.ndarray:
    """Leading asymptotics of the far field beyond the end S of the s grid, (na, 6).

    There g − g∞ -> w C₁(θ), w = (T1 ka/s)², C₁ = Σ_k c_k T_k(−1). Averaged over their
    oscillation, the weights of the edge point tend to 2π iⁿ sinc(s) J_n(s) -> √π s^-3/2 and
    2π iⁿ (j₁(s)/s) J_n(s) -> −√π s^-5/2 for every even n, and sinc² -> 1/(2s²); the centre
    weight 2π sinc(s) leaves 2π cos(S)/S³ (by parts). What is left (the oscillating parts, the WA
    weight, whose r = 1 endpoint is softened by the average) is below (T1 ka)² S^-3.5.
    """
    c1 = _far_limit(table)
    scale = (table.t1 * ka) ** 2
    out = np.zeros((ka.size, 6), dtype=complex)
    edge = np.sum(c1)  # Σ_m C₁_m: the direction φ = 0
    axis = np.sum(c1[table.far_harmonics == 0])
    out[:, 1] = scale * edge * math.sqrt(math.pi) * 0.4 * s_end**-2.5
    out[:, 5] = -scale * edge * math.sqrt(math.pi) * (2 / 7) * s_end**-3.5
    out[:, 3] = scale * axis * 2 * math.pi / 6 * s_end**-3
    out[:, 2] = out[:, 3]  # the axisymmetric WA weight is sinc², the others are ~1e-3 of it
    out[:, 0] = scale * axis * 2 * math.pi * math.cos(s_end) * s_end**-3
    return out


def point_values(table: KernelTable, ksa: float, rbar: np.ndarray, phi: np.ndarray, shape: str):
    """N(r̄, φ) at one k_s a for points (r̄, φ), 0 <= r̄ <= 1, of the flat-punch (``"flat"``) or
    Hertz-shaped (``"hertz"``) oscillating pressure (paper 1, Eq. 22; TP's N_H)."""
    rbar = np.asarray(rbar, dtype=float).ravel()
    phi = np.asarray(phi, dtype=float).ravel()
    shape_fn = _sinc if shape == "flat" else _j1s
    # Static part (closed form).
    g0 = np.mean(table.ginf)
    if shape == "flat":
        out = np.full(rbar.shape, np.pi**2 * g0, dtype=complex)
    else:
        g2 = 2 * np.mean(table.ginf[None, :] * np.cos(2 * (table.theta[None, :] - phi[:, None])), 1)
        out = 2 * np.pi * ((np.pi / 4) * (1 - rbar**2 / 2) * g0 - (np.pi / 16) * rbar**2 * g2)
    if ksa <= 0:
        return out
    # Near field: θ-direct on the full period.
    s = ksa * table.near_kappa  # (nk,)
    nt = _n_theta_near(float(np.max(np.abs(s))))
    vals = _resampled(table.near_values, nt)  # (nk, nt)
    theta = np.pi * np.arange(nt) / nt
    arg = rbar[:, None] * np.cos(theta[None, :] - phi[:, None])  # (np, nt)
    cosw = np.cos(s[None, :, None] * arg[:, None, :])  # (np, nk, nt)
    inner = np.einsum("pkt,kt->pk", cosw, vals) * (2 * np.pi / nt)
    out += np.sum(inner * (table.near_weight * ksa * shape_fn(s))[None, :], axis=1)
    # Far field: harmonics with J_n(s r̄) weights; the grid and Chebyshev basis as in dcsf.
    _, sg, s_end, basis = _far_basis(table, np.array([ksa]))
    basis = basis[0]  # (ns, nf)
    dhat = table.far_coeffs @ basis.T  # (n_m, ns): harmonic m of g − g∞ at s/ksa
    nabs = 2 * np.abs(table.far_harmonics)
    sign = np.where(nabs % 4 == 0, 1.0, -1.0)
    coef = 2 * np.pi * sign[:, None] * dhat * shape_fn(sg)[None, :]  # (n_m, ns)
    ph = np.exp(2j * np.outer(phi, table.far_harmonics))  # (np, n_m)
    orders = {int(n) for n in nabs}
    for lo in range(0, rbar.size, 16):
        r = rbar[lo : lo + 16]
        x = np.outer(r, sg)  # (nr, ns)
        jn = _bessel_even(orders, np.where(x > 0, x, 1.0))
        for i, n in enumerate(nabs):
            j = np.where(x > 0, jn[int(n)], 1.0 if n == 0 else 0.0)
            out[lo : lo + 16] += ph[lo : lo + 16, i] * (j @ coef[i])
    if shape == "flat":
        # Slowly oscillating tail of sinc(s) J_n(s r̄) beyond the grid (see _far_remainder).
        c1 = _far_limit(table)
        edge = ph @ c1
        inside = rbar > 0
        r = np.where(inside, rbar, 1.0)
        tail = (table.t1 * ksa) ** 2 * np.pi * np.sqrt(2 / (np.pi * r)) * _tail_sine(1 - r, s_end)
        centre = _far_remainder(table, np.array([ksa]), s_end)[0, 0]  # F0's tail, r̄ = 0
        out += np.where(inside, edge * tail, centre)
    return out


def _tail_sine(beta: np.ndarray, s_end: float) -> np.ndarray:
    """∫_S^∞ s^-7/2 sin(β s + π/4) ds (β >= 0), the slow tail of the flat-punch weight.

    With u = β s it is β^{5/2} Im[e^{iπ/4} F_{7/2}(βS)], F_ν(x) = ∫_x^∞ u^-ν e^{iu} du, from the
    Fresnel integrals F_{1/2} and F_{ν+1} = (i F_ν + x^-ν e^{ix})/ν (integration by parts).
    """
    beta = np.asarray(beta, dtype=float)
    out = np.full(beta.shape, math.sin(math.pi / 4) * 0.4 * s_end**-2.5)
    pos = beta > 1e-9
    if np.any(pos):
        b = beta[pos]
        x = b * s_end
        fs, fc = special.fresnel(np.sqrt(2 * x / np.pi))
        f = math.sqrt(np.pi / 2) * ((1 - 2 * fc) + 1j * (1 - 2 * fs))  # F_{1/2}(x)
        e = np.exp(1j * x)
        for nu in (0.5, 1.5, 2.5):
            f = (1j * f + x**-nu * e) / nu
        out[pos] = b**2.5 * np.imag(np.exp(1j * np.pi / 4) * f)
    return out
