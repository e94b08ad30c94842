"""Crystal orientations of a polycrystal map (EBSD) as surface-frame matrices.

Conventions
-----------
Sample frame: x = RD (the EBSD map's X), y = TD, z = ND, the surface normal (pointing into the
sample, as the z axis of the contact models). Crystal frame: the frame the stiffness of a
:class:`~contactres.materials.Material` is given in (cube axes for a cubic crystal; for a
hexagonal one the c axis along z and a1 along x, as :meth:`Material.hexagonal`).

Every function returns or takes *surface-frame matrices* ``R`` (shape (..., 3, 3), proper
orthogonal): the rows of ``R`` are the sample axes x, y, z in crystal coordinates, and
``v_sample = R @ v_crystal``. This is the convention of
:func:`~contactres.materials.rotation_to_surface` and :meth:`Material.rotated`, so
``tensor_to_voigt(rotate_tensor(voigt_to_tensor(m.C), R))`` is the crystal ``m`` seen in the
sample frame, and ``R[..., 2, :]`` is the crystal direction along the surface normal.

Euler angles are Bunge's (φ1, Φ, φ2), passive: the orientation matrix
``g = Z(φ2) X(Φ) Z(φ1)`` maps sample coordinates to crystal coordinates (``v_crystal = g @
v_sample``), with the frame rotations ``Z(ω) = [[cos ω, sin ω, 0], [-sin ω, cos ω, 0],
[0, 0, 1]]`` and ``X(ω) = [[1, 0, 0], [0, cos ω, sin ω], [0, -sin ω, cos ω]]``. Hence
``R = gᵀ``. Bunge ranges: φ1, φ2 in [0, 2π), Φ in [0, π].

Quaternions ``q = (q0, q1, q2, q3)`` (scalar q0 first by default) are those of Rowenhorst et al.
(2015) with P = -1, as EBSD software writes them (EDAX OIM, EMsoft, DREAM.3D, orix): ``q``
represents the passive orientation ``g``; their Bunge conversion is
``q = (cos(Φ/2) cos σ, sin(Φ/2) cos δ, sin(Φ/2) sin δ, cos(Φ/2) sin σ)`` with
``σ = (φ1 + φ2)/2``, ``δ = (φ1 - φ2)/2``. In Hamilton algebra (scipy's
:class:`~scipy.spatial.transform.Rotation`) the same ``q`` is the *active* rotation whose matrix
is ``gᵀ = R``. Returned quaternions have q0 ≥ 0.

Symmetry: a proper symmetry operation ``S`` of the crystal (3x3, crystal coordinates) leaves the
stiffness unchanged, so ``R`` and ``R @ S`` describe the same crystal in the sample frame (``g``
and ``Sᵀ g``). Groups: cubic O (432, 24 rotations), hexagonal D6 (622, 12 rotations: six-fold
axis z = c, two-fold axes along x = a1 and every 30° about z).

References
----------
H.-J. Bunge, *Texture Analysis in Materials Science*, Butterworths (1982).
D. Rowenhorst, A. D. Rollett, G. S. Rohrer, M. Groeber, M. Jackson, P. J. Konijnenberg,
M. De Graef, "Consistent representations of and conversions between 3D rotations", Modelling
Simul. Mater. Sci. Eng. 23, 083501 (2015), doi:10.1088/0965-0393/23/8/083501.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ContactresInputError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = [
    "LATTICES",
    "euler_from_surface_matrices",
    "quaternions_from_surface_matrices",
    "random_orientations",
    "reduce_to_fundamental_zone",
    "surface_matrices_from_euler",
    "surface_matrices_from_quaternions",
    "surface_matrix_from_miller",
    "symmetry_operators",
]


def _rotation() -> type[Rotation]:
    """scipy's :class:`~scipy.spatial.transform.Rotation`, imported on first use: it brings
    scipy.sparse and scipy.linalg (~0.25 s of CPU), and this module comes with every EBSD reader,
    which the readers' registry of a job loads also for files that are no EBSD map (issue 31)."""
    from scipy.spatial.transform import Rotation

    return Rotation


# Lattice name -> scipy's name of its proper point group (z = the main axis).
LATTICES: dict[str, str] = {"cubic": "O", "hexagonal": "D6"}

# Largest |angle| accepted: two full turns (beyond it the unit was most likely wrong).
MAX_TURNS = 2.0
# Tolerances: orthogonality of input matrices; unit norm of quaternions; ties in the reduction.
ORTHOGONALITY_TOL = 1e-6
QUATERNION_NORM_TOL = 1e-2
TIE_TOL = 1e-9


