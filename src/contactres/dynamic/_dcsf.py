"""The public DCSF: :func:`dcsf`, :func:`dcsf_models` and :func:`dynamic_contact_stiffness`.

The physics and the numerics are those of :mod:`contactres.dynamic._normal_stiffness` (paper 1,
Eqs. 5-29: the displacement models, the exact rigid punch, the kernel table). These functions
add the promise of accuracy: inside the range where the resolutions were measured to meet
``rtol`` (:func:`~contactres.dynamic._convergence.in_validated_range`) they are that module's
evaluation, unchanged but near a pole of a model's DCSF (``|DCSF|`` >
:data:`~contactres.dynamic._convergence.POLE_DCSF`); there and outside the range each value is
checked at run time against a refined
evaluation and refined where it misses rtol (:mod:`contactres.dynamic._convergence`), and a
value that still misses it comes with an :class:`~contactres.errors.AccuracyWarning` (issue 27).
A value with negative damping (Im DCSF < 0 beyond rtol: no passive contact has it; R0, SA, WA and
TP reach it at high k a) comes with a :class:`~contactres.errors.ContactresWarning` per model,
naming the k a (issue 27, point 7: flagged at run time, not only in the docstrings).
"""

from __future__ import annotations

import warnings

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError, ContactresWarning
from ..halfspace import shear_reference
from ..materials import Material, require_material
from ..validation import nonnegative
from ._convergence import (
    POLE_DCSF,
    CheckedDCSF,
    checked_values,
    in_validated_range,
    warn_unconverged,
)
from ._models import ALL_MODELS
from ._normal_stiffness import (
    CHUNK,
    check_model,
    evaluate_models,
    normalised_wavenumber,
    shear_ka,
    table_for,
)
from ._table import KernelTable

__all__ = ["dcsf", "dcsf_models", "dynamic_contact_stiffness"]


# One BLAS thread around all the work, table included (contactres._threads): one BLAS thread
# is no slower and much cheaper. Measured on 2 cores, 41 points of a new material, all seven
# models: 81 ms of CPU with OpenBLAS's default two threads, 38 ms with one
# (OPENBLAS_NUM_THREADS=1), no gain in wall time from the second thread (issue 31). Threads
# sharing a prepared table get the bits of a serial run (tests/dynamic/test_prepared.py).
@one_blas_thread()
def dcsf_models(
    m: Material,
    ka,
    models=ALL_MODELS,
    loss: float = 0.0,
    wavenumber: str = "longitudinal",
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
    *,
    chunk: int = CHUNK,
    interpolate: bool | None = None,
    warn_negative: bool = True,
) -> dict[str, np.ndarray]:
    """DCSF = K_da/K_sa of several displacement models at once (they share all the work).

    Parameters and returns as :func:`dcsf`, with ``models`` a sequence of model names; returns
    ``{model: complex array shaped like ka}``. ``chunk`` and ``interpolate`` (keyword only) as
    in :func:`dcsf`; so is the check of the accuracy outside the validated range (an
    :class:`~contactres.errors.AccuracyWarning` where rtol is missed) and the
    :class:`~contactres.errors.ContactresWarning` where a model has negative damping
    (``warn_negative``, keyword only: False for a caller that shows it on purpose, as paper 1's
    figures do).
    """
    names = [check_model(x) for x in ([models] if isinstance(models, str) else models)]
    if not (isinstance(chunk, int | np.integer) and chunk >= 1):
        raise ContactresInputError(f"chunk must be a positive integer, got {chunk!r}")
    if interpolate not in (None, True, False):
        raise ContactresInputError(f"interpolate must be None, True or False, got {interpolate!r}")
    ksa = shear_ka(m, ka, wavenumber)
    table = table_for(m, ksa, loss, rtol, prepared)
    # Inside the validated range the resolution meets rtol (measured: _convergence's
    # VALIDATED_* constants) but near a pole of a model's DCSF, which is checked as below;
    # outside it nothing promises that, so each value is checked against a refined one
    # (issue 27).
    if in_validated_range(m, ksa):
        values = evaluate_models(table, ksa, names, rtol, chunk=chunk, interpolate=interpolate)
        poles = _check_near_poles(m, table, ksa, values, loss, rtol, chunk, interpolate)
        if poles is not None:
            out, near = poles
            where = np.broadcast_to(ka, ksa.shape)[near]
            warn_unconverged(m, out, where, wavenumber, f"|DCSF| > {POLE_DCSF:g}: near a pole")
    else:
        out = checked_values(m, table, ksa, names, loss, rtol, chunk=chunk, interpolate=interpolate)
        warn_unconverged(m, out, np.broadcast_to(ka, ksa.shape), wavenumber)
        values = {k: np.asarray(v) for k, v in out.values.items()}
    if warn_negative:
        _warn_negative_damping(values, np.broadcast_to(ka, ksa.shape), wavenumber, rtol)
    return values


