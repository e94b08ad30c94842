"""The table of a coated plate's film corrections and the coated law κ(F_N; E, γ) on it.

The physics (compliance method, tangential stiffness, the film's constants) and the fit:
:mod:`contactres.analysis._coating`; here the table and its interpolation.

**Speed: a table in (E, a).** The layered problem has no scaling in E (the film is fixed, the
substrate scales), so the three film corrections

    q_n = (C(a) − 1/(2aE*)) a²/h,   q_f = (a³/(R P'(a)) − 3/(4E*)) a/h,
    q_t = (C_t(a) − 2(2 − ν)/(8Ga)) a²/h   (complex; C_t the pair's tangential compliance)

(E* = E/(2(1 − ν²)) of the homogeneous pair, h the total film thickness) are solved on a grid
of contact radii and a few Young's moduli (:func:`build_law`) and interpolated: a cubic spline
in ln a (the derivative dC/da from it) and a Lagrange polynomial in ln E. They are nearly
independent of E for a thin film (a film's compression h/(πa²M_f) does not involve the
substrate), so five Chebyshev nodes in E suffice for films softer than the substrate; a film
stiffer than it spreads the load over the substrate, whose compliance its corrections then
carry, and gets seven (:func:`_node_count`). The measured interpolation error is stated in
:func:`build_law` (tested). The layered solutions at the table's E share their quadrature
nodes (set by the film, not by E), so the Galerkin's basis transforms there are computed once
per radius and direction (``transforms=``). The E range of the table is the fit's bound; a
contact radius outside the table is clamped to it while the fit searches
(:meth:`CoatedLaw.contact_radius` returns where): what the analysis then does, in
:mod:`contactres.analysis._coating`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline, PPoly

from ..fitting import Model, Parameter
from ..layered import FrequencyDependentMaterial, LayeredMaterial, material_at, thickness_text
from ..materials import Material
from ..normal import indentation_modulus, sphere_contact_at, static_punch_stiffness
from ..numerics import illinois_step
from ..units import POISSON_OPEN_RANGE
from ..viscoelastic import static_solid

__all__ = ["CoatedLaw", "Coating", "build_law"]

# Kernel truncation of the table's layered solutions (relative; the default 1e-12 costs twice
# as much and moves the corrections by < 1e-8, far below the interpolation error).
_TABLE_TOL = 1e-6
# The contact radius, in thicknesses of the coating, below which the table has _DENSER times
# as many radii a decade (_table_radii; measured in build_law: 5 a decade leave up to 2e-3 in
# P' at a/h < 2, 10 still 1.2e-4 in C (PMMA at a/h 0.2-2 on 30-240 GPa, tested) and 1.7e-4
# in P' (two layers), 15 meet the stated accuracy). The coarse spacing's first interval above
# the knee leaves the most of a table (build_law: up to 2.7e-4 in P'); the knee stays: moved up
# it would change the tables wholly above it (the bundled example's 250 nm of PMMA).
_THICK_FILM = 4.0
_DENSER = 3
# The table's E nodes (build_law, _node_count): five where every layer of the coating is softer
# than the substrate at the table's lowest E (the corrections then hardly depend on E: a film's
# own compression), seven where one is stiffer (the film spreads the load over the substrate,
# whose compliance the corrections then carry: five left 1.1e-4 in C for 300 GPa on 10-40 GPa,
# up to 8e-4 on 30-240 GPa; seven leave <= 6.1e-6, measured in build_law).
_N_E_SOFT = 5
_N_E_STIFF = 7
# Iterations of the contact-radius solve (Illinois on ln a) and its tolerance (relative in F).
_MAX_ITER = 80
_FORCE_RTOL = 1e-9
# Entries per distinct E above which a grid's splines are evaluated each at its own entries
# (CoatedLaw._by_value): below, one call for all costs less than a call per value.
_PER_VALUE = 20


@dataclass(frozen=True)
class Coating:
    """The film(s) on the plate, top first: (material, thickness_m) pairs.

    A material is a :class:`~contactres.Material` or a frequency-dependent one with ``at(f)``
    (e.g. :func:`contactres.pmma`), in the plate's surface frame.
    """

    layers: tuple[tuple[Material | FrequencyDependentMaterial, float], ...]

    @property
    def label(self) -> str:
        """E.g. ``"PMMA 250 nm"`` (layers top first, joined by "on"; each thickness in the
        unit that reads best, :func:`contactres.layered.thickness_text`)."""
        return " on ".join(
            f"{getattr(m, 'name', None) or 'film'} {thickness_text(h)}" for m, h in self.layers
        )

    @property
    def thickness(self) -> float:
        """The total thickness, m."""
        return float(sum(h for _, h in self.layers))

    def record(self) -> dict:
        """The JSON-safe description (summary.json)."""
        return {
            "label": self.label,
            "layers": [
                {"material": getattr(m, "name", None) or "film", "thickness_m": h}
                for m, h in self.layers
            ],
        }


def _solids(E: float, nu: float, coating: Coating, frequency: float):
    """(sphere, static plate, plate at the frequency): isotropic (E, ν) under the film."""
    body = Material.isotropic(E, nu, name="substrate")
    # The normal load is static: each film's storage constants at STATIC_FREQUENCY_HZ; the
    # tangential stiffness is the overtone's: the film's constants there (complex if lossy).
    static = LayeredMaterial(body, [(static_solid(m), h) for m, h in coating.layers])
    dynamic = LayeredMaterial(body, [(material_at(m, frequency), h) for m, h in coating.layers])
    return body, static, dynamic


def _corrections(
    E: float,
    nu: float,
    coating: Coating,
    frequency: float,
    a: np.ndarray,
    transforms: dict | None = None,
):
    """(q_n, q_f, Re q_t, Im q_t) at one E and the radii ``a`` (module docstring), shape
    (a.size, 4), 1/Pa. ``transforms``: the store of the layered solutions' basis transforms
    at the radii ``a`` (:func:`~contactres.normal.static_punch_stiffness`), shared by the
    table's E (the quadrature nodes depend on the film, not on E: the transforms are
    computed once per radius and direction, not once per E)."""
    sphere, static, dynamic = _solids(E, nu, coating, frequency)
    h = coating.thickness
    e_star = E / (2 * (1 - nu**2))
    g = E / (2 * (1 + nu))
    normal = sphere_contact_at(
        static, 1.0, a, tol=_TABLE_TOL, indenter=sphere, transforms=transforms
    )
    q_n = (1 / np.asarray(normal.stiffness) - 1 / (2 * a * e_star)) * a**2 / h
    q_f = (a**3 / np.asarray(normal.force) - 3 / (4 * e_star)) * a / h
    pair = static_punch_stiffness(
        dynamic, a, "tangential", tol=_TABLE_TOL, indenter=sphere, transforms=transforms
    )
    q_t = (1 / np.asarray(pair) - 2 * (2 - nu) / (8 * g * a)) * a**2 / h
    return np.stack([q_n, q_f, q_t.real, q_t.imag], axis=-1)


def _node_sum(w: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Σ_j w_j q_j over the table's E nodes (axis −2 of both; ``w`` (..., n_E, 1) broadcast
    against ``q`` (..., n_E, k)): the Lagrange interpolation in ln E of the nodes' values.

    Added node by node, in their order, as numpy's ``(w * q).sum(axis=-2)`` adds along so short
    a strided axis (one term after the other: the same sums), and one column of q at a time:
    numpy's reduction, or a product of the (..., k) slices, runs its inner loop over the k = 2
    columns, ~3x the cost of these products over the entries (~0.4 ms against ~0.06 ms at
    3600 entries; the bootstrap's contact-radius solve evaluates it ~15 times per solve)."""
    lead = np.broadcast_shapes(w.shape[:-2], q.shape[:-2])  # (w's leading axes may be q's or more)
    out = np.empty(lead + q.shape[-1:], dtype=np.result_type(w, q))
    term = np.empty(lead, dtype=out.dtype)
    for c in range(q.shape[-1]):
        col = out[..., c]
        np.multiply(w[..., 0, 0], q[..., 0, c], out=col)
        for j in range(1, q.shape[-2]):
            col += np.multiply(w[..., j, 0], q[..., j, c], out=term)
    return out