def _angles(value, name: str, degrees: bool) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ContactresInputError(f"Euler angle {name} must be finite (found NaN or inf)")
    limit = MAX_TURNS * (360.0 if degrees else 2 * np.pi)
    worst = float(np.max(np.abs(a))) if a.size else 0.0
    if worst > limit:
        unit, other = ("degrees", "radians") if degrees else ("radians", "degrees")
        raise ContactresInputError(
            f"Euler angle {name} = {worst:.6g} {unit} exceeds the rule |angle| <= "
            f"{limit:.6g} {unit} ({MAX_TURNS:g} turns): were the angles given in {other}? "
            f"Pass degrees={not degrees} if so"
        )
    return np.radians(a) if degrees else a


def _rotations(R, name: str = "R") -> tuple[np.ndarray, tuple[int, ...]]:
    """Check a stack of rotation matrices; return it as (N, 3, 3) with the leading shape."""
    R = np.asarray(R, dtype=float)
    if R.ndim < 2 or R.shape[-2:] != (3, 3):
        raise ContactresInputError(f"{name} must have shape (..., 3, 3), got {R.shape}")
    if not np.all(np.isfinite(R)):
        raise ContactresInputError(f"{name} must be finite (found NaN or inf)")
    flat = R.reshape(-1, 3, 3)
    err = np.abs(flat @ np.swapaxes(flat, -1, -2) - np.eye(3))
    if flat.size and float(err.max()) > ORTHOGONALITY_TOL:
        raise ContactresInputError(
            f"{name} must be orthogonal: max |R Rᵀ - I| = {float(err.max()):.3g} "
            f"(> {ORTHOGONALITY_TOL:g})"
        )
    if flat.size and np.any(np.linalg.det(flat) < 0):
        raise ContactresInputError(f"{name} must be a proper rotation (det = +1), found det = -1")
    return flat, R.shape[:-2]


def surface_matrices_from_euler(phi1, Phi, phi2, *, degrees: bool) -> np.ndarray:
    """Surface-frame matrices of Bunge Euler angles (φ1, Φ, φ2), passive convention.

    Parameters
    ----------
    phi1, Phi, phi2 : array_like
        Bunge angles (broadcast together), e.g. the three columns of an EBSD map. Any values
        within two turns are accepted (the rotation is periodic).
    degrees : bool
        Required: True for degrees, False for radians (no default, the unit must be stated).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``R = gᵀ`` with ``g = Z(φ2) X(Φ) Z(φ1)`` (module docstring): rows = sample x, y, z in
        crystal coordinates. (0, 0, 0) is the identity; (0, 90°, 0) has the surface normal
        along crystal [010] and y along [00-1]; (φ1, arccos(1/√3), 45°) has the normal along
        [111].

    Raises
    ------
    ValueError
        For non-finite angles or an angle beyond two turns (``|angle|`` > 4π rad or > 720°), the
        sign of a unit mix-up.

    Examples
    --------
    >>> import numpy as np
    >>> R = surface_matrices_from_euler(0, 90, 0, degrees=True)
    >>> np.round(R[2], 12) + 0.0  # the surface normal in crystal coordinates: [010]
    array([0., 1., 0.])
    """
    a = np.broadcast_arrays(
        _angles(phi1, "phi1", degrees), _angles(Phi, "Phi", degrees), _angles(phi2, "phi2", degrees)
    )
    shape = a[0].shape
    stacked = np.stack([x.ravel() for x in a], axis=-1)
    # Intrinsic z-x'-z'' (scipy 'ZXZ') active rotation Rz(φ1) Rx(Φ) Rz(φ2) = (Z(φ2) X(Φ) Z(φ1))ᵀ.
    return _rotation().from_euler("ZXZ", stacked).as_matrix().reshape(*shape, 3, 3)


def euler_from_surface_matrices(R, *, degrees: bool) -> np.ndarray:
    """Bunge Euler angles (φ1, Φ, φ2) of surface-frame matrices (inverse of the above).

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Surface-frame matrices (rows = sample axes in crystal coordinates), proper orthogonal
        to 1e-6.
    degrees : bool
        Required: unit of the result.

    Returns
    -------
    ndarray, shape (..., 3)
        (φ1, Φ, φ2) with φ1, φ2 in [0, 2π) and Φ in [0, π] (or degrees). When Φ = 0 or π only
        φ1 ± φ2 is defined: φ2 = 0 is returned (Rowenhorst et al. 2015).
    """
    flat, shape = _rotations(R)
    if not flat.size:
        return np.zeros((*shape, 3))
    with warnings.catch_warnings():  # Φ = 0 (e.g. the cube orientation) is a normal input
        warnings.filterwarnings("ignore", message="Gimbal lock", category=UserWarning)
        e = _rotation().from_matrix(flat).as_euler("ZXZ")
    e[:, [0, 2]] = np.mod(e[:, [0, 2]], 2 * np.pi)
    e[np.isclose(e, 2 * np.pi, rtol=0, atol=1e-12)] = 0.0
    e = e.reshape(*shape, 3)
    return np.degrees(e) if degrees else e


