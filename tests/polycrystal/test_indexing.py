"""Which pixels of an EBSD map are used: indexed, confident enough, of the chosen phase."""

from __future__ import annotations

import numpy as np
import pytest

from contactres.polycrystal import MIN_CI, OrientationMap, indexed_pixels


def _map(phase, confidence, name):
    phase = np.asarray(phase)
    return OrientationMap(
        euler=np.zeros((*phase.shape, 3)),
        step_x=1e-6,
        step_y=1e-6,
        phase=phase,
        confidence=np.asarray(confidence, dtype=float),
        confidence_name=name,
        source="m.ang" if name == "CI" else "m.ctf",
    )


def test_ang_rules_by_confidence_index():
    m = _map([[0, 0, 0, 0]], [[-1.0, 0.05, MIN_CI, 0.9]], "CI")  # a single-phase .ang: id 0
    p = indexed_pixels(m)
    assert p.mask.tolist() == [[False, False, True, True]]
    assert (p.not_indexed, p.low_confidence, p.other_phase) == (1, 1, 0)
    assert p.summary() == (
        "2 of 4 pixels left out: 1 not indexed, 1 below the confidence rule (CI >= 0.1)"
    )
    assert indexed_pixels(m, min_confidence=0.0).mask.tolist() == [[False, True, True, True]]


def test_ctf_rules_by_phase_zero_and_an_optional_mad_limit():
    m = _map([[0, 1, 1, 1]], [[0.0, 0.4, 1.2, 2.5]], "MAD (degrees)")
    assert indexed_pixels(m).mask.tolist() == [[False, True, True, True]]
    p = indexed_pixels(m, max_mad=1.5)
    assert p.mask.tolist() == [[False, True, True, False]] and p.rule == "phase != 0, MAD <= 1.5°"


def test_several_phases_need_a_choice_and_a_missing_phase_is_named():
    m = _map([[1, 2, 2, 0]], [[0.5, 0.5, 0.5, -1.0]], "CI")
    with pytest.raises(ValueError, match=r"m.ang holds phases 1, 2: choose"):
        indexed_pixels(m)
    p = indexed_pixels(m, phase=2)
    assert p.mask.tolist() == [[False, True, True, False]] and p.other_phase == 1
    with pytest.raises(ValueError, match=r"no indexed pixel of phase 7; its phases are 1, 2"):
        indexed_pixels(m, phase=7)


def test_a_map_with_no_usable_pixel_is_an_error_and_synthetic_maps_keep_all():
    with pytest.raises(ValueError, match=r"no pixel is usable \(CI >= 0.1\)"):
        indexed_pixels(_map([[0, 0]], [[-1.0, 0.01]], "CI"))
    p = indexed_pixels(_map([[1, 1]], [[1.0, 1.0]], "confidence"))
    assert p.mask.all() and p.left_out == 0 and p.summary().startswith("all 2 pixels used")
    with pytest.raises(ValueError, match="min_confidence"):
        indexed_pixels(_map([[1]], [[1.0]], "CI"), min_confidence=float("nan"))
