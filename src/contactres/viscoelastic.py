"""Viscoelastic materials: complex, frequency-dependent moduli for the correspondence principle.

A linear viscoelastic solid driven harmonically, with every field ∝ e^{iωt} (ω = 2πf, f in Hz),
obeys the equations of an elastic solid whose constants are complex and depend on f: the
correspondence principle. So any elastic result of contactres (a kernel, a contact stiffness)
holds for a viscoelastic solid at one frequency if it is computed with the constants of
``material.at(f)``. A static result (Hertz, a static kernel) needs the relaxed constants
``material.at(0)``, which a law may not have (a power law relaxes to zero).

Conventions
-----------
- Time factor e^{iωt} throughout, as :meth:`contactres.Material.with_loss`: a modulus reads
  M*(f) = M'(f) + i M''(f) with the loss M'' >= 0 (a passive solid), loss tangent
  tan δ = M''/M'. With the opposite convention (e^{-iωt}, some physics texts) the loss part
  changes sign: conjugate such data before passing them.
- Frequencies are in Hz (cycles per second) in and out; relaxation times τ are in s, and the
  laws use ω = 2πf internally where a formula has ω τ.
- Moduli in Pa; a "law" gives one channel (the shear modulus G, the bulk modulus K, a Young's
  modulus, or the scale of a whole anisotropic stiffness, see
  :meth:`ViscoelasticMaterial.proportional`).

Laws (each a frozen dataclass, vectorised over frequency, checked passive at construction):
:class:`ConstantLoss` (today's C (1 + i Q⁻¹), frequency independent and, strictly, not
causal), :class:`Prony` (generalized Maxwell), :class:`PowerLaw` (springpot) and
:class:`ModulusTable` (measured storage and loss, interpolated in log frequency).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._summary import Summarised, values
from .errors import ContactresInputError
from .materials import (
    Material,
    rotate_tensor,
    rotation_to_surface,
    tensor_to_voigt,
    voigt_to_tensor,
)
from .validation import nonnegative, positive

__all__ = [
    "PMMA_DENSITY",
    "PMMA_LONGITUDINAL_SPEED",
    "PMMA_SHEAR_SPEED",
    "PMMA_STATIC_E",
    "PMMA_STATIC_FREQUENCY",
    "PMMA_STATIC_POISSON",
    "PMMA_ULTRASONIC_FREQUENCY",
    "STATIC_FREQUENCY_HZ",
    "ConstantLoss",
    "Law",
    "ModulusTable",
    "PowerLaw",
    "Prony",
    "ViscoelasticMaterial",
    "material_at",
    "pmma",
    "static_solid",
]


def _frequency(frequency) -> np.ndarray:
    """``frequency`` (Hz) as a float ndarray (0-d for a scalar), finite and >= 0."""
    return np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a


# --------------------------------------------------------------------------------- the laws
@dataclass(frozen=True)
class ConstantLoss:
    """A frequency-independent complex modulus M* = M (1 + i tan δ) (Pa).

    The loss model of paper 1 and of :meth:`contactres.Material.with_loss` (tan δ = Q⁻¹). Its
    static value is the same complex number (the model is not causal: Kramers–Kronig forbids a
    loss that stays finite as f -> 0 with a constant storage modulus; it is the usual
    engineering idealisation over a band of frequencies).

    Parameters
    ----------
    modulus : float
        Storage modulus M (Pa), > 0.
    loss_tangent : float
        tan δ = M''/M' >= 0.
    """

    modulus: float
    loss_tangent: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "modulus", positive("modulus", self.modulus, "Pa"))
        object.__setattr__(
            self, "loss_tangent", nonnegative("loss_tangent (tan δ)", self.loss_tangent)
        )

    reference_frequency = 0.0  # any frequency: the law does not depend on it

    def __call__(self, frequency) -> np.ndarray:
        """M*(f) (Pa, complex), the same at every frequency f >= 0 (Hz)."""
        f = _frequency(frequency)
        return np.full(f.shape, self.modulus * (1 + 1j * self.loss_tangent), dtype=complex)


@dataclass(frozen=True)
class Prony:
    """Generalized Maxwell solid (Prony series): a spring M_∞ in parallel with Maxwell arms.

    Relaxation modulus G(t) = M_∞ + Σ M_i e^{-t/τ_i}; its complex modulus (e^{iωt}, ω = 2πf) is

        M*(ω) = M_∞ + Σ_i M_i iωτ_i / (1 + iωτ_i),

    storage M_∞ + Σ M_i ω²τ_i²/(1 + ω²τ_i²) and loss Σ M_i ωτ_i/(1 + ω²τ_i²) >= 0 (e.g.
    N. W. Tschoegl, *The Phenomenological Theory of Linear Viscoelastic Behavior*, Springer
    1989). Static (relaxed) limit M_∞, glassy (instantaneous) limit M_∞ + Σ M_i.

    Parameters
    ----------
    equilibrium : float
        M_∞ (Pa), >= 0. Zero is a fluid: it has no static limit (``at(0)`` is refused).
    terms : sequence of (modulus_i, tau_i)
        M_i >= 0 (Pa) and τ_i > 0 (s) of each Maxwell arm.

    Notes
    -----
    pyvisco (NREL, the DMA master-curve fitting tool) writes the same series normalised by the
    instantaneous modulus E_0: E(t) = E_0 [1 - Σ α_i + Σ α_i e^{-t/τ_i}] (its
    ``prony.E_relax_norm``; storage and loss in ``prony.E_freq_norm``, with ω in rad/s), with
    E_0 in ``prony['E_0']`` and the columns ``tau_i``, ``alpha_i`` of ``prony['df_terms']``.
    So M_i = E_0 α_i and M_∞ = E_0 (1 - Σ α_i): :meth:`from_pyvisco`. Its frequencies in Hz
    (column ``f``) and its e^{iωt} sign of the loss are the ones used here. Whether the fitted
    modulus is Young's (E) or shear (G) is pyvisco's ``modul`` setting: pass an E law as
    ``proportional`` or convert it before ``isotropic(shear=...)``.
    """

    equilibrium: float
    terms: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        m_inf = nonnegative("Prony equilibrium modulus M_∞", self.equilibrium, "Pa")
        try:
            arr = np.asarray(self.terms, dtype=float).reshape(-1, 2) if len(self.terms) else None
        except (TypeError, ValueError):
            raise ContactresInputError(
                f"Prony terms must be pairs (modulus_i in Pa, tau_i in s), got {self.terms!r}"
            ) from None
        pairs: tuple[tuple[float, float], ...] = ()
        if arr is not None:
            nonnegative("Prony modulus M_i", arr[:, 0], "Pa")
            positive("Prony relaxation time tau_i", arr[:, 1], "s")
            pairs = tuple((float(m), float(t)) for m, t in arr)
        if m_inf + sum(m for m, _ in pairs) <= 0:
            raise ContactresInputError("Prony series is all zero: M_∞ + Σ M_i must be > 0 Pa")
        object.__setattr__(self, "equilibrium", m_inf)
        object.__setattr__(self, "terms", pairs)

    @classmethod
    def from_pyvisco(cls, instantaneous: float, alpha, tau) -> Prony:
        """The series of a pyvisco fit: E_0 = ``instantaneous`` (Pa) and the normalised
        moduli ``alpha`` (α_i >= 0, Σ α_i <= 1) and times ``tau`` (s); M_i = E_0 α_i and
        M_∞ = E_0 (1 - Σ α_i) (exact, see the class notes)."""
        e0 = positive("instantaneous modulus E_0", instantaneous, "Pa")
        a = np.atleast_1d(nonnegative("pyvisco alpha_i", alpha))
        t = np.atleast_1d(np.asarray(tau, dtype=float))
        if a.shape != t.shape or a.ndim != 1:
            raise ContactresInputError(
                f"alpha and tau must be two 1-D arrays of one length, got {a.shape} and {t.shape}"
            )
        total = float(np.sum(a))
        if total > 1 + 1e-12:
            raise ContactresInputError(
                f"pyvisco alpha_i must sum to <= 1 (normalised moduli), got {total:.6g}"
            )
        return cls(max(e0 * (1 - total), 0.0), tuple(zip(e0 * a, t, strict=True)))

    @property
    def instantaneous(self) -> float:
        """The glassy (f -> ∞) modulus M_∞ + Σ M_i (Pa)."""
        return self.equilibrium + sum(m for m, _ in self.terms)

    reference_frequency = 0.0  # the relaxed modulus M_∞

    def __call__(self, frequency) -> np.ndarray:
        """M*(f) (Pa, complex) at frequencies f >= 0 (Hz); M*(0) = M_∞."""
        f = _frequency(frequency)
        out = np.full(f.shape, self.equilibrium, dtype=complex)
        for m, tau in self.terms:
            x = 1j * (2 * np.pi * f * tau)
            out = out + m * x / (1 + x)
        return out


@dataclass(frozen=True)
class PowerLaw:
    """Springpot (fractional element): M*(f) = M_ref (f/f_ref)^{2φ/π} e^{iφ} (Pa).

    A constant phase angle φ (loss tangent tan φ at every frequency) with the modulus growing
    as f^{2φ/π}: the pair that the Kramers–Kronig relations allow for a power law (the only
    causal solid with a frequency-independent phase). The QCM power law of RheoQCM is the same
    law: its ``grho(n, props)`` returns ``|G*| ρ`` at harmonic n as grho3 · (n/3)^{φ/90} with φ in
    degrees (shullgroup/rheoQCM, QCMFuncs/QCM_functions.py), i.e. modulus_ref = grho3/ρ,
    frequency_ref = 3 f_1 and phase = radians(φ).

    Parameters
    ----------
    modulus_ref : float
        ``|M*|`` at ``frequency_ref`` (Pa), > 0.
    frequency_ref : float
        Reference frequency (Hz), > 0.
    phase : float
        φ in radians, 0 <= φ < π/2 (φ = 0 is elastic, φ -> π/2 a Newtonian liquid).

    Notes
    -----
    No static limit: ``|M*|`` -> 0 as f -> 0 for φ > 0, and the law is meant for a band of
    frequencies only; ``__call__`` refuses f = 0 (for φ = 0 too, to keep one rule).
    """

    modulus_ref: float
    frequency_ref: float
    phase: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "modulus_ref", positive("modulus_ref", self.modulus_ref, "Pa"))
        object.__setattr__(
            self, "frequency_ref", positive("frequency_ref", self.frequency_ref, "Hz")
        )
        phi = nonnegative("power-law phase φ", self.phase, "rad")
        if not phi < np.pi / 2:
            raise ContactresInputError(
                f"power-law phase φ must lie in [0, π/2) rad (a passive solid), got {phi!r}"
            )
        object.__setattr__(self, "phase", phi)

    @property
    def reference_frequency(self) -> float:
        return self.frequency_ref

    @property
    def exponent(self) -> float:
        """2φ/π: the slope d ln ``|M*|`` / d ln f."""
        return 2 * self.phase / np.pi

    def __call__(self, frequency) -> np.ndarray:
        """M*(f) (Pa, complex) at frequencies f > 0 (Hz)."""
        f = _frequency(frequency)
        if np.any(f == 0):
            raise ContactresInputError(
                "a power law (springpot) has no static limit (|M*| -> 0 as f -> 0): evaluate it "
                "at a frequency > 0 Hz"
            )
        mag = self.modulus_ref * (f / self.frequency_ref) ** self.exponent
        return mag * np.exp(1j * self.phase)


# repr=False: the summary (Summarised, _facts) replaces the numpy repr of the three columns.
@dataclass(frozen=True, eq=False, repr=False)
class ModulusTable(Summarised):
    """A measured modulus: storage M'(f) and loss M''(f) at frequencies f, interpolated.

    Between two nodes the storage and the loss are each interpolated linearly in
    (log f, log M), i.e. as a power law of f through the two nodes (DMA master curves are
    close to straight lines on log-log axes); a segment where the loss is zero at one end is
    interpolated linearly in (log f, M'') instead. Both rules keep each quantity between its
    two node values, so positive storage and non-negative loss at the nodes (checked) stay so
    everywhere — passivity holds between nodes — and each is monotone between two nodes. The
    nodes are reproduced exactly. Outside [f_min, f_max] the table is refused (no
    extrapolation), so f = 0 is refused too.

    Parameters
    ----------
    frequency : array_like
        Strictly increasing frequencies (Hz), > 0, at least two.
    storage : array_like
        M' (Pa), > 0, one per frequency.
    loss : array_like
        M'' (Pa), >= 0 (e^{iωt} convention), one per frequency.
    """

    frequency: np.ndarray
    storage: np.ndarray
    loss: np.ndarray

    def __post_init__(self) -> None:
        f = np.atleast_1d(positive("table frequency", self.frequency, "Hz"))
        s = np.atleast_1d(positive("table storage modulus", self.storage, "Pa"))
        q = np.atleast_1d(nonnegative("table loss modulus (passive: >= 0)", self.loss, "Pa"))
        if f.ndim != 1 or f.shape != s.shape or f.shape != q.shape or f.size < 2:
            raise ContactresInputError(
                "a modulus table needs 1-D frequency, storage and loss of one length >= 2, got "
                f"shapes {f.shape}, {s.shape}, {q.shape}"
            )
        if np.any(np.diff(f) <= 0):
            raise ContactresInputError("table frequencies must be strictly increasing")
        for name, v in (("frequency", f), ("storage", s), ("loss", q)):
            object.__setattr__(self, name, _read_only(v))

    def _facts(self) -> list[tuple[str, str]]:
        """The nodes: their number and the ranges of f (Hz), M' and M'' (GPa)."""
        return [
            ("nodes", str(self.frequency.size)),
            ("f", values(self.frequency, "Hz")),
            ("M'", values(self.storage, "GPa", 1e9)),
            ("M''", values(self.loss, "GPa", 1e9)),
        ]

    @property
    def reference_frequency(self) -> float:
        return float(self.frequency[0])

    @staticmethod
    def _interp(x: np.ndarray, xp: np.ndarray, yp: np.ndarray) -> np.ndarray:
        lin = np.interp(x, xp, yp)
        with np.errstate(divide="ignore"):
            logy = np.log(yp)
        pos = yp > 0
        seg = np.clip(np.searchsorted(xp, x, side="right") - 1, 0, xp.size - 2)
        use_log = pos[seg] & pos[seg + 1]
        loglin = np.exp(np.interp(x, xp, np.where(pos, logy, 0.0)))
        return np.where(use_log, loglin, lin)

    def __call__(self, frequency) -> np.ndarray:
        """M*(f) = M'(f) + i M''(f) (Pa, complex) for f (Hz) within the table's range."""
        f = _frequency(frequency)
        lo, hi = float(self.frequency[0]), float(self.frequency[-1])
        outside = (f < lo) | (f > hi)
        if np.any(outside):
            bad = float(f[outside].flat[0]) if f.ndim else float(f)
            raise ContactresInputError(
                f"frequency {bad:.6g} Hz is outside the modulus table's range {lo:.6g} to "
                f"{hi:.6g} Hz (no extrapolation)"
            )
        x, xp = np.log(np.where(f > 0, f, lo)), np.log(self.frequency)
        storage = self._interp(x, xp, self.storage)
        loss = self._interp(x, xp, self.loss)
        # The nodes themselves, exactly (exp(log y) may differ from y in the last bit).
        idx = np.clip(np.searchsorted(self.frequency, f), 0, self.frequency.size - 1)
        at_node = self.frequency[idx] == f
        storage = np.where(at_node, self.storage[idx], storage)
        loss = np.where(at_node, self.loss[idx], loss)
        return storage + 1j * loss


