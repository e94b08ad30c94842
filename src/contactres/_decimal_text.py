"""The decimal text of doubles, made in numpy: the bytes of ``"%.Ng" % value`` (Python's ``%``
with a ``g`` conversion of precision N) for a whole array at once.

Why: Python's ``%`` formats a double at ~0.2-0.4 µs; ``qcm analyze`` of 10^5 sweeps writes ~12
million of them with :data:`contactres.fileio.CSV_FLOAT_FORMAT` ("%.10g"), two thirds of its
writing (issue 31, point 3). Here a double costs a few numpy passes over the array, 2.6-3.8x
less CPU than ``%`` (a list of ``"%.10g" % v``), by the data: 65 ns against 240 ns for
uniform doubles in [0, 1), 90 against 285 ns for values of a ``qcm analyze`` curve table
(t4), 110-125 against 310 ns for normal doubles times 10^(-12..12), 130 against 385 ns for
random bits (65,536 doubles a call, CPU time, the least of 15 calls, three runs on a loaded
two-core machine; a review on the same machine measured 75-184 ns against 150-380 ns).

How (the text is Python's to the byte, proved below and tested against Python's ``%``):

1. The decimal exponent ``e`` of ``|x|`` and the scaled value ``y = |x| * 10^(N-1-e)``, which
   lies in ``[10^(N-1), 10^N)``; ``e`` is first taken from ``log10`` and corrected by one where
   ``y`` falls outside.
2. The N significant digits are ``M = rint(y)``: Python rounds the exact binary value to N
   digits, half to even (``dtoa`` mode 2); the integer nearest ``y`` is that rounding wherever
   ``y`` is further than a margin from a half (below). ``M = 10^N`` (``9.9999999996e-5`` at 10
   digits) is ``10^(N-1)`` at exponent ``e + 1``.
3. ``%g``'s notation: exponential (``d.ddde+XX``, at least two exponent digits) where ``e < -4``
   or ``e >= N``, else fixed; trailing zeros of the fraction removed, and the point with them.
   Zeros (``0``, ``-0``), infinities (``inf``, ``-inf``) and NaN (the caller's text) are written
   as they are.
4. The text of a cell is a record of fixed fields (sign, digits before the point, the point,
   digits after it, exponent) whose unused bytes are NUL: the text is the record without its
   NULs. So no cell's text is moved into place one by one: the leading zeros before the point
   and the trailing zeros after it are NUL by the tables of four digits they are read from, and
   the caller drops every NUL of a whole chunk at once (:func:`g_records`).

The error bound (why the margin is safe). ``10^(N-1-e)`` is applied in at most two steps,
``|x| * 10^a * 10^b`` (a division by ``10^-a`` where ``a < 0``), with each power the double
nearest it (``float(10**k)``: exact up to ``10^22``) and each product or quotient correctly
rounded (IEEE 754). That is at most four roundings, each a factor ``1 + d`` with
``|d| <= u/(1 - u)``, ``u = 2^-53`` (``u`` itself but for the rounded power a quotient
divides by), and no intermediate is subnormal or infinite (the steps split the scaling in
halves, each within ``10^±170``). So ``|y - z| <= ((1 + u/(1-u))^4 - 1) z < 4.01 u z`` for the
exact ``z = |x| * 10^(N-1-e)``, and ``z < 10^N (1 + 5u)`` gives ``|y - z| < 4.01 u 10^N (1 +
5u) < 4.1 u 10^N``. Rounding to the nearest integer changes only at the halves ``k + 1/2``:
wherever the fraction of ``y`` is further than :func:`_margin` ``= 8 u 10^N`` from 1/2, ``z``
lies strictly between the same two halves as ``y`` and ``rint(z) = rint(y)``; an exact tie
``z = k + 1/2`` puts ``y`` within the bound of the half, so ties are always Python's. The
cells within the margin (a fraction of about ``1.8e-5`` of random doubles at 10 digits) are
formatted by Python's ``%`` itself. Where ``y`` lies in ``[10^(N-1), 10^N)`` but ``z`` just
outside (within the bound), ``z``'s own exponent gives the same digits: ``z`` just below
``10^(N-1)`` rounds at ``e - 1`` to ``10^N``, that is ``10^(N-1)`` at ``e``, as ``y`` does;
``z`` just above ``10^N`` rounds at ``e + 1`` to ``10^(N-1)``, as ``rint(y) = 10^N`` gives.
``y < 10^13 < 2^53`` for N <= :data:`MAX_PRECISION`: every integer there is a double.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["MAX_PRECISION", "copy_rows", "g_precision", "g_records", "take_rows"]

#: The largest precision formatted here: ``y < 10^N`` must stay below 2^53 (every integer a
#: double) and the digits after the point within 16; past 12 the margin sends ever more cells
#: to Python (1.8 % at 13 digits).
MAX_PRECISION = 13

#: ``%g`` and ``%.Ng`` alone: no flags, no width (other formats keep Python's ``%``).
_G_FORMAT = re.compile(r"%(?:\.([0-9]+))?g")  # ([0-9]: \d takes other scripts' digits too)


def _digits() -> np.ndarray:
    """The four decimal digits of 0..9999, most significant first: every combination of four
    digits in order, shape (10^4, 4), uint8."""
    grid = np.meshgrid(*[np.arange(10, dtype=np.uint8)] * 4, indexing="ij")
    return np.stack(grid, axis=-1).reshape(-1, 4)


def _four_digit_words(blank: str) -> np.ndarray:
    """The four ASCII digits of 0..9999 (most significant first) as the bytes of little-endian
    uint32 words, a row of digits being a view of the words: all of them (``blank=""``), or
    with the leading zeros NUL (``"leading"``: 0 as four NULs; ``"leading1"``: 0 as "0"), or
    the trailing zeros (``"trailing"``: 0 as four NULs). Made on arrays (the tables of Python
    strings cost ~12-15 ms of CPU at every import)."""
    digits = _digits()
    text = digits + np.uint8(ord("0"))
    if blank.startswith("leading"):
        leading = _zeros_from_the_left(digits)
        if blank == "leading1":
            leading[:, -1] = False  # 0 is "0"
        text *= ~leading
    elif blank == "trailing":
        text *= ~_trailing(digits)
    return text.view("<u4").reshape(-1)


def _zeros_from_the_left(digits: np.ndarray) -> np.ndarray:
    """Where the rows of ``digits`` (n, 4) hold their leading zeros: a zero with only zeros
    before it. (A column at a time: ``np.logical_and.accumulate`` along the rows' four
    digits is a loop per row, ~5x slower.)"""
    zeros = digits == 0
    for j in range(1, zeros.shape[1]):
        zeros[:, j] &= zeros[:, j - 1]
    return zeros


def _trailing(digits: np.ndarray) -> np.ndarray:
    """Where the rows of ``digits`` (n, 4) hold their trailing zeros."""
    return _zeros_from_the_left(digits[:, ::-1])[:, ::-1]


def _read_only(table: np.ndarray) -> np.ndarray:
    """``table``, made read-only (a module's table is shared by every call)."""
    table.flags.writeable = False
    return table


#: The words of four digits, read at ``group`` where a group's zeros are digits and at
#: ``group + 10^4`` where they are not text: in :data:`_LEADING` (digits before the point)
#: where every more significant group is 0, in :data:`_TRAILING` (digits after the point)
#: where every less significant group is 0. One gather a group, no choice between tables.
_FOUR = _read_only(_four_digit_words(""))
_LEADING = _read_only(np.concatenate([_FOUR, _four_digit_words("leading")]))
_LEADING_LAST = _read_only(np.concatenate([_FOUR, _four_digit_words("leading1")]))  # 0: "0"
_TRAILING = _read_only(np.concatenate([_FOUR, _four_digit_words("trailing")]))

#: Trailing zero digits of 0..9999 written with four digits (0: four).
_TRAILING_ZEROS = _read_only(_trailing(_digits()).sum(axis=1))

#: The double nearest each 10^k, k = 0..170 (``float`` of an int is correctly rounded).
_POWERS = _read_only(np.array([float(10**k) for k in range(171)]))

#: 10^k as int64, k = 0..18.
_POWERS_INT = _read_only(np.array([10**k for k in range(19)], dtype=np.int64))

_U = 2.0**-53  #: the unit roundoff of a double


def g_precision(float_format) -> int | None:
    """The precision N of a float format that :func:`g_records` writes (``"%.Ng"``, ``"%g"``:
    6; ``"%.0g"``: 1, as Python's ``%``), or None for any other format or N past
    :data:`MAX_PRECISION`."""
    match = _G_FORMAT.fullmatch(float_format) if isinstance(float_format, str) else None
    if match is None:
        return None
    precision = 6 if match.group(1) is None else max(1, int(match.group(1)))
    return precision if precision <= MAX_PRECISION else None


def _margin(precision: int) -> float:
    """Half-width of the band around a half within which ``y``'s rounding is left to Python:
    ``8 u 10^N``, about twice the bound ``4.1 u 10^N`` of ``|y - z|`` (module docstring).
    The test of near halves fails with ``2 u 10^N``."""
    return 8.0 * _U * 10.0**precision


def _scaled(a: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """``a * 10^shift`` for positive doubles ``a`` and integer ``shift`` (|shift| <= 340), in
    at most two correctly rounded steps by the doubles nearest the powers (module docstring:
    the error bound). One step (an exact power) where ``|shift| <= 22``."""
    one = np.abs(shift) <= 22
    if one.all():
        return _times_power(a, shift)
    out = np.empty_like(a)
    out[one] = _times_power(a[one], shift[one])
    far = ~one
    half = shift[far] // 2  # both halves within 10^±170: no step overflows or underflows
    out[far] = _times_power(_times_power(a[far], half), shift[far] - half)
    return out


def _times_power(a: np.ndarray, k: np.ndarray) -> np.ndarray:
    """``a * 10^k`` by one correctly rounded operation: a product by ``10^k`` or a quotient by
    ``10^-k`` (the power itself the double nearest it)."""
    up = k >= 0
    if up.all():
        return a * _POWERS[k]
    if not up.any():
        return a / _POWERS[-k]
    out = np.multiply(a, _POWERS[np.abs(k)], where=up, out=np.empty_like(a))
    return np.divide(a, _POWERS[np.abs(k)], where=~up, out=out)


def _exponent_guess(a: np.ndarray) -> np.ndarray:
    """``floor(log10(a))`` as int64, off by at most one next to a power of ten (:func:`_rounded`
    corrects it)."""
    return np.floor(np.log10(a)).astype(np.int64)


def _rounded(a: np.ndarray, precision: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M, e, exact) for positive finite doubles ``a``: the ``precision`` significant digits
    as an int64 in ``[10^(N-1), 10^N)`` and the decimal exponent of the rounded value; where
    ``exact`` is False the rounding is within the margin of a half and is left to Python."""
    low, high = 10.0 ** (precision - 1), 10.0**precision
    e = _exponent_guess(a)
    y = _scaled(a, precision - 1 - e)
    stray = None
    for _ in range(3):  # log10 is off by at most one near the powers of ten
        off = (y < low) | (y >= high)
        if not off.any():
            break
        e[off] += np.where(y[off] >= high, 1, -1)
        y[off] = _scaled(a[off], precision - 1 - e[off])
    else:  # (never seen) cells still out of range: left to Python, never written wrong
        stray = (y < low) | (y >= high)
        y[stray] = low
    exact = np.abs(y - np.floor(y) - 0.5) > _margin(precision)
    if stray is not None:
        exact &= ~stray
    m = np.rint(y).astype(np.int64)
    carry = m == 10**precision
    if carry.any():
        m[carry] = 10 ** (precision - 1)
        e[carry] += 1
    return m, e, exact


def _groups(values: np.ndarray, count: int) -> list[np.ndarray]:
    """The base-10^4 digits of non-negative int64 ``values`` (below 10^(4 count)), least
    significant first."""
    out = []
    rest = values
    for _ in range(count):
        high = rest // 10_000
        out.append(rest - high * 10_000)
        rest = high
    return out


def _whole_digits(whole: np.ndarray, count: int) -> np.ndarray:
    """The digits of ``whole`` (>= 0) right-aligned in ``4 count`` bytes, its leading zeros NUL
    (0 is a single "0")."""
    words = np.empty((whole.size, count), dtype="<u4")
    above = np.full(whole.size, 10_000)  # every more significant group is 0: NUL for zeros
    for i, g in enumerate(_groups(whole, count)[::-1]):
        words[:, i] = (_LEADING_LAST if i == count - 1 else _LEADING)[g + above]
        above = np.where(g == 0, above, 0) if i < count - 1 else above
    return words.view(np.uint8)


def _fraction_digits(fraction: np.ndarray, count: int) -> tuple[np.ndarray, int]:
    """(digits, used): the ``4 count`` digits of ``fraction`` (below 10^(4 count)) zero-padded
    on the left, its trailing zeros NUL (0: all NUL), and how many columns from the left hold
    a digit in some row (the rest are NUL in every row)."""
    words = np.empty((fraction.size, count), dtype="<u4")
    below = np.full(fraction.size, 10_000)  # every less significant group is 0: NUL for zeros
    used = 0
    for i, g in enumerate(_groups(fraction, count)):
        words[:, count - 1 - i] = _TRAILING[g + below]
        if not used and (zeros := int(_TRAILING_ZEROS[g].min(initial=4))) < 4:
            used = 4 * (count - i) - zeros  # the least significant group with a digit
        if i < count - 1:
            below = np.where(g == 0, below, 0)
    return words.view(np.uint8), used


def _exponent(e: np.ndarray, shown: np.ndarray) -> np.ndarray:
    """``e+XX`` / ``e-XXX`` (at least two digits) of the exponents ``e`` where ``shown``, five
    bytes a cell (NUL where not shown, and for the third digit that ``|e| < 100`` has not)."""
    out = np.zeros((e.size, 5), dtype=np.uint8)
    digits = _FOUR[np.abs(e)].view(np.uint8).reshape(-1, 4)  # |e| <= 324
    out[:, 0] = ord("e")
    out[:, 1] = np.where(e < 0, ord("-"), ord("+"))
    out[:, 2] = np.where(np.abs(e) >= 100, digits[:, 1], 0)
    out[:, 3:] = digits[:, 2:]
    out[~shown] = 0
    return out


def g_records(values: np.ndarray, precision: int, nan_text: bytes = b"nan") -> np.ndarray:
    """The text of ``"%.{precision}g" % v`` for every double of ``values``, as records whose
    NUL bytes are not text (module docstring, point 4).

    Parameters
    ----------
    values : ndarray of float64, shape (n,)
    precision : int
        N, 1..:data:`MAX_PRECISION` (:func:`g_precision` of the format).
    nan_text : bytes
        The text of a NaN (any sign or payload; Python's ``%`` writes ``nan``), without NUL.

    Returns
    -------
    ndarray of uint8, shape (n, width)
        ``records[i]`` without its NUL bytes is the ASCII text of cell i.
    """
    x = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    regular = np.isfinite(x) & (x != 0)
    special: list[tuple[np.ndarray, bytes]] = []  # (rows, text) written as they are
    if not regular.all():
        sign = np.signbit(x)
        for rows, text in (
            (np.isnan(x), nan_text),
            (np.isinf(x) & ~sign, b"inf"),
            (np.isinf(x) & sign, b"-inf"),
            ((x == 0) & ~sign, b"0"),
            ((x == 0) & sign, b"-0"),
        ):
            if rows.any():
                special.append((np.flatnonzero(rows), text))
    at = np.flatnonzero(regular) if special else None
    v = x if at is None else x[at]
    m, e, exact = _rounded(np.abs(v), precision)
    loose_rows = None  # a rounding within the margin of a half: Python's own text
    if not exact.all():  # (the texts as one array, put in place by one assignment)
        loose = np.flatnonzero(~exact)
        loose_rows = loose if at is None else at[loose]
        fmt = f"%.{precision}g"
        loose_text = np.array([fmt % r for r in x[loose_rows].tolist()], dtype="S")
        loose_text = loose_text.view(np.uint8).reshape(loose_rows.size, -1)
    fixed = (e >= -4) & (e < precision)
    small = fixed & (e < 0)  # 0.000ddd
    point = np.where(fixed, precision - 1 - e, precision - 1)  # digits of M after the point
    # whole = M // 10^point by a quotient of doubles: exact, as M < 2^53 and M / 10^point is
    # at least 10^-13 (relative) from the next integer when it is not one.
    whole = np.floor(m / _POWERS[np.minimum(point, precision - 1)]).astype(np.int64)
    whole[small] = 0
    fraction = m - whole * _POWERS_INT[np.minimum(point, precision - 1)]
    fraction[small] = m[small]
    # The fields side by side, each as wide as its widest text in ``values`` (the fewer NULs,
    # the less for the caller to drop): sign, digits before the point, point, digits after
    # it, exponent.
    fields = []
    neg = np.signbit(v)
    if neg.any():
        fields.append((neg.view(np.uint8) * np.uint8(ord("-")))[:, None])
    whole_width = len(str(int(whole.max(initial=0))))
    fields.append(_whole_digits(whole, -(-whole_width // 4))[:, -whole_width:])
    frac_groups = -(-int(point.max(initial=0)) // 4)
    if frac_groups:
        shifted = fraction * _POWERS_INT[4 * frac_groups - point]  # left-aligned in the field
        digits, used = _fraction_digits(shifted, frac_groups)
        if used:
            fields.append(((fraction != 0).view(np.uint8) * np.uint8(ord(".")))[:, None])
            fields.append(digits[:, :used])
    exp_shown = ~fixed
    if exp_shown.any():
        exponent = _exponent(e, exp_shown)
        three = (np.abs(e[exp_shown]) >= 100).any()
        fields.append(exponent if three else exponent[:, [0, 1, 3, 4]])
    width_body = sum(f.shape[1] for f in fields)
    width = max(width_body, max((len(t) for _, t in special), default=0))
    if loose_rows is not None:
        width = max(width, loose_text.shape[1])
    body = np.empty((v.size, width), dtype=np.uint8)
    body[:, width_body:] = 0
    at_field = 0
    for f in fields:
        copy_rows(body[:, at_field : at_field + f.shape[1]], f)
        at_field += f.shape[1]
    if at is None:
        records = body
    else:
        records = np.zeros((x.size, width), dtype=np.uint8)
        records[at] = body
    for rows, text in special:
        records[rows] = 0
        records[rows, : len(text)] = np.frombuffer(text, dtype=np.uint8)
    if loose_rows is not None:
        records[loose_rows] = 0
        records[loose_rows, : loose_text.shape[1]] = loose_text
    return records


def copy_rows(out: np.ndarray, block: np.ndarray) -> None:
    """``out[...] = block`` for uint8 arrays of shape (n, w) whose rows are contiguous (views
    of wider rows are fine): each row copied as one element of w bytes (a void view), ~2.3x
    faster than numpy's copy of narrow rows byte by byte."""
    width = block.shape[1]
    if width < 2 or block.strides[1] != 1 or out.strides[1] != 1:
        out[...] = block
        return
    row = np.dtype((np.void, width))
    out.view(row)[...] = block.view(row)


def take_rows(records: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``records[rows]`` for a C-contiguous uint8 array of shape (n, w) and integer ``rows``:
    each row taken as one element of w bytes (a void view), 4-10x faster than numpy's
    indexing of rows of a two-dimensional array (~10 ns a row against ~1 ns at w = 8-30).
    Anything else (another dtype, a view whose rows are not contiguous, a mask or
    multi-dimensional ``rows``) is taken by numpy's indexing itself, the same result."""
    width = records.shape[1]
    rows = np.asarray(rows)
    simple = records.dtype == np.uint8 and rows.ndim == 1 and rows.dtype.kind in "iu"
    if width < 1 or not simple or not records.flags.c_contiguous:
        return records[rows]
    row = np.dtype((np.void, width))
    return np.take(records.view(row)[:, 0], rows).view(np.uint8).reshape(-1, width)
