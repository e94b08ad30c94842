"""The θ search of the exact-loop fits (:func:`contactres.analysis._loops.fit_cm_loops`): its
short cut (χ² without the residuals, exact χ² only where a trial can be the least) against the
plain search that evaluates :func:`contactres.analysis._loops.solve_projected` at every trial."""

from fractions import Fraction

import numpy as np
import pytest

from contactres.analysis import _loops as loops
from contactres.analysis import _points as points
from contactres.analysis._amplitude import row_sets
from contactres.analysis._loops import (
    GROUP_LOOP,
    INVERSE_MIN_DET,
    X_MAX,
    _inverse_3x3,
    _least_chi2,
    _search_pair,
    _shared_chi2,
    cm_loop_table,
    fit_cm_loops,
    interpolate_table,
    savkoor_loop_table,
    solve_projected,
    table_interpolant,
)

TABLES = {"cm": cm_loop_table(), "savkoor": savkoor_loop_table()}


def _sweeps(table, S=60, M=11, pad=True, seed=3, programmes=None):
    """S sweeps of M amplitudes (the last ones padded in every third row if ``pad``) whose
    shifts follow the loop of ``table`` at random θ, with noise, and a few without any slip;
    measured at one of ``programmes`` sets of amplitudes each (None: every sweep its own)."""
    rng = np.random.default_rng(seed)
    u = np.sort(rng.uniform(0.2e-9, 10e-9, (S, M)), axis=1)
    if programmes is not None:
        u = u[rng.integers(0, min(programmes, S), S)]
    w = np.ones((S, M))
    if pad:
        w[::3, M - 3 :] = 0.0
    x_max = 10.0 ** rng.uniform(-3.0, 1.6, S)  # from no resolved slip to gross sliding
    theta = x_max / np.max(np.where(w > 0, u, 0.0), axis=1)
    g1, g2 = interpolate_table(table_interpolant(table), theta[:, None] * u, ("g1", "g2"))
    df = -200.0 * g1 + rng.normal(0.0, 0.05, (S, M))
    dg = 3.0 + 200.0 * g2 + rng.normal(0.0, 0.05, (S, M))
    sigma = np.full(S, 0.05)
    return u, df * w, dg * w, w, sigma


def _plain_search(u, df, dg, w, sigma, table, rounds=4):
    """θ of the search of fit_cm_loops with solve_projected's χ² at every trial (the search as
    it was before its short cut): the zooming grid, then the parabola's vertex."""
    ip = table_interpolant(table)
    umax = np.max(np.where(w > 0, u, 0.0), axis=1)
    wf = 1.0 / np.maximum(sigma, 1e-6 * np.abs(df).max(axis=1)) ** 2
    wg = 1.0 / np.maximum(sigma, 1e-6 * np.abs(dg).max(axis=1)) ** 2

    def chi2(lx):
        xu = (10.0**lx / umax[:, None])[..., None] * u[:, None, :]
        g1, g2 = interpolate_table(ip, xu, ("c1", "c2"))
        a = (df[:, None], dg[:, None], w[:, None], wf[:, None], wg[:, None])
        return solve_projected(g1, g2, *a)[2]

    lo, hi = -2.5, np.log10(X_MAX)
    grid = np.linspace(lo, hi, 49)
    chi = chi2(np.broadcast_to(grid, (u.shape[0], 49)))
    rows = np.arange(u.shape[0])
    k = np.argmin(chi, axis=1)
    centre, step = grid[k], grid[1] - grid[0]
    for _ in range(rounds):
        local = np.clip(centre[:, None] + np.linspace(-step, step, 9)[None, :], lo, hi)
        chi = chi2(local)
        k = np.argmin(chi, axis=1)
        centre, best, step = local[rows, k], chi[rows, k], step / 4.0
    c0, c2 = chi2(np.clip(centre[:, None] + np.array([-step, step])[None, :], lo, hi)).T
    curv = c0 - 2.0 * best + c2
    shift = np.where(curv > 0, 0.5 * (c0 - c2) / np.where(curv > 0, curv, 1.0), 0.0)
    return 10.0 ** np.clip(centre + np.clip(shift, -1.0, 1.0) * step, lo, hi) / umax


