"""QCM-D of attached particles: the coupled resonance of particle and contact (issue 28).

Paper 2's small-load approximation (Eqs. 1-2) with the point contact replaced by a particle
that has inertia of its own. N particles per area A (the ``coverage``, m⁻²), each of mass m and
moment of inertia I about its centre, touch the resonator surface at one point, a lever arm R
below their centre, through a contact of complex tangential stiffness κ + iωξ and, optionally,
a rotational stiffness κ_r. The surface oscillates tangentially, u e^{iωt}. Each particle
exerts on the surface the force -K_L(ω) u, and

    Δf + iΔΓ = (N/A) K_L(ω_n) / (2nπ² Z_q),    ω_n = 2π n f_F                  (paper 2, Eq. 1)

with N/A in place of n_P/A_eff. K_L, the load stiffness of one particle, is (theory page
docs/theory/particles.md, where every step is derived)

    K_L = (1 - h)² / (c + 1/k) + g,    k = κ + iωξ

where c is the compliance of the free particle at its contact point (c = 1/M_x + R²/M_θ with
M_x = -mω² + iωZ_t, M_θ = -Iω² + κ_r + iωZ_r; a locked rotation drops the second term), h the
displacement of the contact point per surface displacement that the liquid alone imposes, and
g the load that reaches the surface through the liquid (:func:`particle_compliance`; h = g = 0
in vacuum). Limits: κ -> ∞ gives K_L = 1/c in vacuum, -mω² for a locked rotation (Sauerbrey
with m) and -m I/(I + mR²) ω² for a free one (2/7 of m for a sphere); m -> ∞ gives
K_L = κ + iωξ (paper 2, Eq. 1). This form has no cancellation at either limit
(K_L = k(1 - s/u), s the contact point's displacement, would lose all digits for a stiff
contact).

In a liquid (:class:`Medium`), the particle feels the force and torque of a sphere oscillating
in an unbounded viscous fluid (L. D. Landau, E. M. Lifshitz, Fluid Mechanics, 2nd ed., §24: the
translational oscillations in the text, the rotary ones in its problems), on its velocity
relative to the undisturbed shear wave of the surface at its centre (z = R; displacement
w = e^{-qR} and rotation ϑ = -q e^{-qR}/2 per unit surface displacement):

    Z_t = 6πηR (1 + qR + q²R²/9),   Z_r = (8π/3) ηR³ (3 + 3qR + q²R²)/(1 + qR),
    q = (1 + i)/δ,   δ = √(2η/(ρ_l ω)).

The reaction, the force and torque the particle exerts on the liquid, reaches the surface with
the same factors w and ϑ (the area-averaged shear wave is exact for the total force on the wall
and reciprocal), which keeps the load passive (Im K_L >= 0).

The bare liquid's own load (Kanazawa-Gordon, :func:`kanazawa_gordon`) is not in K_L: shifts are
against the bare sensor in the same medium. Approximations (stated on the theory page): dilute
coverage (no particle-particle hydrodynamics, no screening of the surface's own liquid load),
the wall neglected in the force on the sphere (LL's unbounded fluid) and the sphere reduced to
a point force and torque at its centre in the shear wave. They fail where R ≲ δ:
:func:`particle_model_validity` names that case, and the model is then not to be trusted (a
full hydrodynamic treatment, lattice Boltzmann or finite elements, is the tool; A. M.
Leshansky, I. Fouxon, B. Y. Rubinstein, arXiv:2311.15880 (2023), treat the stiff contact in
full).

References: G. L. Dybwad, J. Appl. Phys. 58, 2789 (1985) (the coupled resonance of a particle on
a QCM); A. Pomorska et al., Anal. Chem. 82, 2237 (2010) and A. L. J. Olsson et al., Anal. Chem.
84, 4504 (2012) (colloids and bacteria on a QCM-D, the sign change of Δf); Johannsmann's group,
Nanotechnology 26, 484001 (2015), and D. Johannsmann, A. Langhoff, C. Leppin, Sensors 21, 3490
(2021) (the small-load approximation for point contacts; coupled resonances of translation and
rotation, of which only the force at the contact shifts the resonance); paper 2 (Vlachová,
König, Johannsmann, Beilstein J. Nanotechnol. 6, 845 (2015)). Titles and authors of the
particle papers as cited in issue 28, not re-checked.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..units import SMALL_LOAD_LIMIT
from ..validation import nonnegative, positive

__all__ = [
    "AIR",
    "VALIDITY_RADIUS_RATIO",
    "WATER",
    "Medium",
    "Particle",
    "coupled_resonance",
    "kanazawa_gordon",
    "medium_named",
    "particle_compliance",
    "particle_model_validity",
    "particle_shifts",
    "particle_stiffness",
    "penetration_depth",
    "sphere_drag",
]

#: The model is flagged where R < VALIDITY_RADIUS_RATIO · δ (at the lowest frequency given) and
#: the hydrodynamic force matters (see :func:`particle_model_validity`).
VALIDITY_RADIUS_RATIO = 1.0

# The hydrodynamic force "matters" when |ωZ_t| is at least this fraction of the particle's
# inertial force mω²: below it, an error of the hydrodynamic term of order one changes K_L by
# less than about this fraction (air around micron particles), so no flag is needed.
_HYDRO_WEIGHT = 1e-2


@dataclass(frozen=True)
class Particle:
    """A particle attached to the resonator surface.

    Parameters
    ----------
    mass : m, kg
    moment_of_inertia : I about the particle's centre, kg m²
    radius : R, m: the lever arm from the centre to the contact (the rocking mode's), and the
        hydrodynamic radius in a liquid
    """

    mass: float
    moment_of_inertia: float
    radius: float

    def __post_init__(self):
        positive("particle mass", self.mass, "kg")
        positive("particle moment of inertia", self.moment_of_inertia, "kg m^2")
        positive("particle radius", self.radius, "m")

    @classmethod
    def sphere(cls, radius: float, density: float) -> Particle:
        """A homogeneous sphere: m = (4/3)πR³ρ, I = (2/5) m R².

        Parameters
        ----------
        radius : R, m
        density : ρ, kg/m³

        Examples
        --------
        >>> from contactres.resonators import Particle
        >>> p = Particle.sphere(radius=1e-6, density=2000.0)
        >>> print(f"{p.mass:.4g} kg, I/(mR²) = {p.moment_of_inertia / (p.mass * 1e-12):.2f}")
        8.378e-15 kg, I/(mR²) = 0.40
        """
        r = positive("particle radius", radius, "m")
        rho = positive("particle density", density, "kg/m^3")
        m = 4.0 / 3.0 * np.pi * r**3 * rho
        return cls(mass=m, moment_of_inertia=0.4 * m * r * r, radius=r)


@dataclass(frozen=True)
class Medium:
    """A Newtonian fluid around the particles and above the sensor.

    Parameters
    ----------
    name : label (e.g. "water")
    density : ρ_l, kg/m³
    viscosity : η, Pa s
    """

    name: str
    density: float
    viscosity: float

    def __post_init__(self):
        positive(f"density of {self.name}", self.density, "kg/m^3")
        positive(f"viscosity of {self.name}", self.viscosity, "Pa s")


#: Air at 25 °C and 1 atm: ρ = 1.184 kg/m³, η = 1.849e-5 Pa s (CRC Handbook of Chemistry and
#: Physics, 97th ed., "Properties of air").
AIR = Medium("air", 1.184, 1.849e-5)

#: Water at 25 °C: ρ = 997.05 kg/m³, η = 0.8900e-3 Pa s (CRC Handbook of Chemistry and Physics,
#: 97th ed.; IAPWS R12-08 gives 0.8900 mPa s).
WATER = Medium("water", 997.05, 0.8900e-3)

_MEDIA = {"air": AIR, "water": WATER}


def medium_named(name: str) -> Medium:
    """The medium called ``name`` ("air" or "water", any case), for the command line.

    Examples
    --------
    >>> from contactres.resonators import medium_named
    >>> medium_named("Water").viscosity
    0.00089
    """
    try:
        return _MEDIA[str(name).strip().lower()]
    except KeyError:
        raise ContactresInputError(
            f"unknown medium {name!r}; known: {', '.join(sorted(_MEDIA))}"
        ) from None


def penetration_depth(medium: Medium, frequency):
    """Viscous penetration depth δ = √(2η/(ρ_l ω)), ω = 2πf, m (Landau-Lifshitz §24).

    Examples
    --------
    >>> from contactres.resonators import WATER, penetration_depth
    >>> print(f"{penetration_depth(WATER, 5e6) * 1e9:.0f} nm")
    238 nm
    """
    f = positive("frequency", frequency, "Hz")
    d = np.sqrt(2.0 * medium.viscosity / (medium.density * 2.0 * np.pi * np.asarray(f)))
    return float(d) if d.ndim == 0 else d


def sphere_drag(medium: Medium, radius, frequency):
    """Hydrodynamic impedances of a sphere oscillating in an unbounded viscous fluid.

    Landau & Lifshitz, Fluid Mechanics, §24 (the oscillating sphere and, in its problems, the
    rotary oscillations), written for e^{iωt} with q = (1 + i)/δ, δ = √(2η/(ρ_l ω)):

        Z_t = 6πηR (1 + qR + q²R²/9)                    (force = -Z_t × velocity)
        Z_r = (8π/3) ηR³ (3 + 3qR + q²R²)/(1 + qR)      (torque = -Z_r × angular velocity)

    Re Z_t = 6πηR(1 + R/δ) is LL's drag; Im Z_t = 3πR²√(2ηρ_l ω)(1 + 2R/(9δ)) is
    LL's inertial term (half the displaced mass and the Basset force); ω -> 0 gives Stokes,
    6πηR and 8πηR³.

    Parameters
    ----------
    medium : :class:`Medium`
    radius : R, m
    frequency : f, Hz (array)

    Returns
    -------
    (Z_t in N s/m, Z_r in N m s), complex, broadcast over radius and frequency

    Examples
    --------
    >>> import numpy as np
    >>> from contactres.resonators import WATER, sphere_drag
    >>> zt, zr = sphere_drag(WATER, 1e-6, 1e-6)  # nearly steady: Stokes
    >>> print(f"{zt.real / (6 * np.pi * WATER.viscosity * 1e-6):.4f}")
    1.0000
    """
    r = np.asarray(positive("sphere radius", radius, "m"), dtype=float)
    f = np.asarray(positive("frequency", frequency, "Hz"), dtype=float)
    zt, zr, _, _ = _hydro(medium, r, 2.0 * np.pi * f)
    return zt, zr


def _hydro(medium: Medium | None, radius, omega):
    """Z_t, Z_r (:func:`sphere_drag`) and the shear wave's displacement and rotation at the
    centre height (per unit surface displacement); zeros in vacuum."""
    if medium is None:
        zero = np.zeros(np.shape(omega), dtype=complex)
        return zero, zero, zero, zero
    eta = medium.viscosity
    q = (1.0 + 1.0j) * np.sqrt(medium.density * omega / (2.0 * eta))  # (1 + i)/δ
    qr = q * radius
    zt = 6.0 * np.pi * eta * radius * (1.0 + qr + qr * qr / 9.0)
    zr = 8.0 * np.pi / 3.0 * eta * radius**3 * (3.0 + 3.0 * qr + qr * qr) / (1.0 + qr)
    # The undisturbed shear wave u e^{-qz}: its displacement at z = R and its local rotation
    # (half the vorticity, ½ ∂u_x/∂z, positive when the top moves ahead as θ does).
    wave = np.exp(-qr)
    return zt, zr, wave, -0.5 * q * wave


def _rocking_stiffness(rocking):
    """κ_r (N m/rad) of the rocking option; inf for "locked", 0 for "free"."""
    if isinstance(rocking, str):
        key = rocking.strip().lower()
        if key == "free":
            return 0.0
        if key == "locked":
            return np.inf
        raise ContactresInputError(
            "rocking must be 'free', 'locked' or a rotational stiffness in N m/rad, "
            f"got {rocking!r}"
        )
    return nonnegative("rocking stiffness", rocking, "N m/rad")


def _compliance(particle: Particle, omega, kappa_r, medium: Medium | None):
    """c, h and g of :func:`particle_compliance` for κ_r as given (inf: locked)."""
    m, inertia, r = particle.mass, particle.moment_of_inertia, particle.radius
    zt, zr, wave, spin = _hydro(medium, r, omega)
    iw = 1.0j * omega
    # the particle's generalised coordinates q = (x, θ): M q = e f_c + a u, with the contact
    # vector e = (1, -R) (contact point s = x - Rθ) and the liquid's drive a = iω(Z_t w, Z_r ϑ)
    mx = -m * omega**2 + iw * zt
    ax, at = iw * zt * wave, iw * zr * spin
    kappa_r = np.asarray(kappa_r, dtype=float)
    locked = np.isinf(kappa_r)
    mt = -inertia * omega**2 + np.where(locked, 0.0, kappa_r) + iw * zr
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_t = np.where(locked, 0.0, 1.0 / mt)  # a locked rotation takes no part
    c = 1.0 / mx + r * r * inv_t  # eᵀM⁻¹e
    h = ax / mx - r * at * inv_t  # eᵀM⁻¹a
    # g = (the liquid's pull on the surface of a particle held still) - aᵀM⁻¹a
    g = iw * (zt * wave**2 + zr * spin**2) - (ax * ax / mx + at * at * inv_t)
    return c, h, g


def particle_compliance(particle: Particle, frequency, *, rocking="free", medium=None):
    """The particle as its contact sees it: c, h and g of K_L = (1 - h)²/(c + 1/k) + g.

    With the particle's coordinates q = (x, θ) (centre and rotation), the contact vector
    e = (1, -R) (the contact point moves by s = eᵀq), the particle's dynamic matrix
    M = diag(-mω² + iωZ_t, -Iω² + κ_r + iωZ_r) and the liquid's drive per unit surface
    displacement a = iω(Z_t w, Z_r ϑ) (w = e^{-qR} and ϑ = -q e^{-qR}/2 the shear wave's
    displacement and rotation at the centre, q = (1 + i)/δ; theory page):

    * c = eᵀM⁻¹e (m/N): the compliance of the free particle at its contact point;
    * h = eᵀM⁻¹a: the contact point's displacement per surface displacement that the liquid
      alone imposes;
    * g = iω(Z_t w² + Z_r ϑ²) - aᵀM⁻¹a (N/m): the load the particle puts on the surface through
      the liquid, besides its contact (the force of the liquid on the particle reaches the
      surface with the same factors w, ϑ: reciprocity of the shear wave).

    In vacuum h = g = 0. Any contact k = κ + iωξ then gives K_L (:func:`particle_stiffness`); a
    fit that varies κ, ξ and the coverage for a given particle needs c, h and g only once.

    Parameters
    ----------
    particle, frequency, rocking, medium : as for :func:`particle_stiffness`

    Returns
    -------
    (c, h, g): complex arrays of the broadcast shape of frequency and κ_r

    Examples
    --------
    A free sphere in vacuum: c = -1/(m_eff ω²) with m_eff = 2m/7:

    >>> import numpy as np
    >>> from contactres.resonators import Particle, particle_compliance
    >>> p = Particle.sphere(1e-6, 2000.0)
    >>> c, h, g = particle_compliance(p, 5e6)
    >>> print(f"{float(-1 / (c.real * (2 * np.pi * 5e6) ** 2) / p.mass):.6f}", abs(h), abs(g))
    0.285714 0.0 0.0
    """
    if medium is not None and not isinstance(medium, Medium):
        raise ContactresInputError(f"medium must be a Medium or None, got {medium!r}")
    f = np.asarray(positive("frequency", frequency, "Hz"), dtype=float)
    c, h, g = _compliance(particle, 2.0 * np.pi * f, _rocking_stiffness(rocking), medium)
    return tuple(np.asarray(x, dtype=complex) for x in (c, h, g))


def particle_stiffness(particle: Particle, frequency, kappa, xi, *, rocking="free", medium=None):
    """Load stiffness K_L(ω) of one attached particle, N/m (complex; module docstring).

    The force that one particle exerts on the resonator surface is -K_L u for a surface
    displacement u e^{iωt}: a spring anchored in space gives K_L = κ + iωξ (paper 2, Eq. 1), a
    rigidly attached mass -mω² (Sauerbrey).

    Parameters
    ----------
    particle : :class:`Particle`
    frequency : f = ω/2π, Hz (array)
    kappa : contact stiffness κ, N/m (array, >= 0)
    xi : contact drag coefficient ξ, kg/s (array, >= 0)
    rocking : "free" (no rotational stiffness: the particle may roll about its contact),
        "locked" (no rotation) or a rotational stiffness κ_r in N m/rad (array)
    medium : None (vacuum/air without hydrodynamic load) or a :class:`Medium`; the bare
        liquid's Kanazawa-Gordon load is not included

    Returns
    -------
    complex ndarray of the broadcast shape of frequency, kappa, xi (and κ_r)

    Examples
    --------
    A rigid contact on a free sphere loads the sensor with 2/7 of its mass:

    >>> import numpy as np
    >>> from contactres.resonators import Particle, particle_stiffness
    >>> p = Particle.sphere(1e-6, 2000.0)
    >>> w = 2 * np.pi * 15e6
    >>> k = particle_stiffness(p, 15e6, 1e15, 0.0)
    >>> print(f"{k.real / (-p.mass * w**2):.6f}")
    0.285714
    """
    f = np.asarray(positive("frequency", frequency, "Hz"), dtype=float)
    omega = 2.0 * np.pi * f
    kap = np.asarray(kappa, dtype=float)
    x = np.asarray(xi, dtype=float)
    if np.any(~(kap >= 0)) or np.any(~(x >= 0)):
        raise ContactresInputError(
            "contact stiffness kappa (N/m) and drag xi (kg/s) must be >= 0 and not NaN"
        )
    if medium is not None and not isinstance(medium, Medium):
        raise ContactresInputError(f"medium must be a Medium or None, got {medium!r}")
    c, h, g = _compliance(particle, omega, _rocking_stiffness(rocking), medium)
    k = kap + 1.0j * omega * x
    with np.errstate(divide="ignore", invalid="ignore"):
        # k(1 - h)²/(1 + ck) written as (1 - h)²/(c + 1/k): exact at both limits
        out = np.where(k == 0, 0.0, (1.0 - h) ** 2 / (c + 1.0 / np.where(k == 0, 1.0, k)))
    return out + g


def particle_shifts(
    fundamental,
    overtones,
    particle: Particle,
    kappa,
    xi,
    coverage,
    *,
    rocking="free",
    medium=None,
    zq=8.8e6,
):
    """Δf_n and ΔΓ_n (Hz) of ``coverage`` attached particles per m² (module docstring).

    Δf + iΔΓ = (N/A) K_L(ω_n)/(2nπ² Z_q) (paper 2, Eq. 1 with n_P/A_eff -> coverage), at
    ω_n = 2π n f_F. Δf is not divided by n; ΔΓ is the change of the half bandwidth. Signs as in
    :func:`~contactres.resonators.shifts_from_stiffness` (a spring raises f, a mass lowers it),
    and like it a RuntimeWarning where ``|Δf|``/f exceeds the small-load limit (1e-3). All arguments
    broadcast (e.g. overtones (n,) against parameters (T, 1)).

    Examples
    --------
    Heavy particles (m -> ∞) give paper 2's Eq. 1 with n_P/A_eff = coverage:

    >>> from contactres.resonators import Particle, particle_shifts
    >>> heavy = Particle(mass=1e3, moment_of_inertia=1e3, radius=1e-3)
    >>> df, dg = particle_shifts(5e6, 3, heavy, 1000.0, 1e-7, 1e8, rocking="locked")
    >>> print(f"Δf = {df:.2f} Hz, ΔΓ = {dg:.3f} Hz")
    Δf = 191.90 Hz, ΔΓ = 1.809 Hz
    """
    f0 = positive("fundamental frequency", fundamental, "Hz")
    n = np.asarray(overtones, dtype=float)
    if np.any(~np.isfinite(n)) or np.any(n < 1) or np.any(n != np.round(n)):
        raise ContactresInputError(f"overtones must be integers >= 1, got {overtones!r}")
    cov = np.asarray(coverage, dtype=float)
    if np.any(~(cov >= 0)):
        raise ContactresInputError("coverage (particles per m^2) must be >= 0 and not NaN")
    z = positive("zq", zq, "kg m^-2 s^-1")
    k = particle_stiffness(particle, n * f0, kappa, xi, rocking=rocking, medium=medium)
    shift = cov * k / (2.0 * n * np.pi**2 * z)
    worst = float(np.max(np.abs(shift.real) / (n * f0), initial=0.0))
    if worst > SMALL_LOAD_LIMIT:
        warnings.warn(
            f"|Δf|/f = {worst:.2g} exceeds {SMALL_LOAD_LIMIT:g}: the small-load approximation "
            "of paper 2, Eq. 1 may not hold",
            RuntimeWarning,
            stacklevel=2,
        )
    return _out(shift.real), _out(shift.imag)


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def coupled_resonance(particle: Particle, kappa, *, rocking="free", medium=None):
    """Undamped resonance frequency of the particle on its contact, Hz.

    The surface held still and ξ = 0: the translation mode √(κ/m)/2π for a locked rotation; the
    one mode √(κ(1/m + R²/I))/2π for a free one (the other is rolling at zero frequency; a
    sphere: √(7κ/2m)/2π). With a rotational stiffness κ_r (a number) there are two modes,
    returned along a new last axis (lower, higher): the lower tends to the locked translation
    mode as κ_r -> ∞, the higher to the free mode as κ_r -> 0. In a liquid, the inertia of the
    hydrodynamic force (Im Z/ω, which depends on the frequency) is added to m and I, and the
    frequency found by fixed-point iteration (a contraction: the added inertia varies at most
    as ω^{-1/2}).

    Examples
    --------
    >>> import numpy as np
    >>> from contactres.resonators import Particle, coupled_resonance
    >>> p = Particle.sphere(1e-6, 2000.0)
    >>> f = coupled_resonance(p, 1000.0)
    >>> bool(np.isclose(f, np.sqrt(3.5 * 1000.0 / p.mass) / (2 * np.pi), rtol=1e-12, atol=0))
    True
    """
    kap = np.asarray(kappa, dtype=float)
    if np.any(~(kap >= 0)):
        raise ContactresInputError("contact stiffness kappa (N/m) must be >= 0 and not NaN")
    kappa_r = np.asarray(_rocking_stiffness(rocking), dtype=float)
    # which mode: the translation (locked), the one finite mode (free), or both (a number)
    which = (0,) if np.all(np.isinf(kappa_r)) else (1,) if isinstance(rocking, str) else (0, 1)
    out = np.stack([_mode(particle, kap, kappa_r, medium, i) for i in which], axis=-1)
    out = out[..., 0] if len(which) == 1 else out
    return float(out) if out.ndim == 0 else out


def _mode(particle: Particle, kappa, kappa_r, medium, index):
    """Mode ``index`` (0 lower, 1 higher) of :func:`coupled_resonance`, Hz."""
    m, inertia, r = particle.mass, particle.moment_of_inertia, particle.radius
    omega = _modes(kappa, kappa_r, m, inertia, r)[..., index]
    # In a liquid the added inertia depends on ω: iterate (a contraction, see the docstring);
    # 60 passes reach round-off from the vacuum frequency.
    for _ in range(0 if medium is None else 60):
        w = np.maximum(omega, 1e-300)
        zt, zr, _, _ = _hydro(medium, r, w)
        omega = _modes(kappa, kappa_r, m + zt.imag / w, inertia + zr.imag / w, r)[..., index]
    return omega / (2.0 * np.pi)


def _modes(kappa, kappa_r, m, inertia, r):
    """The two angular frequencies (lower, higher) of K q = ω² M q, q = (x, θ),
    K = [[κ, -κR], [-κR, κR² + κ_r]], M = diag(m, I); rad/s, along a new last axis."""
    locked = np.isinf(kappa_r)
    kr = np.where(locked, 0.0, kappa_r)
    # det(K - λM) = 0: mI λ² - (κI + m(κR² + κ_r)) λ + κκ_r = 0
    a = m * inertia
    b = kappa * inertia + m * (kappa * r * r + kr)
    cc = kappa * kr
    disc = np.sqrt(np.maximum(b * b - 4.0 * a * cc, 0.0))
    hi = (b + disc) / (2.0 * a)
    # the lower root from the product of the roots (no cancellation when κ_r is small)
    lo = np.where(hi > 0, cc / np.where(hi > 0, a * hi, 1.0), 0.0)
    lo = np.where(locked, kappa / m, lo)
    hi = np.where(locked, np.inf, hi)
    return np.stack([np.sqrt(lo), np.sqrt(hi)], axis=-1)


def kanazawa_gordon(fundamental, overtones, medium: Medium, zq=8.8e6):
    """Δf_n, ΔΓ_n (Hz) of the bare sensor in a Newtonian liquid (Kanazawa-Gordon).

    The small-load approximation Δf + iΔΓ = (i f_F/(π Z_q)) Z_L with the liquid's shear-wave
    impedance Z_L = √(iωρ_l η) gives Δf_n = -ΔΓ_n = -√n f_F^{3/2} √(ρ_l η/π)/Z_q, the form of
    K. K. Kanazawa, J. G. Gordon, Anal. Chim. Acta 175, 99 (1985) (with √(ρ_q μ_q) = Z_q).
    Not part of :func:`particle_shifts` (shifts there are against the bare sensor in the medium).

    Examples
    --------
    >>> from contactres.resonators import WATER, kanazawa_gordon
    >>> df, dg = kanazawa_gordon(5e6, 1, WATER)
    >>> print(f"Δf = {df:.0f} Hz, ΔΓ = {dg:.0f} Hz")
    Δf = -675 Hz, ΔΓ = 675 Hz
    """
    f0 = positive("fundamental frequency", fundamental, "Hz")
    n = positive("overtone", overtones)
    z = positive("zq", zq, "kg m^-2 s^-1")
    omega = 2.0 * np.pi * np.asarray(n) * f0
    zl = np.sqrt(1.0j * omega * medium.density * medium.viscosity)
    shift = 1.0j * f0 / (np.pi * z) * zl
    return _out(shift.real), _out(shift.imag)


def particle_model_validity(particle: Particle, frequency, medium=None) -> str | None:
    """Why the particle model does not hold here, in words, or None where it does.

    The liquid's force on the particle (LL §24, no wall, the shear wave taken at the centre) is
    a good approximation only for particles larger than the penetration depth δ. Flagged: R <
    VALIDITY_RADIUS_RATIO · δ at the lowest frequency given (the largest δ), where the
    hydrodynamic force is at least 1 % of the particle's inertial force mω² (so air around
    micron particles is not flagged). A lattice-Boltzmann (or other full hydrodynamic)
    treatment is the tool there.

    Examples
    --------
    >>> from contactres.resonators import WATER, Particle, particle_model_validity
    >>> print(particle_model_validity(Particle.sphere(1e-6, 1050.0), 5e6, WATER))
    None
    >>> reason = particle_model_validity(Particle.sphere(50e-9, 1050.0), 5e6, WATER)
    >>> print(reason.split(" (")[0])
    particle smaller than the penetration depth: R = 50 nm < δ = 238 nm in water at 5 MHz
    """
    if medium is None:
        return None
    f = float(np.min(positive("frequency", frequency, "Hz")))
    delta = penetration_depth(medium, f)
    r = particle.radius
    omega = 2.0 * np.pi * f
    zt = _hydro(medium, r, omega)[0]
    weight = abs(omega * zt) / (particle.mass * omega**2)
    if r < VALIDITY_RADIUS_RATIO * delta and weight >= _HYDRO_WEIGHT:
        return (
            f"particle smaller than the penetration depth: R = {r * 1e9:.3g} nm < δ = "
            f"{delta * 1e9:.3g} nm in {medium.name} at {f / 1e6:.3g} MHz (the hydrodynamic "
            "model needs R > δ; lattice Boltzmann is the tool)"
        )
    return None
