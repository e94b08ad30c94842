"""The bootstrap of the coated fit: E and γ of every resample at once (issue 26, point 4).

The coated law (:class:`contactres.analysis._coating_law.CoatedLaw`) has no closed form in E (the
uncoated law's κ ∝ E^(2/3) gives paper 2's bootstrap its linear least squares in E^(2/3),
:func:`contactres.analysis._jkr.bootstrap_jkr`), so every resample's least-squares fit is
found on a grid of (E, γ) evaluated once for all resamples (the weighted residual sums of
squares from the weighted sums per force), then refined by the quadratic through the grid's
values around the minimum and by Gauss-Newton steps on the model itself.
"""

from __future__ import annotations

import numpy as np

from ..fitting import FitResult

__all__ = ["resampled_coated"]

# The bootstrap's estimator (resampled_coated): a grid of _GRID x _GRID points in (E, γ), then
# Gauss-Newton steps (the grid only finds the basin).
_GRID = 15
_GN_STEPS = 2


def resampled_coated(law, F, kappa, W, R: float, res: FitResult, gamma_max: float):
    """E and γ of the coated fit for every row of weights ``W`` (B, points), all at once
    (``law``: the group's :class:`~contactres.analysis._coating_law.CoatedLaw`; this module does
    not import it: the coated fit imports this one).

    The same estimator as :func:`~contactres.analysis._coating.fit_coated` (least squares of
    the same model), by grid: the model is evaluated at the distinct forces on a 15 x 15 grid
    of (E, γ) around the fit, the weighted residual sum of squares of every resample is formed
    from its weighted sums per force, and its minimum refined by the quadratic through the
    3 x 3 values around it, then by Gauss-Newton steps on the model itself
    (:func:`_gauss_newton`), so that the estimate is the least-squares fit, not the grid's.
    The grid spans ±8 fit errors (at least ±5 % in E) and widens (up to 3 times) while a
    resample's minimum is on its edge.
    """
    F, kappa = np.asarray(F, float), np.asarray(kappa, float)
    forces, which = np.unique(F, return_inverse=True)
    onehot = (which[:, None] == np.arange(forces.size)[None, :]).astype(float)
    S = W @ (onehot * kappa[:, None])  # (B, L): Σ w κ per force
    N = W @ onehot  # (B, L): Σ w per force
    E_hat, g_hat = res.values["E"], res.values["gamma"]
    E_err = np.nan_to_num(res.errors["E"], nan=0.0)
    g_err = np.nan_to_num(res.errors["gamma"], nan=0.0)
    span_E = max(8 * E_err, 0.05 * E_hat)
    span_g = max(8 * g_err, 0.05 * g_hat, 1e-3)
    rows = np.arange(W.shape[0])
    for _ in range(4):
        e_grid = np.linspace(
            max(E_hat - span_E, law.bounds[0]), min(E_hat + span_E, law.bounds[1]), _GRID
        )
        g_grid = np.linspace(max(g_hat - span_g, 0.0), min(g_hat + span_g, gamma_max), _GRID)
        # (L, nE, nγ) in one call (each E's spline made once: CoatedLaw.kappa_grid)
        m = law.kappa_grid(forces[:, None, None], e_grid[None, :, None], g_grid[None, None, :], R)
        m = m.reshape(forces.size, -1)
        rss = -2 * S @ m + N @ (m * m)  # Σ w κ² left out: the same for every grid point
        rss = rss.reshape(-1, e_grid.size, g_grid.size)
        flat = np.argmin(rss.reshape(rss.shape[0], -1), axis=1)
        i, j = np.unravel_index(flat, (e_grid.size, g_grid.size))
        last_E, last_g = e_grid.size - 1, g_grid.size - 1
        inner_E, inner_g = (i > 0) & (i < last_E), (j > 0) & (j < last_g)
        # An edge of the grid that is not a bound of the fit: widen the grid.
        edge_E = ((i == 0) & (e_grid[0] > law.bounds[0])) | (
            (i == last_E) & (e_grid[-1] < law.bounds[1])
        )
        edge_g = ((j == 0) & (g_grid[0] > 0.0)) | ((j == last_g) & (g_grid[-1] < gamma_max))
        if not (edge_E.any() or edge_g.any()):
            break
        span_E, span_g = 2 * span_E, 2 * span_g
    step = np.array([e_grid[1] - e_grid[0], g_grid[1] - g_grid[0]])
    shift = _vertex(rss, rows, i, j, inner_E, inner_g)
    E = e_grid[i] + shift[:, 0] * step[0]
    gam = np.maximum(g_grid[j] + shift[:, 1] * step[1], 0.0)
    return _gauss_newton(law, forces, S, N, E, gam, R, gamma_max)


