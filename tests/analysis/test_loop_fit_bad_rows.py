"""A bad sweep (a NaN, an inf, no weight, one point) among the rows of the batched loop fits
(Cattaneo-Mindlin and Savkoor: fit_cm_loops; the plateau loop: fit_plateau_loops): NaN for
it, and the other rows' results bit for bit those of the batch without it (the SVD of a
pseudo-inverse raised numpy.linalg.LinAlgError for the whole batch)."""

import numpy as np
import pytest
from test_plateau_fit import _sweeps

from contactres.analysis._loops import (
    _inverse_3x3,
    cm_loop_table,
    fit_cm_loops,
    pinv_finite,
    savkoor_loop_table,
)
from contactres.analysis._plateau import fit_plateau_loops, pool_repeats

# What is wrong with each bad row (its index in the batch of 24 sweeps).
BAD = {
    2: "a NaN shift",
    5: "an inf shift",
    8: "a NaN amplitude",
    11: "no weight",
    14: "a single point",
    17: "a NaN noise level",
    20: "an inf weight",
    23: "a NaN hinge",
}


def _batch():
    """Synthetic sweeps (24 rows, plateau and Cattaneo-Mindlin), their bad copies (BAD) and the
    inputs of both (u, Δf, ΔΓ, w, σ_Δf, σ_ΔΓ, u_c)."""
    b, u_c, sig = _sweeps("plateau")
    good = [np.array(a, dtype=float) for a in (b.u, b.df, b.dg, b.w, sig[0], sig[1], u_c)]
    bad = [a.copy() for a in good]
    u, df, dg, w, sf, _, uc = bad
    df[2, 3], dg[5, 6], u[8, 0] = np.nan, np.inf, np.nan
    w[11], w[14, 1:], sf[17], w[20, 4], uc[23] = 0.0, 0.0, np.nan, np.inf, np.nan
    return good, bad


def _fitters():
    cm, savkoor = cm_loop_table(), savkoor_loop_table()
    return {
        "cattaneo-mindlin": lambda *a: fit_cm_loops(*a[:6], cm),
        "savkoor": lambda *a: fit_cm_loops(*a[:6], savkoor),
        "plateau": lambda *a: fit_plateau_loops(*a, cm),
    }


@pytest.mark.parametrize("name", ["cattaneo-mindlin", "savkoor", "plateau"])
def test_bad_rows_get_nan_and_the_others_their_own_fits(name):
    fitter = _fitters()[name]
    good, bad = _batch()
    if name != "plateau":  # (no hinge in these fits: row 23's is ignored, so it is good)
        bad[6][23] = good[6][23]
    wrong = [r for r in BAD if name == "plateau" or r != 23]
    kept = np.setdiff1d(np.arange(24), wrong)
    got = fitter(*bad)
    alone = fitter(*(a[kept] for a in bad))
    assert list(got.columns) == list(alone.columns) and len(got) == 24
    for col in got.columns:
        mine, own = got[col].to_numpy()[kept], alone[col].to_numpy()
        if own.dtype.kind == "f":
            assert mine.tobytes() == own.tobytes(), col
        else:
            assert np.array_equal(mine, own), col
        if got[col].dtype.kind == "f":
            assert np.isnan(got[col].to_numpy()[wrong]).all(), col
        else:
            assert (got[col].to_numpy()[wrong] == "").all(), col
    # the good rows fitted (not NaN: the comparison above would pass on NaN for NaN)
    assert np.isfinite(alone["df0_Hz"]).all() and np.isfinite(alone["lntheta_err"]).all()
    # and the fit of the rows untouched is the fit of the clean batch's same rows, bit for
    # bit: no amplitude repeats within a row here (nothing pooled), so each row's fit is its own
    # arithmetic, whatever rows are beside it
    assert pool_repeats(*good[:4]) is None
    clean = fitter(*good)
    for col in got.columns:
        assert got[col].to_numpy()[kept].tobytes() == clean[col].to_numpy()[kept].tobytes(), col