#: A law of the complex modulus against frequency: any of the four classes above.
Law = ConstantLoss | Prony | PowerLaw | ModulusTable
_LAWS = (ConstantLoss, Prony, PowerLaw, ModulusTable)


def _law(value, name: str):
    """A law as given, or an elastic modulus (Pa) as a lossless :class:`ConstantLoss`."""
    if isinstance(value, _LAWS):
        return value
    if isinstance(value, (int, float, np.floating, np.integer)):
        return ConstantLoss(float(value), 0.0)
    raise ContactresInputError(
        f"{name} must be a modulus law (ConstantLoss, Prony, PowerLaw, ModulusTable) or a "
        f"modulus in Pa, got {type(value).__name__}"
    )


# Voigt bases of an isotropic stiffness: C = K · _BULK + G · _SHEAR (C11 = K + 4G/3,
# C12 = K - 2G/3, C44 = G).
_BULK = _read_only(np.block([[np.ones((3, 3)), np.zeros((3, 3))], [np.zeros((3, 6))]]))
_SHEAR = _read_only(
    np.block(
        [
            [np.full((3, 3), -2 / 3) + 2 * np.eye(3), np.zeros((3, 3))],
            [np.zeros((3, 3)), np.eye(3)],
        ]
    )
)


# ----------------------------------------------------------------------------- the material
# repr=False: the summary (Summarised, _facts) replaces the numpy repr of the 6x6 matrices.
@dataclass(frozen=True, eq=False, repr=False)
class ViscoelasticMaterial(Summarised):
    """A linear viscoelastic solid: C*(f) = Σ_k M_k*(f) B_k, with modulus laws M_k* and
    constant 6x6 Voigt matrices B_k (the structure of the stiffness).

    Build it with :meth:`isotropic` or :meth:`proportional`; evaluate it with :meth:`at`, which
    returns the elastic :class:`contactres.Material` with the complex constants at one
    frequency (the correspondence principle). A result computed from ``at(f)`` belongs to
    that frequency only: a dynamic contact stiffness of a viscoelastic solid is a function of
    f, not of the dimensionless k a alone (the moduli change with f at fixed k a).

    ``frame`` holds the axes of the current frame as rows, as :attr:`Material.frame`.

    Examples
    --------
    A Maxwell arm on a spring: the loss peaks where 2πfτ = 1, at half the arm's modulus.

    >>> import numpy as np
    >>> from contactres import Prony, ViscoelasticMaterial
    >>> law = Prony(1e9, [(2e9, 1e-6)])  # M_∞ and (M_1, τ_1), Pa and s
    >>> m = ViscoelasticMaterial.isotropic(law, poisson=0.3, density=1200.0)
    >>> G = m.at(1 / (2 * np.pi * 1e-6)).C[3, 3]  # C44 = G* at ωτ = 1
    >>> print(f"{G.real / 1e9:.2f} + {G.imag / 1e9:.2f}i GPa")
    2.00 + 1.00i GPa
    """

    terms: tuple[tuple[Law, np.ndarray], ...]
    density: float | None = None
    name: str | None = None
    frame: np.ndarray = field(default_factory=lambda: np.eye(3), repr=False)

    def __post_init__(self) -> None:
        if not self.terms:
            raise ContactresInputError("a viscoelastic material needs at least one modulus law")
        terms = tuple(
            (_law(law, "law"), _read_only(np.asarray(b, dtype=float))) for law, b in self.terms
        )
        object.__setattr__(self, "terms", terms)
        if self.density is not None:
            object.__setattr__(self, "density", positive("density", self.density, "kg/m^3"))
        object.__setattr__(self, "frame", _read_only(np.asarray(self.frame, dtype=float)))

    def _facts(self) -> list[tuple[str, str]]:
        """Name, the modulus laws (by kind), the density and whether the frame is rotated."""
        facts = [("", repr(self.name) if self.name else "unnamed")]
        facts.append(("laws", ", ".join(type(law).__name__ for law, _ in self.terms)))
        if self.density is not None:
            facts.append(("ρ", f"{self.density:.4g} kg/m³"))
        if not np.allclose(self.frame, np.eye(3)):
            facts.append(("frame", "rotated (the matrices in the surface frame)"))
        return facts

    # ----------------------------------------------------------------------- constructors
    @classmethod
    def isotropic(
        cls,
        shear,
        *,
        poisson: float | None = None,
        bulk=None,
        density: float | None = None,
        name: str | None = None,
    ) -> ViscoelasticMaterial:
        """Isotropic solid of shear modulus law G*(f) and either a constant Poisson ratio or a
        bulk modulus K (a law, or an elastic modulus in Pa).

        With ``poisson`` = ν every modulus scales with G*: K* = G* 2(1 + ν)/(3(1 - 2ν)) and
        E* = 2(1 + ν) G*, so the loss tangent is the same in every channel. With ``bulk``,
        C11 = K* + 4G*/3, C12 = K* - 2G*/3, C44 = G*: the usual model of a polymer, whose bulk
        modulus relaxes far less than its shear modulus (ν then depends on f).
        """
        g = _law(shear, "shear")
        if (poisson is None) == (bulk is None):
            raise ContactresInputError("give exactly one of poisson= (constant ν) and bulk=")
        if poisson is not None:
            nu = float(poisson)
            if not (np.isfinite(nu) and -1.0 < nu < 0.5):
                raise ContactresInputError(
                    f"poisson (Poisson's ratio) must lie in (-1, 0.5), got {poisson!r}"
                )
            basis = _SHEAR + 2 * (1 + nu) / (3 * (1 - 2 * nu)) * _BULK
            return cls(((g, basis),), density=density, name=name)
        return cls(((_law(bulk, "bulk"), _BULK), (g, _SHEAR)), density=density, name=name)

    @classmethod
    def proportional(
        cls, material: Material, law, reference_frequency: float | None = None
    ) -> ViscoelasticMaterial:
        """Any anisotropic solid whose constants all follow one law:
        C*(f) = C · M*(f) / M'(f_ref).

        ``material.C`` (real) are thus the storage constants at the reference frequency f_ref:
        by default the law's own (``reference_frequency`` attribute: 0 Hz, the relaxed
        modulus, for :class:`ConstantLoss` and :class:`Prony`; ``frequency_ref`` for
        :class:`PowerLaw`; the first node of a :class:`ModulusTable`). With
        ``ConstantLoss(m, q)`` this is ``material.with_loss(q)`` at every frequency.
        Density, name and frame are the material's.
        """
        if not isinstance(material, Material):
            raise ContactresInputError(
                f"material must be a contactres.Material, got {type(material).__name__}"
            )
        if material.is_lossy:
            raise ContactresInputError(
                "pass the elastic material (real constants): the law gives the loss"
            )
        m = _law(law, "law")
        f_ref = m.reference_frequency if reference_frequency is None else reference_frequency
        ref = float(np.real(m(f_ref)))
        if not ref > 0:
            raise ContactresInputError(
                f"the law's storage modulus at the reference frequency {f_ref!r} Hz is "
                f"{ref!r} Pa: give a reference_frequency where it is > 0"
            )
        return cls(
            ((m, np.asarray(material.C).real / ref),),
            density=material.density,
            name=material.name,
            frame=material.frame,
        )

    @classmethod
    def pmma(cls) -> ViscoelasticMaterial:
        """Glassy PMMA at about 20 °C (see :func:`pmma`)."""
        return pmma()

    # ----------------------------------------------------------------------- evaluation
    def stiffness(self, frequency) -> np.ndarray:
        """C*(f) (Pa, complex): shape f.shape + (6, 6), in the current frame."""
        f = _frequency(frequency)
        out = np.zeros((*f.shape, 6, 6), dtype=complex)
        for law, basis in self.terms:
            out = out + np.asarray(law(f))[..., None, None] * basis
        return out

    def at(self, frequency: float) -> Material:
        """The elastic :class:`contactres.Material` with the complex constants at one
        frequency f (Hz); f = 0 is the relaxed (static) solid, refused by the laws that have
        none (:class:`PowerLaw`, a :class:`Prony` fluid, a table not reaching 0 Hz)."""
        f = _frequency(frequency)
        if f.ndim:
            raise ContactresInputError("at(frequency) takes one frequency (Hz), not an array")
        way_out = (
            "a static contact takes the elastic solid of its storage constants at the "
            "loading frequency, material.storage(f_Hz), e.g. viscoelastic.pmma().storage(1.0), "
            "also as a layer of a LayeredMaterial"
        )
        for law, _ in self.terms:
            try:
                storage = float(np.real(law(f)))
            except ContactresInputError as exc:
                if f != 0:
                    raise
                # The law's own reason (no static limit, a table not reaching 0 Hz) stays
                # first: no storage modulus was computed, so none is quoted.
                raise ContactresInputError(f"{exc}; {way_out}") from exc
            if not storage > 0:
                # The static callers (sphere_contact, indentation_modulus_at, a stack at
                # 0 Hz) land here: name the elastic solid they can take instead.
                where = "no static limit, " if f == 0 else ""
                raise ContactresInputError(
                    f"{self.name or 'this viscoelastic solid'} has {where}no solid at "
                    f"{float(f):g} Hz ({type(law).__name__}: storage modulus {storage:.4g} Pa); "
                    f"{way_out}"
                )
        return Material(C=self.stiffness(f), density=self.density, name=self.name, frame=self.frame)

    def storage(self, frequency: float) -> Material:
        """The elastic :class:`contactres.Material` of the storage constants Re C*(f) (Pa) at
        one frequency f (Hz), density, name and frame kept.

        The quasi-elastic approximation of a static contact (``sphere_contact``,
        ``indentation_modulus_at``) loaded on a time scale of about 1/f: the loss and the load
        history are dropped. For a law with no static limit (:class:`PowerLaw`, the built-in
        :func:`pmma`) it is the way to such a contact; at f = 0 it is ``static()``'s real part.

        Examples
        --------
        >>> from contactres import viscoelastic
        >>> m = viscoelastic.pmma().storage(1.0)
        >>> m.is_lossy
        False
        """
        return static_solid(self, frequency)

    def static(self) -> Material:
        """``at(0)``: the relaxed solid (where the laws have one)."""
        return self.at(0.0)

    def rotated(self, normal=(0, 0, 1), inplane=None) -> ViscoelasticMaterial:
        """The same solid in the frame whose z axis is ``normal`` and x axis ``inplane`` (see
        :meth:`contactres.Material.rotated`): the structure matrices B_k turn, the laws do not,
        so ``rotated(n).at(f)`` has the constants of ``at(f).rotated(n)``."""
        R = rotation_to_surface(normal, inplane)
        terms = tuple(
            (law, tensor_to_voigt(rotate_tensor(voigt_to_tensor(b), R))) for law, b in self.terms
        )
        return ViscoelasticMaterial(terms, self.density, self.name, R @ self.frame)

    @property
    def is_lossy(self) -> bool:
        """True: a viscoelastic solid is treated as lossy (complex constants) by callers."""
        return True


