"""A bad row (a NaN, an inf, no weight, one point) in a batch of contactres.fitting's solver
(levenberg_marquardt, both forms) or of solve_stacked: no exception for the batch, NaN or a
status that says why for the row, and the other rows' results bit for bit those of the batch
without it."""

import numpy as np
import pytest

from contactres.fitting import Model, Parameter, fit, levenberg_marquardt, solve_stacked
from test_fitting_lm import ALL, LEVENBERG, MARQUARDT

FIELDS = ("x", "chi2", "converged", "status", "n_iter", "n_accepted", "last_step")
OUTSIDE = "the starting point is outside the admissible region"
NOT_FINITE = "the derivatives are not finite at the last accepted point"

# Rows 0, 3, 6, 7 are good; 1 has a NaN, 2 an inf, 4 no weight, 5 a single point.
GOOD, BAD = [0, 3, 6, 7], [1, 2, 4, 5]


def weighted_polynomials(P):
    """Weighted straight lines (P = 2) or parabolas (P = 3), one per row, with the bad rows."""
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 1.0, 15)
    basis = np.stack([t**k for k in range(P)], axis=1)
    y = basis @ rng.normal(size=(P, 8)) + 0.05 * rng.normal(size=(15, 8))
    y, w = y.T.copy(), np.ones((8, 15))
    y[1, 4], y[2, 9], w[4], w[5, 1:] = np.nan, np.inf, 0.0, 0.0
    return basis, y, w


def line(p, basis):
    """The polynomials of the rows p at the points of basis, row by row: a BLAS product over
    the batch (p @ basis.T) may round a row differently with the batch around it."""
    return np.einsum("rp,gp->rg", p, basis)


def jacobian_form(basis, y, w):
    def evaluate(p, rows, want):
        out = {"residuals": w[rows] * (line(p, basis) - y[rows])}
        if want:
            out["jacobian"] = w[rows][:, :, None] * basis
        return out

    return evaluate


def gauss_newton_form(basis, y, w):
    def evaluate(p, rows, want):
        J = w[rows][:, :, None] * basis
        r = w[rows] * (line(p, basis) - y[rows])
        grad = np.einsum("rgp,rg->rp", J, r)
        return {"chi2": np.sum(r * r, 1), "gradient": grad, "hessian": J.transpose(0, 2, 1) @ J}

    return evaluate


def only(evaluate, kept):
    """evaluate() of the rows ``kept`` of a batch, as a batch of their own."""
    return lambda p, rows, want: evaluate(p, np.asarray(kept)[rows], want)


def assert_rows_alone(batch, alone, rows):
    for name in FIELDS:
        got, want = getattr(batch, name)[rows], getattr(alone, name)
        assert got.tobytes() == want.tobytes(), name


# (the geodesic acceleration needs the Jacobian form: the solver refuses it with the other)
FORMS_AND_OPTIONS = [
    (form, options)
    for form in (jacobian_form, gauss_newton_form)
    for options in ALL
    if form is jacobian_form or options.geodesic is None
]


@pytest.mark.parametrize("P", [2, 3])
@pytest.mark.parametrize(("form", "options"), FORMS_AND_OPTIONS)
def test_bad_rows_stop_alone_and_leave_the_others_bit_for_bit(P, form, options):
    basis, y, w = weighted_polynomials(P)
    ev = form(basis, y, w)
    start = np.zeros((8, P))
    batch = levenberg_marquardt(ev, start, options=options)
    alone = levenberg_marquardt(only(ev, GOOD), start[GOOD], options=options)
    assert_rows_alone(batch, alone, GOOD)
    # The good rows reach the linear least-squares fit (LAPACK's, row by row; coefficients ~1,
    # hence the absolute tolerance): not all of them
    # stop by a convergence test at these tolerances (ftol 1e-14, xtol 0), so none is asked to.
    for i in GOOD:
        want = np.linalg.lstsq(w[i][:, None] * basis, w[i] * y[i], rcond=None)[0]
        np.testing.assert_allclose(batch.x[i], want, rtol=1e-10, atol=1e-10)
    # A NaN or inf in the data: χ² not finite at the start, which the solver keeps.
    for i in (1, 2):
        assert batch.message(i) == OUTSIDE and not np.isfinite(batch.chi2[i])
        assert np.array_equal(batch.x[i], start[i]) and batch.n_iter[i] == 0
    # No weight: χ² is 0 wherever p is, so the start is a minimum (no step taken); one point:
    # a line of minima, one of them reached. Neither is NaN: the solver cannot tell.
    assert batch.chi2[4] == 0.0 and np.array_equal(batch.x[4], start[4])
    assert batch.chi2[5] < 1e-20 and batch.converged[5]


def test_a_zero_hessian_with_levenberg_damping_is_not_singular():
    # Levenberg's damping λ s₀² I is 0 for a problem without data (s₀ = 0): floored, as
    # Marquardt's diag(JᵀJ) is, so that the damped system of a parabola's fit (LU, P = 3) is
    # not singular. With the floor the first step is exactly 0 (the gradient is 0) and the row
    # converges at once; without it the singular system gives no step, the damping is raised
    # until it is exhausted (12 iterations) and the row is not converged, though at its start.
    ev = gauss_newton_form(*weighted_polynomials(3))
    res = levenberg_marquardt(ev, np.zeros((8, 3)), options=LEVENBERG)
    assert np.array_equal(res.x[4], np.zeros(3)) and res.chi2[4] == 0.0
    assert res.converged[4] and res.n_iter[4] == 1


