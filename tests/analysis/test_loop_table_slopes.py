"""The loop tables' slopes d1, d2 against central differences of the forward model.

The tables' x joins a uniform grid and a finer one; where two of their points fell one
rounding apart (x = 0.9 in the Cattaneo-Mindlin table, 1.4 in Savkoor's), ``np.gradient``
gave slopes of 0 and -1 there instead of -0.21 and -0.48, and every point interpolated beside
them a wrong column of the fits' Jacobian (so wrong errors). Reference: K′/κ and (K″ - ωξ)/κ of
:func:`contactres.shifts_from_loop` (paper 2, Eqs. 4-6, the package's Masing quadrature) at
x ± h, independent of the tables.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import (
    QCM,
    CattaneoMindlinLoop,
    SavkoorLoop,
    shifts_from_loop,
    shifts_from_stiffness,
)
from contactres.analysis._loops import (
    cm_loop_table,
    interpolate_table,
    savkoor_loop_table,
    table_interpolant,
)

CASES = {
    "cattaneo-mindlin": (
        cm_loop_table,
        CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0),
        1.5,
    ),
    "savkoor": (savkoor_loop_table, SavkoorLoop(kappa=1.0, tau=1.0, a=0.5), 1.0),
}


def _shapes(loop, x):
    q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    p = float(np.asarray(shifts_from_stiffness(q, 1.0, 0.0, 1)[0]))
    df, dg = shifts_from_loop(q, loop, x, 1)
    return np.asarray(df, float) / p, np.asarray(dg, float) / p


@pytest.mark.parametrize("name", CASES)
def test_the_slopes_follow_the_forward_model_where_the_grids_meet(name):
    make, loop, slip = CASES[name]
    table = make()
    # Where the grids meet (0.9, 1.4), and a spread of points away from full sliding, whose
    # square-root singularity a central difference cannot follow.
    spread = np.linspace(0.05, 5.0, 40)
    spread = spread[np.abs(spread - slip) > 0.05]
    x = np.concatenate(
        [0.9 + np.linspace(-2e-3, 2e-3, 9), 1.4 + np.linspace(-2e-3, 2e-3, 9), spread]
    )
    h = 1e-5
    up, down = _shapes(loop, x + h), _shapes(loop, x - h)
    d1, d2 = interpolate_table(table_interpolant(table), x, ("d1", "d2"))
    for got, hi, lo in ((d1, up[0], down[0]), (d2, up[1], down[1])):
        want = (hi - lo) / (2 * h)
        # Second-order slopes interpolated linearly err by ~h²·d″/8 on the table's steps:
        # measured <= 3e-6 away from full sliding (a first-order difference errs by 4.7e-4 and
        # fails this; the fault was 0.2-0.5).
        np.testing.assert_allclose(got, want, atol=5e-5)


@pytest.mark.parametrize("name", CASES)
def test_no_two_points_of_a_table_are_a_rounding_apart(name):
    x = CASES[name][0]().x
    assert np.all(np.diff(x) > 1e-12 * np.maximum(x[1:], 1.0))
