"""The sweep analysis at scale (issue 11): flat layout, O(points) hinge, closed-form plateau fit.

Each fast path is checked against a second algorithm: the hinge against a fit of every
candidate (the quadratic search it replaces), the closed-form plateau shapes against the
Masing-loop quadrature, the batched plateau fit against scipy's least_squares on that
quadrature, one sweep at a time.
"""

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import least_squares

from contactres.analysis._amplitude import (
    BLOCK_POINTS,
    PLATEAU_MIN_FLAT,
    PLATEAU_MIN_SLOPE,
    PLATEAU_SUBSTEPS,
    fit_hinge,
    fit_line,
    pad_sweeps,
)
from contactres.analysis._classify import fit_sweeps
from contactres.analysis._loops import (
    X_MAX,
    _interpolate_pair,
    cm_loop_table,
    fit_cm_loops,
    interpolate_table,
    loop_tables,
    plateau_loop_shape,
    savkoor_loop_table,
    solve_projected,
    table_interpolant,
)
from contactres.analysis._models import fit_tables
from contactres.analysis._plateau import PLATEAU_D_C_BOUND, fit_plateau_loops
from contactres.analysis._plateau_series import SERIES_CELLS
from contactres.analysis._plateau_slopes import FIT_SERIES_GROUPS, plateau_loop_slopes
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.resonators._qcm import QCM

Q = QCM(fundamental=5e6, overtone=3, area=2.5e-5)
P = Q.sensitivity(3)


def _study(model="cattaneo-mindlin", n_points=13, n_exp=2, ramps=(2, 3), noise=0.1, name="g"):
    u = tuple(np.linspace(0.5e-9, 8e-9, n_points))
    group = SweepGroup(name, "air", 1.1e-3, 70e9, 0.1, u, 5.0 / P, noise)
    return SweepStudy(
        groups=(group,),
        normal_forces=(3e-3, 6e-3),
        n_experiments=n_exp,
        ramps=ramps,
        qcm=Q,
        model=model,
        mu=1.5,
        plateau_fraction=0.4,
    )


def _table(*studies, seed=1):
    frames = [synthetic_sweeps(s, seed + i, constants=True) for i, s in enumerate(studies)]
    return validate_sweeps(pd.concat(frames, ignore_index=True)).data


def _hinge_by_every_candidate(u, Y, w, n):
    """The hinge search fitting a line for every candidate u_c (O(points²) per sweep)."""
    S = u.shape[0]
    t = np.asarray(PLATEAU_SUBSTEPS)
    u_next = np.concatenate([u[:, 1:], u[:, -1:]], axis=1)
    uc = u[:, :, None] + t[None, None, :] * (u_next - u)[:, :, None]
    Xh = np.maximum(u[:, None, None, :] - uc[..., None], 0.0)
    Wh = np.broadcast_to(w[:, None, None, :], Xh.shape)
    n_flat = (Wh * (Xh == 0.0)).sum(-1)
    valid = (n_flat >= PLATEAU_MIN_FLAT) & (n[:, None, None] - n_flat >= PLATEAU_MIN_SLOPE)
    valid &= ((u_next - u)[:, :, None] > 0) | (t[None, None, :] == 0)
    lines = fit_line(Xh, Y[:, :, None, None, :], Wh)
    logs = np.log(np.maximum(lines.rss[0], 1e-30)) + np.log(np.maximum(lines.rss[1], 1e-30))
    crit = np.where(valid, logs, np.inf).reshape(S, -1)
    best = np.argmin(crit, axis=1)
    rows = np.arange(S)
    picked = [f.reshape(2, S, -1)[:, rows, best] for f in lines.fields()]
    return picked, uc.reshape(S, -1)[rows, best], np.isfinite(crit[rows, best])


