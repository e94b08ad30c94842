"""Tangential contact: Mindlin stiffness and force-displacement loops (paper 2, Eqs. 3-15).

A *loop* describes the tangential force of a contact whose surface is driven (displacement
control) as u(t) = u0 cos ωt. Every loop here is a small frozen dataclass with

* ``virgin(d)`` - the force on first loading from rest to displacement d, N;
* ``branches(u, u0)`` - the forces ``(F_plus, F_minus)`` on the way up (u from -u0 to u0) and on
  the way down, at displacement u with ``|u|`` <= u0, N;
* ``area(u0)`` - the loop area ∮F du, J (= energy dissipated per cycle);
* ``kinks(u0)`` - positions x = u/u0 in [-1, 1] where F₊ + F₋ is not smooth (nan if none), used by
  :func:`contactres.shifts_from_loop` to split its quadrature.

Loops built from a virgin curve by Masing's rule (Cattaneo-Mindlin, Savkoor, the stick plateau)
derive from :class:`MasingLoop`, which also exposes the slope deficit κ - F'(d) and the points where
the virgin curve is not analytic; :func:`contactres.shifts_from_loop` integrates those exactly.

All quantities SI: displacements m, forces N, stiffness N/m, drag coefficient ξ in kg/s (N s/m).

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein
J. Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .errors import ContactresInputError
from .normal import (
    effective_modulus,
    effective_shear_modulus,
    jkr_contact_radius,
    shear_modulus,
)
from .validation import amplitude as _amplitude
from .validation import nonnegative as _nonneg
from .validation import positive as _pos

__all__ = [
    "CattaneoMindlinLoop",
    "DashpotLoop",
    "HysteresisLoop",
    "MasingLoop",
    "PlateauLoop",
    "SavkoorLoop",
    "VoigtLoop",
    "kappa_jkr_mindlin",
    "mindlin_deresiewicz_energy",
    "mindlin_stiffness",
    "with_dashpot",
]

# Series coefficients c_k of 1 - √(1 - z) = Σ_{k>=1} c_k z^k (all positive): c_k =
# -(-1)^k binom(1/2, k), i.e. c_1 = 1/2 and c_{k+1} = c_k (k - 1/2)/(k + 1) (the binomial
# series, A&S 3.6.9). The product recurrence rounds each c_k correctly (checked against exact
# fractions in tests/test_tangential.py) and spares the import of scipy.special.
_NSERIES = 24
_K = np.arange(1, _NSERIES + 1, dtype=float)
_C = np.cumprod(np.concatenate([[0.5], (_K[:-1] - 0.5) / (_K[:-1] + 1.0)]))
# Below this amplitude ratio the loop area comes from its series (the closed form cancels).
_SERIES_BELOW = 0.1


def _branch_args(u, u0):
    u = np.asarray(u, dtype=float)
    u0 = _amplitude(u0)
    u, u0 = np.broadcast_arrays(u, u0)
    outside = np.abs(u) > u0 * (1 + 1e-12) + 1e-300
    if np.any(outside):
        i = np.flatnonzero(outside)[0]
        bad_u, bad_u0 = float(u.flat[i]), float(u0.flat[i])
        raise ContactresInputError(
            f"branches(u, u0) needs |u| <= u0, got u = {bad_u!r} m, u0 = {bad_u0!r} m"
        )
    return u, u0


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def mindlin_stiffness(a, G_star):
    """Tangential stiffness of a circular stick contact, κ = 2 G* a, N/m (paper 2, below Eq. 6).

    ``a``: contact radius, m; ``G_star``: effective shear modulus of paper 2, Eq. 7 (four times
    Johnson's G*), Pa (see :func:`contactres.effective_shear_modulus`).
    """
    a = _nonneg("contact radius a", a, "m")
    G_star = _pos("G_star", G_star, "Pa")
    return _out(2.0 * G_star * a)


def mindlin_deresiewicz_energy(force_amplitude, kappa, mu, normal_force):
    """Energy dissipated per cycle by a Cattaneo-Mindlin contact, J (Mindlin & Deresiewicz 1953).

    For a tangential force oscillating between ±Q* at constant normal force P (Johnson,
    *Contact Mechanics*, Eq. 7.59, written with κ = 8 a G*_Johnson):

        W = (36 μ²P² / (5κ)) [1 - (1 - q)^{5/3} - (5q/6)(1 + (1 - q)^{2/3})],  q = Q*/(μP) <= 1.

    ``force_amplitude`` Q* in N (array), ``kappa`` in N/m, ``mu`` dimensionless, P in N.
    """
    kappa, mu, P = _pos("kappa", kappa), _pos("mu", mu), _pos("normal_force", normal_force)
    Q = np.asarray(force_amplitude, dtype=float)
    q = Q / (mu * P)
    if not np.all(q >= 0) or np.any(q > 1 + 1e-12):
        raise ContactresInputError(f"force_amplitude must lie in [0, μP] = [0, {mu * P!r}] N")
    q = np.minimum(q, 1.0)
    r = 1.0 - q
    w = 1.0 - r ** (5.0 / 3.0) - (5.0 * q / 6.0) * (1.0 + r ** (2.0 / 3.0))
    return _out(36.0 * (mu * P) ** 2 / (5.0 * kappa) * w)


class MasingLoop:
    """Base of loops built from an odd virgin curve F(d) by Masing's rule (paper 2, after Eq. 6).

    F₊(u) = -F(u0) + 2F((u + u0)/2),  F₋(u) = F(u0) - 2F((u0 - u)/2).

    Subclasses define ``kappa`` (initial slope, N/m), ``_virgin(d)`` and ``_virgin_integral(d)``
    (∫₀^d F, for d >= 0), ``slope_loss(d)`` (κ - F'(d) >= 0, computed without cancellation),
    ``breaks`` (displacements d > 0 where F' is not analytic, ascending) and
    ``singular_points`` (where F' has algebraic singularities, possibly negative).
    """

    kappa: float

    def _virgin(self, d):  # pragma: no cover - abstract
        raise NotImplementedError

    def _virgin_integral(self, d):  # pragma: no cover - abstract
        raise NotImplementedError

    def slope_loss(self, d):  # pragma: no cover - abstract
        """κ - F'(d) for d >= 0, N/m (accurate where F' is close to κ)."""
        raise NotImplementedError

    def slope(self, d):
        """F'(d) for d >= 0, N/m (accurate where F' is small, i.e. near full sliding)."""
        return self.kappa - self.slope_loss(d)

    def slopes(self, d):
        """(F'(d), κ - F'(d)) together (subclasses share the work), N/m."""
        return self.slope(d), self.slope_loss(d)

    @property
    def breaks(self) -> tuple[float, ...]:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def singular_points(self) -> tuple[float, ...]:
        return self.breaks

    def _area_series(self, u0):
        """Loop area for small u0 without cancellation (None: use the closed form)."""
        return None

    def slack(self, d):
        """κd - F(d) = ∫₀^d (κ - F') for d >= 0, N (overridden where a series avoids the
        cancellation): the force the contact lacks against full stick."""
        d = np.asarray(d, dtype=float)
        return self.kappa * d - self._virgin(d)

    def virgin(self, d):
        """Virgin (first-loading) force F(d), N; odd in d."""
        d = np.asarray(d, dtype=float)
        return _out(np.sign(d) * self._virgin(np.abs(d)))

    def branches(self, u, u0):
        """(F₊, F₋) at displacement u (``|u|`` <= u0) of the loop of amplitude u0, N (Masing)."""
        u, u0 = _branch_args(u, u0)
        Fu0 = self._virgin(u0)
        up = -Fu0 + 2.0 * self._virgin(np.maximum((u + u0) / 2.0, 0.0))
        down = Fu0 - 2.0 * self._virgin(np.maximum((u0 - u) / 2.0, 0.0))
        return _out(up), _out(down)

    def area(self, u0):
        """Loop area ∮F du = 8∫₀^{u0} F - 4 u0 F(u0), J (energy per cycle)."""
        u0 = _amplitude(u0)
        closed = 8.0 * self._virgin_integral(u0) - 4.0 * u0 * self._virgin(u0)
        series = self._area_series(u0)
        if series is None:
            return _out(closed)
        small, value = series
        return _out(np.where(small, value, closed))

    def kinks(self, u0):
        """x = u/u0 where F₊ + F₋ is not smooth: ±(2b/u0 - 1) for each break b (nan if outside)."""
        u0 = _amplitude(u0)
        b = np.asarray(self.breaks, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = 2.0 * b / u0[..., None] - 1.0
        x = np.concatenate([x, -x], axis=-1)
        return np.where(np.abs(x) < 1.0, x, np.nan)


def _one_minus_sqrt(z):
    """1 - √(1 - z) without cancellation, for z <= 1."""
    return z / (1.0 + np.sqrt(np.maximum(1.0 - z, 0.0)))


@dataclass(frozen=True)
class CattaneoMindlinLoop(MasingLoop):
    """Cattaneo-Mindlin partial slip under Coulomb friction (paper 2, Eq. 6), Masing loops.

    F(d) = μF_N [1 - (1 - d/d*)^{3/2}] for d <= d* = 3μF_N/(2κ), F = μF_N beyond (full sliding:
    the loop becomes a parallelogram of height 2μF_N). ``kappa`` N/m, ``mu`` -, ``normal_force`` N.

    Examples
    --------
    >>> loop = CattaneoMindlinLoop(kappa=1000.0, mu=0.5, normal_force=1e-3)  # N/m, -, N
    >>> loop.slip_displacement, loop.sliding_force, loop.virgin(loop.slip_displacement)  # m, N, N
    (7.5e-07, 0.0005, 0.0005)
    """

    kappa: float
    mu: float
    normal_force: float

    def __post_init__(self):
        _pos("kappa", self.kappa)
        _pos("mu", self.mu)
        _pos("normal_force", self.normal_force)

    @property
    def sliding_force(self) -> float:
        """μF_N, N."""
        return self.mu * self.normal_force

    @property
    def slip_displacement(self) -> float:
        """d* = 3μF_N/(2κ), m: beyond it the contact slides completely."""
        return 1.5 * self.mu * self.normal_force / self.kappa

    @property
    def breaks(self):
        return (self.slip_displacement,)

    def _virgin(self, d):
        z = np.minimum(d / self.slip_displacement, 1.0)
        return self.sliding_force * (1.0 - (1.0 - z) ** 1.5)

    def _virgin_integral(self, d):
        ds = self.slip_displacement
        z = np.minimum(d / ds, 1.0)
        part = d - np.maximum(d - ds, 0.0)  # min(d, d*)
        inside = part - 0.4 * ds * (1.0 - (1.0 - z) ** 2.5)
        return self.sliding_force * (inside + np.maximum(d - ds, 0.0))

    def slope_loss(self, d):
        z = np.asarray(d, dtype=float) / self.slip_displacement
        return self.kappa * np.where(z < 1.0, _one_minus_sqrt(np.minimum(z, 1.0)), 1.0)

    def slope(self, d):
        z = np.asarray(d, dtype=float) / self.slip_displacement
        return self.kappa * np.sqrt(np.maximum(1.0 - z, 0.0))

    def slopes(self, d):
        z = np.asarray(d, dtype=float) / self.slip_displacement
        r = np.sqrt(np.maximum(1.0 - z, 0.0))
        return self.kappa * r, self.kappa * np.where(z < 1.0, z / (1.0 + r), 1.0)

    def _area_series(self, u0):
        # area = 4κu0² Σ c_k λ^k k/((k+1)(k+2)),  λ = u0/d*  (from area = -4∫ loss (u0 - 2d) dd)
        lam = np.asarray(u0, dtype=float) / self.slip_displacement
        lk = np.minimum(lam, _SERIES_BELOW)[..., None] ** _K
        s = np.sum(_C * lk * _K / ((_K + 1) * (_K + 2)), axis=-1)
        return lam < _SERIES_BELOW, 4.0 * self.kappa * u0**2 * s

    def slack(self, d):
        # κd - F(d) = κd* Σ c_k z^{k+1}/(k+1) at small z = d/d*
        d = np.asarray(d, dtype=float)
        z = d / self.slip_displacement
        zk = np.minimum(z, _SERIES_BELOW)[..., None] ** (_K + 1)
        series = self.kappa * self.slip_displacement * np.sum(_C * zk / (_K + 1), axis=-1)
        return np.where(z < _SERIES_BELOW, series, self.kappa * d - self._virgin(d))


@dataclass(frozen=True)
class SavkoorLoop(MasingLoop):
    """Savkoor's partial slip with a constant sliding traction τ0 (paper 2, Eqs. 13-14).

    √(a² - c²) = κd/(4aτ0) (stick radius c), F(d) = 2τ0[a² arccos(c/a) + c√(a² - c²)]; full
    sliding at d_s = 4a²τ0/κ, where F = πa²τ0. ``kappa`` N/m, ``tau`` Pa, ``a`` (contact radius) m.
    """

    kappa: float
    tau: float
    a: float

    def __post_init__(self):
        _pos("kappa", self.kappa)
        _pos("tau", self.tau)
        _pos("a", self.a)

    @property
    def sliding_force(self) -> float:
        """πa²τ0, N."""
        return np.pi * self.a**2 * self.tau

    @property
    def slip_displacement(self) -> float:
        """d_s = 4a²τ0/κ, m."""
        return 4.0 * self.a**2 * self.tau / self.kappa

    @property
    def breaks(self):
        return (self.slip_displacement,)

    @property
    def singular_points(self):
        return (self.slip_displacement, -self.slip_displacement)

    def _virgin(self, d):
        z = np.minimum(d / self.slip_displacement, 1.0)
        return 2.0 * self.tau * self.a**2 * (np.arcsin(z) + z * np.sqrt(1.0 - z * z))

    def _virgin_integral(self, d):
        ds = self.slip_displacement
        z = np.minimum(d / ds, 1.0)
        r = np.sqrt(1.0 - z * z)
        inside = z * np.arcsin(z) + r - 1.0 + (1.0 - r**3) / 3.0
        return 2.0 * self.tau * self.a**2 * ds * inside + self.sliding_force * np.maximum(
            d - ds, 0.0
        )

    def slope_loss(self, d):
        z = np.asarray(d, dtype=float) / self.slip_displacement
        return self.kappa * np.where(z < 1.0, _one_minus_sqrt(np.minimum(z, 1.0) ** 2), 1.0)

    def slope(self, d):
        z = np.minimum(np.asarray(d, dtype=float) / self.slip_displacement, 1.0)
        return self.kappa * np.sqrt((1.0 - z) * (1.0 + z))

    def _area_series(self, u0):
        # area = 4κu0² Σ c_k λ^{2k} 2k/((2k+1)(2k+2)),  λ = u0/d_s
        lam = np.asarray(u0, dtype=float) / self.slip_displacement
        lk = np.minimum(lam, _SERIES_BELOW)[..., None] ** (2 * _K)
        s = np.sum(_C * lk * 2 * _K / ((2 * _K + 1) * (2 * _K + 2)), axis=-1)
        return lam < _SERIES_BELOW, 4.0 * self.kappa * u0**2 * s

    def slack(self, d):
        # κd - F(d) = κd_s Σ c_k z^{2k+1}/(2k+1) at small z = d/d_s
        d = np.asarray(d, dtype=float)
        z = d / self.slip_displacement
        zk = np.minimum(z, _SERIES_BELOW)[..., None] ** (2 * _K + 1)
        series = self.kappa * self.slip_displacement * np.sum(_C * zk / (2 * _K + 1), axis=-1)
        return np.where(z < _SERIES_BELOW, series, self.kappa * d - self._virgin(d))


@dataclass(frozen=True)
class PlateauLoop(MasingLoop):
    """A Masing loop whose contact edge sticks below a critical displacement d_c.

    Virgin curve: F = κd for d <= d_c, then κd_c + F_inner(d - d_c), where F_inner is the virgin
    curve of ``loop`` (same κ). The shifts stay at their low-amplitude values for u0 <= d_c (the
    "plateau" seen in some sweeps of paper 2) and then follow the inner model. The sliding force
    is F_inner's plus κd_c. ``critical_displacement`` in m.
    """

    loop: MasingLoop
    critical_displacement: float

    def __post_init__(self):
        if not isinstance(self.loop, MasingLoop):
            raise ContactresInputError(
                "PlateauLoop needs a Masing loop (Cattaneo-Mindlin, Savkoor)"
            )
        _nonneg("critical_displacement", self.critical_displacement)

    @property
    def kappa(self) -> float:  # type: ignore[override]
        return self.loop.kappa

    @property
    def breaks(self):
        dc = self.critical_displacement
        return (dc, *tuple(b + dc for b in self.loop.breaks))

    @property
    def singular_points(self):
        # d_c is a break (F'' jumps) but not a square-root singularity
        dc = self.critical_displacement
        return tuple(p + dc for p in self.loop.singular_points)

    def _virgin(self, d):
        dc = self.critical_displacement
        d = np.asarray(d, dtype=float)
        return np.where(
            d <= dc, self.kappa * d, self.kappa * dc + self.loop._virgin(np.maximum(d - dc, 0.0))
        )

    def _virgin_integral(self, d):
        dc = self.critical_displacement
        d = np.asarray(d, dtype=float)
        e = np.maximum(d - dc, 0.0)
        lin = 0.5 * self.kappa * np.minimum(d, dc) ** 2
        return lin + self.kappa * dc * e + self.loop._virgin_integral(e)

    def slope_loss(self, d):
        e = np.maximum(np.asarray(d, dtype=float) - self.critical_displacement, 0.0)
        return self.loop.slope_loss(e)

    def slope(self, d):
        e = np.maximum(np.asarray(d, dtype=float) - self.critical_displacement, 0.0)
        return self.loop.slope(e)

    def slopes(self, d):
        e = np.maximum(np.asarray(d, dtype=float) - self.critical_displacement, 0.0)
        return self.loop.slopes(e)

    def area(self, u0):
        """Loop area, J: inner area at v = u0 - d_c + 4 d_c (κv - F_inner(v)), no cancellation."""
        u0 = _amplitude(u0)
        v = np.maximum(u0 - self.critical_displacement, 0.0)
        inner = np.asarray(self.loop.area(v), dtype=float)
        return _out(inner + 4.0 * self.critical_displacement * self.loop.slack(v))


@dataclass(frozen=True)
class VoigtLoop:
    """Linear viscoelastic contact (a spring κ and a dashpot ξ in parallel): an ellipse.

    F± = κu ± ωξ√(u0² - u²) (paper 2, Eq. 4-5 with Eq. 1). ``kappa`` N/m, ``xi`` kg/s,
    ``omega`` rad/s (use :attr:`contactres.QCM.omega`).
    """

    kappa: float
    xi: float
    omega: float

    def __post_init__(self):
        _nonneg("kappa", self.kappa)
        _nonneg("xi", self.xi)
        _pos("omega", self.omega)

    def virgin(self, d):
        return _out(self.kappa * np.asarray(d, dtype=float))

    def branches(self, u, u0):
        u, u0 = _branch_args(u, u0)
        visc = self.omega * self.xi * np.sqrt(np.maximum(u0**2 - u**2, 0.0))
        return _out(self.kappa * u + visc), _out(self.kappa * u - visc)

    def area(self, u0):
        return _out(np.pi * self.omega * self.xi * _amplitude(u0) ** 2)

    def kinks(self, u0):
        return np.empty((*np.shape(u0), 0))


class HysteresisLoop(Protocol):
    """What :class:`DashpotLoop` reads of the loop inside it (any loop of this module will do):
    initial slope ``kappa`` (N/m), the virgin curve, the two branches, the area and the kinks."""

    @property
    def kappa(self) -> float: ...

    def virgin(self, d): ...

    def branches(self, u, u0): ...

    def area(self, u0): ...

    def kinks(self, u0): ...


@dataclass(frozen=True)
class DashpotLoop:
    """Any loop with a linear dashpot ξ in parallel (paper 2, Eq. 12: the ad-hoc viscous term).

    Adds ±ωξ√(u0² - u²) to the branches and πωξu0² to the area, hence exactly ωξ to K″.
    """

    loop: HysteresisLoop
    xi: float
    omega: float

    def __post_init__(self):
        _nonneg("xi", self.xi)
        _pos("omega", self.omega)
        for name in ("virgin", "branches", "area", "kinks"):
            if not hasattr(self.loop, name):
                raise ContactresInputError(f"DashpotLoop: the inner loop has no {name}()")

    @property
    def kappa(self) -> float:
        return self.loop.kappa

    def virgin(self, d):
        return self.loop.virgin(d)

    def branches(self, u, u0):
        u, u0 = _branch_args(u, u0)
        up, down = self.loop.branches(u, u0)
        visc = self.omega * self.xi * np.sqrt(np.maximum(u0**2 - u**2, 0.0))
        return _out(up + visc), _out(down - visc)

    def area(self, u0):
        u0 = _amplitude(u0)
        return _out(self.loop.area(u0) + np.pi * self.omega * self.xi * u0**2)

    def kinks(self, u0):
        return self.loop.kinks(u0)


def with_dashpot(loop, xi: float, omega: float) -> DashpotLoop:
    """``loop`` plus a linear dashpot ξ (kg/s) at angular frequency ω (rad/s)."""
    return DashpotLoop(loop, xi, omega)


def kappa_jkr_mindlin(force, E, gamma, radius, poisson):
    """Tangential stiffness κ(F_N) of a sphere on a flat of the same material, N/m.

    κ = 2G*a (paper 2, below Eq. 6), G* from Eq. 7 with G = E/(2(1 + ν)) (Eq. 8) on both sides,
    a from JKR (Eq. 9) with E* from Eq. 10 (E1 = E2 = E, ν1 = ν2 = ν). ``force`` N per contact,
    ``E`` Pa, ``gamma`` J/m² (paper 2's γ; work of adhesion w = 2γ), ``radius`` m.
    """
    E_star = effective_modulus(E, poisson)
    G_star = effective_shear_modulus(shear_modulus(E, poisson), poisson)
    a = jkr_contact_radius(E_star, radius, force, gamma)
    return mindlin_stiffness(a, G_star)
