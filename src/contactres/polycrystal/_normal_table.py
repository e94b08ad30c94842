"""Contact properties over the fundamental triangle of surface normals, interpolated.

The indentation modulus M (paper 1, Eqs. 1-4) and the DCSF of the exact rigid flat punch (and
WA2D; paper 1, Eqs. 23-29) integrate over every in-plane direction θ of the contact, so they do
not change when the sample frame turns about the surface normal: they depend only on the
crystal direction ``n = R[..., 2, :]`` of the normal. The stiffness is centrosymmetric, so with
the Laue group of the crystal n can be reduced to a fundamental triangle of the sphere:

cubic (m-3m)
    Sort ``|n|`` ascending: 0 ≤ n_x ≤ n_y ≤ n_z, the standard stereographic triangle
    [001]-[011]-[111] (1/48 of the sphere). Coordinates: polar angle θ = arccos n_z from [001]
    and φ = atan2(n_x, n_y) in [0, 45°]; θ ≤ arctan(1/cos φ) ≤ arctan √2 = 54.74°.
hexagonal (6/mmm)
    n_z ≥ 0 and the azimuth of n about c, from a1 (x), reduced to [0, 30°]: θ in [0, 90°],
    φ in [0, 30°] (1/24 of the sphere).

:func:`prepare_normal_table` tabulates M (and optionally the DCSF at given k a values) on a
uniform (θ, φ) grid over the bounding rectangle of the triangle (the rectangle covers it; the
part outside maps to other, equivalent directions where the functions are just as smooth) and
interpolates with bicubic splines (:class:`scipy.interpolate.RectBivariateSpline`). The grid is
doubled until the interpolation error at the centres of the grid cells, evaluated exactly, is
below ``rtol`` relative; the error reached is stored in the table. Nodes already evaluated are
reused (the cell centres of one grid are nodes of the next).

The approximate DCSF models R1, SA, WA, TP take the edge point or the line average along the
in-plane x axis, so they are not functions of n alone: they are not offered here. R0 is
invariant but has negative damping at high k a; "exact" (default) and "WA2D" are offered.

References
----------
Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010),
doi:10.3844/ajeassp.2010.56.63. J. J. Vlassak and W. D. Nix, J. Mech. Phys. Solids 42, 1223
(1994).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import RectBivariateSpline, make_interp_spline

from .._summary import Summarised, values
from ..dynamic import dcsf_models, prepare
from ..errors import ContactresInputError
from ..materials import Material, require_material
from ._moduli import indentation_moduli
from ._orientations import LATTICES

__all__ = [
    "DCSF_MODELS",
    "NormalTable",
    "normals_from_coordinates",
    "prepare_normal_table",
    "reduce_normals",
    "surface_matrices_from_normals",
    "zone_bounds",
]

#: DCSF models that depend on the surface normal only (rotation-invariant about it).
DCSF_MODELS = ("exact", "WA2D")
# Largest |n| deviation from 1 accepted for a direction (normals are normalised).
_MIN_NORM = 1e-12


def zone_bounds(lattice: str) -> tuple[float, float]:
    """(θ_max, φ_max), rad: the bounding rectangle [0, θ_max] x [0, φ_max] of the triangle."""
    if lattice == "cubic":
        return math.atan(math.sqrt(2.0)), math.pi / 4
    if lattice == "hexagonal":
        return math.pi / 2, math.pi / 6
    raise ContactresInputError(f"lattice must be one of {sorted(LATTICES)}, got {lattice!r}")


def normals_from_coordinates(theta, phi, lattice: str) -> np.ndarray:
    """Unit normals (..., 3), crystal coordinates, of the triangle coordinates (θ, φ) in rad.

    cubic: n = (sin θ sin φ, sin θ cos φ, cos θ) (so n_x ≤ n_y for φ ≤ 45°); hexagonal:
    n = (sin θ cos φ, sin θ sin φ, cos θ), φ the azimuth from a1. Inverse of
    :func:`reduce_normals` inside the triangle.
    """
    zone_bounds(lattice)
    t, p = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
    s = np.sin(t)
    if lattice == "cubic":
        return np.stack([s * np.sin(p), s * np.cos(p), np.cos(t)], axis=-1)
    return np.stack([s * np.cos(p), s * np.sin(p), np.cos(t)], axis=-1)


def reduce_normals(n, lattice: str) -> tuple[np.ndarray, np.ndarray]:
    """Reduce crystal directions to the fundamental triangle of the Laue group.

    Parameters
    ----------
    n : array_like, shape (..., 3)
        Directions in crystal coordinates (e.g. ``R[..., 2, :]`` of surface matrices); they are
        normalised here.
    lattice : {"cubic", "hexagonal"}
        The crystal symmetry (m-3m or 6/mmm: the proper group of
        :func:`~contactres.polycrystal.symmetry_operators` with the inversion).

    Returns
    -------
    normals : ndarray, shape (..., 3)
        The equivalent unit direction in the triangle (module docstring).
    coordinates : ndarray, shape (..., 2)
        Its (θ, φ), rad.

    Raises
    ------
    ValueError
        For a wrong shape, non-finite entries, a zero vector or an unknown lattice.

    Examples
    --------
    >>> import numpy as np
    >>> v, c = reduce_normals([-1.0, 0.0, -1.0], "cubic")
    >>> np.round(v, 6) + 0.0, np.round(np.degrees(c), 6) + 0.0
    (array([0.      , 0.707107, 0.707107]), array([45.,  0.]))
    """
    zone_bounds(lattice)
    v = np.asarray(n, dtype=float)
    if v.ndim < 1 or v.shape[-1] != 3:
        raise ContactresInputError(f"normals must have shape (..., 3), got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ContactresInputError("normals must be finite (found NaN or inf)")
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    if np.any(norm < _MIN_NORM):
        raise ContactresInputError("normals must not be zero vectors")
    v = v / norm
    if lattice == "cubic":
        red = np.sort(np.abs(v), axis=-1)
        theta = np.arccos(np.clip(red[..., 2], -1.0, 1.0))
        phi = np.arctan2(red[..., 0], red[..., 1])
    else:
        z = np.abs(v[..., 2])
        s = np.hypot(v[..., 0], v[..., 1])
        psi = np.mod(np.arctan2(v[..., 1], v[..., 0]), math.pi / 3)
        phi = np.minimum(psi, math.pi / 3 - psi)
        theta = np.arctan2(s, z)
        red = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)
    return red, np.stack([theta, phi], axis=-1)


def surface_matrices_from_normals(n) -> np.ndarray:
    """Surface matrices (..., 3, 3) with ``R[..., 2, :] = n`` (unit n, crystal coordinates).

    The in-plane x axis is the crystal axis least aligned with n, projected onto the plane;
    y = z × x (proper rotations). For the invariant quantities of this module the in-plane
    axis does not matter.
    """
    z = np.asarray(n, dtype=float)
    z = z / np.linalg.norm(z, axis=-1, keepdims=True)
    e = np.zeros_like(z)
    np.put_along_axis(e, np.argmin(np.abs(z), axis=-1)[..., None], 1.0, axis=-1)
    x = e - np.sum(e * z, axis=-1, keepdims=True) * z
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=-2)


def _normals_of(orientations=None, normals=None) -> np.ndarray:
    """The normals of surface matrices (..., 3, 3) or given normals (..., 3), one of the two."""
    if (orientations is None) == (normals is None):
        raise ContactresInputError("give exactly one of the surface matrices or normals=")
    if normals is not None:
        return np.asarray(normals, dtype=float)
    R = np.asarray(orientations, dtype=float)
    if R.ndim < 2 or R.shape[-2:] != (3, 3):
        raise ContactresInputError(f"surface matrices must have shape (..., 3, 3), got {R.shape}")
    return R[..., 2, :]


def _spline(theta: np.ndarray, phi: np.ndarray, values: np.ndarray):
    """Bicubic interpolating spline of (nθ, nφ) values, real or complex; returns f(θ, φ)."""
    kx, ky = min(3, theta.size - 1), min(3, phi.size - 1)
    re = RectBivariateSpline(theta, phi, values.real, kx=kx, ky=ky, s=0)
    if not np.iscomplexobj(values):
        return lambda t, p: re.ev(t, p)
    im = RectBivariateSpline(theta, phi, values.imag, kx=kx, ky=ky, s=0)
    return lambda t, p: re.ev(t, p) + 1j * im.ev(t, p)


def _ka_weights(nodes: np.ndarray, ka: np.ndarray) -> np.ndarray:
    """Cardinal weights (..., K) of the cubic spline through the k a nodes, at ``ka`` (...)."""
    if nodes.size == 1:
        return np.ones((*ka.shape, 1))
    k = min(3, nodes.size - 1)
    return make_interp_spline(nodes, np.eye(nodes.size), k=k)(ka)


def _relative(got: np.ndarray, exact: np.ndarray) -> float:
    """Largest relative difference of interpolated and exact values."""
    return float(np.max(np.abs(got - exact) / np.abs(exact)))


def _refine(
    exact: Callable[[np.ndarray, np.ndarray], np.ndarray],
    width: int,
    bounds: tuple[float, float],
    rtol: float,
    start: int,
    largest: int,
    label: str,
    measure: Callable[[np.ndarray, np.ndarray], float] = _relative,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[float, ...], int]:
    """Double a uniform (θ, φ) grid until the error at the cell centres is below ``rtol``.

    ``exact(theta, phi)`` returns exact values (P, width) at P points; ``measure(got, exact)``
    the error of the interpolated values (P, width) at the cell centres. Returns (theta, phi,
    values (nθ, nφ, width), errors, evaluations).
    """
    known: dict[tuple[int, int], np.ndarray] = {}
    scale = 2 * largest  # keys: indices on the centre lattice of the finest allowed grid

    def values_at(it, ip, level):
        keys = [
            (int(a) * (scale // level), int(b) * (scale // level))
            for a, b in zip(it, ip, strict=True)
        ]
        todo = [i for i, key in enumerate(keys) if key not in known]
        if todo:
            t = np.array([keys[i][0] for i in todo]) / scale * bounds[0]
            p = np.array([keys[i][1] for i in todo]) / scale * bounds[1]
            for i, val in zip(todo, exact(t, p), strict=True):
                known[keys[i]] = val
        return np.array([known[key] for key in keys]).reshape(len(keys), width)

    errors: list[float] = []
    n = start
    while True:
        it, ip = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
        nodes = values_at(2 * it.ravel(), 2 * ip.ravel(), 2 * n).reshape(n + 1, n + 1, -1)
        ct, cp = np.meshgrid(2 * np.arange(n) + 1, 2 * np.arange(n) + 1, indexing="ij")
        check = values_at(ct.ravel(), cp.ravel(), 2 * n)
        theta = np.linspace(0.0, bounds[0], n + 1)
        phi = np.linspace(0.0, bounds[1], n + 1)
        t_c, p_c = ct.ravel() / (2 * n) * bounds[0], cp.ravel() / (2 * n) * bounds[1]
        got = np.stack(
            [_spline(theta, phi, nodes[..., j])(t_c, p_c) for j in range(nodes.shape[-1])], -1
        )
        errors.append(measure(got, check))
        if errors[-1] <= rtol or 2 * n > largest:
            break
        n *= 2
    if errors[-1] > rtol:
        warnings.warn(
            f"{label}: interpolation error {errors[-1]:.3g} > rtol={rtol:g} with {n} intervals "
            "(largest allowed); the table states the error reached",
            RuntimeWarning,
            stacklevel=3,
        )
    return theta, phi, nodes, tuple(errors), len(known)


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the grids.
@dataclass(frozen=True, eq=False, repr=False)
class NormalTable(Summarised):
    """M (and optionally the DCSF) tabulated over the fundamental triangle of normals.

    Built by :func:`prepare_normal_table`; evaluate with :meth:`modulus` and :meth:`dcsf`.

    Attributes
    ----------
    material : Material
        The crystal, in its crystal frame.
    lattice : str
        "cubic" or "hexagonal".
    theta, phi : ndarray
        The M grid, rad (uniform over the bounding rectangle, :func:`zone_bounds`).
    moduli : ndarray, shape (len(theta), len(phi))
        Exact M at the nodes, Pa.
    error : float
        Largest relative error of the interpolated M at the cell centres of the final grid.
    errors : tuple of float
        That error for every grid of the refinement (4, 8, 16, ... intervals).
    evaluations : int
        Exact M evaluations made (nodes and check points).
    ka : ndarray or None
        k_l a nodes of the DCSF (k_l = ω √(ρ/C33') with C33' the stiffness along the normal:
        the default ``wavenumber="longitudinal"`` of :func:`contactres.dcsf` for each face).
    dcsf_theta, dcsf_phi, dcsf_values
        The DCSF grid (rad) and values (nθ, nφ, len(ka)), complex; None without ``ka``.
    dcsf_error : float or None
        Largest relative error of the interpolated DCSF at the cell centres of the final DCSF
        grid, at the k a nodes and the midpoints between them.
    dcsf_errors : tuple of float
        That error for every DCSF grid (2, 4, ... intervals).
    dcsf_evaluations : int
        Orientations for which a kernel table was built (one :func:`contactres.dynamic.prepare`
        each).
    model, loss : str, float
        DCSF model ("exact" or "WA2D") and Q⁻¹.
    """

    material: Material
    lattice: str
    theta: np.ndarray
    phi: np.ndarray
    moduli: np.ndarray
    error: float
    errors: tuple[float, ...]
    evaluations: int
    ka: np.ndarray | None = None
    dcsf_theta: np.ndarray | None = None
    dcsf_phi: np.ndarray | None = None
    dcsf_values: np.ndarray | None = None
    dcsf_error: float | None = None
    dcsf_errors: tuple[float, ...] = ()
    dcsf_evaluations: int = 0
    model: str = "exact"
    loss: float = 0.0

    def _facts(self) -> list[tuple[str, str]]:
        """The crystal, the lattice, M over the grid (GPa) and its error; the DCSF's k a."""
        facts = [
            ("", repr(self.material.name) if self.material.name else "unnamed"),
            ("", self.lattice),
            ("M", values(self.moduli, "GPa", 1e9)),
            ("grid", f"{len(self.theta)} x {len(self.phi)} (error {self.error:.2g})"),
        ]
        if self.ka is not None:
            facts.append(("DCSF k a", f"{values(self.ka)} ({self.model}, Q⁻¹ {self.loss:g})"))
        return facts

    def modulus(self, orientations=None, *, normals=None) -> np.ndarray:
        """Interpolated indentation modulus M, Pa, shape (...).

        Parameters
        ----------
        orientations : array_like, shape (..., 3, 3), optional
            Surface matrices (rows = sample axes in crystal coordinates).
        normals : array_like, shape (..., 3), optional
            Or the crystal directions of the surface normal (keyword only).

        Notes
        -----
        Vectorised: one reduction to the triangle and one spline evaluation for all pixels.
        Accurate to about :attr:`error` relative (see the tests for the factor between the
        cell-centre estimate and the true maximum).
        """
        _, c = reduce_normals(_normals_of(orientations, normals), self.lattice)
        return _spline(self.theta, self.phi, self.moduli)(c[..., 0], c[..., 1])

    def dcsf(self, ka, orientations=None, *, normals=None) -> np.ndarray:
        """Interpolated DCSF = K_da/K_sa at k_l a = ``ka`` (broadcast with the pixels), complex.

        ``ka`` is the longitudinal k_l a of each pixel's own face (k_l = ω √(ρ/C33'), C33' =
        n_i n_j n_k n_l C_ijkl), within [ka[0], ka[-1]] of the table (cubic spline in k a
        between the nodes). Other arguments as :meth:`modulus`.
        """
        if (
            self.dcsf_values is None
            or self.ka is None
            or self.dcsf_theta is None
            or self.dcsf_phi is None
        ):  # all four are given together (prepare_normal_table with ka=) or none
            raise ContactresInputError("the table has no DCSF: pass ka= to prepare_normal_table")
        _, c = reduce_normals(_normals_of(orientations, normals), self.lattice)
        x = np.asarray(ka, dtype=float)
        lo, hi = float(self.ka[0]), float(self.ka[-1])
        if not np.all((x >= lo * (1 - 1e-12)) & (x <= hi * (1 + 1e-12))):
            raise ContactresInputError(
                f"ka must lie within the table's nodes [{lo:g}, {hi:g}] (k_l a); got "
                f"{float(np.min(x)):g} to {float(np.max(x)):g}"
            )
        x, t, p = np.broadcast_arrays(x, c[..., 0], c[..., 1])
        vals = np.stack(
            [
                _spline(self.dcsf_theta, self.dcsf_phi, self.dcsf_values[..., j])(t, p)
                for j in range(self.ka.size)
            ],
            axis=-1,
        )
        return np.sum(_ka_weights(self.ka, x) * vals, axis=-1)


def _exact_dcsf(m, lattice, theta, phi, ka, model, loss, rtol) -> np.ndarray:
    """Exact DCSF (P, K) at the triangle points (θ, φ) and k_l a nodes + midpoints."""
    out = []
    for n in normals_from_coordinates(theta, phi, lattice):  # one kernel table per orientation
        face = m.rotated(tuple(n))
        table = prepare(face, loss, rtol)
        d = dcsf_models(face, ka, (model,), loss, "longitudinal", rtol, table, interpolate=False)
        out.append(d[model])
    return np.array(out)


def prepare_normal_table(
    material: Material,
    lattice: str,
    rtol: float = 1e-4,
    *,
    ka=None,
    model: str = "exact",
    loss: float = 0.0,
    dcsf_rtol: float = 1e-3,
    max_intervals: int = 64,
    dcsf_max_intervals: int = 16,
) -> NormalTable:
    """Tabulate M (and the DCSF) over the fundamental triangle, refined to a measured error.

    M: a uniform (θ, φ) grid of 4 intervals per axis over the bounding rectangle of the
    triangle, doubled until the bicubic interpolant differs from the exact M
    (:func:`~contactres.polycrystal.indentation_moduli`, one vectorised call per grid)
    by at most ``rtol`` relative at every cell centre. Measured for Cu (cubic): the default
    rtol = 1e-4 stops at 16 x 16 intervals (errors 1.5e-3, 1.4e-4, 6.0e-6 at 4, 8, 16):
    545 exact evaluations (289 nodes + 256 centres, earlier grids reused), ~0.3 s; over 2000
    random orientations the true largest error is 4.9e-6, below the stated 6.0e-6.
    rtol = 1e-6: 32 x 32 intervals, 2113 evaluations, ~1 s, 2.6e-7 stated (2.2e-7 true).
    Interpolating a map then costs ~1 µs per pixel.

    DCSF (optional, ``ka`` given): the same scheme on its own grid, starting at 2 x 2 intervals
    (biquadratic), doubled until the error at the cell centres, at every k a node and at the
    midpoints between nodes (cubic spline in k a), is below ``dcsf_rtol``. Each orientation
    needs its own kernel table (:func:`contactres.dynamic.prepare`), ~0.02-0.1 s for Cu.
    Measured for Cu, exact model, one node k_l a = 0.33 (k_s a ≈ 0.5 on (001)):
    dcsf_rtol = 1e-3 -> 8 x 8 intervals, 145 orientations, 1.6e-4 reached, 6.4 s;
    dcsf_rtol = 1e-4 -> 16 x 16, 545 orientations, 6.9e-6 reached, 125 s (errors 2.0e-2,
    1.7e-3, 1.6e-4, 6.9e-6 at 2, 4, 8, 16 intervals). Five nodes k_l a = 0.25-0.45 at
    dcsf_rtol = 1e-3: 8 x 8, 2.2e-4, 28 s. The tests use dcsf_rtol = 4e-2 (2 x 2, 13
    orientations, ~1 s).

    Parameters
    ----------
    material : Material
        The crystal in its crystal frame (cube axes; c along z for hexagonal), stiffness in Pa.
        Lossless for the DCSF (its damping is ``loss``).
    lattice : {"cubic", "hexagonal"}
        Its Laue symmetry. Trigonal or lower symmetries are not reduced here (use the exact
        :func:`~contactres.polycrystal.indentation_moduli`).
    rtol : float
        Target relative interpolation error of M, in [1e-8, 1e-2].
    ka : array_like, optional
        Increasing k_l a nodes (≥ 0; 1 value or at least 2) at which to tabulate the DCSF, in
        the longitudinal convention of :func:`contactres.dcsf` for each face. Between nodes a
        cubic spline (linear for 2 nodes); choose them to cover the map's k a range
        (:func:`contactres.polycrystal.map_wavenumbers`).
    model : {"exact", "WA2D"}
        The DCSF model (only those invariant about the normal).
    loss : float
        Q⁻¹ of the constants for the DCSF (default 0).
    dcsf_rtol : float
        Target relative interpolation error of the DCSF, in [1e-6, 1e-1]; the DCSF itself is
        evaluated with ``rtol = dcsf_rtol/10`` (at least 1e-6).
    max_intervals, dcsf_max_intervals : int
        Largest number of intervals per axis (a RuntimeWarning when the target is not met;
        the table states the error reached).

    Returns
    -------
    NormalTable
    """
    m = require_material(material)
    bounds = zone_bounds(lattice)
    rtol = float(rtol)
    if not 1e-8 <= rtol <= 1e-2:
        raise ContactresInputError(f"rtol must lie in [1e-8, 1e-2], got {rtol!r}")

    def exact_m(theta, phi):
        R = surface_matrices_from_normals(normals_from_coordinates(theta, phi, lattice))
        return indentation_moduli(m, R, rtol=min(1e-8, rtol / 100))[:, None]

    theta, phi, mod, errors, count = _refine(
        exact_m, 1, bounds, rtol, 4, int(max_intervals), "M table"
    )
    mod = mod[..., 0]
    table = NormalTable(m, lattice, theta, phi, mod, errors[-1], errors, count)
    if ka is None:
        return table
    if model not in DCSF_MODELS:
        raise ContactresInputError(
            f"model must be one of {DCSF_MODELS} (R1, SA, WA, TP depend on the in-plane axis, "
            f"R0 has negative damping), got {model!r}"
        )
    nodes = np.atleast_1d(np.asarray(ka, dtype=float))
    if nodes.ndim != 1 or not np.all(np.isfinite(nodes)) or np.any(nodes < 0):
        raise ContactresInputError(f"ka must be a 1-D array of finite values >= 0, got {ka!r}")
    if np.any(np.diff(nodes) <= 0):
        raise ContactresInputError("ka nodes must be strictly increasing")
    dcsf_rtol = float(dcsf_rtol)
    if not 1e-6 <= dcsf_rtol <= 1e-1:
        raise ContactresInputError(f"dcsf_rtol must lie in [1e-6, 1e-1], got {dcsf_rtol!r}")
    mids = 0.5 * (nodes[1:] + nodes[:-1])
    allka = np.concatenate([nodes, mids])
    weights = _ka_weights(nodes, mids)

    k = nodes.size

    def exact_d(theta, phi):
        return _exact_dcsf(m, lattice, theta, phi, allka, model, loss, max(1e-6, dcsf_rtol / 10))

    def measure(got, check):
        # The k a nodes, and the k a spline of the interpolated node values at the midpoints.
        if k == 1:
            return _relative(got, check)
        at_mids = got[:, :k] @ weights.T
        return max(_relative(got[:, :k], check[:, :k]), _relative(at_mids, check[:, k:]))

    dt, dp, dvals, derr, dcount = _refine(
        exact_d, allka.size, bounds, dcsf_rtol, 2, int(dcsf_max_intervals), "DCSF table", measure
    )
    return NormalTable(
        m,
        lattice,
        theta,
        phi,
        mod,
        errors[-1],
        errors,
        count,
        ka=nodes,
        dcsf_theta=dt,
        dcsf_phi=dp,
        dcsf_values=dvals[..., :k],
        dcsf_error=derr[-1],
        dcsf_errors=derr,
        dcsf_evaluations=dcount,
        model=model,
        loss=float(loss),
    )
