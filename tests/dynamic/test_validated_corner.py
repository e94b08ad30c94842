"""The corner of the validated range where the resolutions miss rtol (found by review R26b):
A < 0.25 with ν > 0.44 (_convergence.VALIDATED_CORNER), where TP has a narrow feature near
k_l a = 1.95 that the coarse grid misses by 2.3e-4 at rtol = 1e-4 (9e-7 of 1e-6 at the
default). The public functions must check it at run time there (checked_values).

Reference: TP on a kernel table with every resolution of the rtol's grid doubled (the measure of
resolution_for's docstring), and for rtol = 1e-4 also the default grid doubled (far finer).
"""

import warnings

import numpy as np
import pytest

from contactres import Material
from contactres.dynamic import dcsf, shear_wavenumber_ratio
from contactres.dynamic._convergence import in_validated_range
from contactres.dynamic._normal_stiffness import evaluate_models
from contactres.dynamic._table import kernel_table, resolution_for
from contactres.errors import AccuracyWarning

CORNER = Material.cubic_from_ratios(0.2000001, 0.4499999)


@pytest.mark.parametrize(
    ("zener", "poisson", "inside"),
    [
        (0.2000001, 0.4499999, False),  # the reproducer of R26b
        (0.2, 0.4401, False),
        (0.2499, 0.45, False),
        (0.2000001, 0.4399999, True),  # the edges kept: measured within rtol/10 and 3e-8
        (0.2500001, 0.4499999, True),
    ],
)
def test_the_corner_is_left_out_of_the_validated_range(zener, poisson, inside):
    m = Material.cubic_from_ratios(zener, poisson)
    assert in_validated_range(m, np.array([1.0 * shear_wavenumber_ratio(m)])) is inside


@pytest.mark.parametrize(("rtol", "loss"), [(1e-4, 0.02), (1e-4, 0.01), (1e-6, 0.01)])
def test_tp_at_the_corner_meets_rtol_or_says_so(rtol, loss):
    """R26b's reproducer: dcsf(..., "TP", rtol) against every resolution doubled, within rtol
    (before: 2.3e-4 and 2.7e-4 at rtol 1e-4, silently)."""
    kla = np.array([1.94, 1.945, 1.95, 1.955, 1.96])
    ksa = kla * shear_wavenumber_ratio(CORNER)
    refs = [resolution_for(rtol).doubled()]
    if rtol >= 1e-4:
        refs.append(resolution_for(1e-6).doubled())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = dcsf(CORNER, kla, "TP", loss=loss, rtol=rtol)
    assert not [w for w in caught if issubclass(w.category, AccuracyWarning)]
    for res in refs:
        ref = evaluate_models(kernel_table(CORNER, loss, res), ksa, ["TP"], 1e-8)["TP"]
        assert np.max(np.abs(got / ref - 1)) <= rtol


@pytest.mark.parametrize("rtol", [1e-4, 1e-6])
def test_sa_near_its_pole_meets_rtol_or_says_so(rtol):
    """Inside the validated range SA has a pole near k_l a = 1.2677 on A = 0.2, ν = 0.25
    (lossless; ``|SA|`` ~ 3700): there its relative error is that of N, which grows like
    ``|DCSF|`` (1.8e-4 at rtol = 1e-4 before the values beyond POLE_DCSF were checked). Against
    every resolution doubled: within rtol, or an AccuracyWarning."""
    m = Material.cubic_from_ratios(0.2000001, 0.25)
    kla = np.linspace(1.266, 1.2695, 8)
    ksa = kla * shear_wavenumber_ratio(m)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = dcsf(m, kla, "SA", rtol=rtol)
    ref = evaluate_models(kernel_table(m, 0.0, resolution_for(rtol).doubled()), ksa, ["SA"], 1e-8)
    assert np.max(np.abs(ref["SA"])) > 1000  # the pole is sampled
    err = np.abs(got / ref["SA"] - 1)
    warned = [w for w in caught if issubclass(w.category, AccuracyWarning)]
    assert np.max(err) <= rtol or warned
