"""Resonance-curve fits of QCM admittance spectra: f_r and Γ of every spectrum, batched.

Each amplitude step of a QCM sweep (paper 2: Vlachová, König, Johannsmann, Beilstein J.
Nanotechnol. 6, 845 (2015)) is an admittance spectrum Y = G + iB of the quartz around one
overtone. The fitted curve is the motional branch of the Butterworth–van Dyke (BVD) circuit
(R, L, C in series, C0 in parallel; Johannsmann, *The Quartz Crystal Microbalance in Soft Matter
Research*, Springer 2015, ch. 4) in resonance parameters, with an instrumental phase rotation
and a sloping complex baseline::

    Y(f) = G_max e^{iφ} / (1 + i u(f)) + (G_off + i B_off) + (s' + i s'') (f − f_c)
    u = (f² − f_r²) / (2 f Γ)     model "bvd" (default): the BVD circuit exactly
    u = (f − f_r) / Γ             model "lorentzian": the usual approximation

(R = 1/G_max, L = R/(4πΓ), C = 1/((2π f_r)² L), see :mod:`.synthetic_spectra`; f_c a fixed
frequency inside the spectrum). C0 adds iωC0 = i2πC0·f, linear in f: the offset and slope absorb
it exactly, and a C0 drifting by ΔC0 during a sweep over Δf up to 2πΔC0(f − f_start)²/Δf, orders
of magnitude below any noise.

The parameters (φ = 0, baseline removed; Q = f_r/(2Γ)):

- ``f_r`` is the series resonance, the maximum of G. For "bvd", G = G_max/(1 + u²) is G_max/2
  at u = ±1, i.e. at f± = √(f_r² + Γ²) ± Γ: the full width at half height is exactly 2Γ, so Γ
  is exactly the half width at half height of G; the midpoint of f± lies Γ²/(2f_r) = Γ/(4Q)
  above f_r. For "lorentzian", G = G_max Γ²/((f − f_r)² + Γ²): symmetric, half width Γ.
- u_bvd = u_lor (1 + ε u_lor)/(1 + 2ε u_lor), ε = Γ/(2f_r) = 1/(4Q): an odd distortion of
  first order in ε. A Lorentzian fitted to a BVD curve returns Γ to second order, ``|Γ_lor/Γ − 1|``
  ~ ε² = 1/(16Q²) (< 1e-9 at Q >= 1e4), and f_r off by up to εΓ = Γ/(4Q) (2.5e-5 Γ at
  Q = 1e4): with B by −εΓ (the real part √(f_r² − Γ²) of the complex pole), for G alone by a
  fraction of +εΓ (0.59 over f_r ± 5Γ). tests/measurements/test_spectra_fit.py checks this.
- ``g_max_S`` = G_max = 1/R and ``phase_rad`` = φ: the complex amplitude is G_max e^{iφ}.

Where B is not given (``B_S=None``, or all NaN in a spectrum) G alone is fitted,
G = G_max/(1 + u²) + G_off + s'(f − f_c), φ = 0 assumed (``phase_rad`` NaN: not fitted).

Method: the curve is linear in the amplitude and the baseline, so only (f_r, Γ) are iterated
(variable projection; Golub & Pereyra, SIAM J. Numer. Anal. 10, 413 (1973)).
:func:`scipy.optimize.least_squares` iterates them for every spectrum of a batch at once (no
Python loop over spectra; see :func:`_solve`) from the peak and half-height points
(:func:`_batch`), within bounds that keep a lost fit contained (it ends flagged). Convergence is
checked per spectrum (:data:`STEP_TOL`); a spectrum that fails is iterated again.

Standard errors: inv(JᵀJ)·s², J the Jacobian of the full curve (8 real parameters, 5 for G
alone; the baseline marginalised), s² = RSS/(N − P) the residual variance of the spectrum (N
real residuals), so they hold whatever the noise. ``reduced_chi2`` = s²/σ², σ = ``noise_S`` if
given, else the point-to-point noise of the residuals, ``σ² = Σ|r_{j+1} − r_j|²/(2(N − 1))`` per
component (von Neumann): about 1 for white residuals, above 1 for a curve that does not fit.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from scipy import sparse
from scipy.optimize import least_squares

from .._threads import one_blas_thread
from ..errors import ContactresInputError

__all__ = ["COLUMNS", "FLAGS", "MODELS", "fit_resonances", "resonance_curve"]

#: The fitted curves (see the module docstring).
MODELS = ("bvd", "lorentzian")
#: The columns of :func:`fit_resonances`, in order.
COLUMNS = tuple(
    "spectrum f_r_Hz f_r_err_Hz gamma_Hz gamma_err_Hz g_max_S phase_rad reduced_chi2 "
    "n_points converged flags".split()
)
#: Points a spectrum needs to be fitted (8 parameters with B, 5 for G alone).
MIN_POINTS = 8
#: |G| or |B| above this (S; a milliohm is 1e3 S) is no admittance a network analyser measures.
MAX_ADMITTANCE_S = 1e6
#: Fewer points than this within f_r ± Γ: flag ``too-few-points``.
MIN_WITHIN = 5
#: Fewer points than this within f_r ± Γ: no value either (the peak lies between the points).
MIN_WITHIN_VALUE = 3
#: A resonance is told from noise when G_max is at least this many standard errors (pure noise
#: reaches ~4 in 1000 spectra of 200 points).
MIN_SIGNIFICANCE = 8.0
#: Converged: the remaining Gauss–Newton step of f_r and Γ below this many standard errors.
STEP_TOL = 0.05
#: least_squares runs per batch (the later ones on the spectra not yet converged), evaluations
#: per run, at most.
PASSES, MAX_NFEV = 5, 8
#: The relative cost tolerance of a batch (scipy's ``ftol``; convergence is checked per spectrum).
FTOL = 1e-6
_NUMERIC = frozenset({"floating", "integer", "mixed-integer-float", "decimal", "empty"})

#: The flags, in the order listed. Each leaves the fitted values (f_r, Γ, G_max, φ, errors) NaN,
#: except ``too-few-points`` with at least :data:`MIN_WITHIN_VALUE` points within f_r ± Γ.
FLAGS = {
    "bad-values": (
        "NaN/inf frequency or G, inf B, B at some points only, f <= 0, or |G| or |B| above "
        "1e6 S (no measured admittance): not fitted"
    ),
    "frequencies-not-increasing": "not strictly increasing (duplicates, out of order): not fitted",
    "too-few-points": f"< {MIN_POINTS} points (not fitted), or < {MIN_WITHIN} within f_r ± Γ",
    "no-peak": f"G_max < {MIN_SIGNIFICANCE:g} standard errors (< 0, G alone): only noise",
    "peak-not-covered": "f_r − Γ or f_r + Γ (a half-height point) outside the measured range",
    "not-converged": f"step of f_r or Γ > {STEP_TOL:g} standard errors after {PASSES} passes",
}


def _u(d, x_f, einv, model: str):
    """u for d = (f − f_r)/w, x_f = w/f, einv = w/Γ: "bvd" (f² − f_r²)/(2fΓ), else (f − f_r)/Γ."""
    return d * einv * (1.0 - 0.5 * d * x_f) if model == "bvd" else d * einv


def resonance_curve(
    frequency_Hz, f_r, gamma, g_max, phase=0.0, offset=0.0, slope=0.0, f_c=None, model="bvd"
) -> np.ndarray:
    """The fitted curve Y = G_max e^{iφ}/(1 + iu) + offset + slope·(f − f_c), S (complex): f in
    Hz, G_max and offset in S, slope in S/Hz, φ in rad, f_c = f_r by default, ``model`` "bvd" or
    "lorentzian" (module docstring). With φ = 0 its real part is the curve fitted to G alone."""
    if model not in MODELS:
        raise ContactresInputError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    f = np.asarray(frequency_Hz, dtype=float)
    f_r, gamma = np.asarray(f_r, dtype=float), np.asarray(gamma, dtype=float)
    u = _u((f - f_r) / gamma, gamma / f, 1.0, model)
    fc = f_r if f_c is None else np.asarray(f_c, dtype=float)
    return g_max * np.exp(1j * np.asarray(phase)) / (1.0 + 1j * u) + offset + slope * (f - fc)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Σ conj(a)·b along the last axis (np.vecdot from numpy 2 on: fast, no temporary)."""
    return np.vecdot(a, b) if hasattr(np, "vecdot") else np.einsum("...m,...m->...", a.conj(), b)