def test_flat_layout_holds_every_point_once_and_pads_only_on_request():
    data = _table(_study(n_points=13), _study(n_points=9, name="h"))
    p = pad_sweeps(data)
    assert p.points_u.size == len(data) and p.n.sum() == len(data)
    for i in (0, 5, len(p.n) - 1):
        u, df, dg = p.points(i)
        rows = data[data["sweep"] == p.sweeps[i]].sort_values("amplitude_m", kind="stable")
        np.testing.assert_array_equal(u, rows["amplitude_m"].to_numpy())
        np.testing.assert_array_equal(df, rows["df_Hz"].to_numpy())
        # the padded views of older code give the same points
        m = p.w[i] > 0
        np.testing.assert_array_equal(p.u[i][m], u)
        np.testing.assert_array_equal(p.dg[i][m], dg)
    rows = np.array([0, len(p.n) - 1])
    b = p.block(rows)
    assert b.u.shape == (2, p.n[rows].max())
    np.testing.assert_array_equal(b.u[b.w > 0], p.points(rows)[0])
    np.testing.assert_array_equal(p.u_min, np.min(np.where(p.w > 0, p.u, np.inf), axis=1))
    np.testing.assert_array_equal(p.u_max, np.max(np.where(p.w > 0, p.u, 0.0), axis=1))


def test_one_long_sweep_pads_only_its_own_block():
    long_study = _study(n_points=700, n_exp=1, ramps=(2,), name="long")
    p = pad_sweeps(_table(_study(n_exp=30), long_study))
    groups = p.blocks(max_points=2000)
    rows = np.sort(np.concatenate(groups))
    np.testing.assert_array_equal(rows, np.arange(len(p.n)))  # every sweep once
    for g in groups:
        n = p.n[g]
        assert len(g) == 1 or len(g) * n.max() <= 2000
        assert n.max() <= 1.25 * n.min() or n.max() <= 16  # no long sweep among short ones
    padded = sum(len(g) * p.n[g].max() for g in groups)
    assert padded <= 1.25 * p.n.sum()  # memory linear in the points, not sweeps x longest
    assert BLOCK_POINTS <= 1 << 20


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("programmes", [None, 4])
def test_hinge_from_suffix_sums_equals_fitting_every_candidate(seed, programmes):
    # Ragged sweeps (3-15 points) with repeated amplitudes, a plateau and noise; the suffix-sum
    # search must pick the same hinge as a fit of every candidate, bit for bit. Each sweep at
    # its own amplitudes, or at one of a few amplitude programmes (what depends on the
    # amplitudes alone then computed once per programme).
    rng = np.random.default_rng(seed)
    data = []
    shared = [
        np.sort(np.round(rng.uniform(0.5, 10.0, rng.integers(3, 16)), 1 + 5 * (i % 2))) * 1e-9
        for i in range(programmes or 0)
    ]
    for s in range(60):
        n = rng.integers(3, 16)
        u = np.sort(np.round(rng.uniform(0.5, 10.0, n), 1 if s % 3 == 0 else 6)) * 1e-9
        if programmes:
            u = shared[s % programmes]
            n = u.size
        knee = rng.uniform(0.2, 0.6) * u.max()
        slope = rng.uniform(-5e9, 5e9, 2)
        for k in range(n):
            y = 100.0 + slope * max(u[k] - knee, 0.0) + rng.normal(0, 0.05, 2) * (s % 5 != 0)
            data.append((f"s{s}", u[k], y[0], y[1]))
    table = pd.DataFrame(data, columns=["sweep", "amplitude_m", "df_Hz", "dgamma_Hz"])
    p = pad_sweeps(table)
    b = p.block(np.arange(len(p.n)))  # one block: sweeps of every length, padded
    hinge = fit_hinge(b)
    lines, uc, found = _hinge_by_every_candidate(b.u, np.stack([b.df, b.dg]), b.w, b.n)
    np.testing.assert_array_equal(hinge.found, found)
    np.testing.assert_array_equal(hinge.u_c[found], uc[found])
    for got, ref in zip(hinge.line.fields(), lines, strict=True):
        np.testing.assert_array_equal(got[:, found], ref[:, found])


