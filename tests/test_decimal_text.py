"""The decimal text of doubles made in numpy (contactres._decimal_text, issue 31 point 3) is
Python's own ``"%.Ng" % value`` to the byte. The reference is CPython's ``%`` (David Gay's
correctly rounded dtoa, round half to even on the exact binary value): an algorithm of its own,
not this module's output pasted back."""

import numpy as np
import pytest

from contactres._decimal_text import MAX_PRECISION, g_precision, g_records, take_rows


def _texts(values, precision: int, nan_text: bytes = b"nan") -> list[str]:
    """The text of each cell: its record without the NUL bytes (a cell per line)."""
    records = g_records(np.asarray(values, dtype=np.float64), precision, nan_text)
    assert records.dtype == np.uint8 and records.shape[0] == len(values)
    lines = np.concatenate([records, np.full((len(values), 1), ord("\n"), np.uint8)], axis=1)
    return lines.tobytes().translate(None, b"\0").decode("ascii").split("\n")[:-1]


def _python(values, precision: int) -> list[str]:
    return [f"%.{precision}g" % v for v in np.asarray(values, dtype=np.float64).tolist()]


def _mismatches(values, precision: int) -> list[tuple[float, str, str]]:
    values = np.asarray(values, dtype=np.float64)
    got, want = _texts(values, precision), _python(values, precision)
    return [(v, g, w) for v, g, w in zip(values.tolist(), got, want, strict=True) if g != w]


def _random_bits(rng, n: int) -> np.ndarray:
    """Doubles of uniformly random bit patterns: every binary exponent, both signs,
    subnormals, NaNs and infinities."""
    return rng.integers(0, 2**64, n, dtype=np.uint64, endpoint=False).view(np.float64)


def test_random_bit_patterns_over_every_exponent_are_pythons_text():
    """Two million doubles of random bits (all 2046 binary exponents, both signs, subnormals,
    NaN and infinities among them) at the reports' ten digits."""
    rng = np.random.default_rng(20261130)
    for _ in range(4):
        values = _random_bits(rng, 500_000)
        assert _mismatches(values, 10) == []


def test_random_decimal_magnitudes_at_every_precision():
    """Doubles over 10^-30..10^30 (where the fixed notation and the one-step scaling live) and
    random bits, at every precision covered, from %.1g to %.13g."""
    rng = np.random.default_rng(7)
    values = np.concatenate(
        [
            rng.normal(size=40_000) * 10.0 ** rng.integers(-30, 30, 40_000),
            rng.integers(1, 10**6, 10_000) / 2.0 ** rng.integers(0, 30, 10_000),  # short ones
            _random_bits(rng, 20_000),
        ]
    )
    for precision in range(1, MAX_PRECISION + 1):
        assert _mismatches(values, precision) == [], precision


def test_special_values_and_extremes():
    specials = [
        0.0,
        -0.0,
        np.inf,
        -np.inf,
        5e-324,  # the smallest subnormal
        -5e-324,
        2.2250738585072009e-308,  # the largest subnormal
        2.2250738585072014e-308,  # the smallest normal
        1.7976931348623157e308,  # the largest double
        -1.7976931348623157e308,
        1e-320,
        1e300,
        1e-300,
        1.0,
        -1.0,
        0.1,
        0.3,
    ]
    assert _texts(specials, 10) == _python(specials, 10)
    assert _texts([0.0, -0.0], 10) == ["0", "-0"]


def test_a_nan_of_any_sign_or_payload_is_the_callers_text():
    nans = np.array(
        [0x7FF8000000000000, 0xFFF8000000000000, 0x7FF0000000000001, 0xFFFFFFFFFFFFFFFF],
        dtype=np.uint64,
    ).view(np.float64)
    assert np.isnan(nans).all()
    assert _texts(nans, 10) == ["nan"] * 4  # Python's %: "nan" whatever the sign
    assert _texts(nans, 10, b"") == [""] * 4
    assert _texts(np.concatenate([nans, [1.5]]), 10, b"NA") == ["NA"] * 4 + ["1.5"]