def test_a_bad_row_that_is_the_widest_once_pooled_leaves_the_narrower_batch():
    # Rows 0-5: three sweeps of one 13-amplitude grid side by side (each amplitude three
    # times: pooled to 13 points); row 6: one sweep of 20 distinct amplitudes, the widest
    # pooled row, spoiled by a NaN. The good rows are then fitted as the batch without row 6,
    # pooled to width 13, bit for bit; the clean batch pools them to width 20 (padding at
    # weight 0), whose sums round otherwise: the same fit to rounding.
    b, u_c, sig = _sweeps("plateau")
    grid = [
        np.stack([a[i:18:3] for i in range(3)], axis=-1).reshape(6, -1)
        for a in (b.u, b.df, b.dg, b.w)
    ]
    wide_u = np.linspace(0.5e-9, 8e-9, 20)
    pad = grid[0].shape[1] - wide_u.size
    wide = [
        np.r_[wide_u, np.full(pad, wide_u[-1])],
        *(np.r_[np.interp(wide_u, b.u[0], a[0]), np.zeros(pad)] for a in (b.df, b.dg)),
        np.r_[np.ones(wide_u.size), np.zeros(pad)],
    ]
    u, df, dg, w = (np.vstack([g, x]) for g, x in zip(grid, wide, strict=True))
    per_row = [np.r_[a[:18:3], a[0]] for a in (sig[0], sig[1], u_c)]
    assert pool_repeats(u, df, dg, w)[0].shape[1] == 20
    assert pool_repeats(u[:6], df[:6], dg[:6], w[:6])[0].shape[1] == 13
    table = cm_loop_table()
    clean = fit_plateau_loops(u, df, dg, w, *per_row, table)
    spoiled = df.copy()
    spoiled[6, 3] = np.nan
    got = fit_plateau_loops(u, spoiled, dg, w, *per_row, table)
    alone = fit_plateau_loops(u[:6], df[:6], dg[:6], w[:6], *(a[:6] for a in per_row), table)
    assert got.iloc[6].drop("edge").isna().all() and np.isfinite(alone["df0_Hz"]).all()
    for col in got.columns:
        mine = got[col].to_numpy()[:6]
        assert mine.tobytes() == alone[col].to_numpy().tobytes(), col
        if mine.dtype.kind == "f":
            np.testing.assert_allclose(mine, clean[col].to_numpy()[:6], rtol=1e-12, atol=0)
    # (and the widths do round otherwise: numpy's pairwise sums over 13 and 20 points)
    assert (
        got["theta_per_m"][:6].to_numpy().tobytes() != clean["theta_per_m"][:6].to_numpy().tobytes()
    )


def test_a_theta_start_that_is_not_finite_spoils_its_row_alone():
    good, _ = _batch()
    theta = np.full(24, 3e6)
    theta[4] = np.nan
    table = cm_loop_table()
    got = fit_plateau_loops(*good, table, theta_start=theta)
    kept = np.r_[0:4, 5:24]
    alone = fit_plateau_loops(*(a[kept] for a in good), table, theta_start=theta[kept])
    assert got["df0_Hz"].to_numpy()[kept].tobytes() == alone["df0_Hz"].to_numpy().tobytes()
    assert got.iloc[4].drop("edge").isna().all() and got["edge"][4] == ""


def test_a_batch_of_bad_rows_only_is_all_nan():
    _, bad = _batch()
    for name, fitter in _fitters().items():
        rows = [r for r in BAD if name == "plateau" or r != 23]  # (a hinge: the plateau's)
        got = fitter(*(a[rows] for a in bad))
        numeric = got.drop(columns="edge").to_numpy(float)
        assert len(got) == len(rows) and np.isnan(numeric).all(), name


def test_inverses_of_matrices_that_are_not_finite_are_nan():
    # _inverse_3x3 (the loop fits' errors) and pinv_finite (the plateau fit's): a NaN or inf
    # matrix gives NaN, the others are what they are in a stack without it (and the inverse
    # to rounding, checked against the identity); a zero matrix keeps pinv's zeros.
    rng = np.random.default_rng(2)
    for inverse, size in ((_inverse_3x3, 3), (pinv_finite, 4)):
        j = rng.normal(size=(7, 12, size))
        m = j.transpose(0, 2, 1) @ j
        m[1, 0, 2] = m[1, 2, 0] = np.nan
        m[3, 1, 1] = np.inf
        m[5] = 0.0
        got = inverse(m)
        kept = [0, 2, 4, 5, 6]
        assert got[kept].tobytes() == inverse(m[kept]).tobytes()
        assert np.isnan(got[[1, 3]]).all() and (got[5] == 0.0).all()
        eye = np.broadcast_to(np.eye(size), (4, size, size))
        np.testing.assert_allclose(got[[0, 2, 4, 6]] @ m[[0, 2, 4, 6]], eye, atol=1e-9)


@pytest.mark.parametrize("name", ["cattaneo-mindlin", "savkoor", "plateau"])
def test_copies_of_one_amplitude_count_once(name):
    # The loops are functions of the amplitude: three points at one amplitude give two
    # residuals' worth (Δf and ΔΓ there), fewer than the loops' 3 or 4 parameters, so the row
    # has no fit; three points at three amplitudes are enough for both (6 residuals).
    fitter = _fitters()[name]
    good, _ = _batch()
    u, df, dg, w = (a.copy() for a in good[:4])
    w[[3, 6], 3:] = 0.0
    u[3, 1:3] = u[3, 0]
    got = fitter(u, df, dg, w, *good[4:])
    assert got.iloc[3].drop("edge").isna().all() and got["edge"][3] == ""
    assert np.isfinite(got["df0_Hz"][6])  # (fitted; the plateau's errors may be NaN at 3)
    kept = np.r_[0:3, 4:24]
    alone = fitter(*(a[kept] for a in (u, df, dg, w, *good[4:])))
    for col in got.columns:
        assert got[col].to_numpy()[kept].tobytes() == alone[col].to_numpy().tobytes(), col
