"""The rows of padded sweeps that a batched fit can take, and its results spread back over all.

Why: the loop fits (:func:`contactres.analysis._loops.fit_cm_loops`, Cattaneo-Mindlin and
Savkoor, and :func:`contactres.analysis._plateau.fit_plateau_loops`) solve thousands of sweeps
at once, and a NaN or an inf in one sweep, or a sweep with no point of weight > 0, made the
linear algebra of the whole batch raise (numpy.linalg.LinAlgError: the SVD of pinv). A sweep
of too few distinct amplitudes (no more residuals, two an amplitude, than the fit has
parameters) fits exactly, with errors of 0 that mean nothing. Such a sweep has no fit: the
other rows are fitted alone, exactly as a batch without it (the same call on the same arrays,
so their numbers bit for bit), and it gets NaN. The analysis (:func:`contactres.analyze`)
validates its sweeps and passes no NaN or inf, but a sweep of one or two points reaches the
fits (the validation warns that it is too short and keeps its row: its loops then have no
BIC); the fits are also called directly.

The same count of distinct amplitudes decides, for every fit that
:func:`contactres.analysis._classify.fit_models` makes (each class's fit, exact or closed form,
per sweep and per load block), whether the sweep identifies the fit's k parameters at all
(:func:`identified`, :func:`blank_unidentified`): two residuals an amplitude (Δf and ΔΓ), so a
fit of more parameters than twice the distinct amplitudes — a straight line's four through
points at one amplitude, which has no slope — has no parameters and no criterion. The plateau
loop that :func:`contactres.analysis._classify.add_plateau_fits` adds later to the sweeps of
contending blocks does not pass through it: that loop refuses a sweep by its own, stricter
count (3 distinct amplitudes for its 4 parameters, :func:`usable_rows`), so the rule holds for
it too.

A fit that is identified may still have no residual degree of freedom: where its k parameters
are at least its 2n residuals (n the points of weight > 0, copies of one amplitude counted
each time: they do add residuals), it passes through every point, its residual sums and its
errors are ~0, which mean nothing (:func:`has_residuals`, :func:`blank_errors`). Such a class
keeps its parameter values (an exactly determined fit still gives them: a one-point sweep's
Δf0 and ΔΓ0) but has no errors and no criterion.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .._levenberg_marquardt import all_finite

__all__ = [
    "blank_errors",
    "blank_unidentified",
    "distinct_amplitudes",
    "has_residuals",
    "identified",
    "points_of",
    "spread_rows",
    "usable_rows",
]

#: What marks a field of a batched fit as an uncertainty, not a parameter value: a standard
#: error (``df0_err_Hz``, ``df_b_err``, ``lntheta_err``, ``d_c_err_m``), a covariance
#: (``df_cov_ab``, ``cov_df0_lntheta``) or a residual sum (``rss_df``), as the fitters of
#: :mod:`contactres.analysis._models` name them.
UNCERTAINTY_MARKS = ("_err", "cov_", "rss_")


def usable_rows(points, per_row, min_points: int) -> np.ndarray | None:
    """Which rows of padded sweeps a fit can take, or None if it can take all of them.

    Parameters
    ----------
    points : (u, Δf, ΔΓ, w), each (S, M): amplitudes (m), shifts (Hz), weights (0 for padding)
    per_row : arrays (S,) of the rows' other inputs (noise levels in Hz, hinges in m, ...)
    min_points : the fewest distinct amplitudes of w > 0 a row needs (two residuals each, Δf
        and ΔΓ: more residuals than the fit's parameters)

    Returns
    -------
    None if every row is usable (the usual case, found by one sum of each whole array),
    else (S,) bool: False for a row with a NaN or an inf in any of its values (padding
    included: the fits form products such as w·Δf over the whole row) or with fewer than
    ``min_points`` distinct amplitudes of w > 0 (a NaN weight is no point).

    Notes
    -----
    The loops are functions of the amplitude: the copies of one amplitude (the ramps of a
    block fitted jointly) add residuals but no information, and the plateau fit pools them
    into one point (:func:`contactres.analysis._plateau.pool_repeats`). They are counted once
    where they stand side by side, as that pooling finds them (amplitudes ascending, as
    :func:`contactres.analysis._amplitude.pad_sweeps` lays them out): ~7 ms for 10⁵ rows of 13,
    against ~20 ms for a sort that would also find copies apart in rows out of order, which
    are then counted more than once (a row passed that a sort would refuse; never the reverse).
    """
    arrays = [np.asarray(a, dtype=float) for a in (*points, *per_row)]
    good = distinct_amplitudes(arrays[0], arrays[3]) >= min_points
    # (an overflow of finite values only sends the rows to the test one by one below)
    if good.all() and all_finite(*arrays):
        return None
    for a in arrays:
        good &= np.isfinite(a).reshape(len(good), -1).all(axis=1)
    return good


def distinct_amplitudes(u, w) -> np.ndarray:
    """(S,) the number of distinct amplitudes of weight > 0 in each row of padded sweeps ``u``,
    ``w`` (S, M) (m, and weights: 0 for padding, a NaN weight is no point); copies of one
    amplitude are counted once where they stand side by side (see :func:`usable_rows`)."""
    u = np.asarray(u, dtype=float)
    data = np.asarray(w, dtype=float) > 0
    repeats = (u[:, 1:] == u[:, :-1]) & data[:, 1:] & data[:, :-1]
    return np.count_nonzero(data, axis=1) - np.count_nonzero(repeats, axis=1)


def identified(distinct: np.ndarray, k: int) -> np.ndarray:
    """(S,) bool: whether a sweep of ``distinct`` amplitudes (:func:`distinct_amplitudes`)
    identifies a fit of ``k`` parameters to both channels: no more parameters than its
    2·distinct residuals that carry information (Δf and ΔΓ at each amplitude)."""
    return 2 * distinct >= k


def points_of(w) -> np.ndarray:
    """(S,) the number of points of weight > 0 in each row of padded sweeps of weights ``w``
    (S, M) (0 for padding; a NaN weight is no point), copies of one amplitude each counted."""
    return np.count_nonzero(np.asarray(w, dtype=float) > 0, axis=1)


def has_residuals(points: np.ndarray, k: int) -> np.ndarray:
    """(S,) bool: whether a fit of ``k`` parameters to both channels of sweeps of ``points``
    points (:func:`points_of`) leaves a residual degree of freedom: more residuals, 2·points
    (Δf and ΔΓ at each point), than parameters. Where not, the fit passes through every point:
    its residual sums are ~0 and its BIC is :func:`contactres.analysis._amplitude.bic`'s floor
    for a perfect fit, not a measure of fit."""
    return 2 * points > k


def _emptied(fields: dict[str, np.ndarray], ok: np.ndarray, which) -> dict[str, np.ndarray]:
    """``fields`` with the sweeps not ``ok`` emptied in the fields ``which(key)`` selects."""
    if ok.all():
        return fields
    out = {}
    for key, v in fields.items():
        if not which(key):
            out[key] = v
            continue
        v = np.array(v, copy=True)
        kind = v.dtype.kind
        if kind in "iu":
            # No integer has a meaning of "none" here, and "" or NaN cannot be written into it:
            # said, not written as a number that would read as a result.
            raise TypeError(
                f"the fit field {key!r} is an integer array ({v.dtype}): it has no empty value "
                "to write for the sweeps emptied here"
            )
        v[..., ~ok] = False if kind == "b" else (np.nan if kind in "fc" else "")
        out[key] = v
    return out


def blank_unidentified(fields: dict[str, np.ndarray], ok: np.ndarray) -> dict[str, np.ndarray]:
    """The fields of a batched fit (arrays with the sweep as last axis) with the sweeps not
    ``ok`` (:func:`identified`) emptied: NaN in float and complex fields (the parameters, their
    errors and the residual sums, so that the class has no criterion), False in flags (a hinge
    not ``found``), "" in text; ``fields`` itself where every sweep is ``ok`` (the usual case:
    the same arrays).

    Raises
    ------
    TypeError
        for an integer field where a sweep is not ``ok`` (no fitter returns one): an integer
        has no empty value, and a number written there would read as a result.
    """
    return _emptied(fields, ok, lambda key: True)


def blank_errors(fields: dict[str, np.ndarray], ok: np.ndarray) -> dict[str, np.ndarray]:
    """The fields of a batched fit with the uncertainties (:data:`UNCERTAINTY_MARKS`: standard
    errors, covariances, residual sums) of the sweeps not ``ok`` (:func:`has_residuals`) set
    to NaN, so that the class has no criterion and no errors; the parameter values and the other
    fields kept. ``fields`` itself where every sweep is ``ok``. Raises as
    :func:`blank_unidentified` for an integer uncertainty."""
    return _emptied(fields, ok, lambda key: any(mark in key for mark in UNCERTAINTY_MARKS))


def spread_rows(fit: pd.DataFrame, good: np.ndarray) -> pd.DataFrame:
    """The table ``fit`` of the rows ``good`` (a mask of S rows) spread over all S rows: NaN in
    the numeric columns of the others, "" in the text columns (``edge``)."""
    at = np.flatnonzero(good)
    columns = {}
    for name in fit.columns:
        v = fit[name].to_numpy()
        text = v.dtype.kind not in "fc"
        full = np.full(good.size, "" if text else np.nan, dtype=object if text else v.dtype)
        full[at] = v
        columns[name] = full
    return pd.DataFrame(columns)
