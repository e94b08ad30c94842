"""The plateau's evidence integrated over d_c (issue 27, point 11)."""

import numpy as np
import pytest

from contactres.analysis._loops import plateau_loop_shape
from contactres.analysis._plateau_evidence import plateau_log_evidence


def _block(seed: int, dc_ratio: float, noise: float = 0.6):
    """Three ramps of 11 amplitudes of a loop behind a plateau d_c = ``dc_ratio`` u_max (0:
    Cattaneo-Mindlin), Pκ = 40 Hz, Pωξ = 5 Hz, x_max = θ u_max = 1.2, Gaussian noise."""
    rng = np.random.default_rng(seed)
    umax = 2e-9
    u = np.tile(np.linspace(0.1, 1.0, 11) * umax, 3)
    theta = 1.2 / umax
    g1, g2 = plateau_loop_shape(theta * u, theta * dc_ratio * umax)
    df = 40.0 * g1 + noise * rng.standard_normal(u.size)
    dg = 5.0 + 40.0 * g2 + noise * rng.standard_normal(u.size)
    return np.sort(u), df[np.argsort(u, kind="stable")], dg[np.argsort(u, kind="stable")]


def _reference(u, df, dg, sigma, ratio_prior, y):
    """2 ln B by brute force: the quadrature shapes (plateau_loop_shape), Pκ and Pωξ by a
    weighted least-squares solve (its 2 x 2 normal equations at every node in y at once), the
    trapezoidal rule over y on ``y`` and over z = ln(d_c/u_max) on 41 nodes across ±4 prior
    widths (a flat prior in y, the same in both models)."""
    umax = u.max()
    m, v = ratio_prior
    z = np.linspace(m - 4 * np.sqrt(v), m + 4 * np.sqrt(v), 41)
    w0, w1 = sigma[0] ** -2.0, sigma[1] ** -2.0

    def log_l(dl):
        theta = np.exp(y)[:, None] / (umax * (1 - dl))  # (y, 1)
        g1, g2 = plateau_loop_shape(theta * u, theta * dl * umax)  # (y, u)
        # Minimise w0 |df − A g1|² + w1 |dg − B − A g2|² over (A, B) at each y.
        a11 = w0 * np.sum(g1 * g1, 1) + w1 * np.sum(g2 * g2, 1)
        a12, a22 = w1 * np.sum(g2, 1), w1 * u.size
        b1, b2 = w0 * (g1 @ df) + w1 * (g2 @ dg), w1 * np.sum(dg)
        det = a11 * a22 - a12 * a12
        A = ((a22 * b1 - a12 * b2) / det)[:, None]
        B = ((a11 * b2 - a12 * b1) / det)[:, None]
        rf, rg = df - A * g1, dg - B - A * g2
        return -0.5 * u.size * (np.log(np.sum(rf * rf, 1)) + np.log(np.sum(rg * rg, 1)))

    ref = log_l(0.0)
    top = ref.max()
    z0 = np.log(np.trapezoid(np.exp(ref - top), y))
    marg = np.array([np.log(np.trapezoid(np.exp(log_l(np.exp(zz)) - top), y)) for zz in z])
    prior = np.exp(-0.5 * (z - m) ** 2 / v) / np.sqrt(2 * np.pi * v)
    return 2 * (np.log(np.trapezoid(np.exp(marg) * prior, z)) - z0)


@pytest.mark.parametrize(("seed", "dc_ratio"), [(1, 0.0), (2, 0.3)])
def test_evidence_is_the_integral_of_the_likelihood_over_the_prior(seed, dc_ratio):
    u, df, dg = _block(seed, dc_ratio)
    sigma = np.array([0.6, 0.6])
    prior = (np.log(0.3), 0.1**2)
    nan = np.array([np.nan])
    out = plateau_log_evidence(
        u[None],
        df[None],
        dg[None],
        np.ones((1, u.size)),
        sigma[:, None],
        (nan, nan),
        (np.array([prior[0]]), np.array([prior[1]])),
        np.array([1.0]),
    )
    # The posterior in y lies within ±1 of its peak at x_max ≈ 1.2 (ln 1.2 ≈ 0.18).
    y = np.linspace(-1.2, 1.6, 141)
    # 12 nodes in z against 41: within a tenth of the unit of evidence that decides (2).
    assert out[0, 0] == pytest.approx(_reference(u, df, dg, sigma, prior, y), abs=0.2)


def test_water_plateaus_are_classified_right_with_the_integrated_evidence(shared_water_study):
    # One seed, 30 % of the loads with a plateau: 69 of 78 plateau sweeps of ramps 2-4 right
    # (48 with the priors applied at the fit's optimum, where d_c often ended on its bound 0),
    # every Cattaneo-Mindlin sweep still right (138).
    sw = shared_water_study(2, 0.3)[1]
    sw = sw[sw["ramp"] > 1]
    for model, share in (("plateau", 0.8), ("cattaneo-mindlin", 0.97)):
        truth = sw["true_model"] == model
        assert truth.sum() > 50
        assert (sw.loc[truth, "model"] == model).mean() > share


def _evidence(u, df, dg, noise, prior):
    nan = np.array([np.nan])
    return plateau_log_evidence(
        u[None],
        df[None],
        dg[None],
        np.ones((1, u.size)),
        np.full((2, 1), noise),
        (nan, nan),
        (np.array([prior[0]]), np.array([prior[1]])),
        np.array([1.0]),
    )[:, 0]


@pytest.mark.parametrize("noise", [0.6, 1.5])
def test_a_confident_plateau_prior_keeps_a_cattaneo_mindlin_block(noise):
    # A mixed study whose clear plateaus sit at 0.3 u_max (±10 %): its Cattaneo-Mindlin blocks
    # are not pulled into plateaus (2 ln B < -2: positive evidence against), at the noise of
    # the water study (0.6 Hz) and at 2.5 times it.
    prior = (np.log(0.3), 0.1**2)
    for seed in (1, 3, 5):
        assert _evidence(*_block(seed, 0.0, noise), noise, prior)[0] < -2


def test_a_plateau_at_the_prior_is_one_and_its_mu_covers_the_truth():
    # A plateau block at 0.3 u_max under the same prior: positive evidence for the plateau,
    # and its μ with d_c integrated out covers the truth (μ = Pκ/θ = 40/(1.2/u_max) at
    # to_mu = 1) within two of its errors.
    prior = (np.log(0.3), 0.1**2)
    for seed in (2, 4, 6):
        two_ln_b, mu, err = _evidence(*_block(seed, 0.3, 0.6), 0.6, prior)
        assert two_ln_b > 2
        assert abs(mu - 40.0 / (1.2 / 2e-9)) < 2 * err