def _broadcast(E, a) -> tuple[np.ndarray, np.ndarray]:
    """E and a as float arrays of one shape: as they come where they have it already (each
    step of the contact-radius solve: numpy's broadcast_arrays costs ~5 us per call)."""
    E, a = np.asarray(E, dtype=float), np.asarray(a, dtype=float)
    if E.shape != a.shape:
        E, a = np.broadcast_arrays(E, a)
    return E, a


def _with_derivative(poly: PPoly) -> PPoly:
    """One piecewise polynomial of ``poly``'s columns followed by those of its derivative, so
    that a contact-radius step evaluates both in one call (~1500 steps of a coated analysis).

    The derivative's coefficients (``poly.derivative()``: one degree less) get a zero leading
    coefficient: scipy sums a piece's terms from the lowest power up, so the zero's term comes
    last and adds +0 (−0 left of the first breakpoint), which leaves every sum as it was but
    a −0 (none here: a nonzero sum): the same values as the derivative evaluated apart, at
    finite x (where a power of x overflows, 0 times it is NaN; the law's x = ln a is finite
    and within the table)."""
    d = poly.derivative().c
    padded = np.concatenate([np.zeros((1, *d.shape[1:])), d])
    return PPoly(np.concatenate([poly.c, padded], axis=-1), poly.x)


