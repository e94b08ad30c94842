"""The batched Levenberg-Marquardt solver of the package's own fits (:mod:`contactres.fitting`
holds its public names: :func:`levenberg_marquardt`, :class:`LMOptions`,
:class:`LeastSquaresResult`, :func:`solve_stacked`; :func:`solve_finite_stacked`, the same
solve without the test for NaN and inf, is the package's own, for hot paths whose systems are
finite: the plateau fit of :mod:`contactres.analysis`).

What the solver does and which fits it serves: :mod:`contactres.fitting`'s module docstring
(the public face of these names); :func:`all_finite`, the one-test guard of the package's
batched fits, is here too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._summary import Summarised
from ._summary import values as value_range
from .errors import ContactresInputError

__all__ = [
    "LMOptions",
    "LeastSquaresResult",
    "all_finite",
    "levenberg_marquardt",
    "solve_finite_stacked",
    "solve_stacked",
]

#: Relative singular value below which a direction of the (scaled) Jacobian is never moved: the
#: data say nothing about it (the rounding of J is ~1e-16 of its largest singular value).
_SINGULAR_CUTOFF = 1e-13

# Codes of :attr:`LeastSquaresResult.status`.
_RUNNING, _STEP, _CHI2, _EXHAUSTED, _MAX_ITER, _MAX_ACCEPTED, _OUTSIDE, _NOT_FINITE = range(8)


@dataclass(frozen=True)
class LMOptions:
    """Settings of :func:`levenberg_marquardt` (each a classic variant of the method).

    Attributes
    ----------
    damping : "marquardt": the damping term is λ diag(JᵀJ) (D. W. Marquardt, J. SIAM 11, 431
        (1963): invariant to the units of the parameters); "levenberg": λ s₀² I, s₀² the
        largest eigenvalue of JᵀJ, floored at 1e-300 (a zero JᵀJ still gets a solvable damped
        system) (K. Levenberg, Q. Appl. Math. 2, 164 (1944); for parameters of one kind, e.g.
        all logarithms)
    update : "nielsen": after a success λ is multiplied by max(1/3, 1 - (2ρ - 1)³) (ρ: actual
        over predicted decrease of χ²), after a failure by ν, which doubles with each failure
        in a row (H. B. Nielsen, report IMM-REP-1999-05, Technical University of Denmark);
        "tenfold": divided by 10 after a success, multiplied by 10 after a failure (Marquardt)
    lam0, lam_min : starting damping and its floor (dimensionless)
    lam_max : a problem whose damping exceeds it stops ("damping exhausted")
    max_reject : a problem with this many failed steps in a row stops ("damping exhausted";
        None: no limit)
    geodesic : step h of the geodesic acceleration (None: off): the second directional
        derivative of the residuals along the step v, from one more evaluation at p + h v,
        bends the step along a curved valley to v + a/2; a step with 2|a| > 0.75|v| counts as
        failed (M. K. Transtrum and J. P. Sethna, arXiv:1201.5885 (2012)). Needs the residuals
        and the Jacobian (not the Gauss-Newton form) of the problem.
    max_step : largest change of any parameter in one step (the whole step is shortened)
    relative_step : indices of the parameters whose change ``max_step`` bounds relative to
        their size, by ``max_step max(|p|, 1)`` (absolute within 1 of 0, where a cap relative
        to ``|p|`` would stall), instead of absolutely. For a parameter that is
        not a logarithm and may lie many of its units from the start: reaching p takes
        ~p/max_step steps with the absolute cap, ~ln(p)/ln(1 + max_step) with the relative one
    xtol, x_abs : a problem has converged when a step changes every parameter by at most
        ``xtol |p| + x_abs``, ...
    ftol, chi2_floor : ... or when an accepted step lowers χ² by at most
        ``ftol max(χ², chi2_floor)``, or when both the actual and the predicted decrease of a
        step are below that (MINPACK's ftol test: at the minimum no step gains more than the
        rounding; χ² after the step)
    judge_failed : whether the step and MINPACK tests apply to a failed step too (a step too
        small to matter ends the iteration although it did not lower χ²); if False only an
        accepted step can end it as converged (a failed one raises the damping and goes on)
    max_iter : largest number of steps tried per problem
    max_accepted : largest number of accepted steps per problem (None: no limit)
    """

    damping: str = "marquardt"
    update: str = "nielsen"
    lam0: float = 1e-3
    lam_min: float = 1e-15
    lam_max: float = 1e14
    max_reject: int | None = None
    geodesic: float | None = None
    max_step: float = np.inf
    relative_step: tuple[int, ...] = ()
    xtol: float = 1e-7
    x_abs: float = 1e-17
    ftol: float = 1e-7
    chi2_floor: float = 0.0
    judge_failed: bool = True
    max_iter: int = 60
    max_accepted: int | None = None

    def __post_init__(self):
        if self.damping not in ("marquardt", "levenberg"):
            raise ContactresInputError(
                f"damping must be 'marquardt' or 'levenberg', got {self.damping!r}"
            )
        if self.update not in ("nielsen", "tenfold"):
            raise ContactresInputError(
                f"update must be 'nielsen' or 'tenfold', got {self.update!r}"
            )


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of every problem.
@dataclass(frozen=True, repr=False)
class LeastSquaresResult(Summarised):
    """Outcome of :func:`levenberg_marquardt` for a batch of R problems of P parameters.

    Attributes
    ----------
    x : (R, P) the last accepted parameters (the start where no step was accepted)
    chi2 : (R,) χ² there
    converged : (R,) whether a tolerance was met
    status : (R,) why each problem stopped (in words: :meth:`message`)
    n_iter, n_accepted : (R,) steps tried and steps accepted
    last_step : (R,) the largest change of a parameter in the last accepted step (0: none)
    """

    x: np.ndarray
    chi2: np.ndarray
    converged: np.ndarray
    status: np.ndarray
    n_iter: np.ndarray
    n_accepted: np.ndarray
    last_step: np.ndarray

    def _facts(self) -> list[tuple[str, str]]:
        """Problems and parameters, how many converged, χ² and the steps tried."""
        R, P = np.shape(self.x)
        return [
            ("problems", f"{R} of {P} parameters"),
            ("converged", f"{int(np.count_nonzero(self.converged))} of {R}"),
            ("χ²", value_range(self.chi2)),
            ("steps", value_range(self.n_iter)),
        ]

    def message(self, i: int = 0) -> str:
        """Why problem ``i`` stopped, in words."""
        return {
            _RUNNING: "not started",
            _STEP: f"converged (last step {self.last_step[i]:.2g})",
            _CHI2: f"converged (last step {self.last_step[i]:.2g})",
            _EXHAUSTED: "no step lowers chi2 (damping exhausted)",
            _MAX_ITER: f"no convergence in {int(self.n_iter[i])} steps",
            _MAX_ACCEPTED: f"no convergence in {int(self.n_accepted[i])} iterations",
            _OUTSIDE: "the starting point is outside the admissible region",
            _NOT_FINITE: "the derivatives are not finite at the last accepted point",
        }[int(self.status[i])]


def levenberg_marquardt(evaluate, p0, lo=-np.inf, hi=np.inf, options: LMOptions = LMOptions()):
    """Minimise χ² = ‖r(p)‖² of R independent problems at once by Levenberg-Marquardt.

    The problems share the number of parameters P (and, in the Jacobian form, of residuals G:
    pad with zero residuals); each keeps its own damping and stops on its own while the others
    go on. A single problem is a batch of one.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(p, rows, jacobian)``, with ``p`` (n, P) the parameters of the problems
        ``rows`` (n,) (indices into the batch), returns a mapping of arrays, either

        * the Jacobian form: ``"residuals"`` r (n, G), dimensionless (weighted), and, when
          ``jacobian`` is true, ``"jacobian"`` dr/dp (n, G, P); or
        * the Gauss-Newton form: ``"chi2"`` (n,), ``"gradient"`` Jᵀr (n, P) and ``"hessian"``
          JᵀJ (n, P, P), for a problem that has them in a better form than J (variable
          projection), always (whatever ``jacobian`` says).

        It must neither change ``p`` nor keep it (the solver goes on with that array).

        A non-finite χ² (or a row of residuals that is not finite) marks p outside the
        admissible region (e.g. a stiffness that is not positive definite): such a step fails
        like one that raises χ², so the damping grows until the step stays inside. No penalty
        term is added, so the minimum is that of the data alone. A problem whose χ² is not
        finite at the start stops there ("outside the admissible region"), and one whose
        derivatives (Jacobian, or gradient and Hessian) are not finite where its χ² is
        (a NaN or an inf in its data or its model) stops at that point ("derivatives not
        finite"): its step would be NaN, and the other problems go on as if it were not in
        the batch.
    p0 : (R, P) or (P,) starting parameters (any units; see ``options.damping``)
    lo, hi : bounds broadcasting against p0 (may be infinite); every trial is clipped into
        them, and a parameter on a bound that the gradient pushes outwards is held there for
        the step (projection)
    options : :class:`LMOptions`

    Returns
    -------
    LeastSquaresResult (its ``x`` is (R, P), also for a 1-d ``p0``)

    Notes
    -----
    The damped normal equations (JᵀJ + λD) δ = -Jᵀr are solved, in the Jacobian form, through
    the SVD of J with its columns scaled by √diag D (filter factors s/(s² + λ)): a direction
    whose singular value is below 1e-13 (``_SINGULAR_CUTOFF``) of the largest is never moved, so an
    ill-conditioned problem (a parameter the data do not determine) takes no wild step along
    it. In the Gauss-Newton form they are solved directly (Cramer's rule for P = 2).
    """
    o = options
    x = np.array(p0, dtype=float, ndmin=2)
    lo = np.broadcast_to(np.asarray(lo, dtype=float), x.shape)
    hi = np.broadcast_to(np.asarray(hi, dtype=float), x.shape)
    n_rows = x.shape[0]
    relative = None
    if o.relative_step:
        relative = np.zeros(x.shape[1], bool)
        try:
            relative[list(o.relative_step)] = True
        except IndexError:
            raise ContactresInputError(
                f"relative_step {o.relative_step} names a parameter beyond the {x.shape[1]} given"
            ) from None
    cur = _local_model(evaluate(x, np.arange(n_rows), True))
    if o.geodesic is not None and "hessian" in cur:
        raise ContactresInputError("the geodesic acceleration needs the Jacobian form")
    # The results of every problem, written when it stops ...
    chi2, status = cur["chi2"], np.where(np.isfinite(cur["chi2"]), _RUNNING, _OUTSIDE)
    broken = _broken_rows(cur, status == _RUNNING)
    if broken is not None:
        status[broken] = _NOT_FINITE
    n_iter, n_acc, last = np.zeros(n_rows, int), np.zeros(n_rows, int), np.zeros(n_rows)
    # ... and the state of the running ones, compacted when some stop (a gather then, not one
    # of every array at every step); each row's arithmetic is the same whatever rows run with it.
    rows = np.flatnonzero(status == _RUNNING)
    model = {k: v[rows] for k, v in cur.items()}
    state = {
        "p": x[rows],
        "lo": lo[rows],
        "hi": hi[rows],
        "lam": np.full(rows.size, float(o.lam0)),
        "nu": np.full(rows.size, 2.0),
        "n_iter": n_iter[rows],
        "n_acc": n_acc[rows],
        "n_rej": np.zeros(rows.size, int),
        "last": last[rows],
    }
    while rows.size:
        q, lo_i, hi_i, lam = state["p"], state["lo"], state["hi"], state["lam"]
        c2, g = model["chi2"], model["gradient"]
        held = ((q <= lo_i) & (g > 0)) | ((q >= hi_i) & (g < 0))
        v, solve = _damped_steps(model, held, lam, o.damping)
        if np.isfinite(o.max_step):
            size = np.abs(v)
            if relative is not None:  # in units of max(|p|, 1) where asked
                size = size / np.where(relative, np.maximum(np.abs(q), 1.0), 1.0)
            big = np.maximum(np.max(size, axis=1), 1e-300)
            v *= np.minimum(1.0, o.max_step / big)[:, None]
        ok = None  # (None: every trial stands, the usual case)
        if o.geodesic is None:
            trial = np.clip(q + v, lo_i, hi_i)
        else:
            trial, ok = _accelerated(evaluate, rows, q, v, model, solve, (lo_i, hi_i), o)
        step = trial - q
        moved = q + step
        new = None
        if ok is None or ok.all():
            new = _local_model(evaluate(moved, rows, False))
            chi2_t = new["chi2"]
        else:
            chi2_t = np.full(rows.size, np.inf)
            if ok.any():
                new = _local_model(evaluate(moved[ok], rows[ok], False))
                chi2_t[ok] = new["chi2"]
        gain = c2 - chi2_t
        pred = -2.0 * np.einsum("ri,ri->r", g, step) - _quadratic(model, step)
        # A step that does not raise χ² is accepted (a tie then ends the iteration: its decrease
        # is below any ftol); NaN (a failed evaluation) and -inf (inadmissible) are failures.
        better = gain >= 0
        # (of the step from the old point, before the accepted rows move)
        size = np.abs(step)
        small_step = _rows_reduce(np.logical_and, size <= o.xtol * np.abs(q) + o.x_abs, True)
        every = better.all()
        if every:
            state["p"] = moved
            model["chi2"] = chi2_t
        else:  # (copyto where: the values of q[better] = moved[better], in one pass)
            np.copyto(q, moved, where=better[:, None])
            np.copyto(c2, chi2_t, where=better)
        # (0.0: the value of a problem without parameters, not a start of the maximum; the same
        # as the old max(initial=0) only because the sizes are |step| >= 0)
        state["last"] = np.where(better, _rows_reduce(np.maximum, size, 0.0), state["last"])
        broken = None
        if new is not None and "jacobian" not in model:  # the Gauss-Newton form comes complete
            # (ok is None here: the geodesic acceleration needs the Jacobian form)
            for key in ("gradient", "hessian"):
                if every:
                    model[key] = new[key]
                else:
                    mask = better.reshape(-1, *(1,) * (new[key].ndim - 1))
                    np.copyto(model[key], new[key], where=mask)
            broken = _broken_rows(model, better)
        # Damping: down after a success, up after a failure.
        nu = state["nu"]
        if o.update == "nielsen":
            rising = pred > 0
            rho = np.where(rising, gain / np.where(rising, pred, 1.0), 0.5)
            shrink = np.maximum(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            lam = np.where(better, np.maximum(lam * shrink, o.lam_min), lam * nu)
            state["nu"] = np.where(better, 2.0, 2.0 * nu)
        else:
            lam = np.where(better, np.maximum(lam / 10.0, o.lam_min), lam * 10.0)
        state["lam"] = lam
        state["n_iter"] = n_it = state["n_iter"] + 1
        state["n_acc"] = n_ac = state["n_acc"] + better
        state["n_rej"] = n_rej = np.where(better, 0, state["n_rej"] + 1)
        # Stopping, in order of precedence: converged, damping exhausted, out of steps.
        tol_f = o.ftol * np.maximum(model["chi2"], o.chi2_floor)
        small_gain = better & (gain <= tol_f)
        if o.judge_failed:
            # (a failed evaluation, NaN, predicts and gains nothing: "not above" holds for it;
            # an inadmissible one, -inf, gains more than any finite tolerance)
            small_gain |= ~(np.abs(gain) > tol_f) & (pred <= tol_f)
        else:
            small_step &= better
        exhausted = lam > o.lam_max
        if o.max_reject is not None:
            exhausted |= n_rej >= o.max_reject
        out = n_it >= o.max_iter
        # (the first test that holds wins: nested from the last, cheaper than np.select)
        code = np.where(out, _MAX_ITER, _RUNNING)
        if o.max_accepted is not None:
            code = np.where(n_ac >= o.max_accepted, _MAX_ACCEPTED, code)
        code = np.where(exhausted, _EXHAUSTED, code)
        code = np.where(small_step, _STEP, np.where(small_gain, _CHI2, code))
        going = code == _RUNNING
        # The Jacobian form: residuals and Jacobian at the new point, where the problem goes on.
        go_on = better & going
        if "jacobian" in model and go_on.any():
            fresh = _local_model(evaluate(state["p"][go_on], rows[go_on], True))
            for key in ("residuals", "jacobian", "gradient"):  # χ² is that of the trial
                model[key][go_on] = fresh[key]
            broken = _broken_rows(model, go_on)
        if broken is not None:  # (a row that converged there has its result: it stays so)
            code[broken & going] = _NOT_FINITE
            going &= ~broken
        if not going.all():
            done, ended = rows[~going], ~going
            x[done], chi2[done], status[done] = state["p"][ended], model["chi2"][ended], code[ended]
            n_iter[done], n_acc[done] = state["n_iter"][ended], state["n_acc"][ended]
            last[done] = state["last"][ended]
            # (the rows that go on found once, then np.take of whole rows: the same numbers
            # as a[going], without a scan of the mask per array)
            kept = np.flatnonzero(going)
            rows = rows[kept]
            model = {k: np.take(a, kept, axis=0) for k, a in model.items()}
            state = {k: np.take(a, kept, axis=0) for k, a in state.items()}
    return LeastSquaresResult(
        x=x,
        chi2=chi2,
        converged=(status == _STEP) | (status == _CHI2),
        status=status,
        n_iter=n_iter,
        n_accepted=n_acc,
        last_step=last,
    )


def _broken_rows(loc, rows: np.ndarray) -> np.ndarray | None:
    """The ``rows`` (a mask) whose derivatives in ``loc`` (Jacobian, or gradient and Hessian)
    are not finite, or None if there are none (one test of the whole arrays in the usual case).

    Why: a NaN or inf in the derivatives makes the step of its problem NaN (and the SVD of the
    Jacobian form raise for the whole batch), so such a problem stops where it is."""
    # (the Jacobian form's gradient Jᵀr: of the Jacobian and the finite residuals)
    keys = ["jacobian"] if "jacobian" in loc else [k for k in ("gradient", "hessian") if k in loc]
    if all_finite(*(loc[k] for k in keys)):
        return None
    finite = np.ones(rows.size, dtype=bool)
    for k in keys:
        finite &= np.isfinite(loc[k]).reshape(rows.size, -1).all(axis=1)
    broken = rows & ~finite
    return broken if broken.any() else None


def _rows_reduce(ufunc: np.ufunc, a: np.ndarray, empty) -> np.ndarray:
    """``ufunc.reduce(a, axis=1)`` of an (R, P) array, column by column (``empty`` in every row
    where P = 0): a reduction along rows of a few parameters pays numpy's per-row cost
    (``np.all`` ~8 µs and ``np.max`` ~17 µs for 450 rows of 2, against ~1.6 µs). The same
    values: ``np.logical_and`` and ``np.maximum`` give theirs in any order, and a NaN
    propagates through ``np.maximum`` as in the reduction."""
    if a.shape[1] == 0:
        return np.full(a.shape[0], empty, dtype=a.dtype)
    out = a[:, 0].copy()
    for p in range(1, a.shape[1]):
        ufunc(out, a[:, p], out=out)
    return out


def _local_model(out) -> dict[str, np.ndarray]:
    """The arrays of one evaluation (:func:`levenberg_marquardt`), as float arrays, with χ²
    (inf outside the admissible region) and the gradient Jᵀr of the Jacobian form."""
    loc = {k: np.array(v, dtype=float) for k, v in out.items() if v is not None}
    if "residuals" in loc:
        r = loc["residuals"]
        c2 = np.array([row @ row for row in r])  # row by row: the sum of one problem alone
        loc["chi2"] = np.where(np.isfinite(c2), c2, np.inf)
        if "jacobian" in loc:
            loc["gradient"] = np.einsum("rgp,rg->rp", loc["jacobian"], r)
    return loc


def _quadratic(loc, step) -> np.ndarray:
    """δᵀJᵀJδ per row (the curvature term of the predicted decrease of χ²)."""
    if "hessian" in loc:
        return np.einsum("ri,rij,rj->r", step, loc["hessian"], step)
    Jd = np.einsum("rgp,rp->rg", loc["jacobian"], step)
    return np.einsum("rg,rg->r", Jd, Jd)


def _damped_steps(loc, held, lam, damping: str):
    """The steps δ of (JᵀJ + λD) δ = -Jᵀr (held parameters fixed) and, in the Jacobian form, a
    function solving the same damped system for other residuals (rows (n, G) -> (n, P))."""
    if "hessian" in loc:
        H, g = loc["hessian"], loc["gradient"]
        eye = np.eye(H.shape[-1])
        diag = np.maximum(np.diagonal(H, axis1=1, axis2=2), 1e-300)
        if damping == "marquardt":
            Hs = H + lam[:, None, None] * diag[:, :, None] * eye
        else:
            # (floored as diag is: a zero Hessian, no data, would leave Hs singular)
            top = np.maximum(np.linalg.eigvalsh(H)[:, -1], 1e-300)
            Hs = H + (lam * top)[:, None, None] * eye
        # A held parameter: its row and column decoupled, its gradient zero, so its step is 0.
        if held.any():
            Hs = np.where(held[:, :, None] | held[:, None, :], eye * diag[:, :, None], Hs)
            g = np.where(held, 0.0, g)
        # (H and g are finite here, _broken_rows: the solve without solve_stacked's test)
        return -solve_finite_stacked(Hs, g[:, :, None])[:, :, 0], None
    # The Jacobian form, problem by problem (an SVD each; ~20 µs, far below an evaluation).
    factors = []
    for J, keep_out, lam_i in zip(loc["jacobian"], held, lam, strict=True):
        d = None
        if damping == "marquardt":
            d = np.linalg.norm(J, axis=0)
            d = np.where(d > 0, d, 1.0)
            J = J / d
        if keep_out.any():
            J = np.where(keep_out, 0.0, J)
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        keep = s > s[0] * _SINGULAR_CUTOFF
        s_k, U_k, V_k = s[keep], U[:, keep], Vt[keep].T
        ref = s[0] ** 2 if damping == "levenberg" else 1.0
        factors.append((U_k, V_k, s_k / (s_k**2 + lam_i * ref), d, keep_out))

    def solve(rhs):
        out = []
        for (U_k, V_k, filt, d, keep_out), r in zip(factors, rhs, strict=True):
            x = -(V_k @ (filt * (U_k.T @ r)))
            x = x if d is None else x / d
            out.append(np.where(keep_out, 0.0, x))
        return np.array(out)

    return solve(loc["residuals"]), solve


def _accelerated(evaluate, idx, q, v, loc, solve, bounds, o):
    """Trials p + v + a/2 with the geodesic acceleration a (:class:`LMOptions`), and which of
    them stand (admissible at p + h v and 2|a| <= 0.75|v|); the others are failed steps."""
    lo, hi = bounds
    h = float(o.geodesic)
    r_h = _local_model(evaluate(np.clip(q + h * v, lo, hi), idx, False))
    ok = np.isfinite(r_h["chi2"])
    trial = np.clip(q + v, lo, hi)
    if not ok.any():
        return trial, ok
    J, r = loc["jacobian"], loc["residuals"]
    rvv = np.array(
        [
            (2.0 / h) * ((a - b) / h - Ji @ vi)
            for a, b, Ji, vi in zip(r_h["residuals"], r, J, v, strict=True)
        ]
    )
    acc = solve(np.where(ok[:, None], rvv, 0.0))
    for i in np.flatnonzero(ok):
        ok[i] = 2 * np.linalg.norm(acc[i]) <= 0.75 * np.linalg.norm(v[i])
        if ok[i]:
            trial[i] = np.clip(q[i] + v[i] + 0.5 * acc[i], lo[i], hi[i])
    return trial, ok


def solve_stacked(a, b):
    """a⁻¹ b for stacks of P x P matrices a (R, P, P) and b (R, P, K): Cramer's rule for
    P = 2 (thousands of 2 x 2 systems at a fraction of LAPACK's cost per call), else LU.

    Each row is solved alone, and one bad row never raises for the stack nor changes the
    others' solutions (those of a stack without it, bit for bit): a row whose a or b holds a
    NaN or an inf gets NaN throughout (not LAPACK's or Cramer's partial values), without a
    warning; for P != 2 a row that LAPACK's LU finds singular (an exact zero pivot, as of a
    matrix of zeros) gets NaN. For P = 2 a determinant 0 is replaced by the smallest normal
    double instead (the rule of :func:`solve_finite_stacked`, which the solver's damped steps
    take: the step of a problem without data, a zero system whose damping underflows, is then
    0/tiny = 0, not NaN); a singular row with b off its range gives ±inf there.
    """
    # (invalid: inf - inf, inf/inf and 0·inf of a row with an inf, made NaN below)
    with np.errstate(invalid="ignore"):
        out = solve_finite_stacked(a, b)
    # The solutions tested, not a and b: they are new and contiguous, while a and b may be
    # views (the plateau fit's are), which np.vdot would copy. A NaN or inf in a or b leaves
    # one in its row's solution; the rows are told apart only then (the usual case: one test).
    if not all_finite(out):
        finite = np.isfinite(a).all(axis=(1, 2)) & np.isfinite(b).all(axis=(1, 2))
        out[~np.broadcast_to(finite, out.shape[:1])] = np.nan
    return out


def all_finite(*arrays) -> bool:
    """Whether every entry of float ``arrays`` is finite, by the sum of their sums of squares:
    a NaN or an inf makes it NaN or inf. An overflow of finite entries answers False too,
    which costs its caller only its row-by-row test. (~8k instructions a contiguous array of
    ~10³ entries: half of isfinite(a).all(), a reduction's setup; np.vdot copies any other.)
    For the package's guards of batched fits (one test in the usual case, all finite)."""
    total = 0.0
    for a in arrays:
        total += np.vdot(a, a)
    return math.isfinite(total)


def solve_finite_stacked(a, b):
    """:func:`solve_stacked` of stacks without NaN or inf (Cramer's rule for P = 2, else LU),
    without its test of them: for the package's own hot paths, whose systems are finite
    (the solver's damped steps; the plateau fit's projections, of finite sweeps)."""
    if a.shape[-1] != 2:
        try:
            return np.linalg.solve(a, b)
        except np.linalg.LinAlgError:
            return _solve_around_singular(a, b)
    a00, a01, a10, a11 = a[:, 0, 0], a[:, 0, 1], a[:, 1, 0], a[:, 1, 1]
    det = a00 * a11
    det -= a01 * a10
    det = np.where(det != 0, det, _TINY)
    # Column by column of b (K is 1 or 2 here), each numerator written into its place and
    # divided there: the numbers of (a₁₁b₀ - a₀₁b₁)/det and (a₀₀b₁ - a₁₀b₀)/det, on 1-d arrays
    # of the R rows. Operations that broadcast a row's one number over its two or four (a[:, 1,
    # 1, None] * b[:, 0], out /= det[:, None, None]) copy the rows one by one into numpy's
    # buffers: ~48 µs against ~19 µs for 450 rows and K = 2 (~18 against ~12 for K = 1).
    R = np.broadcast_shapes(a.shape[:1], b.shape[:1])[0]  # (an empty stack against one row: 0)
    out = np.empty((R, 2, *b.shape[2:]), dtype=np.result_type(a, b, det))
    t = np.empty(R, dtype=out.dtype)
    for k in range(out.shape[2]):
        b0, b1, top, bottom = b[:, 0, k], b[:, 1, k], out[:, 0, k], out[:, 1, k]
        np.multiply(a11, b0, out=top)
        top -= np.multiply(a01, b1, out=t)
        top /= det
        np.multiply(a00, b1, out=bottom)
        bottom -= np.multiply(a10, b0, out=t)
        bottom /= det
    return out


def _solve_around_singular(a, b):
    """np.linalg.solve(a, b) of stacks with a row that LAPACK finds singular: those rows NaN,
    the others LAPACK's solutions (each matrix is factorised alone: the same numbers)."""
    R = np.broadcast_shapes(a.shape[:1], b.shape[:1])[0]
    a = np.broadcast_to(a, (R, *a.shape[1:]))
    # slogdet factorises as solve does (getrf): its sign is 0 exactly where a pivot is 0.
    with np.errstate(invalid="ignore"):  # (a NaN row's sign: NaN, solved below)
        singular = np.linalg.slogdet(a)[0] == 0
    eye = np.eye(a.shape[-1], dtype=a.dtype)
    out = np.linalg.solve(np.where(singular[:, None, None], eye, a), b)
    out[singular] = np.nan
    return out


#: The smallest normal double: the determinant put where it is 0 (a NaN-free step of 0/tiny).
_TINY = np.finfo(float).tiny
