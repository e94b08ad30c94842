"""Elastic materials: 6x6 Voigt stiffness, constructors, rotation, anisotropy measures, loss.

Conventions
-----------
Voigt order 11, 22, 33, 23, 13, 12 with engineering shear strains, so that the elastic energy
density is ``0.5 * e @ C @ e`` with ``e = (e11, e22, e33, 2 e23, 2 e13, 2 e12)``. Stiffness in Pa,
density in kg/m^3. Damping follows paper 1: the constants are made complex, C(1 + i Q^-1).

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63. Its cubic parameters (Zener ratio A, ν = C12/(C11 + C12))
and its loss convention are used here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._summary import Summarised, number
from .crystals import crystal_record
from .errors import ContactresInputError
from .validation import nonnegative, positive

__all__ = [
    "AT_CUT_ANGLE",
    "Material",
    "at_cut_quartz",
    "require_material",
    "rotate_tensor",
    "rotation_to_surface",
    "tensor_to_voigt",
    "voigt_to_tensor",
]

# Voigt index of each tensor index pair (i, j).
_VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])
_PAIRS = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]

# Relative tolerance for symmetry checks of stiffness matrices (round-off of a rotation is ~1e-15).
_SYM_RTOL = 1e-9


def voigt_to_tensor(C: np.ndarray) -> np.ndarray:
    """Return the 3x3x3x3 stiffness tensor c_ijkl of a 6x6 Voigt matrix (Pa)."""
    C = np.asarray(C)
    return C[np.ix_(_VOIGT.ravel(), _VOIGT.ravel())].reshape(3, 3, 3, 3)


def tensor_to_voigt(c: np.ndarray) -> np.ndarray:
    """Return the 6x6 Voigt matrix of a 3x3x3x3 stiffness tensor (Pa)."""
    c = np.asarray(c)
    idx = np.array(_PAIRS)
    return c[idx[:, 0][:, None], idx[:, 1][:, None], idx[:, 0][None, :], idx[:, 1][None, :]]


def rotate_tensor(c: np.ndarray, R: np.ndarray) -> np.ndarray:
    """c'_ijkl = R_ia R_jb R_kc R_ld c_abcd: the 3x3x3x3 tensor ``c`` in the frame ``v' = R v``
    (any orthogonal ``R``, reflections included)."""
    return np.einsum("ia,jb,kc,ld,abcd->ijkl", R, R, R, R, c, optimize=True)


def _unit(v, name: str) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ContactresInputError(f"{name} must be three finite numbers, got {v.tolist()!r}")
    n = np.linalg.norm(v)
    if n == 0:
        raise ContactresInputError(f"{name} must not be the zero vector")
    return v / n


def rotation_to_surface(normal, inplane=None) -> np.ndarray:
    """Rotation matrix whose rows are the new axes (x', y', z') in crystal coordinates.

    Parameters
    ----------
    normal : sequence of 3 numbers
        Direction of the new z axis (the inward surface normal), e.g. Miller indices (h, k, l)
        of a cubic crystal. Need not be normalised.
    inplane : sequence of 3 numbers, optional
        Direction of the new x axis; its component along ``normal`` is removed. Default: the
        component of [100] perpendicular to ``normal``; [010] when ``normal`` is parallel to
        [100]. So (001) keeps x = [100], (011) has x = [100], (111) has x along [2 -1 -1].

    Returns
    -------
    ndarray, shape (3, 3)
        Proper orthogonal matrix ``R`` with ``v_new = R @ v_crystal``.
    """
    z = _unit(normal, "normal")
    if inplane is None:
        x = np.array([1.0, 0.0, 0.0])
        if abs(z @ x) > 1 - 1e-12:
            x = np.array([0.0, 1.0, 0.0])
    else:
        x = _unit(inplane, "inplane")
    x = x - (x @ z) * z
    nx = np.linalg.norm(x)
    if nx < 1e-9:
        raise ContactresInputError(
            f"inplane {list(inplane)!r} is parallel to normal {list(normal)!r}"
        )
    x = x / nx
    y = np.cross(z, x)
    return np.vstack([x, y, z])


def _check_stiffness(C) -> np.ndarray:
    C = np.array(C, dtype=complex if np.iscomplexobj(C) else float)
    if C.shape != (6, 6):
        raise ContactresInputError(f"stiffness C must be a 6x6 Voigt matrix, got shape {C.shape}")
    if not np.all(np.isfinite(C)):
        raise ContactresInputError("stiffness C must be finite (found NaN or inf)")
    scale = np.max(np.abs(C))
    if scale == 0:
        raise ContactresInputError("stiffness C must not be all zero")
    asym = np.max(np.abs(C - C.T))
    if asym > _SYM_RTOL * scale:
        raise ContactresInputError(
            f"stiffness C must be symmetric: max |C - C^T| = {asym:.3g} Pa "
            f"(relative {asym / scale:.2g} > {_SYM_RTOL:g})"
        )
    C = 0.5 * (C + C.T)
    eig = np.linalg.eigvalsh(C.real)
    if eig[0] <= 1e-12 * eig[-1]:
        raise ContactresInputError(
            "stiffness C must have a positive-definite real part: smallest eigenvalue "
            f"{eig[0]:.4g} Pa (largest {eig[-1]:.4g} Pa)"
        )
    if np.iscomplexobj(C):
        loss_min = np.linalg.eigvalsh(C.imag)[0]
        if loss_min < -1e-12 * eig[-1]:
            raise ContactresInputError(
                "stiffness C has an active loss part: Im C must be positive semi-definite (no "
                f"energy gain), smallest eigenvalue {loss_min:.4g} Pa"
            )
    C.setflags(write=False)
    return C


def _poisson(nu, name: str = "nu") -> float:
    v = float(nu)
    if not (-1.0 < v < 0.5):
        raise ContactresInputError(f"{name} (Poisson's ratio) must lie in (-1, 0.5), got {nu!r}")
    return v


# repr=False: the summary (Summarised, _facts) replaces a numpy repr of the 6x6 stiffness.
@dataclass(frozen=True, eq=False, repr=False)
class Material(Summarised):
    """A linear elastic solid: 6x6 Voigt stiffness ``C`` (Pa) and optional density (kg/m^3).

    Use the constructors (:meth:`isotropic`, :meth:`cubic`, :meth:`cubic_from_ratios`,
    :meth:`hexagonal`, :meth:`trigonal`, :meth:`from_voigt`, :meth:`crystal`) rather than the
    bare class. ``C`` is stored read-only; it may be complex (loss, see :meth:`with_loss`). ``C``
    refers to the material's current frame: the crystal frame after construction, the surface
    frame after :meth:`rotated`. ``frame`` (3x3) holds the axes of the current frame as rows,
    in crystal coordinates (the identity after construction).
    """

    C: np.ndarray
    density: float | None = None
    name: str | None = None
    frame: np.ndarray = field(default_factory=lambda: np.eye(3), repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "C", _check_stiffness(self.C))
        if self.density is not None:
            object.__setattr__(self, "density", positive("density", self.density, "kg/m^3"))
        frame = np.array(self.frame, dtype=float)
        frame.setflags(write=False)
        object.__setattr__(self, "frame", frame)

    # ----------------------------------------------------------------------------- constructors
    @classmethod
    def from_voigt(cls, C, density: float | None = None, name: str | None = None) -> Material:
        """Material from a 6x6 Voigt stiffness matrix ``C`` (Pa, real or complex)."""
        return cls(C=np.asarray(C), density=density, name=name)

    @classmethod
    def isotropic(
        cls, E: float, nu: float, density: float | None = None, name: str | None = None
    ) -> Material:
        """Isotropic solid of Young's modulus ``E`` (Pa) and Poisson's ratio ``nu`` in (-1, 0.5).

        Examples
        --------
        >>> from contactres import Material
        >>> glass = Material.isotropic(70e9, 0.22, density=2500.0)  # E in Pa, ρ in kg/m³
        >>> round(float(glass.C[3, 3]) / 1e9, 4), round(70 / (2 * (1 + 0.22)), 4)  # C44 = G, GPa
        (28.6885, 28.6885)
        """
        E = positive("E", E, "Pa")
        nu = _poisson(nu)
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        mu = E / (2 * (1 + nu))
        return cls.cubic(lam + 2 * mu, lam, mu, density=density, name=name)

    @classmethod
    def cubic(
        cls,
        c11: float,
        c12: float,
        c44: float,
        density: float | None = None,
        name: str | None = None,
    ) -> Material:
        """Cubic crystal in its cube-axis frame; ``c11, c12, c44`` in Pa.

        Stability (positive definiteness) requires c11 > ``|c12|``, c11 + 2 c12 > 0, c44 > 0.

        Examples
        --------
        >>> from contactres import Material
        >>> cu = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0, name="Cu")  # Pa, kg/m³
        >>> round(float(cu.zener_ratio), 4), round(2 * 75.4 / (168.4 - 121.4), 4)  # 2c44/(c11-c12)
        (3.2085, 3.2085)
        """
        for v, n in ((c11, "c11"), (c44, "c44")):
            positive(n, v, "Pa")
        if not np.isfinite(c12):
            raise ContactresInputError(f"c12 must be finite, got {c12!r}")
        if not (c11 > abs(c12) and c11 + 2 * c12 > 0):
            raise ContactresInputError(
                f"cubic constants c11={c11:.4g}, c12={c12:.4g} Pa are unstable: need "
                "c11 > |c12| and c11 + 2 c12 > 0"
            )
        C = np.zeros((6, 6))
        C[:3, :3] = c12
        C[[0, 1, 2], [0, 1, 2]] = c11
        C[[3, 4, 5], [3, 4, 5]] = c44
        return cls(C=C, density=density, name=name)

    @classmethod
    def cubic_from_ratios(
        cls, zener: float, poisson: float, c44: float = 1.0, density: float | None = None
    ) -> Material:
        """Cubic crystal from Zener ratio A = 2 C44/(C11 - C12) and ν = C12/(C11 + C12).

        Inverse (paper 1): C11 = 2 C44 (1 - ν)/(A (1 - 2ν)), C12 = 2 C44 ν/(A (1 - 2ν)).
        ``c44`` in Pa (default 1: dimensionless constants, as the paper's figures use).
        """
        A = positive("zener", zener, "dimensionless")
        nu = _poisson(poisson, "poisson")
        c44 = positive("c44", c44, "Pa")
        c11 = 2 * c44 * (1 - nu) / (A * (1 - 2 * nu))
        c12 = 2 * c44 * nu / (A * (1 - 2 * nu))
        return cls.cubic(c11, c12, c44, density=density)

    @classmethod
    def hexagonal(
        cls,
        c11: float,
        c12: float,
        c13: float,
        c33: float,
        c44: float,
        density: float | None = None,
        name: str | None = None,
    ) -> Material:
        """Hexagonal (transversely isotropic) crystal, c axis along z; constants in Pa.

        C66 = (C11 - C12)/2.
        """
        C = np.zeros((6, 6))
        C[0, 0] = C[1, 1] = c11
        C[0, 1] = C[1, 0] = c12
        C[0, 2] = C[2, 0] = C[1, 2] = C[2, 1] = c13
        C[2, 2] = c33
        C[3, 3] = C[4, 4] = c44
        C[5, 5] = 0.5 * (c11 - c12)
        return cls(C=C, density=density, name=name)

    @classmethod
    def trigonal(
        cls,
        c11: float,
        c12: float,
        c13: float,
        c14: float,
        c33: float,
        c44: float,
        density: float | None = None,
        name: str | None = None,
    ) -> Material:
        """Trigonal crystal of the classes 32, 3m and -3m (alpha-quartz, sapphire); constants in Pa.

        Frame and convention: z along the three-fold (optic, c) axis and x along a two-fold axis
        (classes 32, -3m) or normal to a mirror plane (3m), y = z × x; Voigt order 11, 22, 33, 23,
        13, 12. Six independent constants, and

            C22 = C11,  C23 = C13,  C55 = C44,  C66 = (C11 - C12)/2,
            C24 = -C14,  C56 = C14,

        all other C_ij = 0 (J. F. Nye, *Physical Properties of Crystals*, Oxford 1957, Appendix B;
        IEEE Std 176-1987, *IEEE Standard on Piezoelectricity*; table not re-checked here). The
        sign of C14 depends on which way +x points along the two-fold axis (and, for quartz, on
        the handedness and the edition of the standard): pass the constants with the sign their
        source gives in its own frame, and give directions (:meth:`rotated`) in that frame.

        Stability (positive definiteness) requires C11 > ``|C12|``, C44 > 0,
        C13² < C33 (C11 + C12)/2 and C14² < C44 (C11 - C12)/2: C splits into the block
        [[C11 + C12, √2 C13], [√2 C13, C33]] (in-plane dilatation, e33) and two blocks each
        congruent to [[C66, C14], [C14, C44]] (an in-plane shear with a transverse one).

        Raises
        ------
        ValueError
            For non-finite or unstable constants; the message names the condition that fails.
        """
        values = {"c11": c11, "c12": c12, "c13": c13, "c14": c14, "c33": c33, "c44": c44}
        for n, v in values.items():
            if not np.isfinite(v):
                raise ContactresInputError(f"trigonal constant {n} must be finite, got {v!r}")
        failed = [
            rule
            for ok, rule in (
                (c11 > abs(c12), "C11 > |C12|"),
                (c44 > 0, "C44 > 0"),
                (c33 > 0 and 2 * c13**2 < c33 * (c11 + c12), "C13² < C33 (C11 + C12)/2"),
                (2 * c14**2 < c44 * (c11 - c12), "C14² < C44 (C11 - C12)/2"),
            )
            if not ok
        ]
        if failed:
            got = ", ".join(f"{n}={v:.4g}" for n, v in values.items())
            raise ContactresInputError(
                f"trigonal constants {got} Pa are unstable (C not positive definite): need "
                + " and ".join(failed)
            )
        C = np.array(cls.hexagonal(c11, c12, c13, c33, c44).C)  # the hexagonal part, + C14
        C[0, 3] = C[3, 0] = c14
        C[1, 3] = C[3, 1] = -c14
        C[4, 5] = C[5, 4] = c14
        return cls(C=C, density=density, name=name)

    @classmethod
    def crystal(cls, name: str) -> Material:
        """A solid from the built-in tables, in its crystal frame (case-insensitive ``name``).

        Cubic crystals in their cube-axis frame; trigonal ones (``"quartz"``, ``"sapphire"``) in
        the frame of :meth:`trigonal`; isotropic ones (``"fused-silica"``,
        ``"soda-lime-glass"``, ``"Si3N4"``) need none. ``contactres crystals`` and
        :func:`contactres.crystal_names` list them with their sources; unknown names raise
        ValueError. For the AT-cut quartz plate of a QCM see :func:`at_cut_quartz`.

        Examples
        --------
        >>> from contactres import Material
        >>> si = Material.crystal("Si")
        >>> print(f"c11 = {si.C[0, 0] / 1e9:.1f} GPa, ρ = {si.density:.0f} kg/m^3")
        c11 = 165.7 GPa, ρ = 2329 kg/m^3
        """
        r = crystal_record(name)
        if r.symmetry == "isotropic":
            assert r.E is not None and r.nu is not None  # the table fills both (crystals.py)
            return cls.isotropic(r.E, r.nu, density=r.density, name=r.name)
        if r.symmetry == "trigonal":
            assert r.c13 is not None and r.c14 is not None and r.c33 is not None  # as above
            return cls.trigonal(
                r.c11, r.c12, r.c13, r.c14, r.c33, r.c44, density=r.density, name=r.name
            )
        return cls.cubic(r.c11, r.c12, r.c44, density=r.density, name=r.name)

    # ----------------------------------------------------------------------------- operations
    def rotated(self, normal=(0, 0, 1), inplane=None) -> Material:
        """The same solid in the frame whose z axis is along ``normal``, x along ``inplane``.

        ``normal`` and ``inplane`` are given in the material's current frame (for a freshly
        constructed crystal: crystal axes, so ``normal=(1, 1, 1)`` is the (111) surface of a
        cubic crystal). See :func:`rotation_to_surface` for the default in-plane axis.
        """
        R = rotation_to_surface(normal, inplane)
        return Material(
            C=tensor_to_voigt(rotate_tensor(voigt_to_tensor(self.C), R)),
            density=self.density,
            name=self.name,
            frame=R @ self.frame,
        )

    def with_loss(self, q_inv: float) -> Material:
        """The solid with complex constants C (1 + i Q^-1) (paper 1; Q^-1 = 0.02 there)."""
        q = nonnegative("q_inv (loss factor Q^-1)", q_inv)
        return Material(
            C=np.asarray(self.C) * (1 + 1j * q),
            density=self.density,
            name=self.name,
            frame=self.frame,
        )

    def at(self, frequency: float) -> Material:
        """The solid at frequency ``frequency`` (Hz): ``self``, since an elastic or constant-loss
        material does not depend on frequency. It lets callers treat a :class:`Material` and a
        :class:`contactres.viscoelastic.ViscoelasticMaterial` alike (``m.at(f)``)."""
        return self

    # ----------------------------------------------------------------------------- properties
    @property
    def is_lossy(self) -> bool:
        """True when C has a non-zero imaginary part."""
        return bool(np.iscomplexobj(self.C) and np.any(self.C.imag != 0))

    def _cubic_constants(self) -> tuple[float, float, float]:
        C = np.asarray(self.C).real
        scale = np.max(np.abs(C))
        tol = 1e-9 * scale
        ok = (
            np.ptp(np.diag(C)[:3]) <= tol
            and np.ptp([C[0, 1], C[0, 2], C[1, 2]]) <= tol
            and np.ptp(np.diag(C)[3:]) <= tol
            and np.max(np.abs(C[:3, 3:])) <= tol
            and np.max(np.abs(C[3:, 3:] - np.diag(np.diag(C)[3:]))) <= tol
        )
        if not ok:
            raise ContactresInputError(
                "material does not have cubic symmetry in its current frame (zener_ratio and "
                "cubic_poisson are defined for a cubic crystal in its cube-axis frame)"
            )
        return float(C[0, 0]), float(C[0, 1]), float(C[3, 3])

    @property
    def zener_ratio(self) -> float:
        """Zener anisotropy ratio A = 2 C44/(C11 - C12) (1 for isotropic); cubic frame only."""
        c11, c12, c44 = self._cubic_constants()
        return 2 * c44 / (c11 - c12)

    @property
    def cubic_poisson(self) -> float:
        """ν = C12/(C11 + C12) of a cubic crystal (paper 1's second parameter)."""
        c11, c12, _ = self._cubic_constants()
        return c12 / (c11 + c12)

    @property
    def isotropic_constants(self) -> tuple[float, float]:
        """(E, ν) of an isotropic material (Pa, dimensionless); error if not isotropic."""
        c11, c12, c44 = self._cubic_constants()
        if abs(c11 - c12 - 2 * c44) > 1e-9 * c11:
            raise ContactresInputError(
                f"material is not isotropic (Zener ratio {2 * c44 / (c11 - c12):.6g} != 1)"
            )
        mu, lam = c44, c12
        return mu * (3 * lam + 2 * mu) / (lam + mu), lam / (2 * (lam + mu))

    def _facts(self) -> list[tuple[str, str]]:
        """Name, symmetry of the current frame, the independent constants (GPa, real parts),
        the loss Im C11/Re C11 if any, the density and whether the frame is rotated."""
        C = np.asarray(self.C)
        facts = [("", repr(self.name) if self.name else "unnamed")]
        try:
            c11, c12, c44 = self._cubic_constants()
            kind = "isotropic" if abs(c11 - c12 - 2 * c44) <= 1e-9 * c11 else "cubic"
            shown = [(1, 1), (1, 2), (4, 4)]
        except ContactresInputError:
            kind = "anisotropic"
            shown = [(1, 1), (1, 2), (1, 3), (3, 3), (4, 4), (6, 6)]
        facts.append(("", kind))
        facts += [(f"C{i}{j}", number(C[i - 1, j - 1].real, "GPa", 1e9)) for i, j in shown]
        if kind == "isotropic":
            E, nu = self.isotropic_constants
            facts += [("E", number(E, "GPa", 1e9)), ("ν", number(nu))]
        if self.is_lossy:
            facts.append(("loss Im/Re C11", number(C[0, 0].imag / C[0, 0].real)))
        if self.density is not None:
            facts.append(("ρ", number(self.density, "kg/m³")))
        if not np.allclose(self.frame, np.eye(3)):
            facts.append(("frame", "rotated (C in the surface frame)"))
        return facts

    def energy_density(self, strain) -> np.ndarray:
        """Elastic energy density 0.5 e·C·e (J/m^3) of Voigt strains ``e`` (..., 6)."""
        e = np.asarray(strain)
        return 0.5 * np.einsum("...i,ij,...j->...", e, np.asarray(self.C).real, e)


# The AT cut: a rotated Y cut, (YXl) θ in the notation of IEEE Std 176, with θ = 35°15'.
AT_CUT_ANGLE = 35.25


def at_cut_quartz(theta: float = AT_CUT_ANGLE) -> Material:
    """The AT-cut quartz plate of a QCM in its surface frame (built-in ``"quartz"`` constants).

    A rotated Y cut: the plate normal is the crystal Y axis turned by ``theta`` (degrees) about
    the crystal X axis (a two-fold axis), Y' = (0, cos θ, sin θ) in crystal axes. The surface
    frame is the one of :meth:`Material.rotated` (``normal=Y'``, ``inplane=X``):

    - x' = X, the direction of the thickness-shear motion;
    - z' = Y', the plate normal (into the plate from the face the sphere touches);
    - y' = z' × x' = (0, sin θ, -cos θ), i.e. -Z' of the rotated crystal frame.

    So ``at_cut_quartz().C[4, 4]`` (Voigt 55: shear along x' with the gradient along z') is the
    thickness-shear stiffness c66' of the quartz literature, which in the rotated crystal frame
    (X, Y', Z') reads c66' = C66 cos²θ + C44 sin²θ + 2 C14 sin θ cos θ: 28.98 GPa with the
    table's constants (C14 < 0 as McSkimin et al. 1965 give it: the AT cut is then at
    θ = +35.25°, as in IEEE Std 176-1949; the later editions flip the sign of C14 and quote the
    same cut at θ = -35.25°; not re-checked). The QCM literature's μ_q = 2.947e10 Pa and
    Z_q = 8.8e6 kg m^-2 s^-1 (D. Johannsmann et al., *Sensors* 21, 3490 (2021)) are
    piezoelectrically stiffened: tests/test_builtin_materials.py compares them.

    Purely elastic constants at 25 °C: neither the piezoelectric stiffening (c66' grows by
    e26²/(ε_q ε0), 0.23 GPa or 0.8 % with e26 = 9.65e-2 C/m² and ε_q = 4.54 of the same
    review) nor the temperature dependence is modelled (so neither is the zero first-order
    temperature coefficient of the frequency for which the AT cut is chosen).

    Parameters
    ----------
    theta : float
        Cut angle in degrees (default :data:`AT_CUT_ANGLE`, 35.25°).

    Examples
    --------
    The thickness-shear constant C55 and the shear-wave impedance √(ρ C55) (cf. ``QCM.zq``):

    >>> q = at_cut_quartz()  # z along the plate normal; C55 = 28.98 GPa, Z = 8.76e6 kg/m²s
    >>> print(f"{q.C[4, 4] / 1e9:.2f} GPa")
    28.98 GPa
    >>> bool(abs((q.density * q.C[4, 4]) ** 0.5 / 8.8e6 - 1) < 0.01)  # paper 2: Z_q = 8.8e6
    True
    """
    t = np.radians(float(theta))
    if not np.isfinite(t):
        raise ContactresInputError(f"theta (cut angle, degrees) must be finite, got {theta!r}")
    quartz = Material.crystal("quartz")
    return quartz.rotated(normal=(0.0, np.cos(t), np.sin(t)), inplane=(1.0, 0.0, 0.0))


def require_material(m, *, lossless: bool = False) -> Material:
    """``m`` itself after checking that it is a :class:`Material` (and, with ``lossless``, that
    its constants are real); a ValueError naming what was passed otherwise."""
    if not isinstance(m, Material):
        hint = ""
        if isinstance(m, Summarised) and callable(getattr(m, "at", None)):
            # A LayeredMaterial or a viscoelastic solid (issue 26): the functions of k a alone
            # (dcsf, tangential_dcsf, ...) have no meaning for it; say which ones take it.
            # Summarised first: pandas objects have an ``at`` accessor too.
            hint = (
                " (a layered or frequency-dependent solid: its DCSF and dynamic stiffness depend"
                " on the frequency and the radius, not on k a alone; contactres.dynamic."
                "layered_dcsf and contactres.flat_punch_stiffness take it; the elastic solid"
                " of a viscoelastic one at a frequency: material.storage(f_Hz))"
            )
        raise ContactresInputError(f"m must be a contactres.Material, got {type(m).__name__}{hint}")
    if lossless and m.is_lossy:
        raise ContactresInputError(
            "pass the undamped material (real constants) and set the damping with loss= "
            "(constants C (1 + i loss), paper 1); the material given is already lossy"
        )
    return m