@dataclass(frozen=True)
class _Batch:
    """Spectra padded to one length m (weight 0 on the padding), x in units of the start."""

    x: np.ndarray  # (f − f_c)/w, (nb, m)
    x_f: np.ndarray  # w/f
    f_c: np.ndarray  # (nb, 1) Hz
    w: np.ndarray  # (nb, 1) Hz
    e1: np.ndarray  # the weighted baseline W·1, W·x, orthonormalised (dtype of y)
    e2: np.ndarray
    y: np.ndarray  # W·Y, baseline projected out
    wt: np.ndarray  # W: 1/σ over the starting peak height, 0 on the padding
    model: str

    def take(self, k: np.ndarray) -> _Batch:
        names = [n for n in self.__dataclass_fields__ if n != "model"]
        return replace(self, **{n: getattr(self, n)[k] for n in names})

    def moved(self, f_c: np.ndarray, w: np.ndarray) -> _Batch:
        """The same spectra in the units of another start (the baseline span is the same)."""
        f = self.f_c + self.w * self.x
        x = np.where(self.wt > 0, (f - f_c) / w, 0.0)
        return _Batch(x, w / f, f_c, w, self.e1, self.e2, self.y, self.wt, self.model)

    def proj(self, v: np.ndarray) -> np.ndarray:
        """v less its weighted baseline part."""
        e1, e2 = self.e1, self.e2
        return v - e1 * _dot(e1, v)[:, None] - e2 * _dot(e2, v)[:, None]

    def state(self, p: np.ndarray, q: np.ndarray, derivatives: bool = False) -> dict:
        """At f_r = f_c + w p, Γ = w e^q: residuals r, amplitude a, the weighted curve shape wl
        and its projection ``basis`` (norm²); with ``derivatives`` the projected ∂curve/∂p,q."""
        einv = np.exp(-q)[:, None]
        u = _u(self.x - p[:, None], self.x_f, einv, self.model)
        den = 1.0 / (1.0 + u * u)
        if np.iscomplexobj(self.y):
            shape = np.empty(u.shape, dtype=complex)
            shape.real, shape.imag = den, -u * den  # 1/(1 + iu)
        else:
            shape = den
        wl = self.wt * shape
        basis = self.proj(wl)
        norm = np.maximum(_dot(basis, basis).real, 1e-300)
        a = _dot(wl, self.y) / norm  # = <basis, y>: y has no baseline part
        out = {"r": self.y - a[:, None] * basis, "a": a, "basis": basis, "norm": norm, "wl": wl}
        if derivatives:
            if np.iscomplexobj(self.y):
                ds = (-1j * a)[:, None] * (shape * shape) * self.wt  # a ∂shape/∂u
            else:
                ds = a[:, None] * (-2.0 * u * den * den) * self.wt
            dudp = -einv * (self.f_c / self.w + p[:, None]) * self.x_f  # −f_r w/(fΓ)
            out["dp"] = self.proj(ds * (dudp if self.model == "bvd" else -einv))
            out["dq"] = self.proj(ds * -u)
        return out