def test_blocks_evaluated_together_equal_each_alone():
    # All blocks' nodes are evaluated in a few batches, each block's slopes at its distinct
    # amplitudes: blocks of other lengths, blocks of one length with 11 and 33 distinct
    # amplitudes (padded to a common number), a prior on μ for one of them and one without an
    # amplitude prior (NaN out) give each block what it gives alone.
    blocks = [_block(1, 0.0), _block(2, 0.3), _block(3, 0.3), _block(4, 0.0)]
    blocks[1] = tuple(a[:-5] for a in blocks[1])  # a shorter block (its last points dropped)
    uu = blocks[2][0] * (1.0 + 1e-3 * np.arange(33) / 33)  # every amplitude distinct, ascending
    blocks[2] = (uu, *blocks[2][1:])
    M = max(b[0].size for b in blocks)
    u, df, dg, w = np.zeros((4, 4, M))
    for k, (uu, ff, gg) in enumerate(blocks):
        u[k, : uu.size], df[k, : uu.size], dg[k, : uu.size], w[k, : uu.size] = uu, ff, gg, 1.0
    sigma = np.full((2, 4), 0.6)
    mu = (
        np.array([np.nan, np.log(40.0 / 0.6e9), np.nan, np.nan]),
        np.array([np.nan, 0.04] + 2 * [np.nan]),
    )
    ratio = (np.array(3 * [np.log(0.3)] + [np.nan]), np.array(3 * [0.01] + [np.nan]))
    to_mu = np.ones(4)
    both = plateau_log_evidence(u, df, dg, w, sigma, mu, ratio, to_mu)
    assert np.isfinite(both[0, :3]).all() and np.isnan(both[:, 3]).all()
    for k in range(4):
        n = int(w[k].sum())
        alone = plateau_log_evidence(
            u[k : k + 1, :n],
            df[k : k + 1, :n],
            dg[k : k + 1, :n],
            w[k : k + 1, :n],
            sigma[:, k : k + 1],
            tuple(a[k : k + 1] for a in mu),
            tuple(a[k : k + 1] for a in ratio),
            to_mu[k : k + 1],
        )
        np.testing.assert_array_equal(both[:, k], alone[:, 0])