# ------------------------------------------------------------------ the solid of a static contact
#: The loading frequency, Hz, at which a frequency-dependent material's storage constants stand
#: for its static ones (:func:`static_solid`'s default) where contactres loads a coating
#: statically: the static columns of the ``contact`` job on a coated face (and the ``dcsf``
#: job's K_sa there), the coated QCM fit's normal contact, and the coatings of ``afm invert``,
#: ``rum invert`` (through :func:`contactres.jobs.afm_invert.coated_film`) and ``maps
#: predict``. Not everywhere: the coated QCM radiation's K₀ takes the storage constants at the
#: overtone frequency, and a bare face (``sphere_contact``, the bare jobs) takes an undamped
#: Material only, refusing a lossy one. Why 1 Hz: the quasi-static moduli of
#: polymers are quoted at about 1 Hz (datasheets; the built-in PMMA's anchors,
#: :data:`PMMA_STATIC_FREQUENCY`), and a power law (the built-in PMMA's) has no relaxed limit
#: to take instead (its moduli relax to zero at 0 Hz).
STATIC_FREQUENCY_HZ = 1.0


def material_at(m, frequency: float) -> Material:
    """The :class:`~contactres.Material` of ``m`` at ``frequency`` (Hz).

    Defined here, beside the frequency-dependent materials, so that :func:`static_solid` and
    :func:`contactres.layered.material_at` (the same function) share one rule and message.

    Parameters
    ----------
    m : Material or frequency-dependent material
        A plain Material is returned as is (its constants do not depend on frequency); any other
        object must have ``at(frequency_Hz) -> Material`` (``frequency = 0``: static limit).
    frequency : float
        Frequency, Hz (>= 0).

    Returns
    -------
    Material
        The elastic constants at that frequency.

    Raises
    ------
    ContactresInputError
        ``m.at(frequency)`` returns no Material (or refuses the frequency itself).
    """
    if isinstance(m, Material):
        return m
    out = m.at(frequency)
    if not isinstance(out, Material):
        raise ContactresInputError(
            f"{type(m).__name__}.at({frequency!r}) must return a contactres.Material, "
            f"got {type(out).__name__}"
        )
    return out