@pytest.mark.parametrize("name", ["cm", "savkoor"])
@pytest.mark.parametrize("pad", [False, True])
def test_least_chi2_is_solve_projected_where_it_matters(name, pad):
    """At trials of every θ from no slip to gross sliding, repeated (ties: the first wins): the
    least χ² of each sweep sits where solve_projected's least sits, with its value bit for bit,
    and every value given is solve_projected's."""
    table = TABLES[name]
    u, df, dg, w, sigma = _sweeps(table, pad=pad)
    S = u.shape[0]
    wf, wg = 1.0 / sigma**2, 1.0 / sigma**2
    lx = np.linspace(-2.5, np.log10(X_MAX), 25)
    lx = np.broadcast_to(np.concatenate([lx, lx[::-1]]), (S, 50))  # each trial twice
    theta = 10.0**lx / u.max(axis=1)[:, None]
    ip = table_interpolant(table)
    g1, g2 = interpolate_table(ip, theta[..., None] * u[:, None, :], ("c1", "c2"))
    a = (df[:, None], dg[:, None], w[:, None], wf[:, None], wg[:, None])
    full = solve_projected(g1, g2, *a)[2]
    got = _least_chi2(np.moveaxis(g1, 2, 0), np.moveaxis(g2, 2, 0), df, dg, w, wf, wg)
    rows = np.arange(S)
    assert np.array_equal(np.argmin(got, axis=1), np.argmin(full, axis=1))
    assert np.array_equal(got.min(axis=1), full[rows, np.argmin(full, axis=1)])
    given = np.isfinite(got)
    assert np.array_equal(got[given], full[given])
    assert given.sum() < 0.2 * got.size  # the short cut spares most trials the exact χ²


@pytest.mark.parametrize("name", ["cm", "savkoor"])
@pytest.mark.parametrize("programmes", [None, 2, 40])
def test_fit_lands_where_the_plain_search_lands(name, programmes):
    """fit_cm_loops' θ is the plain search's, bit for bit, for sweeps with and without padding,
    in chunks of the search or not, from no resolved slip to gross sliding; each sweep at its
    own amplitudes, or sweeps of a few amplitude programmes sharing their lookups (the sums by
    set, or per sweep on gathered shapes), sorted by programme and back."""
    table = TABLES[name]
    for S in (5, 300, 3000):  # sweeps of 11 points: one chunk of the search, or several
        if S == 3000 and programmes is None:
            continue  # several chunks of distinct amplitudes: 300 has them
        u, df, dg, w, sigma = _sweeps(table, S=S, seed=S, programmes=programmes)
        fit = fit_cm_loops(u, df, dg, w, sigma, sigma, table)
        plain = _plain_search(u, df, dg, w, sigma, table)
        assert np.array_equal(fit["theta_per_m"].to_numpy(), plain)


@pytest.mark.parametrize("name", ["cm", "savkoor"])
def test_small_chunks_of_mixed_sweeps_land_where_the_plain_search_lands(name, monkeypatch):
    """200 sweeps of one amplitude programme and 100 of their own, in chunks sized for a round's
    trials (60 sweeps): the chunks of mostly distinct sweeps take the grid by parts (11 sweeps),
    and θ is the plain search's, bit for bit, in the sweeps' own order."""
    table = TABLES[name]
    one = _sweeps(table, S=200, seed=5, programmes=1)
    own = _sweeps(table, S=100, seed=6)
    u, df, dg, w, sigma = (np.concatenate(p) for p in zip(one, own, strict=True))
    monkeypatch.setattr(loops, "CHUNK_CELLS", 9 * 11 * 60)
    fit = fit_cm_loops(u, df, dg, w, sigma, sigma, table)
    assert np.array_equal(fit["theta_per_m"].to_numpy(), _plain_search(u, df, dg, w, sigma, table))