def test_padding_between_the_points_is_ignored():
    # The blocks' distinct amplitudes, their numbers of points, means and scatter are found
    # for all blocks at once (_levels): points of weight 0 anywhere in a row, with any values,
    # change nothing, bit for bit, against the rows without them.
    blocks = [_block(1, 0.3), _block(2, 0.0), _block(3, 0.2)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    rng = np.random.default_rng(7)
    M = u.shape[1] + 6
    pad = np.zeros((3, M), bool)
    for k in range(3):
        pad[k, rng.choice(M, 6, replace=False)] = True
    U, F, G, W = np.zeros((4, 3, M))
    for A, a in ((U, u), (F, df), (G, dg)):
        A[~pad] = a.ravel()
        A[pad] = rng.uniform(0.0, 3e-9, pad.sum())  # junk where the weight is 0
    W[~pad] = 1.0
    rest = (np.full((2, 3), 0.6), (np.full(3, np.nan),) * 2,
            (np.full(3, np.log(0.3)), np.full(3, 0.1)), np.ones(3))  # fmt: skip
    compact = plateau_log_evidence(u, df, dg, np.ones_like(u), *rest)
    assert np.isfinite(compact[0]).all()
    np.testing.assert_array_equal(plateau_log_evidence(U, F, G, W, *rest), compact)


def test_blocks_on_one_grid_share_their_slopes_and_equal_each_alone(monkeypatch):
    # Blocks measured on one grid of amplitudes under one amplitude prior have the same nodes
    # (x, c), so their slopes are evaluated once for all of them: each block still gets, bit
    # for bit, what it gets alone (other noise, other d_c, another μ prior), and the slopes
    # are evaluated at fewer points than for the blocks one by one (their coarse rows alone,
    # 13 of each block's ~20, are the same four times over).
    from contactres.analysis import _plateau_evidence

    points = []
    slopes = _plateau_evidence.plateau_loop_slopes

    def spy(x, c, **kw):
        points.append(np.size(x))
        return slopes(x, c, **kw)

    monkeypatch.setattr(_plateau_evidence, "plateau_loop_slopes", spy)
    blocks = [_block(5, 0.0), _block(6, 0.3), _block(7, 0.3, 1.5), _block(8, 0.2)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    w = np.ones_like(u)
    sigma = np.array([[0.6, 0.6, 1.5, 0.6], [0.6, 0.6, 1.5, 0.6]])
    mu = (np.array([np.nan, np.log(40.0 / 0.6e9), np.nan, np.nan]), np.array([np.nan, 0.04, 1, 1]))
    ratio = (np.full(4, np.log(0.3)), np.full(4, 0.1))
    to_mu = np.ones(4)
    both = plateau_log_evidence(u, df, dg, w, sigma, mu, ratio, to_mu)
    together = sum(points)
    assert np.isfinite(both[0]).all()
    points.clear()
    for k in range(4):
        one = slice(k, k + 1)
        alone = plateau_log_evidence(
            u[one],
            df[one],
            dg[one],
            w[one],
            sigma[:, one],
            tuple(a[one] for a in mu),
            tuple(a[one] for a in ratio),
            to_mu[one],
        )
        np.testing.assert_array_equal(both[:, k], alone[:, 0])
    assert together < 0.7 * sum(points)  # 0.59 with the sharing, 1 without


@pytest.fixture(scope="module")
def study_evidence_call(water_study):
    """The arguments of the analysis's last call of plateau_log_evidence (its undecided blocks)
    on the water study of seed 1 with 30 % plateau loads: the study analysed once for the two
    tests that take real blocks from it."""
    import contactres.analysis._blocks as blocks

    calls = []

    def spy(*args):
        calls.append(args)
        return plateau_log_evidence(*args)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(blocks, "plateau_log_evidence", spy)
        water_study(1, 0.3)
    return calls[-1]


def test_no_row_of_nodes_has_its_slopes_evaluated_twice(monkeypatch):
    # One block a chunk (the chunks' cells shrunk), so that blocks on one grid under one prior
    # meet in no chunk: their rows of nodes (x, c) are still evaluated once in the whole call
    # (the call's store of slopes), and each block gets what it gets in one chunk with the
    # others, bit for bit.
    from contactres.analysis import _plateau_evidence

    blocks = [_block(5, 0.0), _block(6, 0.3), _block(7, 0.3, 1.5), _block(8, 0.2)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    args = (u, df, dg, np.ones_like(u), np.full((2, 4), 0.6), (np.full(4, np.nan),) * 2,
            (np.full(4, np.log(0.3)), np.full(4, 0.1)), np.ones(4))  # fmt: skip
    together = plateau_log_evidence(*args)
    rows = []
    slopes = _plateau_evidence.plateau_loop_slopes

    def spy(x, c, **kw):
        rows.extend(np.concatenate([x, c], axis=-1).reshape(x.shape[0], -1).tolist())
        return slopes(x, c, **kw)

    monkeypatch.setattr(_plateau_evidence, "plateau_loop_slopes", spy)
    monkeypatch.setattr(_plateau_evidence, "EVIDENCE_CHUNK_CELLS", 1)
    apart = plateau_log_evidence(*args)
    np.testing.assert_array_equal(apart, together)
    assert np.isfinite(apart[0]).all()
    # Chunk by chunk the 12 coarse rows in z of the blocks on one grid came four times over.
    assert len({tuple(r) for r in rows}) == len(rows)


def _store_spy(monkeypatch):
    """One block a chunk (the chunks' cells shrunk), and per call of the slopes the rows of
    nodes it asks for (the number of nodes in y and the bytes of θ, d_c/u_max and the
    amplitudes) and the number of rows the call's store of slopes holds after it; the store
    itself last."""
    from contactres.analysis import _plateau_evidence

    calls: list = []
    slopes = _plateau_evidence._slopes

    def spy(theta, dl, lev, store):
        got = slopes(theta, dl, lev, store)
        rows = np.concatenate([theta, dl, lev[:, 0]], axis=1)
        calls.append(({(theta.shape[1], r.tobytes()) for r in rows}, len(store), store))
        return got

    monkeypatch.setattr(_plateau_evidence, "_slopes", spy)
    monkeypatch.setattr(_plateau_evidence, "EVIDENCE_CHUNK_CELLS", 1)
    return calls


def test_the_store_of_slopes_holds_no_row_that_is_not_read_again(monkeypatch):
    # Blocks with amplitudes of their own (measured ones differ by a little from sweep to
    # sweep) share no row of nodes: the store keeps none, where it kept every row of the call
    # (review R24a: 2.3 GB on 10^4 such sweeps). After every call of the slopes it holds at
    # most the rows asked for both before and after it; each block gets what it gets alone.
    blocks = [_block(5, 0.0), _block(6, 0.3), _block(7, 0.3, 1.5), _block(8, 0.2)]
    u = np.stack([b[0] * (1.0 + 1e-6 * k) for k, b in enumerate(blocks)])
    df, dg = (np.stack([b[k] for b in blocks]) for k in (1, 2))
    args = (u, df, dg, np.ones_like(u), np.full((2, 4), 0.6), (np.full(4, np.nan),) * 2,
            (np.full(4, np.log(0.3)), np.full(4, 0.1)), np.ones(4))  # fmt: skip
    alone = []
    for k in range(4):
        one = slice(k, k + 1)
        points = (a[one] for a in args[:4])
        priors = (tuple(v[one] for v in a) for a in args[5:7])
        alone.append(plateau_log_evidence(*points, args[4][:, one], *priors, args[7][one]))
    calls = _store_spy(monkeypatch)
    out = plateau_log_evidence(*args)
    assert np.isfinite(out[0]).all()
    np.testing.assert_array_equal(out, np.concatenate(alone, axis=1))
    asked = [rows for rows, _, _ in calls]
    for i, (_, held, _) in enumerate(calls):
        again = set().union(*asked[: i + 1]) & set().union(*asked[i + 1 :])
        assert not again and held == 0  # blocks of their own amplitudes: nothing to keep


def test_the_store_of_slopes_is_empty_after_each_call(monkeypatch):
    # Blocks on one grid under one prior, one a chunk, share rows across chunks (the store
    # keeps them for the later chunks: no row evaluated twice, above), and the store lets go
    # of each after its last chunk: empty when the call returns, having held fewer rows than
    # the call asked for.
    blocks = [_block(5, 0.0), _block(6, 0.3), _block(7, 0.3, 1.5), _block(8, 0.2)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    args = (u, df, dg, np.ones_like(u), np.full((2, 4), 0.6), (np.full(4, np.nan),) * 2,
            (np.full(4, np.log(0.3)), np.full(4, 0.1)), np.ones(4))  # fmt: skip
    calls = _store_spy(monkeypatch)
    assert np.isfinite(plateau_log_evidence(*args)[0]).all()
    assert len(calls[-1][2]) == 0
    assert max(held for _, held, _ in calls) < len(set().union(*(rows for rows, _, _ in calls)))


def test_the_default_nodes_converge_on_real_study_blocks(study_evidence_call, monkeypatch):
    # Issue 27, point 11 (F1): on undecided water blocks of a seeded study the default nodes give
    # 2 ln B within 0.5 of a grid about seven times finer in z (81 uniform nodes, no refinement)
    # and y (256 + 201): a quarter of the unit that decides (2, Kass & Raftery's "positive");
    # μ within 2 % and its error within 10 %, a tenth of that error, whose own uncertainty
    # with ~30 points per block is ~13 % (1/sqrt(2n)).
    import contactres.analysis._plateau_evidence as pe

    *args, rows = study_evidence_call
    rows = np.flatnonzero(rows)[::4]  # a quarter of the undecided blocks, to keep it quick
    sel = np.zeros(len(args[0]), bool)
    sel[rows] = True
    base = plateau_log_evidence(*args, sel)[:, rows]
    monkeypatch.setattr(pe, "EVIDENCE_NODES", (81, 0, 256, 201))
    fine = plateau_log_evidence(*args, sel)[:, rows]
    assert rows.size >= 10 and np.isfinite(base[0]).all()
    np.testing.assert_array_equal(np.isfinite(base), np.isfinite(fine))
    assert np.abs(base[0] - fine[0]).max() < 0.5
    mu = np.isfinite(base[1])
    assert mu.sum() >= 5
    np.testing.assert_allclose(base[1, mu], fine[1, mu], rtol=0.02)
    np.testing.assert_allclose(base[2, mu], fine[2, mu], rtol=0.1)


def test_the_node_steps_in_blocks_of_rows_give_each_row_its_own_numbers(
    study_evidence_call, monkeypatch
):
    # The projected solve's ratios, the logarithms and the sums over y run in blocks of rows
    # (NODE_BLOCK_CELLS, for the cache): one row a block, and all rows of a chunk in one
    # block (as before the blocks), give the same numbers bit for bit on real study blocks,
    # with the prior on μ and the refined nodes.
    import contactres.analysis._plateau_evidence as pe

    *args, rows = study_evidence_call
    default = plateau_log_evidence(*args, rows)
    assert np.isfinite(default[0]).sum() >= 20 and np.isfinite(default[1]).sum() >= 5
    for cells in (1, 1 << 40):
        monkeypatch.setattr(pe, "NODE_BLOCK_CELLS", cells)
        np.testing.assert_array_equal(plateau_log_evidence(*args, rows), default)


def test_the_nodes_end_at_the_widest_plateau_the_sweep_shows():
    # F6: a prior centred beyond the widest plateau that leaves PLATEAU_MIN_SLOPE amplitudes
    # above it (0.8 u_max here) still integrates over the part below it (a finite, negative
    # 2 ln B: most of the prior's mass counts against the plateau), and a prior wholly beyond
    # it leaves the block to the fit's criterion (NaN), not a veto of -inf.
    block = _block(2, 0.3)
    part = _evidence(*block, 0.6, (np.log(0.8), 0.15**2))
    assert np.isfinite(part[0]) and part[0] < 0
    wider = _evidence(*block, 0.6, (np.log(0.8), 0.3**2))
    assert part[0] < wider[0]  # more of the prior below the limit: less against the plateau
    assert np.isnan(_evidence(*block, 0.6, (np.log(0.95), 0.01**2))).all()


def test_the_marginal_mu_does_not_follow_the_mu_prior():
    # F5: μ's moments use the likelihood alone, so a prior on μ a factor 3 off the truth (which
    # moves the peak of L π, where fine nodes go) leaves the marginal μ as without it.
    u, df, dg = _block(4, 0.3)
    nan = np.array([np.nan])
    ratio = (np.array([np.log(0.3)]), np.array([0.1**2]))
    args = (u[None], df[None], dg[None], np.ones((1, u.size)), np.full((2, 1), 0.6))
    free = plateau_log_evidence(*args, (nan, nan), ratio, np.array([1.0]))[:, 0]
    true_mu = 40.0 / (1.2 / 2e-9)
    prior = (np.array([np.log(3 * true_mu)]), np.array([0.2**2]))
    pulled = plateau_log_evidence(*args, prior, ratio, np.array([1.0]))[:, 0]
    assert pulled[1] == pytest.approx(free[1], rel=0.01)
    assert pulled[2] == pytest.approx(free[2], rel=0.05)


def test_an_unresolved_mu_is_left_to_the_fit(monkeypatch):
    # F4: at five times the water noise the plateau's μ is known to no better than ~90 % (sd of
    # ln μ 0.9-1.6): no marginal μ, while the evidence is still given. The old cut (sd <= 1)
    # let the first through.
    import contactres.analysis._plateau_evidence as pe

    blocks = [_block(seed, 0.3, 3.0) for seed in (1, 2, 3)]
    prior = (np.log(0.3), 0.1**2)
    for block in blocks:
        two_ln_b, mu, err = _evidence(*block, 3.0, prior)
        assert np.isfinite(two_ln_b)
        assert np.isnan(mu) and np.isnan(err)
    monkeypatch.setattr(pe, "MU_MARGINAL_MAX_SD", 1.0)
    monkeypatch.setattr(pe, "MU_MARGINAL_MAX_EDGE", 1.0)
    _, mu, err = _evidence(*blocks[0], 3.0, prior)
    assert 0.5 < err / mu < 1.0


def test_a_mu_piled_up_at_the_fitters_bound_is_left_to_the_fit(monkeypatch):
    # F4: a loop that slips far beyond the loop table (x_max = θ u_max = 100 > X_MAX = 30) has its
    # likelihood rising to the end of the y grid: the moments of ln μ there are the grid's
    # (sd < 0.5, but μ 3-4 times the truth), so no marginal μ; without the edge rule there is one.
    import contactres.analysis._plateau_evidence as pe

    rng = np.random.default_rng(2)
    umax, x_max = 2e-9, 100.0
    u = np.sort(np.tile(np.linspace(0.1, 1.0, 11) * umax, 3))
    g1, g2 = plateau_loop_shape(x_max / umax * u, x_max * 0.3)
    df = 40.0 * g1 + 0.6 * rng.standard_normal(u.size)
    dg = 5.0 + 40.0 * g2 + 0.6 * rng.standard_normal(u.size)
    prior = (np.log(0.3), 0.1**2)
    two_ln_b, mu, _ = _evidence(u, df, dg, 0.6, prior)
    assert np.isfinite(two_ln_b) and np.isnan(mu)
    monkeypatch.setattr(pe, "MU_MARGINAL_MAX_EDGE", 1.0)
    _, mu, err = _evidence(u, df, dg, 0.6, prior)
    assert err / mu < 0.5 and mu > 2 * 40.0 / (x_max / umax)


def test_the_evidence_over_worker_processes_equals_the_serial_one(study_evidence_call, monkeypatch):
    # Issue 31, point 3: the undecided blocks of a seeded study split over 2 worker processes
    # (the per-worker threshold lowered so that this small study splits) give every block
    # bit for bit what the serial call gives, NaN where the serial call leaves NaN.
    import contactres.analysis._blocks as blocks

    chunks = []

    def run(fn, workers, first, *rest):
        chunks.append([len(a) for a in first])
        return run_pool(fn, workers, first, *rest)

    run_pool = blocks.run_in_workers
    args = study_evidence_call
    rows = np.flatnonzero(args[-1])
    assert rows.size >= 20 and rows.size < len(args[-1])  # some blocks are left out (NaN)
    serial = plateau_log_evidence(*args)
    monkeypatch.setattr(blocks, "run_in_workers", run)
    monkeypatch.setattr(blocks, "EVIDENCE_ROWS_PER_WORKER", 5)
    two = blocks._evidence(2, *args)
    assert chunks == [[(rows.size + 1) // 2, rows.size // 2]]  # two interleaved halves
    assert np.isfinite(serial[0]).sum() >= 10
    assert np.array_equal(two, serial, equal_nan=True)


def test_the_sums_of_a_chunks_points_formed_once_are_each_evaluations_own(
    study_evidence_call, monkeypatch
):
    # A chunk's sums of its blocks' points (weights, C_f, C_Γ, n, ...; the numbers of their rows
    # of weights) are formed once and handed to each of its evaluations (coarse nodes, fine ones
    # around each peak): every output the same, bit for bit, as with each evaluation forming its
    # own from the chunk's points, and the sums are met at every evaluation. On the undecided
    # blocks of a seeded study (several grids, numbers of points and priors) and on blocks of
    # one grid under one prior (their rows share their slopes) whose numbers of points at an
    # amplitude differ (points dropped: the rows on one row of slopes have other weights).
    from contactres.analysis import _plateau_evidence as ev

    blocks = [_block(5, 0.0), _block(6, 0.3), _block(7, 0.3, 1.5), _block(8, 0.2)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    w = np.ones_like(u)
    w[1, 4], w[2, [0, 9]] = 0.0, 0.0  # each amplitude still measured: the same grid
    grid = (u, df, dg, w, np.full((2, 4), 0.6), (np.full(4, np.nan),) * 2,
            (np.full(4, np.log(0.3)), np.full(4, 0.1)), np.ones(4))  # fmt: skip
    inner, given = ev._integrand_in_sets, []

    def own(pts, dl, y, store, out, own=None, sums=None):
        given.append(sums is not None)
        return inner(pts, dl, y, store, out, own)

    for args in (study_evidence_call, grid):
        shared = plateau_log_evidence(*args)
        with monkeypatch.context() as m:
            m.setattr(ev, "_integrand_in_sets", own)
            alone = plateau_log_evidence(*args)
        assert len(given) >= 3 and all(given)
        assert np.isfinite(shared[0]).sum() >= 3
        assert np.array_equal(alone, shared, equal_nan=True)


def test_few_undecided_blocks_stay_in_this_process(monkeypatch):
    # Below EVIDENCE_ROWS_PER_WORKER blocks a worker no pool starts (a small study with
    # workers > 1 pays nothing for it), and the result is the serial call's.
    import contactres.analysis._blocks as blocks

    def no_pool(*args):
        raise AssertionError("a pool started")

    monkeypatch.setattr(blocks, "run_in_workers", no_pool)
    u, df, dg = _block(1, 0.3)
    n = 2 * blocks.EVIDENCE_ROWS_PER_WORKER - 1
    args = (
        np.tile(u, (n, 1)),
        np.tile(df, (n, 1)),
        np.tile(dg, (n, 1)),
        np.ones((n, u.size)),
        np.full((2, n), 0.6),
        (np.full(n, np.nan), np.full(n, np.nan)),
        (np.full(n, np.log(0.3)), np.full(n, 0.01)),
        np.ones(n),
        np.arange(n) % 40 == 0,  # a few of them, as in a small study
    )
    assert np.array_equal(blocks._evidence(2, *args), plateau_log_evidence(*args), equal_nan=True)


def test_blocks_under_different_priors_equal_each_alone():
    # Blocks under different d_c priors have different nodes in z: a fine node clipped onto its
    # own block's coarse end must be recognised against that block's ends, not another's (it
    # was read from unwritten memory, NaN, when blocks of other priors came after it). Twelve
    # seeded draws of four blocks, priors from d_c = 0.02 to 0.6 u_max, some narrow enough for
    # the peak to sit at an end of the nodes.
    rng = np.random.default_rng(7)
    for _ in range(12):
        ratios = rng.choice([0.0, 0.1, 0.3, 0.5], size=4)
        blocks = [_block(int(rng.integers(1 << 30)), r) for r in ratios]
        u, df, dg = (np.array(a) for a in zip(*blocks, strict=True))
        w = np.ones_like(u)
        sigma = np.full((2, 4), 0.6)
        mu = (np.full(4, np.nan), np.full(4, np.nan))
        ratio = (np.log(rng.uniform(0.02, 0.6, 4)), rng.choice([0.0025, 0.01, 0.25], size=4))
        both = plateau_log_evidence(u, df, dg, w, sigma, mu, ratio, np.ones(4))
        for k in range(4):
            one = slice(k, k + 1)
            alone = plateau_log_evidence(
                u[one], df[one], dg[one], w[one], sigma[:, one],
                tuple(a[one] for a in mu), tuple(a[one] for a in ratio), np.ones(1),
            )  # fmt: skip
            np.testing.assert_array_equal(both[:, k], alone[:, 0])


def test_a_fit_exact_to_rounding_keeps_its_node():
    """Review R22b: data equal to the model at one node of y (no scatter). The expanded square
    of the projected solve then comes out at rounding level, and could come out negative: that
    node's ln L was -inf, the best node lost. Held at its rounding floor it stays the largest
    ln L of the row, and finite."""
    from contactres.analysis import _plateau_evidence as ev
    from contactres.analysis._plateau_slopes import plateau_loop_slopes

    n_amp, n_y = 11, 5
    umax = 2e-9
    lev = np.linspace(0.1, 1.0, n_amp) * umax
    dl = np.array([[0.3]])
    y = np.linspace(-0.5, 0.5, n_y)[None]
    theta = np.exp(y) / (umax * (1 - dl))
    x = theta[..., None] * lev
    c = np.broadcast_to((theta * dl * umax)[..., None], x.shape)
    g1, g2 = plateau_loop_slopes(x, c, derivatives=False)
    df, dg = 40.0 * g1[0, 2], 5.0 + 40.0 * g2[0, 2]
    n_lev = np.full((1, 1, n_amp), 3.0)
    one, none = np.array([[1.0]]), np.array([[np.nan]])
    zero = np.zeros((1, 1))
    pts = (lev[None, None], n_lev, df[None, None], dg[None, None], zero, zero,
           np.array([[umax]]), one, one, none, none, one)  # fmt: skip
    _, lnl, _ = ev._integrand(pts, dl, y)
    assert np.all(np.isfinite(lnl[0]))
    assert np.argmax(lnl[0]) == 2


def test_rows_of_the_same_bytes_are_found_as_by_a_sort_of_the_bytes(monkeypatch):
    # The slopes' distinct rows of nodes (found by an integer of their bits) are the sets of
    # rows numpy.unique finds by their bytes: duplicated rows, rows one ulp apart in one
    # column (whose sums of doubles round to the same), -0.0 against 0.0, and two rows of
    # other bytes with the same integer (the sort of the bytes decides: its fallback).
    from contactres.analysis import _plateau_evidence as ev
    from contactres.analysis._plateau_evidence import _distinct_rows

    sorts = []

    def void_rows(a):
        sorts.append(a.shape)
        return real_void_rows(a)

    real_void_rows = ev._void_rows
    monkeypatch.setattr(ev, "_void_rows", void_rows)
    rng = np.random.default_rng(3)
    base = rng.random((40, 23))
    near = base[:10].copy()
    at = (np.arange(10), rng.integers(0, 23, 10))
    near[at] = np.nextafter(near[at], 2.0)
    signed = np.zeros((2, 23))
    signed[1, 5] = -0.0
    # The integer is sum_j bits_j * odd_j mod 2^64 with odd_0 = 1, odd_1 = K | 1: column 1's
    # bits minus 1 and column 0's plus K | 1 keep it. Checked here as the function computes it;
    # the fallback having run is checked below by its call of _void_rows.
    k = np.uint64(0x5851F42D4C957F2D | 1)
    pair = base[11:13].copy()
    pair[1] = pair[0]
    bits = pair.view(np.uint64)
    bits[1, 1] -= np.uint64(1)
    bits[1, 0] += k
    odd = (np.arange(23, dtype=np.uint64) * k) | np.uint64(1)
    hashes = (bits * odd).sum(axis=1)
    assert hashes[0] == hashes[1] and (bits[0] != bits[1]).any()
    rows = np.concatenate([base, base[::3], near, signed, base[:7], pair[1:]])
    rows = rows[rng.permutation(rows.shape[0])]
    first, inv = _distinct_rows(rows)
    assert sorts == [rows.shape]  # the fallback ran
    _, ref_first, ref_inv = np.unique(
        rows.view(np.dtype((np.void, 8 * 23)))[:, 0], return_index=True, return_inverse=True
    )
    assert first.size == ref_first.size
    # The same partition of the rows: each row's first is the reference's first.
    np.testing.assert_array_equal(first[inv], ref_first[ref_inv])


def test_an_even_number_of_fine_nodes_evaluates_l_one_step_from_l_pi(monkeypatch):
    # Review R27c: with an even nf no fine node of L's span falls on L π's, so where the peaks
    # of L and L π lie one coarse step apart every node of L's span is evaluated (it took
    # L π's values at L π's nodes: 2 ln B off by 0.8 here). A μ prior pulled off the truth
    # puts the peaks one step apart; an even and an odd nf (24, 25) then give 2 ln B alike,
    # as they do where the peaks coincide.
    import contactres.analysis._plateau_evidence as pe

    u, df, dg = _block(4, 0.3)
    args = (u[None], df[None], dg[None], np.ones((1, u.size)), np.full((2, 1), 0.6))
    ratio = (np.array([np.log(0.3)]), np.array([0.1**2]))
    true_mu = 40.0 / (1.2 / 2e-9)
    apart = []
    patterns = pe._y_patterns

    def spy(at_p, at_l, *rest):
        apart.extend(np.abs(at_l - at_p).tolist())
        return patterns(at_p, at_l, *rest)

    monkeypatch.setattr(pe, "_y_patterns", spy)
    for factor in (1.5, 2.0):
        prior = (np.array([np.log(factor * true_mu)]), np.array([0.05**2]))
        two_ln_b = []
        for nf in (24, 25):
            monkeypatch.setattr(pe, "EVIDENCE_NODES", (12, 5, 32, nf))
            apart.clear()
            two_ln_b.append(plateau_log_evidence(*args, prior, ratio, np.array([1.0]))[0, 0])
            assert 1 in apart  # the case at stake is met
        assert np.isfinite(two_ln_b).all()
        assert abs(two_ln_b[0] - two_ln_b[1]) < 0.05


def _rows_as_alone(pts, dl, y, own):
    """_integrand's values of the rows ``own`` (their blocks in ``pts``), checked finite and
    each as the row evaluated alone (within 1e-13: another BLAS may round other product shapes
    otherwise); returns them."""
    from contactres.analysis import _plateau_evidence as ev

    by_index = ev._integrand(pts, dl, y, own=own)
    assert np.isfinite(by_index).all()
    scale = np.abs(by_index).max()
    for r, b in enumerate(own):
        alone = ev._integrand(tuple(a[[b]] for a in pts), dl[[r]], y)
        np.testing.assert_allclose(by_index[:, r], alone[:, 0], rtol=1e-13, atol=1e-13 * scale)
    return by_index


def test_rows_evaluated_together_equal_each_row_evaluated_alone():
    # The integrand takes each block's points once and each row's block by index (``own``),
    # orders the rows into sets that share their slopes and scatters each segment's values
    # back: every row's numbers must be those of the row evaluated alone, bit for bit (a
    # block's result depends on its own row alone: the evidence deals blocks out to worker
    # processes), for rows sharing their slopes (one grid of amplitudes, equal d_c/u_max), rows
    # of their own, a prior on μ for one block, and nodes in y given once for all rows. A row
    # alone takes another path (its own slopes, the stacked products), so a row written to
    # another row's place or solved with another block's numbers is caught, which the same
    # rows given copies of their points (the same ordering and scatter) would not catch. Those
    # are products of other shapes, which another BLAS build may round otherwise: within
    # 1e-13 of the values' scale here (equal bits on this machine; what the workers need, the
    # same shapes whatever the split, is tests/analysis/test_workers.py's), while either
    # mistake moves them by far more.
    from contactres.analysis import _plateau_evidence as ev

    blocks = [_block(1, 0.0), _block(2, 0.3), _block(3, 0.3)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    w = np.ones_like(u)
    sigma = np.array([[0.6, 0.5, 0.7], [0.6, 0.8, 0.5]])
    mu = (np.array([np.nan, np.log(40.0 / 0.6e9), np.nan]), np.array([np.nan, 0.04, np.nan]))
    per_block = ev._levels(u, df, dg, w, np.arange(3))
    pts = ev._rows(per_block, sigma, mu, np.ones(3), [0, 1, 2])
    own = np.array([2, 0, 1, 0, 2, 1, 1, 0])
    dl = np.array([0.3, 0.3, 0.3, 0.1, 0.1, 0.2, 0.05, 0.0])[:, None]
    y = np.linspace(-4.0, 1.0, 9)[None]
    by_index = _rows_as_alone(pts, dl, y, own)
    # Nodes in y given row by row: the same numbers.
    np.testing.assert_array_equal(
        by_index, ev._integrand(pts, dl, np.repeat(y, own.size, axis=0), own=own)
    )


@pytest.mark.parametrize("sizes", [[1, 1, 1], [5, 1, 7, 2, 2, 9, 1], [40], [3] * 20])
def test_segments_are_runs_of_whole_sets_of_at_least_the_rows_asked(sizes):
    # The node steps run over segments of whole sets of rows that share their slopes: every
    # set in one segment, in their order, each segment the fewest sets that reach the rows
    # asked (the last: what is left).
    from contactres.analysis._evidence_solve import segments

    cut = np.concatenate([[0], np.cumsum(sizes)])
    for rows in (1, 4, 10, 1000):
        got = segments(cut, rows)
        expect, start, total = [], 0, 0
        for d, n in enumerate(sizes):
            total += n
            if total >= rows or d == len(sizes) - 1:
                expect.append((start, d + 1))
                start, total = d + 1, 0
        assert got == expect


def test_the_solve_at_the_nodes_is_the_weighted_least_squares_fit_of_the_points():
    # ln L + ln π, ln L and ln μ at a node from the sums over a block's distinct amplitudes
    # (level_weights, level_sums, node_values) against the weighted least-squares fit of its
    # points one by one, written out here: min over Pκ, Pωξ of
    # w_f Σ (Δf - Pκ G′)² + w_Γ Σ (ΔΓ - Pωξ - Pκ G″)², w = 1/σ², then
    # ln L = -n/2 (ln RSS_f + ln RSS_Γ), μ = Pκ to_mu / θ. The noise levels differ and the
    # channels disagree on Pκ (40 Hz in Δf, 25 Hz in ΔΓ), so that Pκ, and every value, depends
    # on which channel carries which weight. Both paths of the sums are taken: rows on slopes
    # of their own (stacked products; block 2 on fewer amplitudes, padded) and two blocks on one
    # grid of amplitudes sharing one row of slopes.
    from contactres.analysis import _plateau_evidence as ev
    from contactres.analysis._evidence_solve import level_sums, level_weights, node_values

    rng = np.random.default_rng(7)
    umax = 2e-9
    grid, short = np.linspace(0.1, 1.0, 11) * umax, np.linspace(0.2, 1.0, 9) * umax
    u = [np.tile(grid, 3), np.tile(grid, 3), np.tile(short, 4)]
    data = []
    for uu in u:
        g1, g2 = plateau_loop_shape(1.2 / umax * uu, 1.2 * 0.3)  # x_max 1.2, d_c 0.3 u_max
        df = 40.0 * g1 + 0.6 * rng.standard_normal(uu.size)
        data.append((df, 5.0 + 25.0 * g2 + 0.6 * rng.standard_normal(uu.size)))
    arrays = np.zeros((4, 3, 36))  # u, Δf, ΔΓ, w of each block, padded
    for b, (uu, (df, dg)) in enumerate(zip(u, data, strict=True)):
        arrays[:3, b, : uu.size] = uu, df, dg
        arrays[3, b, : uu.size] = 1.0
    sigma = np.array([[0.4, 1.5, 1.5], [1.5, 0.4, 0.3]])  # σ_f, σ_Γ (rows) of each block
    to_mu = np.array([1.0, 2.0, 0.5])
    mu = (np.array([np.log(40.0 / 0.6e9), np.nan, np.nan]), np.array([0.04, np.nan, np.nan]))
    per_block = ev._levels(*arrays, np.arange(3))
    pts = ev._rows(per_block, sigma, mu, to_mu, [0, 1, 2])
    levels = pts[0][:, 0]  # (3, 11): block 2's padded with u_max
    W, n, per = level_weights(pts, levels.shape[1])
    theta = np.array([0.4, 0.9, 1.2, 1.7, 2.5]) / umax

    def slopes_at(uu, dl):  # [G′; G″] (2Y, len(uu)) at the nodes θ
        g1, g2 = plateau_loop_shape(theta[:, None] * uu, theta[:, None] * dl * umax)
        return np.concatenate([g1, g2])

    def reference(b, dl):  # the fit of block b's points at each node: (3, Y)
        (df, dg), root = data[b], np.sqrt(sigma[:, b] ** -2.0)
        out = np.empty((3, theta.size))
        for j, t in enumerate(theta):
            g1, g2 = plateau_loop_shape(t * u[b], t * dl * umax)
            zero, one = np.zeros_like(g1), np.ones_like(g1)
            design = np.concatenate([root[0] * np.c_[g1, zero], root[1] * np.c_[g2, one]])
            rhs = np.concatenate([root[0] * df, root[1] * dg])
            (A, B), *_ = np.linalg.lstsq(design, rhs, rcond=None)
            rss_f, rss_g = np.sum((df - A * g1) ** 2), np.sum((dg - B - A * g2) ** 2)
            ln_l = -0.5 * g1.size * (np.log(rss_f) + np.log(rss_g))
            ln_mu = np.log(A * to_mu[b] / t)
            m, v = mu[0][b], mu[1][b]
            ln_pi = 0.0  # no prior on μ: flat
            if np.isfinite(m):
                ln_pi = -0.5 * (ln_mu - m) ** 2 / v - 0.5 * np.log(2 * np.pi * v)
            out[:, j] = ln_l + ln_pi, ln_l, ln_mu
        return out

    dl = np.array([0.3, 0.1, 0.2])
    cases = [  # (slopes, the rows' blocks, their sets, d_c/u_max of each row)
        (np.stack([slopes_at(levels[b], dl[b]) for b in range(3)]), [0, 1, 2], [0, 1, 2, 3], dl),
        (slopes_at(grid, 0.3)[None], [0, 1], [0, 2], [0.3, 0.3]),
    ]
    for slopes, block, cut, row_dl in cases:
        block, cut = np.array(block), np.array(cut)
        got = np.empty((3, block.size, theta.size))
        lin, sq = level_sums(slopes, slopes * slopes, W, n, block, cut, 0, cut.size - 1)
        node_values(lin, sq, per[block], np.tile(theta, (block.size, 1)), got)
        for r, b in enumerate(block):
            # The sums by the expanded square round to ~3e-13 of ln L here (level_sums); the
            # weights of Δf and ΔΓ swapped move every value by up to 7 %.
            np.testing.assert_allclose(got[:, r], reference(b, row_dl[r]), rtol=2e-12, atol=0)


def test_the_sums_over_y_read_each_node_where_it_was_evaluated():
    # _over_y evaluates each node of the rule once, leaves the values where the integrand
    # formed them (rows in sets that share their slopes; L's nodes that L π's stand for not
    # evaluated again) and reads each row's nodes from there in their order of y. Against
    # every node of the rule evaluated row by row, in order, and summed by the trapezoidal
    # rule written out here, for rows whose peaks of L and L π coincide, lie one coarse step
    # apart either way and further apart (a μ prior off the truth moves L π's): the same
    # numbers to rounding (a node that another stands for differs from it by rounding in y,
    # where a value read from a wrong node differs by far more).
    from contactres.analysis import _plateau_evidence as ev
    from contactres.analysis._loops import X_MAX
    from contactres.analysis._slope_store import SlopeStore

    factors = [0.5, 0.7, 0.9, 1.0, 1.2, 1.5, 2.0, 3.0]
    blocks = [_block(seed, 0.3) for seed in range(len(factors))]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    B = len(factors)
    mu = (np.log(np.array(factors) * 40.0 / (1.2 / 2e-9)), np.full(B, 0.05**2))
    per_block = ev._levels(u, df, dg, np.ones_like(u), np.arange(B))
    pts = ev._rows(per_block, np.full((2, B), 0.6), mu, np.ones(B), list(range(B)))
    own = np.repeat(np.arange(B), 3)
    dl = np.tile([0.05, 0.3, 0.5], B)
    got = np.array(ev._over_y(pts, own, dl, SlopeStore()))
    _, _, ny, nf = ev.EVIDENCE_NODES
    coarse = np.linspace(np.log(10.0**-2.5), np.log(X_MAX), ny)
    offsets = np.linspace(-1.0, 1.0, nf) * (coarse[1] - coarse[0])
    sides = set()
    for r, b in enumerate(own):
        one, at = tuple(a[[b]] for a in pts), dl[[r]][:, None]
        lp, ll, _ = ev._integrand(one, at, coarse[None])[:, 0]
        peaks = [int(np.argmax(lp)), int(np.argmax(ll))]
        sides.add(int(np.clip(peaks[1] - peaks[0], -2, 2)))
        fine = [np.clip(coarse[k] + offsets, coarse[0], coarse[-1]) for k in peaks]
        y = np.sort(np.concatenate([coarse, *fine]))
        lp, ll, mu_y = ev._integrand(one, at, y[None])[:, 0]
        ep, el = np.exp(lp - lp.max()), np.exp(ll - ll.max())
        z = np.trapezoid(el, y)
        cells = 0.5 * (el[1:] + el[:-1]) * np.diff(y)
        edge = (y[1:] <= coarse[1]) | (y[:-1] >= coarse[-2])
        expect = [
            np.log(np.trapezoid(ep, y)) + lp.max(),
            np.log(z) + ll.max(),
            np.trapezoid(el * mu_y, y) / z,
            np.trapezoid(el * mu_y**2, y) / z,
            cells[edge].sum() / z,
        ]
        np.testing.assert_allclose(got[:5, r], expect, rtol=1e-9)
        assert got[5, r] == min((ep >= 0.1).sum(), (el >= 0.1).sum())
    assert sides == {-2, -1, 0, 1, 2}  # every way of sharing L π's nodes is met


def test_rows_of_one_set_with_other_numbers_of_points_keep_their_own_sums():
    # The sums of the squares of the slopes are formed once for a set of rows on one distinct
    # row of slopes where all its blocks have the same numbers of points at each amplitude;
    # a block with another number at one amplitude (a point dropped: weight 0) on the same
    # grid and d_c shares the set but not the sums: each row equals the row evaluated alone.
    from contactres.analysis import _plateau_evidence as ev

    blocks = [_block(1, 0.3), _block(2, 0.3), _block(3, 0.3), _block(4, 0.3)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    w = np.ones_like(u)
    w[1, 4] = 0.0  # block 1: two points at its second amplitude, the others three
    w[3, [4, 9]] = 0.0  # block 3: two at its second and at its fourth
    B = len(blocks)
    per_block = ev._levels(u, df, dg, w, np.arange(B))
    assert len({per_block[b][0].tobytes() for b in range(B)}) == 1  # one grid
    assert len({per_block[b][1].tobytes() for b in range(B)}) == 3  # three sets of numbers
    pts = ev._rows(per_block, np.full((2, B), 0.6), (np.full(B, np.nan),) * 2, np.ones(B), range(B))
    own = np.array([0, 1, 2, 3, 1, 0, 3])
    dl = np.array([0.3, 0.3, 0.3, 0.3, 0.1, 0.1, 0.1])[:, None]
    y = np.linspace(-4.0, 1.0, 9)[None]
    _rows_as_alone(pts, dl, y, own)


def test_nodes_without_a_likelihood_are_none_beside_nodes_with_one():
    # Where the projected solve's Pκ is not positive (Δf against the loop's shape) a node has
    # no likelihood: ln L π and ln L -inf, ln μ 0 there; the rows evaluated with it (the same
    # grid and d_c: one set of slopes) keep their values, those of each alone. Pκ's sign by
    # the weighted least-squares fit of the points written out here (the 2 x 2 normal
    # equations of _reference), node by node.
    from contactres.analysis import _plateau_evidence as ev

    blocks = [_block(5, 0.3), _block(6, 0.3), _block(7, 0.3)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    df[1] = -df[1]  # block 1: Δf against the shape, Pκ < 0
    sigma = np.array([[0.6, 0.6, 0.6], [0.6, 0.6, 0.6]])
    per_block = ev._levels(u, df, dg, np.ones_like(u), np.arange(3))
    pts = ev._rows(per_block, sigma, (np.full(3, np.nan),) * 2, np.ones(3), [0, 1, 2])
    y = np.linspace(-7.0, 1.0, 41)
    dl = np.full((3, 1), 0.3)
    got = ev._integrand(pts, dl, y[None])
    umax = u.max()
    theta = np.exp(y)[:, None] / (umax * (1 - 0.3))
    w0, w1 = sigma[0, 0] ** -2.0, sigma[1, 0] ** -2.0
    for b in range(3):
        g1, g2 = plateau_loop_shape(theta * u[b], theta * 0.3 * umax)
        a11 = w0 * np.sum(g1 * g1, 1) + w1 * np.sum(g2 * g2, 1)
        a12, a22 = w1 * np.sum(g2, 1), w1 * u.shape[1]
        b1, b2 = w0 * (g1 @ df[b]) + w1 * (g2 @ dg[b]), w1 * np.sum(dg[b])
        pk = (a22 * b1 - a12 * b2) / (a11 * a22 - a12 * a12)
        assert (pk < 0).all() if b == 1 else (pk > 0).all()
        none = pk < 0
        assert (got[0, b, none] == -np.inf).all() and (got[1, b, none] == -np.inf).all()
        assert (got[2, b, none] == 0.0).all()
        assert np.isfinite(got[:, b, ~none]).all()
        alone = ev._integrand(tuple(a[[b]] for a in pts), dl[[b]], y[None])[:, 0]
        np.testing.assert_array_equal(got[:, b], alone)


def test_the_cells_of_rows_laid_end_to_end_are_the_trapezoidal_rules():
    # _cells forms the trapezoid's terms on the rows laid end to end (the pairs across the end
    # of a row fall in a last column, times the spacing 0 there): the sums of the first N - 1
    # columns are numpy.trapezoid's on each row alone, bit for bit, with large values at the
    # ends of the rows (where a pair across rows would show) and one row of infinities.
    from contactres.analysis._plateau_evidence import _cells

    rng = np.random.default_rng(3)
    x = np.cumsum(rng.uniform(0.01, 0.3, (5, 9)), axis=1)
    f = rng.uniform(0.0, 1.0, x.shape)
    f[:, [0, -1]] = 1e3
    f[2] = np.inf
    half = np.zeros(x.shape)
    half[:, :-1] = np.diff(x, axis=1) / 2.0
    with np.errstate(invalid="ignore"):
        got = _cells(f, half)[:, :-1].sum(axis=1)
    np.testing.assert_array_equal(got, np.trapezoid(f, x, axis=1))


@pytest.mark.parametrize("to_mu", [0.0, np.inf])
def test_a_row_of_infinite_ln_mu_leaves_the_rows_beside_it_alone(to_mu):
    # _over_y_rows forms the trapezoid's terms on its rows laid end to end: the pair across
    # the end of a row falls in a last column, times a spacing 0, and is left out of the sums.
    # Where the next row's first value is not finite (ln μ = ±inf: to_mu 0 or inf and no prior
    # on μ; L's density 0 there, 0·inf = NaN) that pair is NaN: a row's moments of ln μ must
    # not take it. Every row of a call against the row evaluated alone.
    from contactres.analysis import _plateau_evidence as ev
    from contactres.analysis._slope_store import SlopeStore

    blocks = [_block(s, 0.3) for s in range(6)]
    u, df, dg = (np.stack([b[k] for b in blocks]) for k in range(3))
    B = len(blocks)
    to = np.ones(B)
    to[[1, 4]] = to_mu
    per_block = ev._levels(u, df, dg, np.ones_like(u), np.arange(B))
    nan = np.full(B, np.nan)
    pts = ev._rows(per_block, np.full((2, B), 0.6), (nan, nan), to, list(range(B)))
    own = np.repeat(np.arange(B), 4)
    dl = np.tile([0.0, 0.1, 0.3, 0.5], B)
    got = np.array(ev._over_y(pts, own, dl, SlopeStore()), dtype=float)
    assert np.isfinite(got[2, own != 1]).any()
    for r, b in enumerate(own):
        one = tuple(a[[b]] for a in pts)
        alone = np.array(ev._over_y(one, np.array([0]), dl[[r]], SlopeStore()), dtype=float)
        np.testing.assert_allclose(got[:, r], alone[:, 0], rtol=1e-13)