@dataclass(frozen=True)
class CoatedLaw:
    """κ(F_N; E, γ) on a coated plate from the tabulated film corrections (module docstring).

    Attributes
    ----------
    coating : the film(s)
    poisson : ν of sphere and substrate
    frequency : Hz, at which the film's tangential constants are taken
    E_nodes : Young's moduli of the table, Pa (Chebyshev nodes in ln E over ``E_range``)
    log_a : ln of the table's contact radii (m)
    values : (len(log_a), len(E_nodes), 4): q_n, q_f, Re q_t, Im q_t, 1/Pa
    E_range : (lowest, highest) E of the table, Pa: the fit's bounds
    """

    coating: Coating
    poisson: float
    frequency: float
    E_nodes: np.ndarray
    log_a: np.ndarray
    values: np.ndarray
    E_range: tuple[float, float]
    spline: CubicSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "spline", CubicSpline(self.log_a, self.values, axis=0))

    @property
    def radius_range(self) -> tuple[float, float]:
        """The smallest and largest tabulated contact radius, m."""
        return float(np.exp(self.log_a[0])), float(np.exp(self.log_a[-1]))

    def _weights(self, E) -> np.ndarray:
        """Lagrange weights in ln E of the table's nodes at E (shape E.shape + (n_E,))."""
        x = np.log(self.E_nodes)
        t = np.log(np.asarray(E, dtype=float))
        if t.ndim == 0:
            # One E (each contact-radius solve of a fit): the same products in Python floats
            # (IEEE doubles, the same roundings), not ~60 numpy calls on 0-d arrays.
            xs, tv = x.tolist(), float(t)
            one = [1.0] * len(xs)
            for j in range(len(xs)):
                for m in range(len(xs)):
                    if m != j:
                        one[j] *= (tv - xs[m]) / (xs[j] - xs[m])
            return np.array(one)
        w = np.ones((*t.shape, x.size))
        for j in range(x.size):
            for m in range(x.size):
                if m != j:
                    w[..., j] *= (t - x[m]) / (x[j] - x[m])
        return w

    def _interpolant(
        self, E, columns: slice = slice(None), slope: bool = True, by_value: bool = False
    ):
        """a -> (q, dq/d ln a), each a.shape + (4,), at Young's modulus E (an array broadcast
        against a, or one value: then the spline of that E alone, a fifth of the work);
        ``columns``: only these of the four (the others are not evaluated; q[..., columns] of
        the whole has the same values); ``slope``: False leaves dq None; ``by_value``: E takes
        a few values (a grid): each value's spline as one value's alone, all evaluated at once
        (the same numbers as one call per value, without a call per value)."""
        E = np.asarray(E, dtype=float)
        coef = self.spline.c[..., columns]
        if by_value:
            return self._by_value(E, coef, slope)
        if E.size and np.all(E == E.flat[0]):
            c = np.einsum("j,abjk->abk", self._weights(E.flat[0]), coef)
            one = PPoly(c, self.spline.x)
            if not slope:
                return lambda a, at=None: (one(np.log(a)), None)
            both = _with_derivative(one)
            k = c.shape[-1]

            def single(a, at=None):
                q = both(np.log(a))
                return q[..., :k], q[..., k:]

            return single
        w = self._weights(E)[..., None]
        part = PPoly(coef, self.spline.x)

        def values(a, at=None):
            # ``at``: a at the entries ``at`` of E only (the others' weights left out).
            wa = w if at is None else w[at]
            x = np.log(a)
            return _node_sum(wa, part(x)), _node_sum(wa, part(x, 1)) if slope else None

        return values

    def _by_value(self, E: np.ndarray, coef: np.ndarray, slope: bool):
        """:meth:`_interpolant` with ``by_value``: the spline of each distinct value of E (made
        as for that value alone: the same coefficients). Few entries: all the splines side by
        side in one piecewise polynomial, evaluated at every a and each entry's own taken (the
        others cost little against a call each); many (> :data:`_PER_VALUE` per value, the
        first steps of the bootstrap's grid of 15 E): each value's spline at its own entries
        only (a fifteenth of the evaluations: ~1.0 -> ~0.2 ms at 1350 entries). A column of a
        piecewise polynomial is evaluated alone either way: the same values."""
        levels, index = np.unique(E, return_inverse=True)
        cols = coef.shape[-1]
        each = [
            PPoly(np.einsum("j,abjk->abk", self._weights(v), coef), self.spline.x) for v in levels
        ]
        one = PPoly(np.concatenate([p.c for p in each], axis=-1), self.spline.x)
        # With the slope: the splines' columns, then their derivatives', in one call.
        parts = 2 if slope else 1
        poly = _with_derivative(one) if slope else one
        own = [_with_derivative(p) for p in each] if slope else each

        def pick(x, rows):
            flat, rows = np.ravel(x), np.ravel(rows)
            if flat.size > _PER_VALUE * levels.size:
                out = np.empty((flat.size, parts, cols))
                order = np.argsort(rows, kind="stable")
                ends = np.searchsorted(rows[order], np.arange(levels.size + 1))
                for v in np.flatnonzero(np.diff(ends)):
                    at = order[ends[v] : ends[v + 1]]
                    out[at] = own[v](flat[at]).reshape(at.size, parts, cols)
            else:
                out = poly(flat).reshape(flat.size, parts, levels.size, cols)
                out = out[np.arange(flat.size), :, rows]  # (entries, parts, cols)
            return [out[:, i].reshape(*np.shape(x), cols) for i in range(parts)]

        rows_all = index.reshape(E.shape)

        def values(a, at=None):
            # ``at``: a at the entries ``at`` of E only (as :meth:`_interpolant`'s).
            rows = rows_all if at is None else rows_all[at]
            q = pick(np.log(a), rows)
            return q[0], q[1] if slope else None

        return values

    def normal(self, E, a, interp=None):
        """(C, −dC/da, P'R/a³): the pair's punch compliance (m/N), its derivative (1/N) and
        the non-adhesive force factor (Pa) at contact radius a, Young's modulus E
        (``interp``: :meth:`normal_interpolant` of E, if already made)."""
        E, a = np.broadcast_arrays(np.asarray(E, float), np.asarray(a, float))
        q, minus_dC, force = self._normal_terms(E, a, interp)
        C = 1 / (2 * a * self._e_star(E)) + q[..., 0] * self.coating.thickness / a**2
        return C, minus_dC, force

    def _e_star(self, E):
        return E / (2 * (1 - self.poisson**2))

    def _normal_terms(self, E, a, interp=None):
        """(q, −dC/da, P'R/a³) at E and a (broadcast already): :meth:`normal` without C."""
        h = self.coating.thickness
        e_star = self._e_star(E)
        q, dq = (interp or self.normal_interpolant(E))(a)
        minus_dC = 1 / (2 * a**2 * e_star) + (2 * q[..., 0] - dq[..., 0]) * h / a**3
        force = 1 / (3 / (4 * e_star) + q[..., 1] * h / a)
        return q, minus_dC, force

    def normal_interpolant(self, E, by_value: bool = False):
        """:meth:`_interpolant` of q_n and q_f (the normal contact's two columns) at E."""
        return self._interpolant(E, slice(0, 2), by_value=by_value)

    def force(self, E, gamma, a, R, interp=None):
        """P(a) of the adhesive contact, N (module docstring)."""
        E, a = _broadcast(E, a)
        _, minus_dC, factor = self._normal_terms(E, a, interp)
        return factor * a**3 / R - np.sqrt(8 * np.pi * gamma * a / minus_dC)

    def contact_radius(self, F, E, gamma, R, by_value: bool = False):
        """a(F) on the stable branch, m, and a mask of the radii clamped to the table
        (``by_value``: E takes a few values, :meth:`_interpolant`)."""
        arrays = np.broadcast_arrays(*(np.asarray(v, float) for v in (F, E, gamma, R)))
        shape = arrays[0].shape
        F, E, gamma, R = (np.ravel(v) for v in arrays)
        lo = np.full(F.shape, self.log_a[0])
        hi = np.full(F.shape, self.log_a[-1])
        interp = self.normal_interpolant(E, by_value)  # E is fixed while a is sought

        def f(x, at=slice(None)):
            # At the entries ``at`` only: each entry's arithmetic is that of the whole.
            return (
                self.force(E[at], gamma[at], np.exp(x[at]), R[at], lambda a: interp(a, at)) - F[at]
            )

        f_lo, f_hi = f(lo), f(hi)
        below, above = f_lo > 0, f_hi < 0
        x = np.where(below, lo, hi)
        todo = ~(below | above)
        side = np.zeros(F.shape, dtype=int)
        tol = _FORCE_RTOL * np.maximum(np.abs(F), np.abs(f_hi - f_lo))
        for _ in range(_MAX_ITER):
            if not todo.any():
                break
            x_new = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
            x = np.where(todo, x_new, x)
            # The force only where the root is still sought (most converge in a few steps).
            at = np.flatnonzero(todo)
            fx = np.zeros(F.shape)
            fx[at] = f(x, at)
            todo &= np.abs(fx) > tol
            lo, hi, f_lo, f_hi, side = illinois_step(x, fx, (lo, hi, f_lo, f_hi, side))
        return np.exp(x).reshape(shape), (below | above).reshape(shape)

    def tangential(self, E, a, by_value: bool = False):
        """κ at contact radius a, N/m: sphere and coated plate sharing the traction, storage
        part (``by_value``: E takes a few values, :meth:`_interpolant`)."""
        E, a = np.broadcast_arrays(np.asarray(E, float), np.asarray(a, float))
        h, nu = self.coating.thickness, self.poisson
        g = E / (2 * (1 + nu))
        q, _ = self._interpolant(E, slice(2, 4), slope=False, by_value=by_value)(a)
        C_t = 2 * (2 - nu) / (8 * g * a) + (q[..., 0] + 1j * q[..., 1]) * h / a**2
        return np.real(1 / C_t)

    def kappa(self, force, E, gamma, radius, poisson=None):
        """κ(F_N), N/m (``poisson`` is the table's; accepted for the model's signature)."""
        a, _ = self.contact_radius(force, E, gamma, radius)
        return self.tangential(E, a)

    def kappa_grid(self, force, E, gamma, radius):
        """:meth:`kappa` where E takes a few values (a grid; broadcast against the others):
        the numbers of one call per value, in one call."""
        arrays = np.broadcast_arrays(*(np.asarray(v, float) for v in (force, E, gamma, radius)))
        a, _ = self.contact_radius(*arrays, by_value=True)
        return self.tangential(arrays[1], a, by_value=True)

    def model(self, gamma_max: float) -> Model:
        """The fitted model: E bounded by the table, γ by ``gamma_max``."""
        return Model(
            "jkr-mindlin-coated",
            "JKR + Mindlin on a coated plate",
            (
                Parameter("E", "Young's modulus E", "Pa", "E_Pa", self.bounds, scale=1e10),
                Parameter(
                    "gamma",
                    "energy of adhesion γ",
                    "J/m^2",
                    "gamma_J_m2",
                    (0, gamma_max),
                    scale=0.1,
                ),
                Parameter("radius", "sphere radius R", "m", "sphere_radius_m", (1e-9, 1.0), True),
                Parameter("poisson", "Poisson ratio ν", "-", "poisson", POISSON_OPEN_RANGE, True),
            ),
            "normal_force",
            "N",
            "kappa",
            "N/m",
            "compliance method (Shull 2002) on the layered plate + Mindlin in series",
            self.kappa,
        )

    @property
    def bounds(self) -> tuple[float, float]:
        """The E range of the table, Pa."""
        return float(self.E_range[0]), float(self.E_range[1])