def test_sweeps_fit_the_same_alone_and_among_others():
    # Blocks group sweeps by length, so a sweep's fit does not depend on the other sweeps.
    short = _table(_study(model="plateau", n_exp=2))
    mixed = _table(
        _study(model="plateau", n_exp=2),
        _study(n_points=300, n_exp=1, ramps=(2,), name="long"),
        _study(n_points=7, name="short"),
    )
    table = loop_tables()
    alone, alone_fits = _with_fits(fit_sweeps(pad_sweeps(short), tables=table))
    among, among_fits = _with_fits(fit_sweeps(pad_sweeps(mixed), tables=table))
    keep = among["sweep"].isin(alone["sweep"]).to_numpy()
    pd.testing.assert_frame_equal(alone, among[keep].reset_index(drop=True))
    assert list(alone_fits) == list(among_fits)
    for key, fits in alone_fits.items():
        pd.testing.assert_frame_equal(fits, among_fits[key][keep].reset_index(drop=True))


def _with_fits(fitted):
    """The named table of :func:`fit_sweeps` and every model's fit table."""
    sw, fields = fitted
    return sw, fit_tables(sw["sweep"], fields)


def test_workers_give_the_same_table():
    data = _table(_study(model="plateau", n_exp=3), _study(n_points=9, name="h"))
    p = pad_sweeps(data)
    table = loop_tables()
    one, one_fits = _with_fits(fit_sweeps(p, tables=table))
    two, two_fits = _with_fits(fit_sweeps(p, tables=table, workers=2))
    pd.testing.assert_frame_equal(one, two)
    assert list(one_fits) == list(two_fits)
    for key, fits in one_fits.items():
        pd.testing.assert_frame_equal(fits, two_fits[key])


# ---- plateau loop: closed form and batched fit ------------------------------------------------


def test_plateau_slopes_equal_the_quadrature():
    # Near and far from full sliding (x = c + 3/2), small x (the series branch), c = 0
    # (the Cattaneo-Mindlin loop) and below d_c (stick).
    cs = np.array([0.0, 1e-3, 0.05, 0.3, 1.0, 4.0, 20.0])
    ys = np.concatenate([np.geomspace(1e-6, 40.0, 60), 1.5 + np.array([-1e-6, 0.0, 1e-6])])
    c = np.repeat(cs, ys.size + 2)
    x = np.concatenate([np.concatenate([[0.5 * ci, ci], ci + ys]) for ci in cs])
    g1, g2, *_ = plateau_loop_slopes(x, c)
    q1, q2 = plateau_loop_shape(x, c)
    assert np.max(np.abs(g1 - q1)) < 3e-11 and np.max(np.abs(g2 - q2)) < 3e-11
    # Without the derivatives (the evidence's nodes; G′'s integral by its series,
    # tests/analysis/test_plateau_series.py): the same two arrays to rounding.
    h1, h2 = plateau_loop_slopes(x, c, derivatives=False)
    assert np.max(np.abs(h1 - q1)) < 3e-11 and np.max(np.abs(h1 - g1)) < 1e-12
    assert np.array_equal(h2, g2)


def test_plateau_slopes_are_the_derivatives():
    # Richardson-extrapolated central differences, away from the kinks at x = c and x = c + 3/2
    # and from the switch between the two evaluations (m = min(x, e)/max(x, e) =
    # FIT_SERIES_GROUPS[-1]/SERIES_CELLS: the series below, the elliptic form above).
    rng = np.random.default_rng(4)
    c = rng.uniform(0.02, 3.0, 400)
    x = c + rng.uniform(0.02, 6.0, 400)
    e = c + 1.5
    switch = FIT_SERIES_GROUPS[-1] / SERIES_CELLS
    keep = (np.abs(x - e) > 0.05) & (np.abs(np.minimum(x, e) / np.maximum(x, e) - switch) > 0.01)
    x, c = x[keep], c[keep]
    small = rng.uniform(0.0, 0.01, 50)
    x, c = np.concatenate([x, small + rng.uniform(0.02, 0.1, 50)]), np.concatenate([c, small])
    got = plateau_loop_slopes(x, c)

    def central(k, dx, dc, h):
        a = plateau_loop_slopes(x + dx * h, c + dc * h)[k]
        b = plateau_loop_slopes(x - dx * h, c - dc * h)[k]
        return (a - b) / (2 * h)

    for k, (dx, dc) in enumerate([(1, 0), (0, 1)]):
        for g in (0, 1):
            d1, d2 = central(g, dx, dc, 2e-4), central(g, dx, dc, 1e-4)
            np.testing.assert_allclose(got[2 + 2 * g + k], d2 + (d2 - d1) / 3, atol=2e-9)


