"""Dynamic contact stiffness of a rigid sphere on an anisotropic half-space (paper 1, Eqs. 5-29).

A sphere pressed statically onto the half-space (anisotropic Hertz, contact radius a) gets a small
oscillating force on top. For small amplitudes the oscillating pressure over the fixed contact has
the flat-punch shape δf ∝ 1/√(1 − r̄²) (Eqs. 5-9), and its normal displacement (Eqs. 21-22) is

    u_z(r̄, φ) = (2a δa/(π C44 R I₁)) N(r̄, φ),
    N(r̄, φ) = ∫₀^{2π} dθ ∫₀^∞ ds g(s/(k_s a), θ) (sin s / s) cos(s r̄ cos(θ − φ)),

g(κ, θ) the dimensionless dynamic kernel of :mod:`contactres.halfspace` and k_s = ω√(ρ/C44). The
displacement is not uniform, so a displacement condition fixes which N the sphere feels:

    R0 (Sung)      N(0)                     R1   N(1, φ = 0) (edge, along x = [100])
    SA (Barkan)    [N(0) + N(1, 0)]/2       WA (Bycroft)  ∫₀¹ N(r̄, 0) r̄/√(1 − r̄²) dr̄ (Eq. 27)
    TP (Tian)      two-parameter pressure α√(1 − r̄²) + β/√(1 − r̄²) with u(0) = u(1, 0)
    WA2D           the WA average over the whole contact (all φ; an extension)

and K_da = 4π² a C44/N_model (Eq. 28); DCSF = K_da/K_sa = N_st/N_model (Eq. 29), N_st the static
N of the undamped constants, so DCSF -> 1 + iQ⁻¹ as k a -> 0.

The wave number of the paper's figures is the longitudinal one, k_l a = ω a √(ρ/C33) (C33 of the
surface frame; C11 for a cubic (001) face): ``wavenumber="longitudinal"`` (default) or
``"shear"`` (k_s a). Damping: constants C (1 + i Q⁻¹) with Q⁻¹ = ``loss``. The default is the
lossless solid, ``loss=0`` (the limit Q⁻¹ -> 0⁺, exact, by a contour above the real axis): Im DCSF
is then the radiation damping alone. The paper's figures use Q⁻¹ = 0.02, which swamps it at
small k a (Si(001), 1 MHz: Im K 28 000 times the lossless one for R = 10 nm, F = 10 nN; 2.3 times
for R = 1 mm, F = 1 N): pass it only to reproduce them, or for a solid that has that loss.

Which model? ``model="exact"`` (the rigid flat punch: uniform displacement under the sphere,
Galerkin, :mod:`contactres.dynamic._exact`) is what the approximations aim at and costs about as
much as one of them: use it. Against it (``contactres figures paper1``, paper1_model_ranking.csv;
ν = 0.25, A = 0.25 ... 4, k_l a <= 1) the paper's approximations rank TP (0.2-5 %), WA ≈ WA2D
(2-40 %), SA, R1, R0 (10-100 %); up to k_l a = 2 only TP stays within 10 % for A >= 1. The
paper recommends WA because R0, SA and TP turn negative at high k a; the wiggles of WA (the
maxima of Fig. 4) are not in the exact curve. See :mod:`contactres.dynamic._quadrature` for the
numerics and their accuracy.

Two traps of the approximations (measured, lossless and Q⁻¹ = 0.02 alike): R0 has negative
damping, Im DCSF < 0, at high k a (k_l a >= 1.91 on Cu(001), >= 1.56 at A = 0.5, ν = 0.25; not
for A >= 1 up to k_l a = 2), which no passive contact has. And R1, SA, WA and TP depend on the
in-plane axis (the x axis of the surface frame, along which they take the edge point or the line
average): turning it by 0-45° on Cu(001) changes WA by up to 1.2 % for k_l a <= 1 and 19 % at
k_l a = 2 (R1 2.7 %/21 %, SA 0.9 %/32 %, TP 0.6 %/7 %); R0, WA2D and exact do not depend on it.

Near incompressibility (contrast above :data:`~contactres.dynamic.MAX_STIFFNESS_CONTRAST`,
isotropic ν > 0.4999) the kernels lose the stated accuracy to round-off: ValueError then.

Curves of many k a values (more than :data:`INTERPOLATE_ABOVE` distinct ones) are interpolated
by default between 33-257 direct values at Chebyshev points (1/DCSF, which is smooth), with the
interpolation error measured and kept below rtol/10 (:mod:`contactres.dynamic._interpolation`;
``interpolate=False`` evaluates every value).

Most of the cost of a curve is the material's kernel table: :func:`prepare` builds it once, and
every function here takes it as ``prepared=`` (same material, loss and rtol) to evaluate many
curves without rebuilding it; otherwise each call prepares its own (nothing is cached).
"""