def _gauss_newton(law, forces, S, N, E, gam, R, gamma_max, steps: int = _GN_STEPS):
    """Gauss-Newton steps from (E, γ) on every resample's Σ_l N_l (m_l − S_l/N_l)² (the
    weighted residual sum of squares up to a constant), the model's derivatives by forward
    differences; γ held at its bound 0 where a step would cross it (E alone then), E kept in
    the table. From the grid's vertex, two steps reach the least-squares fit (to 2e-4 in E,
    tested)."""
    mean = S / np.where(N > 0, N, 1.0)
    lo, hi = law.bounds
    for _ in range(steps):
        dE, dg = 1e-6 * E, np.maximum(1e-6 * gam, 1e-9)
        # The model at (E, γ), (E + dE, γ) and (E, γ + dγ) in one call (each entry's numbers
        # are those of its own call: one loop of the contact-radius solve instead of three).
        m0, mE, mg = law.kappa(
            forces[None, None, :],
            np.stack([E, E + dE, E])[..., None],
            np.stack([gam, gam, gam + dg])[..., None],
            R,
        )
        JE = (mE - m0) / dE[:, None]
        Jg = (mg - m0) / dg[:, None]
        r = m0 - mean
        a11, a12, a22 = (N * JE * JE).sum(1), (N * JE * Jg).sum(1), (N * Jg * Jg).sum(1)
        b1, b2 = (N * JE * r).sum(1), (N * Jg * r).sum(1)
        det = a11 * a22 - a12**2
        ok = det > 0
        safe = np.where(ok, det, 1.0)
        sE = np.where(ok, (a22 * b1 - a12 * b2) / safe, 0.0)
        sg = np.where(ok, (a11 * b2 - a12 * b1) / safe, 0.0)
        pinned = gam - sg < 0  # the bound γ = 0: E alone
        sE = np.where(pinned, b1 / np.where(a11 > 0, a11, 1.0), sE)
        sg = np.where(pinned, gam, sg)
        E = np.clip(E - sE, lo, hi)
        gam = np.clip(gam - sg, 0.0, gamma_max)
    return E, gam


def _vertex(rss, rows, i, j, inner_E, inner_g) -> np.ndarray:
    """The vertex of the quadratic through the 3 x 3 grid values around each minimum (i, j), in
    grid steps, shape (B, 2): both directions at once, since E and γ are correlated (a vertex
    in E at the grid's γ would carry the γ step's error into E); one direction where the other
    is at an edge (a bound: γ = 0), none where the quadratic has no minimum."""
    ic = np.clip(i, 1, rss.shape[1] - 2)
    jc = np.clip(j, 1, rss.shape[2] - 2)

    def r(di, dj):
        return rss[rows, ic + di, jc + dj]

    # Central differences of the quadratic at the (clipped) centre.
    gx, gy = (r(1, 0) - r(-1, 0)) / 2, (r(0, 1) - r(0, -1)) / 2
    hxx, hyy = r(1, 0) - 2 * r(0, 0) + r(-1, 0), r(0, 1) - 2 * r(0, 0) + r(0, -1)
    hxy = (r(1, 1) - r(1, -1) - r(-1, 1) + r(-1, -1)) / 4
    det = hxx * hyy - hxy**2
    both = inner_E & inner_g & (hxx > 0) & (det > 0)
    safe = np.where(both, det, 1.0)
    dx = np.where(both, -(hyy * gx - hxy * gy) / safe, 0.0)
    dy = np.where(both, -(hxx * gy - hxy * gx) / safe, 0.0)
    # At the edge of one direction, the other alone (the value on the grid's row/column).
    only_E = inner_E & ~inner_g
    only_g = inner_g & ~inner_E
    along_E = [rss[rows, ic + d, j] for d in (-1, 0, 1)]
    along_g = [rss[rows, i, jc + d] for d in (-1, 0, 1)]
    dx = np.where(only_E, _parabola(*along_E), dx)
    dy = np.where(only_g, _parabola(*along_g), dy)
    return np.clip(np.stack([dx, dy], axis=1), -1.0, 1.0)


def _parabola(r0, r1, r2):
    """The vertex of the parabola through three equally spaced values, in steps from the
    middle (clipped to ±1; 0 where the values are not convex)."""
    denom = r0 - 2 * r1 + r2
    shift = np.where(denom > 0, 0.5 * (r0 - r2) / np.where(denom > 0, denom, 1.0), 0.0)
    return np.clip(shift, -1.0, 1.0)