def _least_squares_per_sweep(u, df, dg, sig, uc0, y0):
    """The plateau-loop fit of one sweep by scipy's least_squares (trf) on the quadrature of
    plateau_loop_shape: the same starts, passes, bounds and tolerances as the batched fit."""
    umax, w = u.max(), np.ones(u.size)
    lo, hi = [np.log(10.0**-2.5), 0.0], [np.log(X_MAX), np.sort(u)[u.size - 3] / umax]

    def shapes(p):
        theta = np.exp(p[0]) / (umax * (1.0 - p[1]))
        return plateau_loop_shape(theta * u, theta * p[1] * umax)

    def solve(starts, wf, wg):
        def residuals(p):
            g1, g2 = shapes(p)
            A, B, _, _, _ = solve_projected(g1, g2, df, dg, w, wf, wg)
            return np.concatenate([np.sqrt(wf) * (df - A * g1), np.sqrt(wg) * (dg - B - A * g2)])

        sols = [
            least_squares(residuals, x0, bounds=(lo, hi), x_scale=[1.0, 0.1], xtol=1e-10)
            for x0 in starts
        ]
        best = min(sols, key=lambda r: r.cost)  # the first on a tie
        return best.x, solve_projected(*shapes(best.x), df, dg, w, wf, wg)

    dls = [min(uc0 / umax, hi[1]), u[u < uc0 * (1 - 1e-9)].max() / umax]
    starts = [(np.clip(np.log(y0 * (1 - d) / (1 - uc0 / umax)), lo[0], hi[0]), d) for d in dls]
    x1, (_, _, _, rss_f, rss_g) = solve(starts, 1 / sig[0] ** 2, 1 / sig[1] ** 2)
    wf, wg = (u.size - 2) / rss_f, (u.size - 2) / rss_g
    x2, (A, _, chi2, _, _) = solve([x1], wf, wg)
    theta, d_c = np.exp(x2[0]) / (umax * (1 - x2[1])), x2[1] * umax
    # Errors: central differences of the shapes in ln θ and d_c, Jacobian in (A, B, ln θ, d_c).
    h, hd = 1e-5, 1e-5 * umax
    gp, gm = (plateau_loop_shape(theta * np.exp(s) * u, theta * np.exp(s) * d_c) for s in (h, -h))
    cp, cm = (plateau_loop_shape(theta * u, theta * max(d_c + s, 0.0)) for s in (hd, -hd))
    g1, g2 = plateau_loop_shape(theta * u, theta * d_c)
    step = hd + min(d_c, hd)
    cols = [(-g1, -g2), (0 * g1, -1 + 0 * g2)]
    for a, b, dx in ((gp, gm, 2 * h), (cp, cm, step)):
        cols.append((-A * (a[0] - b[0]) / dx, -A * (a[1] - b[1]) / dx))
    J = np.array([np.concatenate([np.sqrt(wf) * f, np.sqrt(wg) * g]) for f, g in cols]).T
    norm = np.linalg.norm(J, axis=0)
    cov = np.linalg.pinv((J / norm).T @ (J / norm)) / np.outer(norm, norm)
    err = np.sqrt(np.diag(cov) * chi2 / (2 * u.size - 4))
    return A, theta, d_c, err