def _check_near_poles(
    m: Material,
    table: KernelTable,
    ksa: np.ndarray,
    values: dict,
    loss: float,
    rtol: float,
    chunk: int,
    interpolate: bool | None,
) -> tuple[CheckedDCSF, np.ndarray] | None:
    """Replace in ``values`` (the level-0 DCSF of each model at the k_s a values ``ksa``) those
    beyond :data:`~contactres.dynamic._convergence.POLE_DCSF` in modulus by their checked
    values (:func:`checked_values`); return the check and the mask of its k a (None: no value
    there).

    Near a pole (N -> 0: SA, R1) the relative error of the DCSF is that of N, the absolute error
    of N over ``|N|``: it grows like ``|DCSF|`` and no resolution meets rtol at every k a."""
    big = {k: np.abs(v) > POLE_DCSF for k, v in values.items()}
    near = np.logical_or.reduce(list(big.values()))
    if not np.any(near):
        return None
    names = [k for k, b in big.items() if np.any(b)]
    out = checked_values(
        m, table, ksa[near], names, loss, rtol, chunk=chunk, interpolate=interpolate
    )
    for k in names:
        values[k] = np.array(values[k])
        values[k][near] = out.values[k]
    return out, near


def _warn_negative_damping(values: dict, ka: np.ndarray, wavenumber: str, rtol: float) -> None:
    """A :class:`~contactres.errors.ContactresWarning` per model whose DCSF ``values`` (at the
    k a values ``ka``) have negative damping, Im DCSF < 0 beyond the accuracy rtol: no passive
    contact has it. The approximate displacement conditions reach it at high k a (R0 near
    k_l a = 1.6-2, SA and WA beyond; paper 1, Figs. 3-5); the exact punch does not."""
    label = "k_l a" if wavenumber == "longitudinal" else "k_s a"
    for name, v in values.items():
        v = np.asarray(v)
        negative = v.imag < -max(rtol, 1e-12) * np.abs(v)
        if not np.any(negative):
            continue
        where = np.broadcast_to(ka, v.shape)[negative]
        lo, hi = float(np.min(where)), float(np.max(where))
        span = f"{lo:.4g}" if lo == hi else f"{lo:.4g}-{hi:.4g}"
        warnings.warn(
            f"DCSF ({name} model) has negative damping, Im DCSF < 0, at {label} = {span} "
            f"({int(np.count_nonzero(negative))} value(s)): no passive contact has it, the "
            "displacement condition fails there; use the exact model",
            ContactresWarning,
            stacklevel=4,
        )