def static_solid(material, frequency: float = STATIC_FREQUENCY_HZ) -> Material:
    """The undamped elastic solid that a static contact on ``material`` takes: its storage
    constants Re C*(f) (Pa) at the loading frequency f.

    A contact loaded on a time scale of about 1/f sees, to first order, the storage part of a
    linear viscoelastic solid's constants at f (the quasi-elastic approximation of
    :meth:`ViscoelasticMaterial.storage`: the loss and the load history are dropped). A static
    solution (Hertz, JKR, a static punch) needs real constants; a law with no relaxed limit
    (:class:`PowerLaw`, the built-in :func:`pmma`) has none at 0 Hz, hence the default
    :data:`STATIC_FREQUENCY_HZ`.

    Parameters
    ----------
    material : Material or frequency-dependent material
        A :class:`~contactres.Material`, whose constants do not depend on frequency: a lossy
        one, C (1 + i tan δ) (:meth:`~contactres.Material.with_loss`), gives its elastic part
        C, as the same solid written as ``ViscoelasticMaterial.proportional(m,
        ConstantLoss(M, tan δ))`` does. Or any object with ``at(frequency_Hz)`` returning a
        Material (e.g. a :class:`ViscoelasticMaterial`).
    frequency : float
        The loading frequency f, Hz (>= 0; default :data:`STATIC_FREQUENCY_HZ`). f = 0 takes
        the relaxed constants, refused by a law that has none.

    Returns
    -------
    Material
        Real constants Re C*(f), Pa (a float array, also where the imaginary part is zero),
        with the density, name and frame of ``material.at(f)``; a Material whose constants are
        real already is returned as it is.

    Raises
    ------
    ContactresInputError
        f is not one finite number >= 0 (checked for every material, a Material too);
        ``material`` is a stack (a :class:`~contactres.LayeredMaterial`: its layers and
        substrate each have their own static solid); ``material.at(f)`` refuses f (e.g. 0 Hz
        for a power law), or returns no Material; ``material`` has no ``at`` (a name such as
        ``"steel"``, a number: checked first).

    Examples
    --------
    >>> import contactres as cr
    >>> from contactres.viscoelastic import static_solid
    >>> glass = cr.Material.isotropic(70e9, 0.17)
    >>> bool(static_solid(glass.with_loss(0.02)).C[0, 0] == glass.C[0, 0])
    True
    >>> film = static_solid(cr.pmma())  # its storage constants at 1 Hz
    >>> print(f"{film.C[3, 3] / 1e9:.3f} GPa")
    1.092 GPa
    """
    if not callable(getattr(material, "at", None)):
        # A name ("steel") or a number is the caller's input, not a programming error inside:
        # refused in one line, as a layer's material is (layered), not as an AttributeError.
        given = repr(material) if isinstance(material, str) else type(material).__name__
        raise ContactresInputError(
            "static_solid takes a contactres.Material or a frequency-dependent material with "
            f"at(frequency_Hz) (e.g. a ViscoelasticMaterial), got {given}: build the material "
            "first (Material.isotropic(E, ν), Material.crystal(name), contactres.pmma(), ...)"
        )
    # The frequency is checked for every material, also one that does not depend on it: the
    # same rule and message as ViscoelasticMaterial.at's.
    if _frequency(frequency).ndim:
        raise ContactresInputError("the static solid is taken at one frequency (Hz), not an array")
    if hasattr(material, "layers") and hasattr(material, "substrate"):
        # A LayeredMaterial (a higher layer of the package: recognised by its fields).
        raise ContactresInputError(
            f"static_solid takes one material, not a stack ({type(material).__name__}): take "
            "the static solid of each of its layers and of its substrate"
        )
    at = material_at(material, frequency)
    if not np.iscomplexobj(at.C):
        return at
    return Material(C=np.real(at.C), density=at.density, name=at.name, frame=at.frame)