def test_batched_plateau_fit_equals_least_squares_per_sweep():
    data = _table(_study(model="plateau", n_exp=2, noise=0.1))
    p = pad_sweeps(data)
    b = p.block(np.arange(len(p.n)))
    hinge = fit_hinge(b)
    sig = np.sqrt(hinge.line.rss / np.maximum(b.n - 3, 1))
    table = cm_loop_table()
    fit = fit_plateau_loops(b.u, b.df, b.dg, b.w, sig[0], sig[1], hinge.u_c, table)
    excess = np.maximum(b.u - hinge.u_c[:, None], 0.0)
    y0 = fit_cm_loops(excess, b.df, b.dg, b.w, sig[0], sig[1], table)["x_max"]
    for i in range(len(p.n)):
        u, df, dg = p.points(i)
        A, theta, d_c, err = _least_squares_per_sweep(u, df, dg, sig[:, i], hinge.u_c[i], y0[i])
        assert abs(A - fit["df0_Hz"][i]) < 1e-3 * fit["df0_err_Hz"][i]
        assert abs(np.log(theta / fit["theta_per_m"][i])) < 1e-3 * fit["lntheta_err"][i]
        assert abs(d_c - fit["d_c_m"][i]) < 1e-3 * fit["d_c_err_m"][i]
        columns = ("df0_err_Hz", "dgamma0_err_Hz", "lntheta_err", "d_c_err_m")
        np.testing.assert_allclose([fit[c][i] for c in columns], err, rtol=1e-3)
    assert (fit["edge"] == "").all() and np.all(np.isfinite(fit["df0_err_Hz"]))


def _cm_sweeps(n_exp):
    """Padded Cattaneo-Mindlin sweeps (no plateau), their hinges' u_c and noise levels."""
    p = pad_sweeps(_table(_study(model="cattaneo-mindlin", n_exp=n_exp, noise=0.1)))
    b = p.block(np.arange(len(p.n)))
    return b, fit_hinge(b).u_c, np.full(len(p.n), 0.1)


def test_plateau_fit_of_sweeps_without_plateau_stays_in_its_bounds():
    b, u_c, sig = _cm_sweeps(2)
    fit = fit_plateau_loops(b.u, b.df, b.dg, b.w, sig, sig, u_c, cm_loop_table())
    assert np.all(fit["d_c_m"] >= 0.0)
    assert np.all(fit["d_c_m"] <= b.u[np.arange(len(b.n)), b.n - PLATEAU_MIN_SLOPE])
    assert np.all(np.log(fit["x_max"] / X_MAX) <= 1e-9)


@pytest.mark.parametrize("make", [cm_loop_table, savkoor_loop_table])
def test_table_lookup_is_numpy_interp_bit_for_bit(make):
    """The bucketed lookup of the loop fits against numpy.interp's bisection: the same numbers,
    real and as the complex pair of the θ search (both of its forms), at random amplitudes,
    densely around full sliding (where the table is refined and buckets are crowded), on the
    table points, just below them, between them, at and beyond its end, and on arrays shorter
    than the table (where numpy.interp forms each slope per point)."""
    table = make()
    x_tab = table.x
    rng = np.random.default_rng(5)
    x = np.concatenate(
        [
            rng.random(20000) * 1.2 * X_MAX,
            1.5 + rng.normal(0.0, 1e-3, 5000),
            1.0 + rng.normal(0.0, 1e-5, 5000),
            x_tab,
            np.nextafter(x_tab[1:], 0.0),
            0.5 * (x_tab[1:] + x_tab[:-1]),
            [X_MAX, np.nextafter(X_MAX, np.inf), 2 * X_MAX, np.inf],
        ]
    )
    ip = table_interpolant(table)
    for part in (x, x[:100]):
        pair = np.interp(part, x_tab, table.g1 + 1j * table.g2)
        c1, c2, *real = interpolate_table(ip, part, ("c1", "c2", "g1", "g2", "d1", "d2"))
        assert np.array_equal(c1, pair.real) and np.array_equal(c2, pair.imag)
        p1, p2 = _interpolate_pair(ip, part)  # the θ search's one-gather form of the pair
        assert np.array_equal(p1, pair.real) and np.array_equal(p2, pair.imag)
        for got, name in zip(real, ("g1", "g2", "d1", "d2"), strict=True):
            assert np.array_equal(got, np.interp(part, x_tab, getattr(table, name))), name