def _inverse(m: np.ndarray) -> np.ndarray:
    """inv(m) of symmetric (nb, k, k), Jacobi-scaled eigen-decomposition; NaN where singular."""
    d = np.sqrt(np.maximum(np.einsum("nii->ni", m), 1e-300))
    dd = d[:, :, None] * d[:, None, :]
    lam, v = np.linalg.eigh(m / dd)
    ok = lam.min(1) > 1e-13 * lam.max(1)
    inv = np.einsum("nij,nj,nkj->nik", v, 1.0 / np.where(ok[:, None], lam, 1.0), v) / dd
    inv[~ok] = np.nan
    return inv


def _stats(b: _Batch, p: np.ndarray, q: np.ndarray) -> dict:
    """Covariance of (p, q, a) with the baseline marginalised, s², σ² and the Gauss–Newton step."""
    st = b.state(p, q, derivatives=True)
    dp, dq, basis, r, nrm = st["dp"], st["dq"], st["basis"], st["r"], st["norm"]
    pb, qb, pq = _dot(dp, basis), _dot(dq, basis), _dot(dp, dq).real
    pp, qq, rb = _dot(dp, dp).real, _dot(dq, dq).real, _dot(basis, r)
    grad = [_dot(dp, r).real, _dot(dq, r).real, rb.real]
    cplx = np.iscomplexobj(b.y)
    if cplx:  # real parameters p, q, Re a, Im a; ∂curve/∂(Im a) = i·basis
        z = np.zeros_like(pp)
        rows = [[pp, pq, pb.real, -pb.imag], [pq, qq, qb.real, -qb.imag]]
        rows += [[pb.real, qb.real, nrm, z], [-pb.imag, -qb.imag, z, nrm]]
        grad.append(-rb.imag)
    else:
        rows = [[pp, pq, pb.real], [pq, qq, qb.real], [pb.real, qb.real, nrm]]
    inv = _inverse(np.stack([np.stack(row, -1) for row in rows], 1))
    valid = b.wt > 0
    per = 2 if cplx else 1  # real residuals per point
    s2 = _dot(r, r).real / np.maximum(valid.sum(1) * per - (8 if cplx else 5), 1)
    pair = valid[:, 1:] & valid[:, :-1]
    dr = np.diff(r, axis=1) * pair
    noise2 = _dot(dr, dr).real / np.maximum(2.0 * per * pair.sum(1), 1.0)
    step = np.einsum("nij,nj->ni", inv, np.stack(grad, -1))
    cov, a = inv * s2[:, None, None], st["a"]
    if cplx:  # G_max = |a| over its standard error, var |a| = aᵀ C a / |a|²
        var = (
            a.real**2 * cov[:, 2, 2] + a.imag**2 * cov[:, 3, 3] + 2 * a.real * a.imag * cov[:, 2, 3]
        )
        significance = np.abs(a) ** 2 / np.sqrt(var)
    else:
        significance = a.real / np.sqrt(cov[:, 2, 2])
    return dict(a=a, cov=cov, s2=s2, noise2=noise2, step=step, significance=significance)


