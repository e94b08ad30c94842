"""The moduli rows fit_ratios keeps between evaluations (contactres.polycrystal._ratio_fit).

fit_ratios keeps the rows of its last evaluation on the grains, keyed by the bits of the
ratios, and computes only the rows it lacks. Every row the fit stacks (kept or fresh) must be
the row a single indentation_moduli call gives for its own crystal and face; the spies below
see the fresh rows (moduli_and_points), the crystals (unit_material) and every stack
the model uses (np.stack, the module's only one), without changing a bit of the fit.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from contactres import Material
from contactres.polycrystal import _ratio_fit
from contactres.polycrystal._inverse import CUBIC
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._orientations import random_orientations

CU = Material.cubic(168.4e9, 121.4e9, 75.4e9)


class _StackSpy:
    """numpy as seen by _ratio_fit, with np.stack recording a copy of what it returns."""

    def __init__(self) -> None:
        self.stacks: list[np.ndarray] = []

    def __getattr__(self, name: str) -> Any:
        return getattr(np, name)

    def stack(self, arrays, *args, **kwargs) -> np.ndarray:
        out = np.stack(arrays, *args, **kwargs)
        self.stacks.append(out.copy())
        return out


def test_every_row_the_fit_uses_is_its_own_crystals_fresh_row(monkeypatch):
    R = random_orientations(6, seed=3)
    m = indentation_moduli(CU, R)
    made: list[tuple[Material, np.ndarray]] = []  # each unit crystal and its ratios

    def unit(ratios: np.ndarray) -> Material:
        mat = CUBIC.unit_material(ratios)
        made.append((mat, np.array(ratios, dtype=float)))
        return mat

    fresh: list[tuple[list[Material], np.ndarray, np.ndarray]] = []
    real = _ratio_fit.moduli_and_points
    asked: list[int | None] = []  # the θ points each call evaluated up front

    def spy(units, orient, rtol, first_points=None):
        out, points = real(units, orient, rtol, first_points)
        assert rtol == _ratio_fit.MODULUS_RTOL
        fresh.append((list(units), np.array(orient), out.copy()))
        asked.append(first_points)
        return out, points

    numpy_spy = _StackSpy()
    monkeypatch.setattr(_ratio_fit, "moduli_and_points", spy)
    monkeypatch.setattr(_ratio_fit, "np", numpy_spy)
    param = dataclasses.replace(CUBIC, unit_material=unit)
    fit = _ratio_fit.fit_ratios(
        param, R, m, 1e-4 * m, quantity="modulus", guess={"c12_c11": 0.65, "c44_c11": 0.5}
    )
    monkeypatch.undo()
    assert fit.success and fit.n_evaluations > 2

    # Which crystal and face each computed row belongs to, by its bits; every fresh row is
    # the bits of its own indentation_moduli call on that face.
    ratios_of = {id(mat): r for mat, r in made}
    owner: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
    for units, orient, rows in fresh:
        for mat, row in zip(units, rows, strict=True):
            single = indentation_moduli(mat, orient, rtol=_ratio_fit.MODULUS_RTOL)
            np.testing.assert_array_equal(row, single)
            owner[row.tobytes()] = (ratios_of[id(mat)], orient)

    # Each stack the model used: row 0 at the ratios r0, rows 1 + 2j and 2 + 2j at
    # r0 exp(±LOG_STEP e_j), all on one face; a row handed to another crystal breaks the
    # pattern, a row of the grains handed to the reference face (eye) breaks the face.
    faces: list[int] = []
    for stack in numpy_spy.stacks:
        owners = [owner[row.tobytes()] for row in stack]
        r0, face = owners[0]
        faces.append(face.shape[0])
        for i, (r, f) in enumerate(owners):
            np.testing.assert_array_equal(f, face)
            step = np.zeros(r0.size)
            if i:
                step[(i - 1) // 2] = _ratio_fit.LOG_STEP * (1 if i % 2 else -1)
            np.testing.assert_allclose(np.log(r / r0), step, rtol=0, atol=1e-12)
    # The last stack is the summary's reference face, one grain with the crystal z axis up.
    assert faces[-1] == 1 and set(faces[:-1]) == {len(R)}
    np.testing.assert_array_equal(owner[numpy_spy.stacks[-1][0].tobytes()][1], np.eye(3)[None])
    # The memo acted: the stacks on the grains used more rows than were computed for them.
    used = sum(s.shape[0] for s in numpy_spy.stacks if s.shape[1] == len(R))
    computed = sum(rows.shape[0] for _, orient, rows in fresh if orient.shape[0] == len(R))
    assert used > computed
    # After the first rows on the grains, the fit asks for the points its rows needed (Cu: 64),
    # and every row above is still its own call's bits.
    assert asked[0] is None and 64 in asked