def dcsf(
    m: Material,
    ka,
    model: str = "exact",
    loss: float = 0.0,
    wavenumber: str = "longitudinal",
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
    *,
    chunk: int = CHUNK,
    interpolate: bool | None = None,
):
    """Dynamic-contact-stiffness factor DCSF = K_da/K_sa (paper 1, Eq. 29), complex.

    Parameters
    ----------
    m : Material
        Undamped elastic constants in the surface frame (z = inward normal; for a crystal face
        use ``Material.crystal("Cu").rotated((0, 0, 1))``). Density is not needed. A layered
        or viscoelastic solid has no DCSF of k a alone (the film thickness and the frequency
        dependence of the moduli set their own scales): :func:`contactres.dynamic.layered_dcsf`,
        of the radius and the frequency.
    ka : float or array
        Normalised wave number k a >= 0 (a: contact radius), in the convention ``wavenumber``.
    model : str
        Displacement condition: "exact" (default): the rigid flat punch (uniform displacement;
        Galerkin, see :mod:`contactres.dynamic._exact`), the reference the others approximate; or
        "R0", "R1", "SA", "WA", "TP" (paper 1, Eqs. 24-28), "WA2D". Of these, R0 has negative
        damping near k_l a = 1.6-2 and R1, SA, WA, TP depend on the in-plane x axis (module
        docstring; :func:`model_n`).
    loss : float
        Q⁻¹ in C (1 + i Q⁻¹), in [0, 1). Default 0: the lossless solid (only radiation damping); the
        paper's figures use 0.02.
    wavenumber : str
        "longitudinal": k = ω√(ρ/C33) (the paper's k_l a, default) or "shear": k = ω√(ρ/C44).
    rtol : float
        Target relative accuracy (default 1e-6; met for k_l a <= 2, A in [0.2, 10] and
        ν <= 0.45 but not A < 0.25 with ν > 0.44, see the convergence tests and
        :func:`~contactres.dynamic._table.resolution_for`). rtol >= 1e-4 selects a coarser,
        faster resolution. Outside that range (k_l a > 2, or a solid that is not cubic or
        isotropic in its crystal frame or has A or ν beyond it), and inside it where a model's
        ``|DCSF|`` exceeds 500 (near a pole of SA or R1, where the relative error grows like
        ``|DCSF|``), each value is checked at run time against a
        refined evaluation and refined where it misses rtol (up to two doublings of every
        resolution, :func:`checked_dcsf_models`; 5-20 times the cost); a value that still misses
        it is returned with an :class:`~contactres.errors.AccuracyWarning` naming the material,
        the k a and the accuracy reached.
    prepared : KernelTable, optional
        The kernel table from :func:`prepare` for this material, ``loss`` and ``rtol`` (a
        ValueError if it was prepared for others); built for this call when not given.
    chunk : int
        Keyword only: k a values evaluated together (default 64; memory ~0.6 MB per value, not
        growing with the size of ``ka``); the result does not depend on it (to ~1e-15).
    interpolate : bool or None
        Keyword only. True: evaluate directly at 33-257 Chebyshev points of [min, max] of ``ka`` and
        interpolate 1/DCSF (smooth; the DCSF of SA and R1 can have poles), refining until the
        interpolation error, measured at the next refinement's points, is below rtol/10 of the
        largest ``|1/DCSF|`` on the curve (if 257 points do not reach it, every value is evaluated
        directly). False: every distinct value directly. None (default): interpolate above
        :data:`INTERPOLATE_ABOVE` distinct values, so a curve or map of any size costs about as much
        as ~100 points.

    Returns
    -------
    complex or ndarray of complex
        K_da/K_sa, K_sa the static stiffness of the undamped constants (DCSF(0) = 1 + i Q⁻¹).
        Real part: stiffness; imaginary part: radiation (and material) damping.

    Raises
    ------
    ValueError
        For bad arguments, and for a nearly incompressible solid (stiffness contrast beyond
        :data:`~contactres.dynamic.MAX_STIFFNESS_CONTRAST`, isotropic ν > 0.4999), where
        the stated accuracy cannot be met.

    Examples
    --------
    >>> d = dcsf(Material.isotropic(70e9, 1 / 3, density=2500.0), 0.5, wavenumber="shear")
    >>> bool(abs(d - (0.9689 + 0.5j * 0.7931)) < 1e-4)  # rigid disk, (k, c) at a0 = 0.5
    True
    """
    key = check_model(model)
    out = dcsf_models(
        m,
        ka,
        (key,),
        loss=loss,
        wavenumber=wavenumber,
        rtol=rtol,
        prepared=prepared,
        chunk=chunk,
        interpolate=interpolate,
    )[key]
    return complex(out) if out.ndim == 0 else out


def dynamic_contact_stiffness(
    m: Material,
    radius,
    force,
    frequency,
    model: str = "exact",
    loss: float = 0.0,
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
):
    """Dynamic contact stiffness K_da = K_sa × DCSF of a rigid sphere on ``m``, N/m (complex).

    Parameters
    ----------
    m : Material
        Undamped constants in the surface frame, with ``density`` (kg/m^3).
    radius : float or array
        Sphere radius R, m.
    force : float or array
        Static normal force F, N (a from anisotropic Hertz, :func:`contactres.sphere_contact`).
    frequency : float or array
        Oscillation frequency f, Hz (ω = 2πf). ``radius``, ``force`` and ``frequency`` broadcast.
    model, loss, rtol, prepared
        As in :func:`dcsf` (defaults: the exact model, a lossless solid).

    Returns
    -------
    complex or ndarray of complex
        K_da in N/m; its real part is the contact stiffness, ω⁻¹ Im K_da the damping (N s/m).

    Examples
    --------
    >>> from contactres import sphere_contact
    >>> si = Material.crystal("Si")  # (001); R = 50 nm, F = 0.5 µN, f = 1 MHz: k a ≈ 5e-6
    >>> k = dynamic_contact_stiffness(si, 50e-9, 0.5e-6, 1e6)
    >>> bool(abs(k.real / sphere_contact(si, 50e-9, 0.5e-6).stiffness - 1) < 1e-9), k.imag > 0
    (True, True)
    """
    from ..normal import sphere_contact

    density = require_material(m).density
    if density is None:
        raise ContactresInputError("dynamic_contact_stiffness needs the material density (kg/m^3)")
    f = np.asarray(nonnegative("frequency", frequency, "Hz"))
    # As before the a/R check of sphere_contact (issue 30): its callers flag a/R themselves.
    contact = sphere_contact(m, radius, force, check_validity=False)
    a = np.asarray(contact.contact_radius, dtype=float)
    ksa = normalised_wavenumber(f, a, m.density, shear_reference(m))
    ksa, k_sa = np.broadcast_arrays(ksa, np.asarray(contact.stiffness, dtype=float))
    out = k_sa * dcsf(
        m, ksa, model=model, loss=loss, wavenumber="shear", rtol=rtol, prepared=prepared
    )
    out = np.asarray(out)
    return complex(out) if out.ndim == 0 else out
