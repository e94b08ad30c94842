"""``prepare_tangential(ksa_max=...)`` refuses what the table cannot stand for, in one line.

Before: a NaN, a negative value or one beyond :data:`contactres.dynamic.KSA_MAX` was accepted
silently (a NaN gave a table with ``ksa_max`` NaN; 50 a table claiming harmonics no convergence
test covers). Bounds: [0, KSA_MAX] (0 is what a curve at k_s a = 0 alone asks).
"""

from __future__ import annotations

import math

import pytest

from contactres import Material
from contactres.dynamic import KSA_MAX, prepare_tangential
from contactres.errors import ContactresInputError


def _solid() -> Material:
    return Material.isotropic(70e9, 0.3, 2700.0)


@pytest.mark.parametrize(
    "bad", [math.nan, math.inf, -0.5, KSA_MAX * (1 + 1e-12), 50.0, "two", None]
)
def test_a_bad_ksa_max_is_refused_in_one_line_naming_it(bad):
    with pytest.raises(ContactresInputError, match="ksa_max") as err:
        prepare_tangential(_solid(), rtol=1e-3, ksa_max=bad)
    assert "\n" not in str(err.value)


def test_the_ends_of_the_range_are_accepted():
    m = _solid()
    # 0 (a curve at k_s a = 0 only) gets the default table, up to 2.
    assert prepare_tangential(m, rtol=1e-3, ksa_max=0.0).ksa_max == 2.0
    assert prepare_tangential(m, rtol=1e-3, ksa_max=KSA_MAX).ksa_max == KSA_MAX