def derivatives_fail_beyond(limit, form):
    """Straight lines toward (3, 3) whose derivatives (only) are NaN where p₀ > limit[row]."""
    basis, y, w = weighted_polynomials(2)
    y = np.tile(basis @ [3.0, 3.0], (8, 1))
    inner = form(basis, y, np.ones_like(w))
    keys = ("jacobian",) if form is jacobian_form else ("gradient", "hessian")

    def evaluate(p, rows, want):
        out = inner(p, rows, want)
        failed = p[:, 0] > limit[rows]
        for k in keys:
            if k in out:
                out[k] = np.where(failed.reshape(-1, *(1,) * (out[k].ndim - 1)), np.nan, out[k])
        return out

    return evaluate


@pytest.mark.parametrize("form", [jacobian_form, gauss_newton_form])
@pytest.mark.parametrize("options", [MARQUARDT, LEVENBERG])
def test_derivatives_that_are_not_finite_stop_their_row_where_it_is(form, options):
    # Row 1: at the start (χ² finite there); row 2: past p₀ = 1, reached by its first step (the
    # undamped step reaches (3, 3)). Each stops at its last accepted point (where χ² is that of
    # the line there, by hand) with the status that says so; the SVD of the Jacobian form
    # raised for the batch.
    limit = np.array([np.inf, -1.0, 1.0, np.inf, np.inf, np.inf, np.inf, np.inf])
    ev = derivatives_fail_beyond(limit, form)
    start = np.zeros((8, 2))
    res = levenberg_marquardt(ev, start, options=options)
    assert res.message(1) == NOT_FINITE and np.array_equal(res.x[1], [0.0, 0.0])
    assert res.n_iter[1] == 0 and not res.converged[1]
    assert res.message(2) == NOT_FINITE and res.x[2, 0] > 1.0 and res.n_accepted[2] >= 1
    t = np.linspace(0.0, 1.0, 15)
    line = res.x[2, 0] + res.x[2, 1] * t - 3.0 * (1.0 + t)
    assert res.chi2[2] == pytest.approx(line @ line, rel=1e-12)
    good = [0, 3, 4, 5, 6, 7]
    alone = levenberg_marquardt(only(ev, good), start[good], options=options)
    assert_rows_alone(res, alone, good)
    np.testing.assert_allclose(res.x[good], 3.0, rtol=1e-6)


def test_fit_reports_derivatives_that_are_not_finite():
    # y = a x, the model NaN for a > 2, the data's slope 2 on that edge: the step to a ≈ 2 is
    # accepted and its forward-difference Jacobian (at a + h > 2) is NaN, which raised in the
    # solver's SVD. Now the fit stops there, says why, and gives no error bar.
    model = Model(
        key="edge",
        display="edge",
        parameters=(Parameter("a", "a", "1", "a", (-10.0, 10.0)),),
        x="x",
        x_unit="1",
        observable="y",
        unit="1",
        source="test",
        function=lambda x, a: np.where(a > 2.0, np.nan, a * x),
    )
    x = np.linspace(1.0, 2.0, 5)
    res = fit(model, x, 2.0 * x, {"a": 1.0})
    assert not res.success and res.message == NOT_FINITE
    assert res.values["a"] == pytest.approx(2.0, rel=1e-9) and np.isnan(res.errors["a"])


@pytest.mark.parametrize("P", [2, 3])
def test_solve_stacked_bad_rows_are_nan_and_alone(P):
    # NaN in a, inf in a, inf in b, a zero system: the good rows bit for bit those of the stack
    # without them (and LAPACK's to rounding), the bad ones NaN throughout, without warnings;
    # a zero system gives 0 for P = 2 (its determinant replaced by the smallest double), NaN
    # for P = 3 (LAPACK's exact zero pivot).
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(9, P, P)), rng.normal(size=(9, P, 2))
    a[1, 0, 1], a[2, 1, 1], b[4, 0, 1], a[6], b[6] = np.nan, np.inf, -np.inf, 0.0, 0.0
    bad, zero = [1, 2, 4], 6
    good = [0, 3, 5, 7, 8]
    got = solve_stacked(a, b)
    assert got[good].tobytes() == solve_stacked(a[good], b[good]).tobytes()
    np.testing.assert_allclose(got[good], np.linalg.solve(a[good], b[good]), rtol=1e-9)
    assert np.isnan(got[bad]).all()
    assert (got[zero] == 0.0).all() if P == 2 else np.isnan(got[zero]).all()
    one = solve_stacked(a[[zero]], b[[zero]])  # a singular stack of one: no exception either
    assert one.shape == (1, P, 2)


@pytest.mark.parametrize("P", [2, 3])
def test_solve_stacked_of_a_large_finite_stack_is_the_plain_solution(P):
    # The whole-stack test sums squares: 500 systems of entries ~1e153 overflow that sum,
    # though each entry, and Cramer's products (~1e306), are finite. Such rows are solved as
    # ever, none made NaN: the solutions of the scaled-down systems (the same up to rounding:
    # x = a⁻¹b is invariant to scaling a and b alike).
    rng = np.random.default_rng(4)
    a = rng.normal(size=(500, P, P)) + 3.0 * np.eye(P)
    b = rng.normal(size=(500, P, 1))
    got = solve_stacked(1e153 * a, 1e153 * b)
    assert np.isfinite(got).all()
    np.testing.assert_allclose(got, np.linalg.solve(a, b), rtol=1e-10, atol=1e-14)