def _half_height(f: np.ndarray, dev: np.ndarray, valid: np.ndarray):
    """Centre, half width (Hz) and height of the peak of ``dev`` from its interpolated
    half-height points (one side, or a quarter span, where they are not found)."""
    nb, m = f.shape
    rows, j = np.arange(nb), np.arange(m)[None, :]
    dev = np.where(valid, dev, -np.inf)
    peak = np.argmax(dev, 1)
    half = dev[rows, peak] / 2
    below = valid & (dev < half[:, None])
    jl = np.where(below & (j < peak[:, None]), j, -1).max(1)
    jr = np.where(below & (j > peak[:, None]), j, m).min(1)
    has_l, has_r = jl >= 0, jr < m
    jl, jr = np.clip(jl, 0, m - 2), np.clip(jr, 1, m - 1)
    den = np.where(has_l, dev[rows, jl + 1] - dev[rows, jl], 1.0)
    f_l = f[rows, jl] + (half - dev[rows, jl]) * (f[rows, jl + 1] - f[rows, jl]) / den
    den = np.where(has_r, dev[rows, jr - 1] - dev[rows, jr], 1.0)
    f_h = f[rows, jr - 1] + (dev[rows, jr - 1] - half) * (f[rows, jr] - f[rows, jr - 1]) / den
    f_pk = f[rows, peak]
    width = np.where(has_l & has_r, (f_h - f_l) / 2, np.where(has_l, f_pk - f_l, f_h - f_pk))
    span = f[rows, valid.sum(1) - 1] - f[:, 0]
    steps = np.where(valid[:, 1:], np.diff(f, axis=1), np.inf).min(1)
    width = np.clip(np.where(has_l | has_r, width, span / 4), steps, span)
    return np.where(has_l & has_r, (f_l + f_h) / 2, f_pk), width, 2 * half