@pytest.mark.parametrize("name", ["cm", "savkoor"])
@pytest.mark.parametrize("programmes", [3, 2 * GROUP_LOOP, 120])
def test_shared_lookups_are_solve_projected_where_it_matters(name, programmes):
    """The short cut with lookups shared by the sweeps of one amplitude programme (few sets:
    sums by set; more: per sweep on gathered shapes; most sweeps distinct: a lookup per sweep),
    on the θ grid and at trials centred per sweep: the least χ² of each sweep where
    solve_projected's least sits, with its value, and every value given solve_projected's."""
    table = TABLES[name]
    u, df, dg, w, sigma = _sweeps(table, S=240, programmes=programmes, seed=programmes)
    S = u.shape[0]
    wf, wg = 1.0 / sigma**2, 1.0 / sigma**2
    umax = np.max(np.where(w > 0, u, 0.0), axis=1)
    amplitudes = row_sets(np.concatenate([u, w], axis=1).view(np.int64))[1]
    assert (amplitudes.max() + 1 <= GROUP_LOOP) == (programmes == 3)
    rng = np.random.default_rng(programmes)
    centre = np.round(rng.uniform(-2.0, 1.0, S), 1)  # 31 centres: sweeps share some
    grid = np.linspace(-2.5, np.log10(X_MAX), 49)
    for lx, key in (
        (np.broadcast_to(grid, (S, 49)), amplitudes[:, None]),
        (
            centre[:, None] + np.linspace(-0.3, 0.3, 8),
            np.stack([amplitudes, centre.view(np.int64)], 1),
        ),
    ):
        got = _shared_chi2(table_interpolant(table), u, df, dg, w, wf, wg, umax, lx, key)
        xu = (10.0**lx / umax[:, None])[..., None] * u[:, None, :]
        g1, g2 = interpolate_table(table_interpolant(table), xu, ("c1", "c2"))
        a = (df[:, None], dg[:, None], w[:, None], wf[:, None], wg[:, None])
        full = solve_projected(g1, g2, *a)[2]
        best = np.argmin(full, axis=1)
        assert np.array_equal(np.argmin(got, axis=1), best)
        assert np.array_equal(got.min(axis=1), full[np.arange(S), best])
        given = np.isfinite(got)
        assert np.array_equal(got[given], full[given])


@pytest.mark.parametrize("name", ["cm", "savkoor"])
def test_search_lookup_is_numpy_interp_bit_for_bit(name):
    """The θ search's lookup at x = θu (no clip: buckets beyond the table taken as its last)
    against numpy.interp of the complex pair, the θ search's own numbers: at amplitudes of 0,
    of padding beyond the largest weighted one (x past the table's end), around full sliding
    (crowded buckets), and with a θ so large that x·2^LOOKUP_BITS leaves the integers (the
    general lookup)."""
    table = TABLES[name]
    rng = np.random.default_rng(11)
    u = np.sort(rng.uniform(0.0, 10e-9, (40, 9)), axis=1)
    u[:, 0] = 0.0
    theta = 10.0 ** rng.uniform(7.0, 10.5, (40, 12))  # x up to ~300 > X_MAX
    slip = 1.5 if name == "cm" else 1.0
    theta[:, 0] = slip * (1.0 + rng.normal(0.0, 1e-4, 40)) / u[:, 4]  # around full sliding
    for th in (theta, np.full((40, 2), 1e300)):
        g1, g2 = _search_pair(table_interpolant(table), u, th)
        x = th[None, :, :] * u.T[:, :, None]
        pair = np.interp(x, table.x, table.g1 + 1j * table.g2)
        assert g1.shape == x.shape and g1.flags.c_contiguous
        assert np.array_equal(g1, pair.real) and np.array_equal(g2, pair.imag)


def _exact_inverse(m) -> np.ndarray:
    """The inverse of the 3x3 float matrix ``m`` in exact rational arithmetic, rounded once."""
    a = [[Fraction(float(v)) for v in row] for row in m]
    cof = [
        [
            a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
            - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3]
            for j in range(3)
        ]
        for i in range(3)
    ]
    det = sum(a[0][j] * cof[0][j] for j in range(3))
    return np.array([[float(cof[j][i] / det) for j in range(3)] for i in range(3)])


