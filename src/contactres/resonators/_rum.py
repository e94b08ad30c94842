"""The resonance ultrasound microscope (RUM) oscillator: contact stiffness k* from its resonance.

In resonance-type microscopies (AFM contact resonance, RUM) an oscillator touches the sample
through a tip; the tip-sample contact acts as a spring support of stiffness k* that raises the
oscillator's resonance frequency from f0 (free) to f (in contact). Paper 1 describes this setting
(the contact "modeled to be a spring support, whose stiffness is given by the traditional
Hertzian contact theory"; RUM oscillators run at 0.25-1.5 MHz with contact radii below 30 µm) and
computes how the dynamics of the contact changes k* (:mod:`contactres.dynamic`); the oscillator
models below are the standard ones that turn f into k* (they are not equations of paper 1).

Two models of the oscillator (SI units: Hz, N/m, kg):

``"lumped"``
    A mass on a spring: one mode of effective stiffness K_eff (N/m, referred to the tip
    displacement) and effective mass K_eff/(2πf0)². The contact spring adds in parallel::

        (f/f0)² = 1 + k*/K_eff,        k* = K_eff ((f/f0)² − 1).

``"rod"``
    A uniform rod (length L, cross-section A, Young's modulus E, density ρ, bar velocity
    c = √(E/ρ)) in longitudinal vibration, u(x, t) = U(x) e^{iωt}, EA U'' + ρAω² U = 0. Boundary
    conditions assumed: the end x = 0 is free (EA U'(0) = 0), the tip end x = L rests on the
    contact spring to ground (EA U'(L) = −k* U(L)). With U = cos(kx), k = ω/c, the
    characteristic equation is::

        k* = (EA/L) (kL) tan(kL).

    Mode n (n = 1, 2, ...) lives on the branch kL ∈ [nπ, nπ + π/2):

    * k* = 0: kL = nπ, the free-free mode, f0 = n c/(2L);
    * k* -> ∞: kL -> (n + ½)π, the clamped-free mode, f -> (n + ½) f0/n (1.5 f0 for n = 1).

    So f = f0 kL/(nπ) and, with θ = kL − nπ = nπ (f − f0)/f0 (computed from f − f0, so that
    small shifts keep their digits), the closed-form inverse is k* = (EA/L)(nπ + θ) tan θ; the
    forward f(k*) solves (nπ + θ) tan θ = k* L/(EA) on θ ∈ [0, π/2) by Newton's method on
    θ − arctan(β/(nπ + θ)), β = k*L/(EA), whose derivative lies in [1, 1 + 1/(2nπ)]: it
    converges from θ = arctan(β/(nπ)) in a few steps for every β.

    Modal stiffness and calibration. The free mode U = cos(nπx/L), normalised to the tip
    displacement (``|U(L)|`` = 1), has effective mass m_eff = ρA ∫₀ᴸ cos² = m/2 (m = ρAL the rod's
    mass), so K_eff = m_eff (2πf0)² = 2π² m f0² = (EA/L)(nπ)²/2. A rod is therefore fixed by
    f0 and m alone (EA/L = 4 m f0²/n²): :meth:`RUMOscillator.rod`. Expanding the
    characteristic equation for small s = k*/K_eff gives f/f0 = 1 + s/2 − s²/4 + O(s³), the
    lumped model with the same K_eff (f/f0 = 1 + s/2 − s²/8 + O(s³)) to first order.

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..validation import nonnegative, positive

__all__ = ["RUM_MODELS", "RUMOscillator"]

#: The oscillator models of :class:`RUMOscillator`.
RUM_MODELS = ("lumped", "rod")

# Newton steps of the forward rod solution: the map converges quadratically from its start
# (derivative in [1, 1.16]); 8 steps leave a residual at rounding for every k* >= 0.
_NEWTON_STEPS = 8


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


@dataclass(frozen=True)
class RUMOscillator:
    """A RUM (or contact-resonance) oscillator: its free resonance and modal stiffness.

    Build it with :meth:`lumped`, :meth:`rod` or :meth:`rod_from_geometry`.

    Parameters
    ----------
    free_frequency : f0, the resonance without contact, Hz
    effective_stiffness : K_eff, the modal stiffness referred to the tip displacement, N/m (for
        a rod 2π² m f0² = (EA/L)(nπ)²/2, see the module docstring)
    model : "lumped" or "rod"
    mode : the rod's mode n >= 1 (f0 = n c/(2L)); 1 for the lumped model
    """

    free_frequency: float
    effective_stiffness: float
    model: str = "lumped"
    mode: int = 1

    def __post_init__(self):
        positive("RUM free_frequency f0", self.free_frequency, "Hz")
        positive("RUM effective_stiffness K_eff", self.effective_stiffness, "N/m")
        if self.model not in RUM_MODELS:
            raise ContactresInputError(
                f"RUM model must be one of {', '.join(RUM_MODELS)}, got {self.model!r}"
            )
        n = self.mode
        if not np.isfinite(n) or int(n) != n or n < 1:
            raise ContactresInputError(f"RUM mode must be an integer >= 1, got {n!r}")
        if self.model == "lumped" and n != 1:
            raise ContactresInputError(
                f"the lumped RUM model has one mode (mode=1), got mode={n!r}"
            )

    # ----------------------------------------------------------------------------- constructors
    @classmethod
    def lumped(cls, free_frequency: float, effective_stiffness: float) -> RUMOscillator:
        """Mass-on-spring oscillator: f0 in Hz, K_eff in N/m; (f/f0)² = 1 + k*/K_eff."""
        return cls(float(free_frequency), float(effective_stiffness), "lumped", 1)

    @classmethod
    def rod(cls, free_frequency: float, mass: float, mode: int = 1) -> RUMOscillator:
        """Rod (free end, spring at the tip end) from its free frequency f0 (Hz), mass m (kg)
        and mode n: K_eff = 2π² m f0² (effective mass m/2), EA/L = 4 m f0²/n²."""
        f0 = positive("RUM free_frequency f0", free_frequency, "Hz")
        m = positive("RUM rod mass m", mass, "kg")
        return cls(f0, 2.0 * math.pi**2 * m * f0**2, "rod", mode)

    @classmethod
    def rod_from_geometry(
        cls, length: float, area: float, modulus: float, density: float, mode: int = 1
    ) -> RUMOscillator:
        """Rod of length L (m), cross-section A (m²), Young's modulus E (Pa), density ρ (kg/m³):
        f0 = n √(E/ρ)/(2L), m = ρAL, K_eff = (EA/L)(nπ)²/2."""
        L = positive("RUM rod length L", length, "m")
        A = positive("RUM rod area A", area, "m^2")
        E = positive("RUM rod modulus E", modulus, "Pa")
        rho = positive("RUM rod density", density, "kg/m^3")
        if not np.isfinite(mode) or int(mode) != mode or mode < 1:
            raise ContactresInputError(f"RUM mode must be an integer >= 1, got {mode!r}")
        f0 = mode * math.sqrt(E / rho) / (2.0 * L)
        return cls.rod(f0, rho * A * L, int(mode))

    # ----------------------------------------------------------------------------- properties
    @property
    def effective_mass(self) -> float:
        """m_eff = K_eff/(2πf0)², kg (m/2 for a rod of mass m)."""
        return self.effective_stiffness / (2.0 * math.pi * self.free_frequency) ** 2

    @property
    def axial_stiffness(self) -> float:
        """EA/L of the rod, N/m (= 2 K_eff/(nπ)²); NaN for the lumped model."""
        if self.model != "rod":
            return math.nan
        return 2.0 * self.effective_stiffness / (self.mode * math.pi) ** 2

    @property
    def clamped_frequency(self) -> float:
        """The k* -> ∞ limit of f, Hz: (n + ½) f0/n for the rod; ∞ for the lumped model."""
        if self.model != "rod":
            return math.inf
        return (self.mode + 0.5) * self.free_frequency / self.mode

    # ----------------------------------------------------------------------------- conversions
    def _check_frequency(self, frequency) -> np.ndarray:
        f = np.asarray(positive("contact resonance frequency f", frequency, "Hz"), dtype=float)
        f0, fc = self.free_frequency, self.clamped_frequency
        bad = (f < f0) | (f >= fc)
        if np.any(bad):
            idx = np.unravel_index(np.flatnonzero(bad.ravel())[0], f.shape)
            where = "" if f.ndim == 0 else f" at index {idx[0] if len(idx) == 1 else idx}"
            upper = "" if self.model == "lumped" else f" and < the clamped limit {fc:.10g} Hz"
            raise ContactresInputError(
                f"contact resonance frequency f must be >= the free resonance f0 = {f0:.10g} Hz"
                f"{upper} ({self.model} model, mode {self.mode}), got {float(f[idx]):.10g} Hz"
                f"{where}"
            )
        return f

    def contact_stiffness(self, frequency):
        """k* (N/m) from the contact resonance frequency f (Hz); closed form, vectorised.

        Lumped: k* = K_eff (f − f0)(f + f0)/f0². Rod: k* = (EA/L)(nπ + θ) tan θ with
        θ = nπ (f − f0)/f0. f must lie in [f0, clamped limit) (ValueError otherwise).
        """
        f = self._check_frequency(frequency)
        f0 = self.free_frequency
        if self.model == "lumped":
            return _out(self.effective_stiffness * (f - f0) * (f + f0) / f0**2)
        npi = self.mode * math.pi
        theta = npi * (f - f0) / f0
        return _out(self.axial_stiffness * (npi + theta) * np.tan(theta))

    def frequency(self, k_star):
        """Contact resonance frequency f (Hz) for the contact stiffness k* >= 0 (N/m); vectorised.

        Lumped: f = f0 √(1 + k*/K_eff). Rod: the root of (nπ + θ) tan θ = k* L/(EA) on
        θ ∈ [0, π/2) (Newton, see the module docstring), f = f0 (1 + θ/(nπ)).
        """
        k = np.asarray(nonnegative("contact stiffness k*", k_star, "N/m"), dtype=float)
        f0 = self.free_frequency
        if self.model == "lumped":
            return _out(f0 * np.sqrt(1.0 + k / self.effective_stiffness))
        npi = self.mode * math.pi
        beta = k / self.axial_stiffness
        theta = np.arctan(beta / npi)
        for _ in range(_NEWTON_STEPS):
            x = npi + theta
            r = np.hypot(x, beta)  # β/(x² + β²) = (β/r)/r without overflow
            theta = theta - (theta - np.arctan(beta / x)) / (1.0 + (beta / r) / r)
        return _out(f0 * (1.0 + theta / npi))