def _batch(f: np.ndarray, y: np.ndarray, wt: np.ndarray, model: str):
    """The padded _Batch at its start, the bounds of (p, q), the range and the weight scale
    (the weights over the starting peak height times their mean: every spectrum weighs alike in
    scipy's joint stopping rules, no optimum moves; the RSS is scaled back where reported)."""
    valid = wt > 0
    n = valid.sum(1)
    fmin, fmax = f[:, 0], f[np.arange(f.shape[0]), n - 1]
    t = (f - fmin[:, None]) / (fmax - fmin)[:, None]
    ends = [valid & (t <= 0.05), valid & (t >= 0.95)]  # first and last 5 % of the span
    (y0, y1), (f0, f1) = ([np.sum(v * e, 1) / e.sum(1) for e in ends] for v in (y, f))
    dev = y - y0[:, None] - ((y1 - y0) / (f1 - f0))[:, None] * (f - f0[:, None])
    centre, width, height = _half_height(f, np.abs(dev) ** 2 if y.dtype.kind == "c" else dev, valid)
    amp = np.sqrt(np.maximum(height, 0.0)) if y.dtype.kind == "c" else np.maximum(height, 0.0)
    scale = np.where(amp > 0, amp, 1.0) * np.sum(wt, 1) / n
    wt = wt / scale[:, None]
    x = np.where(valid, (f - centre[:, None]) / width[:, None], 0.0)
    e1 = wt / np.sqrt(np.sum(wt * wt, 1, keepdims=True))
    e2 = wt * x - e1 * np.sum(e1 * wt * x, 1, keepdims=True)
    e2 = e2 / np.maximum(np.sqrt(np.sum(e2 * e2, 1, keepdims=True)), 1e-300)
    e1, e2 = e1.astype(y.dtype), e2.astype(y.dtype)
    b = _Batch(x, width[:, None] / f, centre[:, None], width[:, None], e1, e2, wt * y, wt, model)
    b = _Batch(b.x, b.x_f, b.f_c, b.w, e1, e2, b.proj(b.y), wt, model)
    # Again, on the data less the baseline fitted with the amplitude at this start.
    st = b.state(np.zeros(f.shape[0]), np.zeros(f.shape[0]))
    less = (st["a"][:, None] * st["wl"] + st["r"]) / np.where(valid, wt, 1.0)
    centre, width, _ = _half_height(f, np.abs(less) ** 2 if y.dtype.kind == "c" else less, valid)
    b = b.moved(centre[:, None], width[:, None])
    span = fmax - fmin
    steps = np.where(valid[:, 1:], np.diff(f, axis=1), np.inf).min(1)
    lo = np.stack([(fmin - centre - span / 2) / width, np.log(steps / 4 / width)], 1)
    hi = np.stack([(fmax - centre + span / 2) / width, np.log(5 * span / width)], 1)
    return b, lo, hi, fmin, fmax, scale