def surface_matrices_from_quaternions(q, scalar_first: bool = True) -> np.ndarray:
    """Surface-frame matrices of orientation quaternions (Rowenhorst et al. 2015, P = -1).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions of the passive orientation ``g`` (crystal <- sample) as EBSD software
        writes them; normalised here. ``q`` and ``-q`` are the same orientation.
    scalar_first : bool
        True: (q0, q1, q2, q3) with the scalar part first (the EBSD convention); False: the
        scalar part last.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``R = gᵀ``, equal to :func:`surface_matrices_from_euler` of the same orientation.

    Raises
    ------
    ValueError
        For a wrong shape, non-finite entries or a norm off 1 by more than 1 % (not a unit
        quaternion: probably the wrong columns).
    """
    q = np.asarray(q, dtype=float)
    if q.ndim < 1 or q.shape[-1] != 4:
        raise ContactresInputError(f"quaternions must have shape (..., 4), got {q.shape}")
    if not np.all(np.isfinite(q)):
        raise ContactresInputError("quaternions must be finite (found NaN or inf)")
    norm = np.linalg.norm(q, axis=-1)
    if norm.size and float(np.max(np.abs(norm - 1))) > QUATERNION_NORM_TOL:
        raise ContactresInputError(
            f"quaternions must have unit norm (to {QUATERNION_NORM_TOL:g}): found norms from "
            f"{float(norm.min()):.4g} to {float(norm.max()):.4g}"
        )
    shape = q.shape[:-1]
    flat = q.reshape(-1, 4)
    if not flat.size:
        return np.zeros((*shape, 3, 3))
    # The Hamilton active matrix of the P = -1 quaternion of g is gᵀ = R.
    return _rotation().from_quat(flat, scalar_first=scalar_first).as_matrix().reshape(*shape, 3, 3)


def quaternions_from_surface_matrices(R, scalar_first: bool = True) -> np.ndarray:
    """Orientation quaternions (Rowenhorst et al. 2015, P = -1) of surface-frame matrices.

    Returns
    -------
    ndarray, shape (..., 4)
        Unit quaternions of ``g = Rᵀ`` with the scalar part ≥ 0 (first when ``scalar_first``).
    """
    flat, shape = _rotations(R)
    if not flat.size:
        return np.zeros((*shape, 4))
    q = _rotation().from_matrix(flat).as_quat(canonical=True, scalar_first=scalar_first)
    return q.reshape(*shape, 4)