def test_plateau_fit_at_its_bound_is_the_constrained_fit_and_reproducible():
    # Cattaneo-Mindlin sweeps: many plateau fits end with d_c on its bound 0 (or a rounding error
    # off it). Those are refitted with d_c held at 0: d_c's error is not a number, and the other
    # errors (those of the constrained fit) do not depend on which side of the bound a 1e-15
    # change of the data leaves pass 2 (before: ln θ's error 0.05 or 5e3).
    b, u_c, sig = _cm_sweeps(4)
    table = cm_loop_table()
    fit = fit_plateau_loops(b.u, b.df, b.dg, b.w, sig, sig, u_c, table)
    rng = np.random.default_rng(7)
    df, dg = (a * (1.0 + 1e-15 * rng.standard_normal(a.shape)) for a in (b.df, b.dg))
    again = fit_plateau_loops(b.u, df, dg, b.w, sig, sig, u_c, table)
    bound = (fit["d_c_m"] < PLATEAU_D_C_BOUND * b.u.max(axis=1)).to_numpy()
    assert bound.sum() >= 4
    assert np.all(fit["d_c_m"][bound] == 0.0) and np.all(np.isnan(fit["d_c_err_m"][bound]))
    assert np.all(np.isfinite(fit["d_c_err_m"][~bound]))
    columns = ("df0_Hz", "df0_err_Hz", "dgamma0_err_Hz", "theta_per_m", "lntheta_err")
    for c in columns:
        np.testing.assert_allclose(again[c], fit[c], rtol=1e-6, err_msg=c)
    # At d_c = 0 the plateau loop is the Cattaneo-Mindlin loop: ln θ's error is that of a fit of
    # (Pκ, Pωξ, ln θ) alone, resolved (below 1) wherever the loop bends within the sweep.
    bends = bound & (fit["x_max"] > 0.3).to_numpy()
    assert bends.any() and np.all(fit["lntheta_err"][bends] < 1.0)


def _plain_line(X, Y, W):
    """fit_line's sums and solution as the plain formulas write them (every weight multiplied,
    every array broadcast to its full shape first)."""
    X, W = np.broadcast_arrays(X, W)
    Y = np.broadcast_to(Y, (2, *X.shape))
    S0, Sx, Sxx = W.sum(-1), (W * X).sum(-1), (W * X * X).sum(-1)
    Sy, Sxy = (W * Y).sum(-1), (W * X * Y).sum(-1)
    D = S0 * Sxx - Sx**2
    b = (S0 * Sxy - Sx * Sy) / D
    a = (Sy - b * Sx) / S0
    rss = (W * (Y - a[..., None] - b[..., None] * X) ** 2).sum(-1)
    return a, b, rss


@pytest.mark.parametrize("padded", [False, True])
def test_line_fit_is_least_squares_and_the_plain_sums_however_weights_are_given(padded):
    """fit_line against numpy.linalg.lstsq per row (1e-9 relative), and bit for bit the plain
    formulas, with weights of 1 (the products with them skipped) or 0/1 (padding), given in
    full or once for rows that share them (a length-1 axis, as the hinge's candidates do)."""
    rng = np.random.default_rng(8)
    S, K, M = 30, 4, 12
    X = np.sort(rng.uniform(0.0, 3e-9, (S, K, M)), axis=-1)
    Y = np.stack([100.0 - 2e9 * X, 4.0 + 1e9 * X]) + rng.normal(0.0, 0.05, (2, S, K, M))
    Y = Y[:, :, :1]  # the shifts of a sweep are those of each of its candidates
    w = np.ones((S, 1, M))
    if padded:
        w[::2, :, M - 4 :] = 0.0
    for W in (w, np.broadcast_to(w, X.shape), np.ascontiguousarray(np.broadcast_to(w, X.shape))):
        fit = fit_line(X, Y, W)
        a, b, rss = _plain_line(X, Y, W)
        for got, want in ((fit.a, a), (fit.b, b), (fit.rss, rss)):
            assert got.shape == (2, S, K)
            np.testing.assert_array_equal(got, want)
    for c in range(2):
        for s in range(S):
            for k in range(K):
                m = w[s, 0] > 0
                A = np.stack([np.ones(m.sum()), X[s, k, m]], axis=1)
                sol, res = np.linalg.lstsq(A, Y[c, s, 0, m], rcond=None)[:2]
                np.testing.assert_allclose([fit.a[c, s, k], fit.b[c, s, k]], sol, rtol=1e-9)
                np.testing.assert_allclose(fit.rss[c, s, k], res[0], rtol=1e-6)
