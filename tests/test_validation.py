"""Tests of contactres.validation: one ValueError naming the parameter, unit and offending value."""

import numpy as np
import pytest

from contactres.validation import amplitude, nonnegative, positive


def test_values_pass_through_as_floats():
    assert positive("R", 2) == 2.0 and isinstance(positive("R", 2), float)
    np.testing.assert_array_equal(nonnegative("F", [0, 1.5]), [0.0, 1.5])
    # a complex number with zero imaginary part is a real number
    assert positive("R", np.complex128(3.0)) == 3.0


@pytest.mark.parametrize(
    "check, value, match",
    [
        (positive, 0.0, r"radius must be finite and > 0 \(m\), got 0.0"),
        (positive, [1.0, -2.0], r"radius .* got -2.0 at index 1"),
        (nonnegative, [[0.0, 1.0], [np.nan, 2.0]], r"radius .*>= 0 .* at index \(1, 0\)"),
        (positive, np.inf, "radius must be finite"),
        # not silently cast: text, ragged lists, and complex values (numpy would drop Im)
        (positive, "1 mm", r"radius must be a real number .* got '1 mm'"),
        (positive, [1.0, [2.0]], "radius must be a real number"),
        (positive, np.array([1.0 + 0.5j]), "radius must be a real number"),
        (nonnegative, 1j, "radius must be a real number"),
    ],
)
def test_bad_values_are_named(check, value, match):
    with pytest.raises(ValueError, match=match):
        check("radius", value, "m")


def test_amplitude_is_always_a_float_array():
    a = amplitude(2)
    assert isinstance(a, np.ndarray) and a.shape == () and a.dtype == float and a == 2.0
    np.testing.assert_array_equal(amplitude([0, 1e-9]), [0.0, 1e-9])
    with pytest.raises(ValueError, match=r"amplitude u0 must be finite and >= 0 \(m\), got -1e-09"):
        amplitude(-1e-9)
