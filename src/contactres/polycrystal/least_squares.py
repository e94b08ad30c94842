"""Levenberg-Marquardt with geodesic acceleration, box bounds and an admissible region.

The solver of the inverse problems of :mod:`.inverse` and :mod:`.inverse_hexagonal`: it knows
nothing of crystals. The residual function returns ``None`` outside the admissible region (for
the fits, a stiffness that is not positive definite); such a step is rejected exactly like one
that raises χ², so the damping grows until the step stays inside. No penalty term is added, so
the minimum and the covariance are those of the data alone.

Reference: M. K. Transtrum and J. P. Sethna, "Improvements to the Levenberg-Marquardt algorithm
for nonlinear least-squares minimization", arXiv:1201.5885 (2012).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import ContactresInputError

__all__ = ["MAX_LOG_STEP", "levenberg_marquardt"]

# The largest change of a (log-)parameter per iteration: the valleys of the fits are long and
# curved, and a linearised step much longer than this leaves them.
MAX_LOG_STEP = 0.2

# evaluate(theta, jacobian) -> (residuals (G,), Jacobian (G, P) or None), or (None, None) when
# theta is outside the admissible region.
Residuals = Callable[[np.ndarray, bool], tuple[np.ndarray | None, np.ndarray | None]]


def levenberg_marquardt(
    evaluate: Residuals, theta, lo, hi, max_iter: int = 30
) -> tuple[np.ndarray, bool, str]:
    """Minimise ``r @ r`` by Levenberg-Marquardt with geodesic acceleration.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(theta, jacobian)`` returns the weighted residuals (dimensionless) and, when
        ``jacobian`` is true, their Jacobian d r/d theta; ``(None, None)`` outside the admissible
        region. ``theta`` (the start) must be admissible.
    theta : array_like, shape (P,)
        Starting parameters (any unit; the fits use logarithms, so steps are relative changes).
    lo, hi : array_like, shape (P,)
        Box bounds (may be infinite); every trial is clipped into them.
    max_iter : int
        Largest number of accepted steps.

    Returns
    -------
    theta, success, message
        The last accepted parameters, whether the iteration converged, and why it stopped.

    Notes
    -----
    The step solves the damped normal equations through the SVD of J (filter factors
    s/(s² + λ s₀²)), so directions with a singular value below 1e-13 s₀ are never moved: the
    data say nothing about them. The geodesic acceleration (second directional derivative of r
    along the step, by one extra evaluation at ``theta + h v``) bends the step along a curved
    valley; it is accepted when ``2 |a| <= 0.75 |v|``.
    """
    theta = np.asarray(theta, dtype=float)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    r, J = evaluate(theta, True)
    if r is None:
        raise ContactresInputError("the starting point is outside the admissible region")
    chi2 = float(r @ r)
    lam = 1e-6
    h = 0.1
    for _ in range(max_iter):
        # theta is admissible here (the start, checked, or an accepted step): both are given
        assert r is not None and J is not None
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        keep = s > s[0] * 1e-13
        s_k, U_k, V_k = s[keep], U[:, keep], Vt[keep].T
        for _ in range(12):
            filt = s_k / (s_k**2 + lam * s[0] ** 2)
            v = -(V_k @ (filt * (U_k.T @ r)))
            v *= min(1.0, MAX_LOG_STEP / max(float(np.max(np.abs(v))), 1e-300))
            r_h, _ = evaluate(np.clip(theta + h * v, lo, hi), False)
            trial, chi2_t = theta, np.inf
            if r_h is not None:
                rvv = (2.0 / h) * ((r_h - r) / h - J @ v)
                acc = -(V_k @ (filt * (U_k.T @ rvv)))
                if 2 * np.linalg.norm(acc) <= 0.75 * np.linalg.norm(v):
                    trial = np.clip(theta + v + 0.5 * acc, lo, hi)
                    r_t, _ = evaluate(trial, False)
                    # An inadmissible trial counts as a rise of χ²: more damping, shorter step.
                    chi2_t = np.inf if r_t is None else float(r_t @ r_t)
            if chi2_t <= chi2:
                break
            lam = lam * 10.0
        else:
            return theta, False, "no step lowers chi2 (damping exhausted)"
        moved = float(np.max(np.abs(trial - theta)))
        improved = chi2 - chi2_t
        theta = trial
        lam = max(lam / 10.0, 1e-9)
        if moved < 1e-9 or improved <= 1e-9 * max(chi2, 1.0):
            return theta, True, f"converged (last step {moved:.2g})"
        r, J = evaluate(theta, True)
        chi2 = chi2_t
    return theta, False, f"no convergence in {max_iter} iterations"