def _table_radii(lo: float, hi: float, thickness: float, per_decade: int) -> np.ndarray:
    """The table's contact radii from ``lo`` to ``hi``, m (``thickness``: the coating's, m):
    log-spaced, at least ``per_decade`` a decade where a >= :data:`_THICK_FILM` thicknesses
    and at least :data:`_DENSER` times as many below, at least 6 in all (the number of steps
    is rounded up, so the steps are at most 1/``per_decade`` and 1/(:data:`_DENSER` ·
    ``per_decade``) decade; the step that straddles the knee lies between the two).

    Why denser in a thick film: there the corrections grow nearly like a/h (the film's own
    half-space, q ≈ (1/E*_film − 1/E*) a/h), an exponential in ln a, whose cubic spline's
    error goes with the fourth power of the step (measured: :func:`build_law`). Small
    radii also cost the least (the layered solution's work grows like (a/h)²-³). A table
    wholly above the knee is the plain log-spaced one."""
    knee = _THICK_FILM * thickness
    # (1e-9: a table that starts at the knee itself, rounded below it, stays log-spaced)
    if lo >= knee * (1 - 1e-9):
        return np.geomspace(lo, hi, max(6, math.ceil(per_decade * math.log10(hi / lo)) + 1))

    def steps(a: float) -> float:
        # The number of steps from the knee to a (negative below it).
        d = math.log10(a / knee)
        return per_decade * d * (_DENSER if d < 0 else 1)

    u = np.linspace(steps(lo), steps(hi), max(6, math.ceil(steps(hi) - steps(lo)) + 1))
    a = knee * 10 ** np.where(u < 0, u / (_DENSER * per_decade), u / per_decade)
    a[0], a[-1] = lo, hi  # the ends as given, not a rounding of them
    return a