# ------------------------------------------------------------------------------------ PMMA
# Anchors of the built-in PMMA (see pmma()); tests/test_viscoelastic.py checks the material
# against these published numbers, computed there from the complex wave numbers.
#: Density of the built-in PMMA, kg/m^3.
PMMA_DENSITY = 1190.0
#: Quasi-static Young's modulus of the built-in PMMA, Pa (taken at PMMA_STATIC_FREQUENCY).
PMMA_STATIC_E = 3.0e9
#: Quasi-static Poisson ratio of the built-in PMMA.
PMMA_STATIC_POISSON = 0.37
#: The frequency of the quasi-static anchors, Hz.
PMMA_STATIC_FREQUENCY = 1.0
#: Ultrasonic shear phase velocity of the built-in PMMA, m/s (at PMMA_ULTRASONIC_FREQUENCY).
PMMA_SHEAR_SPEED = 1370.0
#: Ultrasonic longitudinal phase velocity of the built-in PMMA, m/s.
PMMA_LONGITUDINAL_SPEED = 2700.0
#: The frequency of the ultrasonic anchors, Hz.
PMMA_ULTRASONIC_FREQUENCY = 5.0e6


def _phase_velocity(modulus: complex) -> float:
    """Phase velocity ω/Re k (m/s) of a plane wave of modulus M* in PMMA: k = ω √(ρ/M*)."""
    return 1.0 / float(np.real(np.sqrt(PMMA_DENSITY / complex(modulus))))