from __future__ import annotations

import math

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..halfspace import shear_reference
from ..materials import Material, require_material
from ..validation import nonnegative
from ._exact import exact_n, galerkin_plan, galerkin_size, model_size, pressure_basis
from ._farfield import far_basis, far_grid
from ._fartail import far_tail, head_grid
from ._interpolation import MAX_INTERVALS as LARGEST
from ._interpolation import chebyshev_values
from ._models import ALL_MODELS, MODELS, WAVENUMBERS
from ._quadrature import far_operator, far_operator_and_moments, functionals, point_values
from ._table import KernelTable, prepare

__all__ = [
    "ALL_MODELS",
    "CHUNK",
    "INTERPOLATE_ABOVE",
    "MODELS",
    "WAVENUMBERS",
    "check_model",
    "contact_displacement",
    "contact_pressure",
    "evaluate_models",
    "model_n",
    "normalised_wavenumber",
    "shear_ka",
    "shear_wavenumber_ratio",
    "table_for",
    "wave_modulus",
]

# Largest k_s a × (largest slowness) accepted: the contour's weights grow like e^{0.3 x this}.
_KA_MAX = 60.0
# k a values evaluated together: ~0.6 MB of far-field basis each, ~40 MB at 64, for any call size.
CHUNK = 64
#: Above this many distinct k a values a call interpolates (``interpolate=None``): the direct
#: cost is ~0.7 ms per value, a Chebyshev curve 33-129 direct values whatever the call's size.
INTERPOLATE_ABOVE = 128


def shear_wavenumber_ratio(m: Material) -> float:
    """k_s/k_l = √(C33/C44) of the surface frame (Re parts): k_s a = k_l a × this ratio."""
    return math.sqrt(float(np.real(m.C[2, 2])) / shear_reference(m))


def check_model(model: str) -> str:
    """``model`` spelt as in :data:`ALL_MODELS` (case-insensitive), or a ContactresInputError."""
    key = str(model).upper()
    key = "exact" if key == "EXACT" else key
    if key not in ALL_MODELS:
        raise ContactresInputError(
            f"model must be one of {', '.join(MODELS)}, exact; got {model!r}"
        )
    return key


def wave_modulus(m: Material, wavenumber: str = "shear") -> float:
    """The stiffness C of the wave number k = ω√(ρ/C) in the convention ``wavenumber``, Pa.

    ``"shear"``: Re C44 of the surface frame (:func:`contactres.halfspace.shear_reference`,
    k_s, paper 1, Eq. 21); ``"longitudinal"``: Re C33 of the surface frame (k_l, the wave number
    of the paper's figures). The undamped constants: a loss does not change the wave number.
    """
    if wavenumber == "shear":
        return shear_reference(m)
    if wavenumber == "longitudinal":
        return float(np.real(np.asarray(m.C)[2, 2]))
    raise ContactresInputError(
        f"wavenumber must be one of {', '.join(WAVENUMBERS)}, got {wavenumber!r}"
    )


def normalised_wavenumber(frequency, contact_radius, density, modulus):
    """The normalised wave number k a = ω a √(ρ/C) of a contact (paper 1, Eq. 21), dimensionless.

    The one place where the library turns a frequency and a contact radius into the k a of the
    DCSF: :func:`dynamic_contact_stiffness`, the tangential stiffness, the polycrystal maps and
    the command line all call it.

    Parameters
    ----------
    frequency : float or array
        Oscillation frequency f, Hz (ω = 2πf).
    contact_radius : float or array
        Contact radius a, m.
    density : float
        Mass density ρ, kg/m^3.
    modulus : float or array
        The stiffness C of the wave, Pa: Re C44 for k_s a, Re C33 for k_l a
        (:func:`wave_modulus`); an array gives one value per point (a map's faces).

    Returns
    -------
    ndarray
        k a, the arguments broadcast.

    Examples
    --------
    A wave speed √(C/ρ) of 1000 m/s, f = 1 MHz, a = 1 mm: k a = 2π f a/v = 2π.

    >>> round(float(normalised_wavenumber(1e6, 1e-3, 1000.0, 1e9)), 12)
    6.28318530718
    """
    # One order of the products for every caller, so a k a is the same number wherever made:
    # the wave number k = 2πf√(ρ/C) first, then times a (the order of the dynamic normal and
    # tangential stiffness before this function existed: their results, and the radiation loss
    # refitted from them, stay the same to the bit).
    k = 2 * np.pi * np.asarray(frequency) * np.sqrt(density / np.asarray(modulus))
    return k * np.asarray(contact_radius)


