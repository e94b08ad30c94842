"""The plateau-loop fit's savings (contactres.analysis._plateau): the gradient and Hessian formed
at accepted steps only (bit for bit), the repeated amplitudes of a block pooled (to rounding)."""

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import _plateau
from contactres.analysis._amplitude import fit_hinge, pad_sweeps
from contactres.analysis._loops import cm_loop_table, projection_data
from contactres.analysis._plateau import fit_plateau_loops, pool_repeats
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.resonators._qcm import QCM

Q = QCM(fundamental=5e6, overtone=3, area=2.5e-5)


def _sweeps(model, n_exp=6, seed=3):
    """Padded sweeps of one amplitude grid (13 points), their hinges' u_c and noise levels."""
    u = tuple(np.linspace(0.5e-9, 8e-9, 13))
    group = SweepGroup("g", "air", 1.1e-3, 70e9, 0.1, u, 5.0 / Q.sensitivity(3), 0.1)
    study = SweepStudy(
        groups=(group,),
        normal_forces=(3e-3, 6e-3),
        n_experiments=n_exp,
        ramps=(2, 3),
        qcm=Q,
        model=model,
        mu=1.5,
        plateau_fraction=0.4,
    )
    table = synthetic_sweeps(study, seed, constants=True)
    p = pad_sweeps(validate_sweeps(pd.DataFrame(table)).data)
    b = p.block(np.arange(len(p.n)))
    hinge = fit_hinge(b)
    sig = np.sqrt(hinge.line.rss / np.maximum(b.n - 3, 1))
    return b, hinge.u_c, sig