def _solve(b: _Batch, p0, q0, lo, hi):
    """least_squares over (p, q) of every spectrum of ``b`` at once, on compressed residuals.

    Spectrum k's residuals r_k (2m real numbers) and their Jacobian J_k (2m x 2, Kaufman's form
    −(I − P)∂curve, P the projector on the amplitude's column) are handed to scipy as the three
    numbers c_k = (Q_kᵀr_k, ``|(I − Q_kQ_kᵀ) r_k|``) with the Jacobian (R_k; 0), J_k = Q_k R_k (QR
    by Cholesky of the 2 x 2 J_kᵀJ_k). Then ``|c_k| = |r_k|``, R_kᵀc_k = J_kᵀr_k, R_kᵀR_k = J_kᵀJ_k:
    the cost, gradient and Gauss–Newton model, hence every step and stopping test of scipy's
    trust-region method, are those of the full problem, at 3 rows a spectrum instead of 2m.
    LSMR stops at 10 iterations: the near-singular blocks of lost spectra would take hundreds.
    """
    nb = b.x.shape[0]
    last: dict = {}  # the state at the last x (scipy asks for f and J at the same x)
    k = np.arange(nb)
    indices = np.stack([2 * k, 2 * k + 1, 2 * k + 1], 1).ravel()
    indptr = np.concatenate([[0], np.cumsum(np.tile([2, 1, 0], nb))])

    def evaluate(theta):
        if "x" not in last or not np.array_equal(last["x"], theta):
            st = b.state(theta[0::2], theta[1::2], derivatives=True)
            bs, n = st["basis"], st["norm"][:, None]
            jp, jq = (-(d - bs * (_dot(bs, d)[:, None] / n)) for d in (st["dp"], st["dq"]))
            r = st["r"]
            r11 = np.sqrt(np.maximum(_dot(jp, jp).real, 1e-300))
            r12 = _dot(jp, jq).real / r11
            r22 = np.sqrt(np.maximum(_dot(jq, jq).real - r12**2, 1e-300))
            c1 = _dot(jp, r).real / r11
            c2 = (_dot(jq, r).real - r12 * c1) / r22
            c3 = np.sqrt(np.maximum(_dot(r, r).real - c1**2 - c2**2, 0.0))
            last["x"], last["c"] = theta.copy(), np.stack([c1, c2, c3], 1).ravel()
            last["R"] = np.stack([r11, r12, r22], 1).ravel()
        return last

    def residuals(theta):
        return evaluate(theta)["c"]

    def jac(theta):
        return sparse.csr_matrix((evaluate(theta)["R"], indices, indptr), shape=(3 * nb, 2 * nb))

    x0 = np.clip(np.stack([p0, q0], 1), lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo)).ravel()
    sol = least_squares(
        residuals,
        x0,
        jac=jac,
        bounds=(lo.ravel(), hi.ravel()),
        method="trf",
        tr_solver="lsmr",
        x_scale="jac",
        ftol=FTOL,
        xtol=1e-10,
        gtol=1e-12,
        max_nfev=MAX_NFEV,
        tr_options={"maxiter": 10},
    )
    return sol.x[0::2], sol.x[1::2]


def _fit_group(f, y, wt, model: str, sigma_given: bool) -> dict:
    """Fit one padded batch (spectra as rows): values, errors and what the flags need."""
    b, lo, hi, fmin, fmax, scale = _batch(f, y, wt, model)
    nb = f.shape[0]
    p, q, groups, lost = np.zeros(nb), np.zeros(nb), [np.arange(nb)], np.zeros(nb)
    st: dict[str, np.ndarray] = {}
    for _ in range(PASSES):
        for k in groups:
            sub = b.take(k)
            p[k], q[k] = _solve(sub, p[k], q[k], lo[k], hi[k])
            for key, v in _stats(sub, p[k], q[k]).items():
                st.setdefault(key, np.full((nb, *v.shape[1:]), np.nan, dtype=v.dtype))[k] = v
        sd = np.sqrt(np.einsum("nii->ni", st["cov"]))
        converged = np.all(np.abs(st["step"][:, :2]) <= np.maximum(STEP_TOL * sd[:, :2], 1e-9), 1)
        f_r, gamma = b.f_c[:, 0] + b.w[:, 0] * p, b.w[:, 0] * np.exp(q)
        covered = (f_r - gamma >= fmin) & (f_r + gamma <= fmax)
        pq = np.stack([p, q], 1)
        todo = ~converged & ~np.any((pq - lo < 1e-6) | (hi - pq < 1e-6), 1)  # not at a bound
        # Lost spectra (no peak, not covered) go apart (they would hold back the others in a
        # shared trust region) and get one more run only.
        plausible = covered & (st["significance"] >= MIN_SIGNIFICANCE)
        lost += todo & ~plausible
        groups = [np.flatnonzero(todo & plausible), np.flatnonzero(todo & ~plausible & (lost < 2))]
        groups = [k for k in groups if k.size]
        if not groups:
            break
    phase = np.angle(st["a"]) if y.dtype.kind == "c" else np.full(nb, np.nan)
    values = (f_r, b.w[:, 0] * sd[:, 0], gamma, gamma * sd[:, 1], np.abs(st["a"]), phase)
    out = dict(zip(COLUMNS[1:7], values, strict=True))
    # s² over σ²: σ given (s² in units of the weights 1/σ), or the point-to-point noise
    out["reduced_chi2"] = st["s2"] * scale**2 if sigma_given else st["s2"] / st["noise2"]
    out["converged"] = converged & np.all(np.isfinite(sd[:, :2]), 1)
    out["within"] = np.sum((wt > 0) & (np.abs(f - f_r[:, None]) <= gamma[:, None]), 1)
    out["too-few-points"] = covered & (out["within"] < MIN_WITHIN)
    out["no-peak"] = ~(st["significance"] >= MIN_SIGNIFICANCE)
    out["peak-not-covered"] = ~covered
    out["not-converged"] = ~out["converged"]
    return out