def _exact_ties(rng, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Doubles whose exact decimal value ends in a 5 just past the precision (exact halves),
    and that precision: c * 2^-m for odd c has exactly m decimal places, the last one a 5."""
    values, precisions = [], []
    while len(values) < n:
        c = int(rng.integers(1, 2**40)) | 1
        m = int(rng.integers(1, 25))
        digits = len(str(c * 5**m))  # the significant digits of c * 2^-m = c * 5^m / 10^m
        precision = digits - 1
        if 1 <= precision <= MAX_PRECISION:
            values.append(c * 2.0**-m)
            precisions.append(precision)
    return np.array(values), np.array(precisions)


def test_exact_ties_round_half_to_even():
    """An exact half at the last digit rounds to the even digit, as Python's % does. Every
    exact tie lies within the margin of a half and is formatted by Python's % itself, so what
    this catches is a tie that is not (no margin: the scaled double rounded half up gives
    "1234567891"; rint's own half to even gets these ties right, their scaled doubles being
    exact) and a text put in place for the cells left to Python that is not Python's
    rounding of the exact value (one ulp off). A half-up rounding of the scaled double alone,
    with the margin in place, changes no cell: there is no tie outside the margin."""
    assert _texts([1234567890.5, 1234567891.5, -1234567890.5], 10) == [
        "1234567890",
        "1234567892",
        "-1234567890",
    ]
    assert _texts([0.125, 0.375, 2.5, 3.5], 2) == ["0.12", "0.38", "2.5", "3.5"]
    assert _texts([0.125, 0.375, 2.5, 3.5], 1) == ["0.1", "0.4", "2", "4"]
    assert _texts([9999999999.5, 9999999998.5], 10) == ["1e+10", "9999999998"]
    rng = np.random.default_rng(31)
    values, precisions = _exact_ties(rng, 3000)
    for precision in np.unique(precisions).tolist():
        tied = values[precisions == precision]
        # the tie itself, and its neighbours one ulp away (no longer ties: they round away)
        near = np.concatenate([tied, np.nextafter(tied, 0), np.nextafter(tied, np.inf)])
        assert _mismatches(np.concatenate([near, -near]), precision) == [], precision


def test_near_halves_over_the_whole_range_at_every_precision():
    """Doubles nearest the decimal halves "k5e(p-N)" (k of N digits) and their neighbours up
    to 40 ulps either side, p over 10^-320..10^300 (the two-step scaling), every precision N,
    both signs: Python's text. These are the cells whose rounding the margin leaves to Python:
    the scaled double ``y`` is within ~4 u 10^N of the exact value, so a rint of ``y`` within
    that of a half may round the wrong way. Most k are drawn from the top tenth of the N-digit
    numbers, where ``y`` is nearest 10^N and its error largest: a margin of 2 u 10^N instead
    of 8 gives wrong cells here at several precisions."""
    rng = np.random.default_rng(29)
    offsets = np.arange(-40, 41)
    for precision in range(1, MAX_PRECISION + 1):
        low, high = 10 ** (precision - 1), 10**precision
        k = np.concatenate(
            [rng.integers(low, high, 100), rng.integers(high - max(1, low), high, 300)]
        )
        p = rng.integers(-320, 300, k.size)
        decimals = [f"{a}5e{b - precision}" for a, b in zip(k.tolist(), p.tolist(), strict=True)]
        halves = np.array([float(d) for d in decimals])
        halves = halves[np.isfinite(halves) & (halves > 0)]
        near = (halves.view(np.int64)[:, None] + offsets).reshape(-1).view(np.float64)
        assert _mismatches(np.concatenate([near, -near]), precision) == [], precision


def test_values_that_round_up_to_the_next_power_of_ten():
    """9.99...95 rounds to 10^k: one digit more before the point, or the next exponent."""
    values = np.array(
        [
            9.9999999995e-5,
            9.9999999995e-6,
            999999999.95,
            9999999999.5,
            99999.999995,
            0.99999999995,
            9.9999999995,
            9.9999999995e22,
            9.9999999995e-300,
        ]
    )
    near = np.concatenate([values, np.nextafter(values, 0), np.nextafter(values, np.inf)])
    assert _mismatches(np.concatenate([near, -near]), 10) == []
    assert _texts([999999999.95, 9.99999999996e-5], 10) == ["1000000000", "0.0001"]


@pytest.mark.parametrize("precision", [1, 6, 10, 13])
def test_the_switch_between_fixed_and_exponential_notation(precision):
    """%g writes d.ddde-05 below 10^-4 and from 10^N on: the switch points and their
    neighbours by one ulp, both signs."""
    points = np.array([1e-5, 1e-4, 1e-3, 1.0, 10.0 ** (precision - 1), 10.0**precision, 1e9, 1e10])
    near = np.concatenate([points, np.nextafter(points, 0), np.nextafter(points, np.inf)])
    assert _mismatches(np.concatenate([near, -near]), precision) == []
    assert _texts([1e-4, 1e-5], precision) == ["0.0001", "1e-05"]


def test_powers_of_ten_and_their_neighbours_over_the_whole_range():
    """Where log10 misjudges the decimal exponent (next to 10^k), and the two-step scaling
    (|k| > 22): every power of ten a double holds, and one ulp either side."""
    powers = np.array([float(f"1e{k}") for k in range(-323, 309)])
    near = np.concatenate([powers, np.nextafter(powers, 0), np.nextafter(powers, np.inf)])
    for precision in (1, 10, 13):
        assert _mismatches(near, precision) == [], precision


def test_the_formats_formatted_here():
    assert g_precision("%.10g") == 10
    assert g_precision("%g") == 6  # Python's default precision
    assert g_precision("%.0g") == 1  # as Python's %: "%.0g" % 123.0 is "1e+02"
    assert g_precision("%.13g") == 13
    for other in ("%.14g", "%.17g", "%10.3g", "%+.3g", "%#.5g", "%.3e", "%.3f", "%.3g mm", None):
        assert g_precision(other) is None, other
    assert _texts([123.0, 0.5], g_precision("%.0g")) == ["1e+02", "0.5"]  # Python's %.0g


def test_a_precision_in_other_digits_than_ascii_is_not_formatted_here():
    """``%`` reads a precision in ASCII digits only: "%.\u0661\u0660g" (Arabic-Indic 10) is
    not "%.10g" (Python's ``%`` refuses it)."""
    arabic_ten = "%.\u0661\u0660g"
    assert g_precision(arabic_ten) is None
    assert g_precision("%.\uff11g") is None  # a fullwidth 1
    with pytest.raises(ValueError):
        _ = arabic_ten % 1.5


def test_the_digit_tables_are_the_digits_as_text():
    """The tables of four digits made by arithmetic are the text of each number written
    small here with Python strings: every digit, leading zeros NUL (0 as nothing, or "0"),
    trailing zeros NUL, the count of trailing zeros; and read-only."""
    from contactres import _decimal_text as dt

    def words(texts):
        return np.frombuffer("".join(texts).encode(), dtype="<u4")

    four = [f"{i:04d}" for i in range(10_000)]
    stripped = [t.lstrip("0") for t in four]
    assert np.array_equal(dt._FOUR, words(four))
    assert np.array_equal(dt._LEADING, words(four + [t.rjust(4, "\0") for t in stripped]))
    last = [(t or "0").rjust(4, "\0") for t in stripped]
    assert np.array_equal(dt._LEADING_LAST, words(four + last))
    trailing = [t.rstrip("0").ljust(4, "\0") for t in four]
    assert np.array_equal(dt._TRAILING, words(four + trailing))
    assert dt._TRAILING_ZEROS.tolist() == [len(t) - len(t.rstrip("0")) for t in four]
    assert dt._POWERS_INT.tolist() == [10**k for k in range(19)]
    for table in (dt._FOUR, dt._LEADING, dt._TRAILING, dt._TRAILING_ZEROS, dt._POWERS):
        assert not table.flags.writeable


def test_an_empty_array_and_one_of_only_special_values():
    assert g_records(np.array([]), 10).shape[0] == 0
    assert _texts([np.nan, 0.0, -np.inf], 10, b"") == ["", "0", "-inf"]


def test_an_exponent_guess_that_stays_wrong_leaves_the_cell_to_python(monkeypatch):
    """The decimal exponent from log10 is corrected by one a step, three steps at most: a
    guess still wrong after them (never seen from log10) gives Python's own text, not a wrong
    one."""
    from contactres import _decimal_text

    guess = _decimal_text._exponent_guess
    values = np.array([1.5, -2.5e-7, 3.25e12, 123456.789, 1e300])
    monkeypatch.setattr(_decimal_text, "_exponent_guess", lambda a: guess(a) + 2)
    assert _mismatches(values, 10) == []  # two steps away: corrected
    monkeypatch.setattr(_decimal_text, "_exponent_guess", lambda a: guess(a) - 5)
    assert _mismatches(values, 10) == []  # five away: still off after three steps


@pytest.mark.parametrize("width", [0, 1, 3, 8, 17, 40])
def test_rows_taken_as_whole_elements_are_numpys_rows(width):
    """take_rows gives numpy's own row indexing, for any width, repeated and unordered rows,
    no rows, and a view whose rows are not contiguous (then numpy's indexing itself)."""
    rng = np.random.default_rng(width)
    records = rng.integers(0, 256, (50, width), dtype=np.uint8)
    rows = rng.integers(0, 50, 300)
    for r in (rows, rows[:0], np.arange(50)[::-1]):
        got = take_rows(records, r)
        assert got.shape == records[r].shape and np.array_equal(got, records[r])
    wide = rng.integers(0, 256, (50, 2 * width + 5), dtype=np.uint8)
    # rows apart in memory; and bytes apart within a row (review R30c: the first alone is
    # taken right by the void view too, so that no test reached the guard)
    for view in (wide[:, 2 : 2 + width], wide[:, ::2][:, :width]):
        assert np.array_equal(take_rows(view, rows), view[rows])
    # another dtype, a mask, a 2-d index: numpy's indexing, not bytes taken as rows
    other = rng.integers(0, 9, (4, width)).astype(np.int32)
    assert np.array_equal(take_rows(other, np.array([3, 0])), other[[3, 0]])
    mask = np.array([True, False, True, False])
    assert np.array_equal(take_rows(records[:4], mask), records[:4][mask])
    two = np.array([[1, 2], [0, 3]])
    assert np.array_equal(take_rows(records, two), records[two])