def shear_ka(m: Material, ka, wavenumber: str) -> np.ndarray:
    """k_s a from ``ka`` given in the convention ``wavenumber`` ("shear" or "longitudinal")."""
    require_material(m, lossless=True)
    ka = np.asarray(nonnegative("ka (normalised wave number k a)", ka))
    if wavenumber == "longitudinal":
        return ka * shear_wavenumber_ratio(m)
    if wavenumber == "shear":
        return ka
    raise ContactresInputError(
        f"wavenumber must be one of {', '.join(WAVENUMBERS)}, got {wavenumber!r}"
    )


def table_for(m: Material, ksa: np.ndarray, loss: float, rtol: float, prepared):
    """The kernel table of ``m`` (``prepared``, checked to be made for ``m``, ``loss`` and
    ``rtol``, or a new one), after checking that k_s a stays where its contour is accurate."""
    if prepared is None:
        table = prepare(m, loss, rtol)
    elif isinstance(prepared, KernelTable):
        table = prepared.check_for(m, loss, rtol)
    else:
        raise ContactresInputError(
            f"prepared must be a kernel table from contactres.dynamic.prepare, "
            f"got {type(prepared).__name__}"
        )
    if ksa.size and float(np.max(ksa)) * table.t1 > _KA_MAX:
        raise ContactresInputError(
            f"ka too large: k_s a = {float(np.max(ksa)):.4g} (k_s a x slowness {table.t1:.3g} "
            f"must stay below {_KA_MAX:g}; the paper's range is k_l a <= 2)"
        )
    return table


def _contact_points(rbar, phi, edge: bool):
    """r̄ in [0, 1] (``edge``) or [0, 1) and finite φ, as float arrays."""
    r = np.asarray(rbar, dtype=float)
    below_top = r <= 1 if edge else r < 1
    if not np.all(np.isfinite(r) & (r >= 0) & below_top):
        where = "[0, 1]" if edge else "[0, 1) (the edge is singular)"
        raise ContactresInputError(f"rbar (r/a) must lie in {where}, got {rbar!r}")
    p = np.asarray(phi, dtype=float)
    if not np.all(np.isfinite(p)):
        raise ContactresInputError(f"phi must be finite (rad), got {phi!r}")
    return r, p


def model_n(f: dict, model: str) -> np.ndarray:
    """N_model of a displacement condition, from the six functionals of N (paper 1, Eqs. 24-28).

    R0: N(0) (Eq. 24); R1: N(1, 0) (Eq. 25); SA: their mean (Eq. 26); WA: the weighted average
    along φ = 0 (Eq. 27); WA2D: the weighted average over the whole contact; TP: the pressure
    α√(1 − r̄²) + β/√(1 − r̄²) of Tian et al. (2004; paper 1, Fig. 3) with u(0) = u(1, 0), i.e.
    α/β = −(N_F(0) − N_F(1, 0))/(N_H(0) − N_H(1, 0)) and N_TP = (α N_H(0) + β N_F(0))/(α/3 + β).
    K_da = 4π² a C44/N_model (Eq. 28).

    R0 gives negative damping (Im DCSF < 0) at high k a (k_l a >= 1.91 on Cu(001), >= 1.56 at
    A = 0.5). R1, SA, WA and TP use the direction φ = 0, so they depend on the in-plane x axis of
    the surface frame: on Cu(001), turning it by up to 45° changes WA by 1.2 % (k_l a <= 1) and
    19 % (k_l a = 2), R1 by 21 %, SA by 32 %, TP by 7 % at k_l a = 2. R0 and WA2D do not.

    Parameters
    ----------
    f : dict
        The functionals of :func:`contactres.dynamic._quadrature.functionals` (complex arrays).
    model : str
        One of :data:`MODELS`.

    Returns
    -------
    ndarray
        Complex N_model, shaped like the functionals.
    """
    if model == "R0":
        return f["F0"]
    if model == "R1":
        return f["F1"]
    if model == "SA":
        return 0.5 * (f["F0"] + f["F1"])
    if model == "WA":
        return f["FW"]
    if model == "WA2D":
        return f["F2D"]
    # TP: δp = α√(1 − ρ²) + β/√(1 − ρ²) with u(0) = u(1, 0); force ∝ α/3 + β (β = 1 here).
    alpha = -(f["F0"] - f["F1"]) / (f["H0"] - f["H1"])
    return (alpha * f["H0"] + f["F0"]) / (alpha / 3 + 1)