def _node_count(coating: Coating, poisson: float, frequency: float, E_low: float) -> int:
    """The number of E nodes of the table (:func:`build_law`): :data:`_N_E_STIFF` where a
    layer's indentation modulus (storage part; statically, for the normal contact, or at
    ``frequency``, for the tangential one, whichever is larger) exceeds the substrate's at
    ``E_low`` (Pa; isotropic, Poisson ratio ``poisson``), else :data:`_N_E_SOFT`.

    Why the lowest E: the contrast of a stiff film is largest there (a film between the
    range's ends is stiffer than part of it, and five nodes left 2.4e-4 in C for 40 GPa on
    30-240 GPa, measured)."""
    substrate = float(np.real(indentation_modulus(Material.isotropic(E_low, poisson))))
    films = (
        float(np.real(indentation_modulus(s)))
        for m, _ in coating.layers
        for s in (static_solid(m), material_at(m, frequency))
    )
    return _N_E_STIFF if max(films) > substrate else _N_E_SOFT


def build_law(
    coating: Coating,
    poisson: float,
    frequency: float,
    E_range: tuple[float, float],
    radius_range: tuple[float, float],
    n_E: int | None = None,
    per_decade: int = 5,
) -> CoatedLaw:
    """Tabulate the film corrections for :class:`CoatedLaw`.

    Parameters
    ----------
    coating : the film(s)
    poisson : ν of sphere and substrate
    frequency : Hz, for the film's tangential constants
    E_range : (lowest, highest) Young's modulus, Pa: ``n_E`` Chebyshev nodes in ln E (they
        halve the largest error of equally spaced ones, measured)
    n_E : the number of E nodes; None (the default): 5 where every layer of the coating is
        softer than the substrate at the range's lowest E, 7 where one is stiffer
        (:func:`_node_count`)
    radius_range : (smallest, largest) contact radius, m: at least ``per_decade`` nodes per
        decade of a (log-spaced) where a is at least 4 coating thicknesses, at least 3x as many
        below (where the contact sits in the film, :func:`_table_radii`), at least 6

    Accuracy (measured against the layered solution between the nodes, ν = 0.17): 250 nm of
    PMMA on E = 30-240 GPa, a = 1-10 µm (a/h 4-40, wholly above the knee: 5 radii a decade):
    the corrections q to 2.5e-4 relative; the punch compliance (< 1e-4), κ (1.0e-4) and the
    force P' (2.2e-4), of which they are a part, to the tested 1e-4, 2e-4 and 3e-4 (the largest
    errors at the smallest a/h, 5; tests/analysis/test_coating.py). P' is nearly all the
    spline's in a: at the E nodes it leaves up to 2.3e-4 in P' (C 5.2e-5, κ 7.6e-5) in the
    first interval (a/h 4-6.3), 8.4e-5 in the second (6.3-10) and <= 1.6e-5 above; the E
    interpolation, at the radius nodes, <= 4.8e-5 in C, 5.4e-5 in P' and 7.5e-5 in κ (six
    nodes in E would leave 6e-5 in q). Where the contact sits inside the film (a/h < 4,
    :func:`_table_radii`: 15 radii a decade there), films of 2 GPa and 2 GPa / 20 GPa (two
    layers of 0.5 µm) on E = 40-160 GPa and PMMA (1 µm, 15 MHz) on 30-240 GPa, tables of a
    decade at a/h 0.02-20: the spline in a leaves <= 2.5e-5 in C, P' and κ (4e-5 in q) below
    the knee (at 5 a decade it left up to 1.1e-3 in C, 2.2e-3 in P' and 1.2e-3 in κ at a/h
    0.02-2, largest in the end intervals; at 10, 9.4e-5 in C for PMMA and 1.7e-4 in P' for
    the two layers, at a/h 0.2-2). Above the knee the radii are 5 a decade, and the spline
    leaves the most in the first interval there (a/h ~4-6), the more where the table starts
    at the knee (that interval a/h 4-6.3, a coarse one on either side) than where it straddles
    it (a finer step below): at the E nodes, the 2 GPa film left 8.0e-5 in P', 7.5e-5 in κ
    and 2.4e-5 in C (a table of a/h 4-40; straddling, a/h 0.6-6: 1.5e-5 in P', 3.6e-5 in κ),
    PMMA 2.3e-4 in P' (the 250 nm case above: the same a/h; straddling 3.9e-5), the two layers
    3.8e-5 (1.3e-5), and a film stiffer than the substrate the most, 300 GPa (1 µm on E =
    10-40 GPa, ν 0.3) 2.7e-4 in P' and 1.2e-4 in κ (straddling 1.0e-4 in P'): within the
    tested tolerances, not within the 2.5e-5 of the denser radii. In the second interval
    (a/h 6.3-10) they left <= 8.4e-5 (PMMA, P'), beyond a/h 10 <= 1.8e-5 (the 300 GPa film's
    κ 4.3e-5). With the E part, the tables of a/h 0.02-20: C <= 7.4e-5, P' <= 8.1e-5, κ <=
    1.04e-4 (PMMA on 30-240 GPa, in the interval straddling the knee; the E part alone up to
    7.5e-5 in κ) (tested: the same tolerances, a/h 0.02-0.26, 0.2-2 and 0.5-5; 10 radii a
    decade fail them, C 1.16e-4 for PMMA on 30-240 GPa at a/h 0.2-2). A film stiffer than the
    substrate needs more E nodes, not radii (the E part at a/h 0.02-20, midway between the E
    nodes, 1 µm films, ν 0.3, 15 MHz): with five, 300 GPa on
    E = 10-40 GPa (the analysis' own width of range, 0.6-2.5 times the uncoated E) left
    1.1e-4 in C, P' and κ at every a/h, and 150, 40 and 12 GPa left 1.0e-4, 6.7e-5 and
    3.5e-5 in C (κ 1.0e-4, 7.5e-5, 5.9e-5); on the wider 30-240 GPa (several groups), 40, 200
    and 400 GPa left 2.4e-4, 6.1e-4 and 8.1e-4 in C (κ to 8.3e-4). The seven nodes of such a
    film (one stiffer than the substrate at the range's lowest E, :func:`_node_count`) leave
    <= 3.5e-7 on 10-40 GPa and <= 6.1e-6 in C, P', κ on 30-240 GPa (tested: 300 GPa on
    10-40 GPa and 200 GPa on 30-240 GPa against the stated tolerances, which five nodes
    fail). Softer films keep five: 10 and 30 GPa on 40-160 GPa leave 1.0e-5 and 2.5e-5 in C
    (κ 1.8e-5, 4.6e-5). The rule's limit, a film just softer than the substrate on a range
    wider than the analysis' own: 25 GPa on 35-280 GPa leaves 1.4e-4 in C and 2.9e-4 in κ with
    five nodes (1.3e-6 and 4.1e-6 with seven, ``n_E=7``). The substrate's own material as a
    film as thick as the contact (2 µm at a = 4-8 µm, E = 35-280 GPa: the corrections vary
    most with E) moved the fitted E by 4.4e-4 with five nodes, 6e-7 with seven (tested to
    1e-5).
    """
    lo, hi = (float(v) for v in radius_range)
    a = _table_radii(lo, hi, coating.thickness, per_decade)
    x0, x1 = (math.log(float(v)) for v in E_range)
    if n_E is None:
        n_E = _node_count(coating, poisson, frequency, float(E_range[0]))
    cheb = np.cos((2 * np.arange(n_E) + 1) * np.pi / (2 * n_E))[::-1]
    E_nodes = np.exp(0.5 * (x0 + x1) + 0.5 * (x1 - x0) * cheb)
    store: dict = {}  # the basis transforms, shared by every E (_corrections)
    values = np.stack(
        [_corrections(float(E), poisson, coating, frequency, a, store) for E in E_nodes], axis=1
    )
    E_bounds = (float(E_range[0]), float(E_range[1]))
    return CoatedLaw(
        coating, float(poisson), float(frequency), E_nodes, np.log(a), values, E_bounds
    )