def _through(static: float, speed: float, other: complex = 0.0) -> PowerLaw:
    """The power law with ``|M*|`` = ``static`` at PMMA_STATIC_FREQUENCY such that a wave of
    modulus M* + ``other`` (the shear part 4G*/3 of the longitudinal modulus) has phase
    velocity ``speed`` at PMMA_ULTRASONIC_FREQUENCY; the phase is found by bisection (the
    velocity grows with the phase, since ``|M*|`` at 5 MHz does)."""
    from scipy.optimize import brentq  # deferred: scipy costs import time

    def law(phi: float) -> PowerLaw:
        return PowerLaw(static, PMMA_STATIC_FREQUENCY, phi)

    def miss(phi: float) -> float:
        m = complex(law(phi)(PMMA_ULTRASONIC_FREQUENCY)) + other
        return _phase_velocity(m) - speed

    return law(brentq(miss, 0.0, 1.0, xtol=1e-15, rtol=1e-15))


def pmma() -> ViscoelasticMaterial:
    """Glassy poly(methyl methacrylate) near 20 °C: isotropic, shear and bulk power laws.

    Meant for 1 Hz to ~50 MHz at room temperature. PMMA's secondary (β) relaxation is broad and
    lies near room temperature at low frequencies, so a nearly constant loss tangent over this
    band is a fair first description (a qualitative statement, not fitted to a loss spectrum
    here); the law is not meant near or above the glass transition (~105 °C) nor at GHz.

    Anchors (published values; the static ones are typical handbook and datasheet numbers for
    cast PMMA, and neither they nor the wave speeds were re-checked against one original here:
    the values are the middles of the ranges the literature quotes, and the ranges give the
    uncertainty below):

    - density ρ = 1190 kg/m³;
    - quasi-static Young's modulus E = 3.0 GPa (datasheets: 2.4–3.3 GPa) and Poisson ratio
      ν = 0.37 (0.35–0.40), taken as ``|E*|`` and ν at 1 Hz: G = 1.095 GPa, K = 3.85 GPa;
    - ultrasonic phase velocities at 5 MHz: shear c_T = 1370 m/s and longitudinal
      c_L = 2700 m/s (the middle of the published 1340–1400 and 2690–2750 m/s; e.g.
      B. Hartmann and J. Jarzynski, J. Acoust. Soc. Am. 56, 1469 (1974); not re-checked here).

    Each modulus is a :class:`PowerLaw` through its 1 Hz value and its 5 MHz value: the
    shear law's phase is the one for which a shear wave (k = ω √(ρ/G*)) has the phase
    velocity c_T at 5 MHz, the bulk law's the one for which a longitudinal wave (modulus
    K* + 4G*/3) has c_L. So the phase follows from the two anchors through the power law's
    own Kramers–Kronig pair, φ = (π/2) d ln ``|M|`` / d ln f. Results: shear φ_G = 0.0725 rad
    (tan δ_G = 0.073), bulk φ_K = 0.040 rad. D. Laux et al., Ultrasonics 134, 107104 (2023)
    measured the shear and longitudinal quality factors of PMMA from 20 kHz to 12 MHz and found
    them falling towards low frequencies; their numbers were not at hand to compare with this
    law's constant tan δ (a check worth making).

    At 15 MHz (paper 2's QCM overtone): G' = 2.34 GPa, tan δ = 0.073. Uncertainty, from the
    anchors' ranges (c_T 1340–1400 m/s, E 2.4–3.3 GPa, ν 0.35–0.40, all corners): G'(15 MHz)
    from 2.22 to 2.49 GPa and tan δ from 0.057 to 0.10; a film spin-cast from solution may be
    softer (residual solvent, lower density) — the issue's 1.5–2.3 GPa allows for that.

    Examples
    --------
    >>> from contactres import pmma
    >>> G = pmma().at(15e6).C[3, 3]  # shear modulus at 15 MHz, Pa
    >>> print(f"G' = {G.real / 1e9:.2f} GPa, tan δ = {G.imag / G.real:.3f}")
    G' = 2.34 GPa, tan δ = 0.073
    """
    g_static = PMMA_STATIC_E / (2 * (1 + PMMA_STATIC_POISSON))
    k_static = PMMA_STATIC_E / (3 * (1 - 2 * PMMA_STATIC_POISSON))
    shear = _through(g_static, PMMA_SHEAR_SPEED)
    g_us = complex(shear(PMMA_ULTRASONIC_FREQUENCY))
    bulk = _through(k_static, PMMA_LONGITUDINAL_SPEED, other=4 / 3 * g_us)
    return ViscoelasticMaterial.isotropic(shear, bulk=bulk, density=PMMA_DENSITY, name="PMMA")