def _direct(table, flat, names, rtol, chunk, span=None, refine=0) -> dict[str, np.ndarray]:
    """N of every model (the denominator of its DCSF, smooth in k a where the DCSF of SA or R1
    can pass through a pole) at the k_s a values ``flat`` (1-D), point by point in chunks.

    ``span`` = (smallest positive, largest) k_s a that sizes the discretisation (default: those
    of ``flat``); calls with one span discretise alike, so their values fit one smooth curve.
    ``refine``: the refinement level of the Galerkin basis (:func:`model_size`).
    """
    approx = [n for n in names if n != "exact"]
    n_out = {name: np.empty(flat.shape, dtype=complex) for name in names}
    pos = flat[flat > 0]
    if span is not None:
        pos = np.append(pos, span)
    # Shared by every chunk, built once per call (far-field grid and weights from the smallest k a,
    # Galerkin bookkeeping and near θ grid from the largest): chunking does not change a result.
    smax = float(np.max(pos, initial=0.0))
    grid = far_grid(table, float(np.min(pos))) if pos.size else None
    size = model_size(smax, rtol, refine=refine)
    # Beyond 2 T₁ × the largest k a the far basis is summed by moments (._fartail): the chunks
    # build it on the head of the grid alone.
    tail = far_tail(table, grid, smax) if grid is not None else None
    far_op = far_moments = None
    if approx and grid is not None:
        if tail is None:
            far_op = far_operator(table, grid)
        else:
            far_op, far_moments = far_operator_and_moments(table, grid, tail)
    plan = None
    if "exact" in names:
        plan = galerkin_plan(table, size, grid.s if grid else None, tail=tail)
    for lo in range(0, flat.size, chunk):
        part = flat[lo : lo + chunk]
        p = part[part > 0]
        far = far_basis(table, p, head_grid(grid, tail)) if p.size and grid else None
        if approx:
            f = functionals(
                table, part, far=far, smax=smax, far_op=far_op, tail=tail, far_moments=far_moments
            )
            for name in approx:
                n_out[name][lo : lo + chunk] = model_n(f, name)
        if plan is not None:
            n_out["exact"][lo : lo + chunk] = exact_n(table, part, size, far=far, plan=plan)
        del far  # the largest array of a chunk (~0.6 MB per k a value)
    return n_out


@one_blas_thread()  # as dcsf_models (free inside its context)
def evaluate_models(
    table: KernelTable,
    ksa: np.ndarray,
    names: list[str],
    rtol: float,
    *,
    chunk: int = CHUNK,
    interpolate: bool | None = None,
    refine: int = 0,
) -> dict[str, np.ndarray]:
    """The DCSF of the checked model names ``names`` at the k_s a values ``ksa`` on ``table``
    (the work of :func:`dcsf_models` after its checks): ``{model: complex array like ksa}``.

    ``refine`` = L > 0 enlarges the Galerkin basis of the exact model (:func:`model_size`);
    with a kernel table whose resolution is doubled L times it is the refined evaluation of the
    run-time convergence check (:mod:`contactres.dynamic._convergence`).
    """
    flat = ksa.ravel()
    uniq, inverse = np.unique(flat, return_inverse=True)
    if interpolate is None:
        interpolate = uniq.size > INTERPOLATE_ABOVE
    if interpolate and uniq.size > 2 and uniq[-1] > 0:
        # N is interpolated, not the DCSF (N_st/N of SA, R1 has poles), to a tenth of rtol; one
        # discretisation for every node set (sized by the finest grid's smallest node).
        low = uniq[0] if uniq[0] > 0 else uniq[-1] * (1 - math.cos(math.pi / LARGEST))
        span = (low / 2, uniq[-1])

        def direct(x):
            return _direct(table, x, names, rtol, chunk, span, refine)

        found = chebyshev_values(direct, uniq, rtol / 10, largest=LARGEST)
        out = (
            found[0]
            if found is not None
            else _direct(table, uniq, names, rtol, chunk, refine=refine)
        )
    else:
        out = _direct(table, uniq, names, rtol, chunk, refine=refine)
    return {k: (table.n_static / v)[inverse].reshape(ksa.shape) for k, v in out.items()}