def test_inverse_3x3_is_exact_to_its_bound_and_pinv_below_it():
    """The closed-form inverse of the loop fits' JᵀJ against exact rational arithmetic, on
    matrices scaled over 12 decades and conditioned from ~1 to its bound (scaled determinant
    10^-5.9): every entry within 20ε·(6.75/det) of the exact inverse, in units of the scaled
    inverse's largest entry (the error grows with the condition number, at most 6.75/det).
    Below the bound and at a zero diagonal the rows are numpy.linalg.pinv's bit for bit; a NaN
    matrix gives NaN, the others unchanged."""
    rng = np.random.default_rng(25)
    S = 400
    # Correlation matrices of chosen determinant: a unit-diagonal Gram matrix of three vectors
    # whose third leans towards the plane of the first two by a chosen angle.
    v = rng.normal(size=(S, 3, 3))
    lean = 10.0 ** rng.uniform(-3.4, 0.0, S)
    v[:, 2] = v[:, 0] + rng.normal(size=(S, 1)) * v[:, 1] + lean[:, None] * v[:, 2]
    v /= np.linalg.norm(v, axis=2, keepdims=True)
    d = 10.0 ** rng.uniform(-6.0, 6.0, (S, 3))
    m = np.einsum("si,sik,sjk,sj->sij", d, v, v, d)
    m = 0.5 * (m + m.transpose(0, 2, 1))
    scaled = m / np.sqrt(np.einsum("sii,sjj->sij", m, m))
    det = np.linalg.det(scaled)
    assert det.min() < 1e-6 < 1e-3 < det.max()  # both sides of the bound
    m[:3, 1, :] = m[:3, :, 1] = 0.0  # singular: a zero diagonal
    got = _inverse_3x3(m)
    exact_rows = np.flatnonzero(det >= 2.0 * INVERSE_MIN_DET)[3:]
    assert exact_rows.size > 150
    for s in exact_rows:
        exact = _exact_inverse(m[s])
        dd = np.sqrt(np.diag(m[s]))
        err = np.abs((got[s] - exact) * np.outer(dd, dd)).max()
        scale = np.abs(exact * np.outer(dd, dd)).max()
        assert err <= 20.0 * np.finfo(float).eps * (6.75 / det[s]) * scale
    below = np.flatnonzero(det < 0.5 * INVERSE_MIN_DET)
    assert below.size > 20
    for rows in (below, np.arange(3)):
        assert np.array_equal(got[rows], np.linalg.pinv(m[rows]))
    m[3, 0, 2] = m[3, 2, 0] = np.nan  # NaN for it (pinv's SVD raised for the stack), the rest kept
    nan = _inverse_3x3(m)
    assert np.isnan(nan[3]).all() and np.array_equal(np.delete(nan, 3, 0), np.delete(got, 3, 0))


@pytest.mark.parametrize("name", ["cm", "savkoor"])
def test_errors_are_the_pseudo_inverse_of_the_jacobian(name):
    """fit_cm_loops' standard errors and covariance against the Jacobian of its residuals in
    (Δf0, ΔΓ0, ln θ) written out (the table's slopes at the fitted θ), JᵀJ summed point by
    point and inverted exactly: within 1e-11 relative (JᵀJ's rounding times the scaled
    condition number, up to ~200 here; numpy.linalg.pinv of the unscaled JᵀJ, condition
    number up to ~1e6, errs by up to ~1e-12 itself), with padding and without; the fitted
    values themselves are the plain search's (tests above)."""
    table = TABLES[name]
    u, df, dg, w, sigma = _sweeps(table, S=200, seed=9)
    fit = fit_cm_loops(u, df, dg, w, sigma, sigma, table)
    theta, A = fit["theta_per_m"].to_numpy(), fit["df0_Hz"].to_numpy()
    x = theta[:, None] * u
    g1, g2, d1, d2 = interpolate_table(table_interpolant(table), x, ("g1", "g2", "d1", "d2"))
    sf, sg = 1.0 / sigma[:, None], 1.0 / sigma[:, None]
    zero = np.zeros_like(u)
    jf = np.stack([sf * g1, zero, sf * A[:, None] * d1 * x], -1) * w[..., None]
    jg = np.stack([sg * g2, sg + zero, sg * A[:, None] * d2 * x], -1) * w[..., None]
    jtj = np.einsum("smi,smj->sij", jf, jf) + np.einsum("smi,smj->sij", jg, jg)
    rss = fit["rss_df"].to_numpy() / sigma**2 + fit["rss_dgamma"].to_numpy() / sigma**2
    inverse = np.array([_exact_inverse(m) for m in jtj])
    cov = inverse * (rss / (2.0 * w.sum(axis=1) - 3.0))[:, None, None]
    for col, want in (
        ("df0_err_Hz", np.sqrt(cov[:, 0, 0])),
        ("dgamma0_err_Hz", np.sqrt(cov[:, 1, 1])),
        ("lntheta_err", np.sqrt(cov[:, 2, 2])),
        ("cov_df0_lntheta", cov[:, 0, 2]),
    ):
        scale = np.sqrt(cov[:, 0, 0] * cov[:, 2, 2]) if col.startswith("cov") else want
        assert np.all(np.abs(fit[col].to_numpy() - want) <= 1e-11 * scale), col