def surface_matrix_from_miller(hkl, uvw) -> np.ndarray:
    """Surface-frame matrix of the ideal orientation (hkl)[uvw] of a cubic crystal.

    Parameters
    ----------
    hkl : array_like, shape (..., 3)
        Miller indices of the crystal plane parallel to the surface; its normal (∝ hkl for a
        cubic lattice) is the sample z axis (ND).
    uvw : array_like, shape (..., 3)
        Crystal direction along the sample x axis (RD); must lie in the plane: hkl · uvw = 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Rows x = uvw/``|uvw|``, y = z × x, z = hkl/``|hkl|``: the matrix of
        :func:`~contactres.materials.rotation_to_surface` ``(hkl, uvw)``.

    Raises
    ------
    ValueError
        For a zero or non-finite vector, or when uvw does not lie in the plane
        (``|hkl · uvw| > 1e-9 |hkl| |uvw|``).

    Notes
    -----
    Cubic lattices only: for a non-cubic lattice the plane normal is the reciprocal-lattice
    vector of (hkl), not ∝ (h, k, l); convert the indices to Cartesian vectors first.

    Examples
    --------
    The Goss orientation (011)[100] is Bunge (0°, 45°, 0°):

    >>> import numpy as np
    >>> R = surface_matrix_from_miller((0, 1, 1), (1, 0, 0))
    >>> np.allclose(R, surface_matrices_from_euler(0, 45, 0, degrees=True), rtol=0, atol=1e-12)
    True
    """
    n = np.asarray(hkl, dtype=float)
    d = np.asarray(uvw, dtype=float)
    for v, name in ((n, "hkl"), (d, "uvw")):
        if v.ndim < 1 or v.shape[-1] != 3:
            raise ContactresInputError(f"{name} must have shape (..., 3), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ContactresInputError(f"{name} must be finite (found NaN or inf)")
        if np.any(np.linalg.norm(v, axis=-1) == 0):
            raise ContactresInputError(f"{name} must not be the zero vector")
    n, d = np.broadcast_arrays(n, d)
    nn, nd = np.linalg.norm(n, axis=-1), np.linalg.norm(d, axis=-1)
    dot = np.sum(n * d, axis=-1)
    bad = np.abs(dot) > 1e-9 * nn * nd
    if np.any(bad):
        i = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise ContactresInputError(
            f"[uvw] = {d[i].tolist()!r} does not lie in the plane (hkl) = {n[i].tolist()!r}: "
            f"hkl · uvw = {float(dot[i]):g}, must be 0"
        )
    z = n / nn[..., None]
    x = d / nd[..., None]
    return np.stack([x, np.cross(z, x), z], axis=-2)


def symmetry_operators(lattice: str) -> np.ndarray:
    """The proper rotations of a crystal's point group, in crystal coordinates.

    Parameters
    ----------
    lattice : {"cubic", "hexagonal"}
        "cubic": the 24 rotations of O (432) about the cube axes. "hexagonal": the 12 rotations
        of D6 (622), six-fold axis along z (c), two-fold axes along x (a1) and every 30° about
        z, the frame of :meth:`Material.hexagonal`.

    Returns
    -------
    ndarray, shape (K, 3, 3)
        The operators ``S`` (``v' = S @ v`` in crystal coordinates), identity first; K = 24 or
        12. Entries that are 0 or ±1 are exact.
    """
    if lattice not in LATTICES:
        raise ContactresInputError(f"lattice must be one of {sorted(LATTICES)}, got {lattice!r}")
    # scipy-stubs list the group names as Literal[..., "Dn", ...]: n stands for 2, 3, ..., so
    # "D6" is valid (scipy's documentation), and no Literal admits it.
    S = _rotation().create_group(LATTICES[lattice]).as_matrix()  # type: ignore[arg-type]
    for exact in (0.0, 1.0, -1.0):  # clean round-off so that the cubic operators are exact
        S[np.isclose(S, exact, rtol=0, atol=1e-12)] = exact
    first = int(np.argmax(np.trace(S, axis1=1, axis2=2)))  # the identity, trace 3
    return np.concatenate([S[first : first + 1], np.delete(S, first, axis=0)])


def _entry(R: np.ndarray, S: np.ndarray, a: int, b: int) -> np.ndarray:
    """Entry (a, b) of every candidate R[n] @ S[k], shape (N, K)."""
    return R[:, a, :] @ S[:, :, b].T


def reduce_to_fundamental_zone(R, lattice: str) -> np.ndarray:
    """The symmetry-equivalent of each orientation nearest the identity (fundamental zone).

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Surface-frame matrices.
    lattice : {"cubic", "hexagonal"}
        Crystal symmetry (:func:`symmetry_operators`).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        For each ``R`` the candidate ``R @ S`` (S in the group) of smallest rotation angle
        ω = arccos((tr - 1)/2), i.e. of largest trace: the Rodrigues fundamental zone (the
        same zone for ``g = Rᵀ``). Ties (traces within 1e-9, on the zone's boundary) go to
        the candidate whose entries, read row by row, are lexicographically largest (each
        within 1e-9), so that all equivalents of an orientation reduce to the same matrix.
        The rotated stiffness, and so every contact property, is unchanged.

    Notes
    -----
    Vectorised: N x K traces and up to nine N x K entry arrays, never N x K matrices.
    """
    flat, shape = _rotations(R)
    S = symmetry_operators(lattice)
    if not flat.size:
        return np.zeros((*shape, 3, 3))
    trace = np.einsum("nij,kji->nk", flat, S)
    keep = trace >= trace.max(axis=1, keepdims=True) - TIE_TOL
    if np.any(keep.sum(axis=1) > 1):
        for a in range(3):  # nine entries, lexicographic tie-break (not a loop over orientations)
            for b in range(3):
                e = np.where(keep, _entry(flat, S, a, b), -np.inf)
                keep &= e >= e.max(axis=1, keepdims=True) - TIE_TOL
    best = np.argmax(keep, axis=1)
    return (flat @ S[best]).reshape(*shape, 3, 3)


def random_orientations(n: int, seed: int | np.random.Generator | None = None) -> np.ndarray:
    """``n`` orientations uniformly distributed on SO(3) (random texture), as surface matrices.

    Parameters
    ----------
    n : int
        Number of orientations (≥ 0).
    seed : int, numpy Generator or None
        Seed of :func:`numpy.random.default_rng` (None: fresh entropy).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Haar-uniform rotations (scipy ``Rotation.random``); ``R`` and ``Rᵀ`` are equally
        distributed, so they are uniform as ``g`` too.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 0:
        raise ContactresInputError(f"n must be a non-negative integer, got {n!r}")
    if n == 0:
        return np.zeros((0, 3, 3))
    return _rotation().random(int(n), rng=np.random.default_rng(seed)).as_matrix().reshape(-1, 3, 3)
