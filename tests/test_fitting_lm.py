"""Tests of contactres.fitting.levenberg_marquardt, the batched solver of the package's fits,
against independent answers: numpy's lstsq on linear problems, the known minimum of
Rosenbrock's function, a box-constrained separable problem solved by hand, and each member of a
batch solved alone."""

from dataclasses import replace

import numpy as np
import pytest

from contactres.fitting import LMOptions, levenberg_marquardt, solve_stacked

# The settings of the two fits of the package, in spirit: the plateau fit (Marquardt, Nielsen)
# and the ratio fit (Levenberg, tenfold, geodesic acceleration, short steps).
MARQUARDT = LMOptions(xtol=1e-12, x_abs=1e-14, ftol=1e-14, max_iter=500)
LEVENBERG = LMOptions(
    damping="levenberg",
    update="tenfold",
    lam0=1e-6,
    lam_min=1e-9,
    max_reject=12,
    xtol=0.0,
    x_abs=1e-12,
    ftol=1e-14,
    judge_failed=False,
    max_iter=2000,
)
GEODESIC = replace(LEVENBERG, geodesic=0.1, max_step=0.5)
ALL = [MARQUARDT, LEVENBERG, GEODESIC]


def jacobian_form(residuals, jacobian):
    """evaluate() of the Jacobian form from functions of one parameter vector."""

    def evaluate(p, rows, want):
        out = {"residuals": np.array([residuals(q, i) for q, i in zip(p, rows, strict=True)])}
        if want:
            out["jacobian"] = np.array([jacobian(q, i) for q, i in zip(p, rows, strict=True)])
        return out

    return evaluate


def linear_problem(P, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(40, P)) * np.logspace(0, 3, P)  # columns of very different scale
    b = rng.normal(size=40)
    return A, b


@pytest.mark.parametrize("options", ALL)
@pytest.mark.parametrize("P", [2, 5])
def test_linear_problem_matches_lstsq(options, P):
    A, b = linear_problem(P, P)
    exact = np.linalg.lstsq(A, b, rcond=None)[0]
    ev = jacobian_form(lambda p, i: A @ p - b, lambda p, i: A)
    res = levenberg_marquardt(ev, np.ones(P), options=options)
    assert res.converged[0], res.message(0)
    np.testing.assert_allclose(res.x[0], exact, rtol=1e-8, atol=1e-12)
    assert res.chi2[0] == pytest.approx(np.sum((A @ exact - b) ** 2), rel=1e-12)


@pytest.mark.parametrize("P", [2, 5])  # Cramer's rule for two parameters, LU beyond
def test_gauss_newton_form_matches_lstsq(P):
    A, b = linear_problem(P, 10 + P)
    exact = np.linalg.lstsq(A, b, rcond=None)[0]

    def evaluate(p, rows, want):
        r = p @ A.T - b
        H = np.broadcast_to(A.T @ A, (len(p), P, P))
        return {"chi2": np.sum(r * r, axis=1), "gradient": r @ A, "hessian": H}

    res = levenberg_marquardt(evaluate, np.outer([0.0, 1.0, -2.0], np.ones(P)), options=MARQUARDT)
    assert res.converged.all()
    np.testing.assert_allclose(res.x, np.tile(exact, (3, 1)), rtol=1e-8, atol=1e-12)


def rosenbrock(a):
    """Residuals (10 (y - x²), a - x): χ² is Rosenbrock's function with its minimum 0 at
    (a, a²), at the end of a long curved valley."""
    return (
        lambda p, i: np.array([10.0 * (p[1] - p[0] ** 2), a[i] - p[0]]),
        lambda p, i: np.array([[-20.0 * p[0], 10.0], [-1.0, 0.0]]),
    )


@pytest.mark.parametrize("options", ALL)
def test_rosenbrock_reaches_its_minimum(options):
    ev = jacobian_form(*rosenbrock(np.array([1.0])))
    res = levenberg_marquardt(ev, [-1.2, 1.0], options=options)
    assert res.converged[0], res.message(0)
    np.testing.assert_allclose(res.x[0], [1.0, 1.0], rtol=0, atol=1e-7)
    assert res.chi2[0] < 1e-14