def test_table_buckets_start_at_the_last_point_at_or_below_their_edge():
    """The bucket index of the table lookup (counted from the points' ceilings) against a binary
    search of every bucket's edge: for the loop tables and for a table with points exactly on
    bucket edges, just beside them (one rounding apart), and below the first edge's bucket."""
    edge = 2.0**-loops.LOOKUP_BITS
    on = np.arange(0, 40) * edge
    x = np.unique(np.concatenate([[0.0, 1e-12], on, np.nextafter(on[1:], 1.0), 3.3 * on + 0.1]))
    odd = loops.LoopTable(x, *(np.sin(k * x) for k in range(1, 5)))
    for table in (*TABLES.values(), odd):
        ip = table_interpolant(table)
        edges = np.arange(ip.first.size) * edge
        want = np.searchsorted(table.x, edges, side="right") - 1
        plain = ip.first >= 0
        assert plain.sum() > 0.8 * plain.size
        assert np.array_equal(ip.first[plain], want[plain])
        # a crowded bucket holds more table points than the lookup steps through
        crowded = np.diff(np.append(want, np.searchsorted(table.x, edges[-1] + edge, "right") - 1))
        assert np.array_equal(~plain, crowded > loops.LOOKUP_STEPS)


def test_point_sum_is_numpy_sum_bit_for_bit():
    """point_sum over the first axis against numpy's own sum over the last (pairwise: the order
    _projected must keep to give solve_projected's numbers) for every row length up to 300 (the
    eight running sums, their rest, and numpy's split beyond PAIRWISE_BLOCK), on terms of
    magnitudes 1e-30 to 1e30 of both signs, where the order of the additions shows; with rows
    of -0.0 (numpy's sum is 0.0), inf and NaN."""
    rng = np.random.default_rng(11)
    plain_differs = 0
    for m in range(301):
        a = rng.standard_normal((40, 3, m)) * 10.0 ** rng.uniform(-30, 30, (40, 3, m))
        a[0, 0] = -0.0
        if m > 1:
            a[1, 0, m // 2] = np.inf
            a[2, 1, 0] = np.nan
        got = points.point_sum(np.ascontiguousarray(np.moveaxis(a, -1, 0)))
        want = a.sum(-1)
        assert got.shape == want.shape
        assert np.array_equal(got.view(np.int64), want.view(np.int64)), m
        plain = np.zeros(a.shape[:-1])
        for i in range(m):  # one term after the other: not numpy's order
            plain += a[..., i]
        plain_differs += not np.array_equal(plain[3:], want[3:])
    assert plain_differs > 250  # the data tell the orders apart


@pytest.mark.parametrize(
    "a_shape, v_shape",
    [((11, 2000), (2000,)), ((7, 3, 700), (3, 700)), ((5, 1, 1500), (2, 1500))],
)
@pytest.mark.parametrize("op", [np.subtract, np.multiply])
def test_by_point_is_the_broadcast_operation(a_shape, v_shape, op, monkeypatch):
    """by_point, point by point (parts of >= BY_POINT_MIN numbers) and in one call (below),
    against the ufunc applied with numpy's broadcasting: the same numbers and shape."""
    rng = np.random.default_rng(5)
    a = rng.standard_normal(a_shape) * 10.0 ** rng.uniform(-20, 20, a_shape)
    v = rng.standard_normal(v_shape)
    want = op(a, v)
    for least in (1, 10**9):  # every part point by point; none
        monkeypatch.setattr(points, "BY_POINT_MIN", least)
        got = points.by_point(op, a, v)
        assert got.shape == want.shape
        assert np.array_equal(got, want)
