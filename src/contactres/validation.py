"""Checks of physical parameters: a ValueError that names the parameter, its unit and the value."""

from __future__ import annotations

import numpy as np

from .errors import ContactresInputError

__all__ = ["amplitude", "nonnegative", "positive"]


def _check(name: str, value, unit: str | None, ok, rule: str):
    unit_text = f" ({unit})" if unit else ""
    try:
        v = np.asarray(value)
        if np.iscomplexobj(v) and np.any(v.imag != 0):
            raise TypeError  # casting would drop the imaginary part silently
        v = np.asarray(v.real if np.iscomplexobj(v) else v, dtype=float)
    except (TypeError, ValueError):  # text, complex, ragged lists
        raise ContactresInputError(
            f"{name} must be a real number or array, finite and {rule}{unit_text}, got {value!r}"
        ) from None
    good = np.isfinite(v) & ok(v)
    if not np.all(good):
        if v.ndim == 0:
            got = repr(value)
        else:
            idx = np.unravel_index(np.flatnonzero(~good.ravel())[0], v.shape)
            where = idx[0] if len(idx) == 1 else tuple(int(i) for i in idx)
            got = f"{float(v[idx])!r} at index {where}"
        raise ContactresInputError(f"{name} must be finite and {rule}{unit_text}, got {got}")
    return float(v) if v.ndim == 0 else v


def positive(name: str, value, unit: str | None = None):
    """``value`` as a float (scalar) or float array, after checking it is finite and > 0."""
    return _check(name, value, unit, lambda v: v > 0, "> 0")


def nonnegative(name: str, value, unit: str | None = None):
    """``value`` as a float (scalar) or float array, after checking it is finite and >= 0."""
    return _check(name, value, unit, lambda v: v >= 0, ">= 0")


def amplitude(u0) -> np.ndarray:
    """An oscillation amplitude u0 (m) as a float ndarray (0-d for a scalar), after checking that
    it is finite and >= 0.

    The loops (:mod:`contactres.tangential`) and the QCM quadrature
    (:mod:`contactres.resonators`) share this check, so their error messages agree.
    """
    return np.asarray(nonnegative("amplitude u0", u0, "m"), dtype=float)