@pytest.mark.parametrize("options", ALL)
def test_a_batch_is_its_members_solved_alone(options):
    a = np.array([1.0, 0.5, -0.7, 2.0])
    starts = np.array([[-1.2, 1.0], [0.0, 0.0], [2.0, -1.0], [1.9, 3.9]])
    ev = jacobian_form(*rosenbrock(a))
    batch = levenberg_marquardt(ev, starts, options=options)
    for i in range(len(a)):
        # the member alone: its residuals see row index i whatever the batch
        alone = levenberg_marquardt(
            lambda p, rows, want, i=i: ev(p, np.full(len(rows), i), want),
            starts[i],
            options=options,
        )
        assert batch.converged[i] and alone.converged[0]
        np.testing.assert_allclose(batch.x[i], alone.x[0], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(batch.x[i], [a[i], a[i] ** 2], rtol=0, atol=1e-6)
    assert len(set(batch.n_iter)) > 1  # the members stopped at different steps


def test_bounds_hold_a_parameter_on_its_bound():
    # Separable: r = (p - c) * w, so the constrained minimum is c clipped into the box.
    c, w = np.array([3.0, -2.0, 0.5]), np.array([1.0, 30.0, 0.2])
    lo, hi = np.array([0.0, -1.0, -5.0]), np.array([1.0, 5.0, 5.0])
    ev = jacobian_form(lambda p, i: (p - c) * w, lambda p, i: np.diag(w))
    for options in ALL:
        res = levenberg_marquardt(ev, [0.5, 0.0, 0.0], lo, hi, options)
        assert res.converged[0], res.message(0)
        np.testing.assert_allclose(res.x[0], np.clip(c, lo, hi), rtol=0, atol=1e-9)


def test_admissible_region_is_never_left_and_a_bad_start_is_reported():
    # r = p - 10 with the region p < 3 admissible (NaN residuals beyond): the fit must stop
    # inside, at the border, with every accepted point admissible.
    seen = []

    def evaluate(p, rows, want):
        r = np.where(p < 3.0, p - 10.0, np.nan)
        seen.extend(p[:, 0][np.isfinite(r[:, 0])])
        return {"residuals": r, "jacobian": np.ones((len(p), 1, 1)) if want else None}

    for options in ALL:
        res = levenberg_marquardt(evaluate, [0.0], options=options)
        assert 2.99 < res.x[0, 0] < 3.0 and np.isfinite(res.chi2[0])
    assert max(seen) < 3.0
    res = levenberg_marquardt(evaluate, [[0.0], [4.0]], options=MARQUARDT)
    assert np.isinf(res.chi2[1]) and not res.converged[1] and res.x[1, 0] == 4.0
    assert "outside the admissible region" in res.message(1)
    assert res.converged[0]


def test_options_are_checked():
    with pytest.raises(ValueError, match="damping"):
        LMOptions(damping="trust-region")
    with pytest.raises(ValueError, match="update"):
        LMOptions(update="fast")

    def gauss_newton(p, rows, want):
        return {"chi2": np.sum(p * p, 1), "gradient": p, "hessian": np.ones((len(p), 1, 1))}

    with pytest.raises(ValueError, match="geodesic"):
        levenberg_marquardt(gauss_newton, [1.0], options=GEODESIC)


def rosenbrock_gauss_newton(a, calls):
    """evaluate() of Rosenbrock's residuals (:func:`rosenbrock`) in the Gauss-Newton form, row
    by row in closed form (no sum over rows); χ² is infinite (inadmissible) for x > 3. Counts
    the evaluations of each row in ``calls``."""

    def evaluate(p, rows, want):
        np.add.at(calls, rows, 1)
        x, y, ai = p[:, 0], p[:, 1], a[rows]
        r0, r1 = 10.0 * (y - x * x), ai - x
        j00 = -20.0 * x  # J = [[j00, 10], [-1, 0]]
        chi2 = np.where(x > 3.0, np.inf, r0 * r0 + r1 * r1)
        grad = np.stack([j00 * r0 - r1, 10.0 * r0], axis=1)
        hess = np.stack([[j00 * j00 + 1.0, 10.0 * j00], [10.0 * j00, np.full_like(x, 100.0)]])
        return {"chi2": chi2, "gradient": grad, "hessian": hess.transpose(2, 0, 1)}

    return evaluate


@pytest.mark.parametrize("options", [MARQUARDT, replace(LEVENBERG, max_iter=300)])
def test_gauss_newton_batch_is_its_members_alone_bit_for_bit(options):
    # members that stop at different steps (the running rows are gathered as others stop), one
    # held on a bound, one starting at its minimum, one starting inadmissible
    a = np.array([1.0, 0.5, -0.7, 2.0, 1.0, 1.5, 0.3])
    starts = np.array(
        [[-1.2, 1.0], [0.0, 0.0], [2.0, -1.0], [1.9, 3.9], [1.0, 1.0], [3.5, 0.0], [-2.0, 4.0]]
    )
    lo = np.full((7, 2), -np.inf)
    hi = np.full((7, 2), np.inf)
    hi[1, 0] = 0.4  # the minimum (0.5, 0.25) lies beyond: x ends on its bound
    calls = np.zeros(len(a), int)
    batch = levenberg_marquardt(rosenbrock_gauss_newton(a, calls), starts, lo, hi, options)
    assert len(set(batch.n_iter)) > 3  # the members stopped at many different steps
    assert batch.message(5) == "the starting point is outside the admissible region"
    assert batch.x[1, 0] == 0.4
    for i in range(len(a)):
        alone_calls = np.zeros(len(a), int)
        ev = rosenbrock_gauss_newton(a, alone_calls)
        alone = levenberg_marquardt(  # (it sees row index i, as in the batch)
            lambda p, rows, want, ev=ev, i=i: ev(p, np.full(len(rows), i), want),
            starts[i],
            lo[i],
            hi[i],
            options,
        )
        # a stopped member is evaluated no more: as often in the batch as alone
        assert calls[i] == alone_calls[i] == alone_calls.sum()
        for name in ("x", "chi2", "converged", "status", "n_iter", "n_accepted", "last_step"):
            got, want = getattr(batch, name)[i], getattr(alone, name)[0]
            assert np.asarray(got).tobytes() == np.asarray(want).tobytes(), (i, name)
    good = [0, 2, 3, 4]  # unbounded and admissible: at the minimum (a, a²)
    np.testing.assert_allclose(batch.x[good], np.c_[a[good], a[good] ** 2], rtol=0, atol=1e-6)


def straight_line_gauss_newton(target):
    """evaluate() of r = p - target per parameter (Gauss-Newton form): the undamped step goes
    to the target at once, so a capped step is exactly the cap."""

    def evaluate(p, rows, want):
        r = p - target
        hess = np.broadcast_to(np.eye(p.shape[1]), (len(p), p.shape[1], p.shape[1]))
        return {"chi2": np.sum(r * r, 1), "gradient": r, "hessian": hess}

    return evaluate


def test_a_relative_step_cap_reaches_a_far_minimum_in_logarithmically_many_steps():
    # From 0 towards 1000 with max_step 2: the absolute cap moves 2 a step (500 steps to get
    # there), the relative one 2 max(|p|, 1) a step, so p_k = 2·3^(k-1) (by hand: 2, 6, 18, ...)
    # and 1000 is 7 steps away (the sixth reaches 486, the seventh, 514 < 2·486, is not capped)
    far = straight_line_gauss_newton(np.array([1000.0]))
    absolute = LMOptions(max_step=2.0, xtol=1e-12, ftol=1e-14, max_iter=2000)
    relative = replace(absolute, relative_step=(0,))
    slow = levenberg_marquardt(far, [0.0], options=absolute)
    fast = levenberg_marquardt(far, [0.0], options=relative)
    assert slow.converged[0] and fast.converged[0]
    assert slow.x[0, 0] == pytest.approx(1000.0) and fast.x[0, 0] == pytest.approx(1000.0)
    assert slow.n_iter[0] >= 500
    assert fast.n_iter[0] <= 7 + 3  # (+ the steps that converge: the damping's remainder)
    for k in (1, 2, 3, 4, 5):
        part = levenberg_marquardt(far, [0.0], options=replace(relative, max_iter=k))
        assert part.x[0, 0] == pytest.approx(2.0 * 3.0 ** (k - 1), rel=1e-12)
    # downhill the cap reads |p|
    down = levenberg_marquardt(
        straight_line_gauss_newton(np.array([-1000.0])),
        [0.0],
        options=replace(relative, max_iter=3),
    )
    assert down.x[0, 0] == pytest.approx(-18.0, rel=1e-12)
    # a parameter not flagged keeps the absolute cap, and the step is shortened as a whole:
    # with equal undamped moves the second one binds, 2 a step for both (alone: -18 for p₀)
    both = levenberg_marquardt(
        straight_line_gauss_newton(np.array([-1000.0, 1000.0])),
        [0.0, 0.0],
        options=replace(absolute, relative_step=(0,), max_iter=3),
    )
    np.testing.assert_allclose(both.x[0], [-6.0, 6.0], rtol=1e-12)


def test_a_relative_step_cap_of_a_parameter_not_given_is_refused():
    with pytest.raises(ValueError, match="relative_step"):
        levenberg_marquardt(
            straight_line_gauss_newton(np.zeros(2)),
            [1.0, 1.0],
            options=LMOptions(max_step=2.0, relative_step=(2,)),
        )


def test_each_parameter_is_capped_relative_to_its_own_size():
    # p₀ capped relative to its size, p₁ absolutely (max_step 2), one step of each row. With
    # H = 1 the step points at the target, shortened as a whole by the largest of
    # |v₀| / max(|p₀|, 1) and |v₁| (by hand):
    # - from (100, -500) to (10⁵, -490): v = (99900, 10), sizes (999, 10): 2/999 of v
    # - from (100, 0) to (10⁴, 1000): v = (9900, 1000), sizes (99, 1000): 2/1000 of v
    # A cap that read p₁'s size for p₀, flagged p₁ instead, or took the row's largest |p|
    # would divide by 500 or 1 and shorten a step by another factor.
    start = np.array([[100.0, -500.0], [100.0, 0.0]])
    target = np.array([[1e5, -490.0], [1e4, 1000.0]])

    def evaluate(p, rows, want):
        r = p - target[rows]
        hess = np.broadcast_to(np.eye(2), (len(p), 2, 2))
        return {"chi2": np.sum(r * r, 1), "gradient": r, "hessian": hess}

    one = levenberg_marquardt(
        evaluate, start, options=LMOptions(max_step=2.0, relative_step=(0,), max_iter=1)
    )
    want = start + (target - start) * np.array([[2 / 999], [2 / 1000]])
    np.testing.assert_allclose(one.x, want, rtol=1e-12)


@pytest.mark.parametrize("K", [1, 3])
def test_solve_stacked_is_cramers_rule_bit_for_bit(K):
    # 2 x 2 systems by Cramer's rule written out here (numerators of the adjugate's rows over
    # the determinant, a singular matrix's determinant replaced by the smallest normal double),
    # bit for bit, and the solutions of LAPACK's LU to rounding.
    rng = np.random.default_rng(11)
    a, b = rng.normal(size=(50, 2, 2)), rng.normal(size=(50, 2, K))
    a[0] = [[1.0, 2.0], [2.0, 4.0]]  # singular: det 0
    det = a[:, 0, 0] * a[:, 1, 1] - a[:, 0, 1] * a[:, 1, 0]
    det = np.where(det != 0, det, np.finfo(float).tiny)
    ref = np.empty_like(b)
    with np.errstate(over="ignore"):  # (the singular system's numerators over tiny: ±inf)
        for r in range(50):
            for k in range(K):
                ref[r, 0, k] = (a[r, 1, 1] * b[r, 0, k] - a[r, 0, 1] * b[r, 1, k]) / det[r]
                ref[r, 1, k] = (a[r, 0, 0] * b[r, 1, k] - a[r, 1, 0] * b[r, 0, k]) / det[r]
        got = solve_stacked(a, b)
    np.testing.assert_array_equal(got, ref)
    np.testing.assert_allclose(got[1:], np.linalg.solve(a[1:], b[1:]), rtol=1e-9, atol=1e-12)


def test_row_reductions_are_numpys():
    # The solver's per-row max and all, column by column: numpy's reductions along the rows,
    # NaN, zeros and negative numbers included; with no column, the value given for none.
    from contactres._levenberg_marquardt import _rows_reduce

    rng = np.random.default_rng(5)
    for P in (1, 2, 3):
        a = rng.normal(size=(40, P))
        a[::7] = 0.0
        a[3, 0] = np.nan
        np.testing.assert_array_equal(_rows_reduce(np.maximum, a, 0.0), np.max(a, axis=1))
        b = a < 0.8
        np.testing.assert_array_equal(_rows_reduce(np.logical_and, b, True), np.all(b, axis=1))
    none = np.zeros((4, 0))
    np.testing.assert_array_equal(_rows_reduce(np.maximum, none, 0.0), np.zeros(4))
    np.testing.assert_array_equal(_rows_reduce(np.logical_and, none < 1, True), np.ones(4, bool))


def test_solve_stacked_broadcasts_an_empty_stack_against_one_row():
    # (as np.linalg.solve's stacks broadcast: review R30a, the row count was the larger one's)
    a = np.eye(2)[None].repeat(0, axis=0)
    assert solve_stacked(a, np.ones((1, 2, 1))).shape == (0, 2, 1)
    one = solve_stacked(np.array([[[2.0, 0.0], [0.0, 4.0]]]), np.ones((3, 2, 1)))
    np.testing.assert_array_equal(one[:, :, 0], [[0.5, 0.25]] * 3)