@one_blas_thread()  # as dcsf_models
def contact_displacement(
    m: Material,
    ka,
    rbar,
    phi=0.0,
    shape: str = "flat",
    loss: float = 0.0,
    wavenumber: str = "longitudinal",
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
):
    """The displacement function N(r̄, φ; k a) under the oscillating pressure (paper 1, Eq. 22).

    u_z = (2a δa/(π C44 R I₁)) N. Statically N is uniform over the contact (N_st); dynamically it
    is not (paper 1, Fig. 2: ``|N(r̄)|``/``|N(0)|``).

    Parameters
    ----------
    m, loss, wavenumber, rtol, prepared
        As in :func:`dcsf`.
    ka : float or array
        Normalised wave number(s).
    rbar : float or array
        r/a, in [0, 1] (inside the contact).
    phi : float or array
        Polar angle from the surface-frame x axis, rad. ``ka``, ``rbar`` and ``phi`` broadcast.
    shape : str
        "flat": the flat-punch pressure 1/√(1 − r̄²) (the paper's δf); "hertz": √(1 − r̄²)
        (the second pressure of the TP model).

    Returns
    -------
    complex ndarray (broadcast shape), dimensionless.
    """
    if shape not in ("flat", "hertz"):
        raise ContactresInputError(f"shape must be 'flat' or 'hertz', got {shape!r}")
    ksa = shear_ka(m, ka, wavenumber)
    r, p = _contact_points(rbar, phi, edge=True)
    ksa, r, p = np.broadcast_arrays(ksa, r, p)
    table = table_for(m, ksa, loss, rtol, prepared)
    out = np.empty(ksa.shape, dtype=complex)
    flat_k, flat_r, flat_p = ksa.ravel(), r.ravel(), p.ravel()
    res = out.reshape(-1)
    for k in np.unique(flat_k):
        sel = flat_k == k
        res[sel] = point_values(table, float(k), flat_r[sel], flat_p[sel], shape)
    return out


@one_blas_thread()  # as dcsf_models
def contact_pressure(
    m: Material,
    ka,
    rbar,
    phi=0.0,
    loss: float = 0.0,
    wavenumber: str = "longitudinal",
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
):
    """Oscillating pressure of the exact solution (rigid flat punch), over its mean δP/(π a²).

    The converged Galerkin pressure of model "exact" (:mod:`contactres.dynamic._exact`). Static
    limit: the flat-punch shape 1/(2√(1 − r̄²)). Complex (phase relative to the displacement).

    Parameters
    ----------
    m, loss, wavenumber, rtol, prepared
        As in :func:`dcsf`.
    ka : float
        Normalised wave number (one value).
    rbar, phi : float or array
        Points r/a in [0, 1) and polar angle (rad, from the surface x axis); they broadcast.
    """
    ksa = shear_ka(m, ka, wavenumber)
    if ksa.ndim != 0:
        raise ContactresInputError("contact_pressure takes one ka at a time")
    r, p = np.broadcast_arrays(*_contact_points(rbar, phi, edge=False))
    table = table_for(m, ksa, loss, rtol, prepared)
    size = galerkin_size(float(ksa), rtol, pressure=True)
    _, c, basis = exact_n(table, np.atleast_1d(ksa), size, return_coeffs=True)
    c = c[0]
    out = np.zeros(r.shape, dtype=complex)
    for coef, (n, k) in zip(c, basis, strict=True):
        out += coef * pressure_basis(n, k, r) * np.exp(1j * n * p)
    return out / (2 * c[0])