def _numeric(name: str, value, n: int) -> np.ndarray:
    """``value`` as a 1-D float array of length n (NaN for missing), else a one-line ValueError."""
    if np.ndim(value) != 1:
        raise ContactresInputError(f"{name} must be a 1-D array, got {np.ndim(value)} dimensions")
    kind = pd.api.types.infer_dtype(value, skipna=True)
    if kind not in _NUMERIC:
        raise ContactresInputError(f"{name} must be real numbers, got {kind} values")
    arr = pd.Series(value).to_numpy(dtype=float, na_value=np.nan)
    if arr.size != n:
        raise ContactresInputError(
            f"{name} has {arr.size} values, spectrum has {n}: the lengths must agree"
        )
    return arr


@one_blas_thread()
def fit_resonances(
    spectrum,
    frequency_Hz,
    G_S,
    B_S=None,
    *,
    model: str = "bvd",
    noise_S=None,
    batch_size: int = 500,
) -> pd.DataFrame:
    """Fit f_r and Γ (and G_max, φ) of every spectrum of a tidy spectra table.

    Parameters
    ----------
    spectrum : the spectrum id of every point (the tidy table's ``spectrum`` column); the points
        of a spectrum need not be contiguous, their order within it is kept
    frequency_Hz : the frequency of every point, Hz, strictly increasing within a spectrum
    G_S : conductance G of every point, S
    B_S : susceptance B, S, or None (G alone for every spectrum); a spectrum whose B is all NaN
        is fitted on G alone
    model : "bvd" (default, the BVD circuit exactly) or "lorentzian" (module docstring)
    noise_S : standard deviation σ of the noise on G and on B, S, scalar or per point
        (optional): weights 1/σ, and ``reduced_chi2`` against σ. Without it the points weigh
        alike and ``reduced_chi2`` is against the point-to-point noise of the residuals. The
        standard errors are scaled by each spectrum's residual variance either way
    batch_size : spectra fitted together in one least-squares problem

    Returns
    -------
    pandas.DataFrame
        One row per spectrum in order of first appearance, columns :data:`COLUMNS`: f_r and Γ
        (the half width at half height of G), Hz, with standard errors; G_max, S; φ, rad (NaN
        for G alone); ``converged``: a fit ran and its remaining step is negligible; ``flags``:
        ';'-separated names of :data:`FLAGS` ("" if none), with NaN values where they say so.

    Raises
    ------
    ValueError
        Arguments of different lengths, not 1-D or not numeric, a missing spectrum id, a bad
        ``model``, ``noise_S`` or ``batch_size``. Bad *spectra* are flagged, never raised.
    """
    if model not in MODELS:
        raise ContactresInputError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    if int(batch_size) < 1:
        raise ContactresInputError(f"batch_size must be >= 1, got {batch_size}")
    if np.ndim(spectrum) != 1:
        raise ContactresInputError(
            f"spectrum must be a 1-D array of ids, got {np.ndim(spectrum)} dimensions"
        )
    codes, uniques = pd.factorize(np.asarray(spectrum, dtype=object), sort=False)
    if np.any(codes < 0):
        raise ContactresInputError("spectrum must not contain missing ids (NaN or None)")
    n = codes.size
    f, g = _numeric("frequency_Hz", frequency_Hz, n), _numeric("G_S", G_S, n)
    b = np.full(n, np.nan) if B_S is None else _numeric("B_S", B_S, n)
    sigma = 1.0 if noise_S is None else noise_S
    sigma = _numeric("noise_S", np.full(n, sigma) if np.ndim(sigma) == 0 else sigma, n)
    if not np.all(np.isfinite(sigma) & (sigma > 0)):
        raise ContactresInputError("noise_S must be finite and > 0 (S)")
    ids, n_spec = np.asarray(uniques, dtype=object), uniques.size
    order = np.argsort(codes, kind="stable")
    codes, f, g, b, sigma = codes[order], f[order], g[order], b[order], sigma[order]
    counts = np.bincount(codes, minlength=n_spec)
    starts = np.cumsum(counts) - counts
    n_b_nan = np.bincount(codes[np.isnan(b)], minlength=n_spec)
    down = np.zeros(n, dtype=bool)  # a point not above the one before, same spectrum
    with np.errstate(invalid="ignore"):
        down[1:] = (codes[1:] == codes[:-1]) & ~(np.diff(f) > 0)

    def any_of(points: np.ndarray) -> np.ndarray:
        return np.bincount(codes[points], minlength=n_spec) > 0

    flag = {name: np.zeros(n_spec, dtype=bool) for name in FLAGS}
    # An admittance above MAX_ADMITTANCE_S is no measurement (and its squares overflow in the
    # fit, which stopped the run with scipy's "residuals are not finite").
    with np.errstate(invalid="ignore"):
        huge = (np.abs(g) > MAX_ADMITTANCE_S) | (np.abs(b) > MAX_ADMITTANCE_S)
    bad = any_of(~np.isfinite(f) | ~(f > 0) | ~np.isfinite(g) | np.isinf(b) | huge)
    flag["bad-values"] = bad | ((n_b_nan > 0) & (n_b_nan < counts))
    flag["frequencies-not-increasing"] = any_of(down) & ~flag["bad-values"]
    fit = ~flag["bad-values"] & ~flag["frequencies-not-increasing"]
    flag["too-few-points"] = fit & (counts < MIN_POINTS)
    fit &= counts >= MIN_POINTS

    out = {c: np.full(n_spec, np.nan) for c in COLUMNS[1:8]}
    keep = np.zeros(n_spec, dtype=bool)
    converged = np.zeros(n_spec, dtype=bool)
    for cplx in (True, False):
        chosen = np.flatnonzero(fit & ((n_b_nan == 0) == cplx))
        chosen = chosen[np.argsort(counts[chosen], kind="stable")]  # similar lengths together
        for first in range(0, chosen.size, int(batch_size)):
            ks = chosen[first : first + int(batch_size)]
            j = np.arange(counts[ks].max())[None, :]
            at = starts[ks][:, None] + np.minimum(j, counts[ks][:, None] - 1)
            y = g[at] + 1j * b[at] if cplx else g[at]
            valid = j < counts[ks][:, None]
            # A flat or pure-noise spectrum may divide by zero inside the fit; such spectra are
            # flagged from the results, so numpy's warnings are not raised here.
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                res = _fit_group(f[at], y, valid / sigma[at], model, noise_S is not None)
            for c in (*COLUMNS[1:8], *list(FLAGS)[2:]):
                (out[c] if c in out else flag[c])[ks] = res[c]
            converged[ks] = res["converged"]
            keep[ks] = res["within"] >= MIN_WITHIN_VALUE
    for name in FLAGS:
        if name != "too-few-points":
            keep &= ~flag[name]
    for c in COLUMNS[1:7]:
        out[c][~keep] = np.nan
    names = np.array(list(FLAGS), dtype=object)
    text = [";".join(names[row]) for row in np.stack([flag[name] for name in FLAGS], 1)]
    frame = pd.DataFrame({"spectrum": ids, **out})
    frame["n_points"], frame["converged"], frame["flags"] = counts, converged, text
    return frame[list(COLUMNS)]