def _blocks(b, u_c, sig):
    """Three sweeps at a time as one row of a block fitted jointly: each amplitude three times,
    side by side (the layout of the blocks of issue 31), a fourth of the rows with a point
    dropped (a block's ramps may differ in length)."""
    k = 3 * (len(b.n) // 3)
    u, df, dg, w = (
        np.stack([a[i:k:3] for i in range(3)], axis=-1).reshape(k // 3, -1)
        for a in (b.u, b.df, b.dg, b.w)
    )
    w[::4, 4] = 0.0
    start = [a[:k:3] for a in (u_c, sig[0], sig[1])]
    return u, df, dg, w, *start


def test_pooled_amplitudes_hold_the_sums_of_squares():
    # Against the sums over the points one by one, for an arbitrary loop per amplitude.
    rng = np.random.default_rng(11)
    u = np.repeat(np.sort(rng.random((6, 5)), axis=1), 3, axis=1)
    df, dg = rng.normal(size=u.shape), rng.normal(size=u.shape)
    w = np.ones(u.shape)
    w[0, 7] = w[1, -2:] = 0.0
    amp, mf, mg, weight, root, within_f, within_g = pool_repeats(u, df, dg, w)
    assert np.allclose(root**2, weight) and np.array_equal(weight.sum(axis=1), w.sum(axis=1))
    model = np.sin(7.0 * amp)  # any function of the amplitude
    direct = (w * (df - np.sin(7.0 * u)) ** 2).sum(axis=1)
    np.testing.assert_allclose((weight * (mf - model) ** 2).sum(axis=1) + within_f, direct)
    direct = (w * (dg - np.sin(7.0 * u)) ** 2).sum(axis=1)
    np.testing.assert_allclose((weight * (mg - model) ** 2).sum(axis=1) + within_g, direct)
    assert pool_repeats(u[:, ::3], df[:, ::3], dg[:, ::3], w[:, ::3]) is None


@pytest.mark.parametrize("model", ["plateau", "cattaneo-mindlin"])
def test_pooled_block_fit_is_the_fit_point_by_point(model, monkeypatch):
    # The bound of the module docstring: each parameter within 1e-3 of its standard error of the
    # fit over the points one by one (pool_repeats off), errors within 1e-3 relative, the same
    # edges and the same fits on the bound d_c = 0.
    u, df, dg, w, u_c, sf, sg = _blocks(*_sweeps(model))
    table = cm_loop_table()
    fit = fit_plateau_loops(u, df, dg, w, sf, sg, u_c, table)
    monkeypatch.setattr(_plateau, "pool_repeats", lambda *a: None)
    ref = fit_plateau_loops(u, df, dg, w, sf, sg, u_c, table)
    assert np.array_equal(fit["edge"], ref["edge"])
    assert np.array_equal(np.isnan(fit["d_c_err_m"]), np.isnan(ref["d_c_err_m"]))
    for col, err in (("df0_Hz", "df0_err_Hz"), ("dgamma0_Hz", "dgamma0_err_Hz")):
        assert np.all(np.abs(fit[col] - ref[col]) <= 1e-3 * ref[err]), col
    lnt = np.abs(np.log(fit["theta_per_m"] / ref["theta_per_m"]))
    assert np.all(lnt <= 1e-3 * ref["lntheta_err"])
    free = np.isfinite(ref["d_c_err_m"])
    assert np.all(np.abs(fit["d_c_m"] - ref["d_c_m"])[free] <= 1e-3 * ref["d_c_err_m"][free])
    assert np.all(fit["d_c_m"][~free] == 0.0)
    for col in ("df0_err_Hz", "dgamma0_err_Hz", "lntheta_err", "d_c_err_m", "rss_df", "rss_dgamma"):
        np.testing.assert_allclose(fit[col], ref[col], rtol=1e-3, err_msg=col)
    # The covariances, against the product of the two errors (a covariance may be ~0).
    for col, a, b in (
        ("cov_df0_lntheta", "df0_err_Hz", "lntheta_err"),
        ("cov_df0_d_c", "df0_err_Hz", "d_c_err_m"),
        ("cov_lntheta_d_c", "lntheta_err", "d_c_err_m"),
    ):
        both = np.isfinite(ref[col])
        assert np.array_equal(both, np.isfinite(fit[col])), col
        gap = np.abs(fit[col] - ref[col])[both]
        assert np.all(gap <= 1e-3 * (ref[a] * ref[b])[both]), col


def test_gradient_at_refused_steps_is_never_read(monkeypatch):
    # The fit forms the gradient and Hessian only where the solver will accept the step: the same
    # numbers, bit for bit, as with them formed at every step (a wrong guess of the solver's
    # test would hand it the zeros of a refused row).
    model = _plateau._plateau_model

    def always(*a, **k):  # the gradient and Hessian at every step, as before
        assert len(a) == 11  # (the last positional argument: the current χ², dropped)
        return model(*a[:-1], None, **k)

    for b, u_c, sig in (_sweeps("plateau"), _sweeps("cattaneo-mindlin", seed=4)):
        args = (b.u, b.df, b.dg, b.w, sig[0], sig[1], u_c, cm_loop_table())
        fit = fit_plateau_loops(*args)
        with monkeypatch.context() as m:
            m.setattr(_plateau, "_plateau_model", always)
            full = fit_plateau_loops(*args)
        pd.testing.assert_frame_equal(fit, full, check_exact=True)


def test_weighted_residual_factors_formed_once_a_pass_are_the_same(monkeypatch):
    # The fit forms √wf·rw and √wg·rw once a pass and hands each evaluation its rows
    # (_plateau_model's ``weighted``): the same fit, bit for bit, as with them formed from the
    # evaluation's own wf, wg and rw, pooled amplitudes (weights 0 or 1) and points one by one
    # (other weights), each channel's factor its own.
    model = _plateau._plateau_model
    given = []

    def own(*a, weighted=None, **k):  # the factors formed by the evaluation itself
        given.append(weighted is not None)
        return model(*a, **k)

    b, u_c, sig = _sweeps("plateau")
    halved = np.where(np.arange(b.w.shape[1]) % 4 == 1, 0.5, 1.0) * b.w
    for w in (b.w, halved):
        args = (b.u, b.df, b.dg, w, sig[0], sig[1], u_c, cm_loop_table())
        fit = fit_plateau_loops(*args)
        with monkeypatch.context() as m:
            m.setattr(_plateau, "_plateau_model", own)
            ref = fit_plateau_loops(*args)
        assert given and all(given)
        pd.testing.assert_frame_equal(fit, ref, check_exact=True)


def _evaluation(pooled, rows=None):
    """A plateau-model evaluation's inputs on synthetic sweeps (their points one by one, or a
    block's pooled amplitudes), at parameters inside the bounds: p, u, u_max, Δf, ΔΓ, w, rw,
    wf, wg and the within-amplitude sums."""
    b, u_c, sig = _sweeps("plateau")
    if pooled:
        u, df, dg, w, _, sf, sg = _blocks(b, u_c, sig)
        u, df, dg, w, rw, *within = pool_repeats(u, df, dg, w)
    else:
        u, df, dg, w, rw, within, sf, sg = b.u, b.df, b.dg, b.w, b.w, None, sig[0], sig[1]
    rows = np.arange(len(u)) if rows is None else rows
    rng = np.random.default_rng(8)
    p = np.column_stack([rng.uniform(-1.0, 1.5, len(u)), rng.uniform(0.05, 0.5, len(u))])
    umax = np.max(np.where(w > 0, u, 0.0), axis=1)
    wf, wg = 1.0 / sf**2, 1.0 / sg**2
    part = None if within is None else [a[rows] for a in within]
    return (p[rows], u[rows], umax[rows], df[rows], dg[rows], w[rows], rw[rows], wf[rows],
            wg[rows], part)  # fmt: skip


def _descent_plainly(ey, dl, x, c, A, B, slopes, sf, sg, df, dg):
    """The gradient and Gauss-Newton Hessian of the projected χ²/2 as written before they shared
    one array: the columns joined, then einsum's sums over (r, i, j)."""
    g1, g2, g1x, g1c, g2x, g2c = slopes
    dx = x / (1.0 - dl)[:, None]
    dc = (ey / (1.0 - dl) ** 2)[:, None]
    phi = np.stack(
        [np.concatenate([sf * g1, sg * g2], 1), np.concatenate([np.zeros_like(sf), sg], 1)], 1
    )
    D = A[:, None, None] * np.stack(
        [
            np.concatenate([sf * (g1x * x + g1c * c), sg * (g2x * x + g2c * c)], 1),
            np.concatenate([sf * (g1x * dx + g1c * dc), sg * (g2x * dx + g2c * dc)], 1),
        ],
        1,
    )
    r = np.concatenate([sf * (df - A[:, None] * g1), sg * (dg - B[:, None] - A[:, None] * g2)], 1)
    gram = np.einsum("rim,rjm->rij", phi, phi)
    pd_ = np.einsum("rim,rjm->rij", phi, D)
    sol = _plateau.solve_finite_stacked(gram, pd_)
    hess = np.einsum("rim,rjm->rij", D, D) - np.einsum("rki,rkj->rij", pd_, sol)
    return -np.einsum("rim,rm->ri", D, r), hess


@pytest.mark.parametrize("pooled", [False, True])
@pytest.mark.parametrize("rows", [None, [3], [0, 5, 7]])
def test_descent_is_the_plain_sums_bit_for_bit(pooled, rows, monkeypatch):
    # _descent's sums share one array and one einsum a column (and its pdᵀ gram⁻¹ pd is summed
    # without einsum): the same numbers, bit for bit, as the plain einsums over (r, i, j), for
    # many rows and for one, points one by one and pooled.
    seen = []

    def plain(*a):
        seen.append(_descent_plainly(*a))
        return seen[-1]

    args = _evaluation(pooled, None if rows is None else np.array(rows))
    fit = _plateau._plateau_model(*args)
    monkeypatch.setattr(_plateau, "_descent", plain)
    ref = _plateau._plateau_model(*args)
    assert seen and np.isfinite(fit["hess"]).all()
    np.testing.assert_array_equal(fit["grad"], ref["grad"])
    np.testing.assert_array_equal(fit["hess"], ref["hess"])


@pytest.mark.parametrize("pooled", [False, True])
def test_gradient_is_that_of_the_projected_chi2(pooled):
    # Kaufman's gradient (the Jacobian at the projected Pκ, Pωξ) against central differences of
    # χ²/2 itself in each parameter: a different route to the same derivative.
    p, *rest = _evaluation(pooled)
    grad = _plateau._plateau_model(p, *rest)["grad"]
    for k, h in ((0, 1e-6), (1, 1e-7)):
        step = np.zeros_like(p)
        step[:, k] = h
        up, down = (_plateau._plateau_model(p + s, *rest)["chi2"] for s in (step, -step))
        fd = (up - down) / (4.0 * h)
        assert np.all(np.abs(grad[:, k] - fd) <= 1e-5 * np.abs(fd) + 1e-9 * np.abs(grad).max())


@pytest.mark.parametrize("M", [13, 4100])
def test_descent_of_a_row_does_not_depend_on_its_batch(M):
    # A row's gradient and Hessian are the same bit for bit evaluated alone or with others, also
    # past 4,096 points a row, where einsum("rim,rjm->rij") summed blocks of its 8,192-element
    # buffer for two rows or more and whole for one (workers 1 and 2 batch rows differently).
    rng = np.random.default_rng(29)
    R = 3
    ey, A, B = (rng.uniform(0.5, 2.0, R) for _ in range(3))
    dl = rng.uniform(0.05, 0.5, R)
    x = rng.uniform(0.0, 3.0, (R, M))
    c = np.repeat(rng.uniform(0.0, 1.0, R), M).reshape(R, M)  # as the fit passes it: (R, M)
    slopes = tuple(rng.normal(size=(R, M)) for _ in range(6))
    sf, sg, df, dg = (rng.normal(size=(R, M)) for _ in range(4))
    batch = _plateau._descent(ey, dl, x, c, A, B, slopes, sf, sg, df, dg)
    for k in range(R):
        one = [a[k : k + 1] for a in (ey, dl, x, c, A, B)]
        alone = _plateau._descent(
            *one, tuple(s[k : k + 1] for s in slopes), *(a[k : k + 1] for a in (sf, sg, df, dg))
        )
        for got, ref in zip(alone, batch, strict=True):
            np.testing.assert_array_equal(got[0], ref[k])


@pytest.mark.parametrize("pooled", [False, True])
@pytest.mark.parametrize("rows", [None, [3], [0, 5, 7]])
def test_model_on_the_data_sums_of_all_rows_is_bit_for_bit(pooled, rows):
    # The fit forms the parts of the projected χ² that depend on the data alone (Σw, the mean of
    # ΔΓ, ΔΓ - mean) once for all the rows of a pass and gathers the running rows'
    # (projection_data): the evaluation on them equals, bit for bit, the one that forms them
    # on the running rows alone.
    p, u, umax, df, dg, w, rw, wf, wg, part = _evaluation(pooled)
    at = np.arange(len(u)) if rows is None else np.array(rows)
    sums = [a[at] for a in projection_data(dg, w)]
    args = [a[at] for a in (p, u, umax, df, dg, w, rw, wf, wg)]
    part = None if part is None else [a[at] for a in part]
    got = _plateau._plateau_model(*args, part, sums=sums)
    ref = _plateau._plateau_model(*args, part)
    assert np.isfinite(ref["chi2"]).all()
    for key in ("A", "B", "chi2", "rss_f", "rss_g", "grad", "hess"):
        np.testing.assert_array_equal(got[key], ref[key], err_msg=key)
