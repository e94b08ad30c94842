"""Tests of contactres.resonators._cantilever_inversion: round trips forward -> inverse for every
model (normal, tilt, lateral + tilt, damped, two modes, both normalisations) and the flags."""

import numpy as np
import pytest

from contactres.resonators._cantilever import FREE_ROOTS, Cantilever, contact_frequencies
from contactres.resonators._cantilever_inversion import (
    FLAG_ABOVE_PINNED,
    FLAG_BELOW_FREE,
    FLAG_INCONSISTENT_MODES,
    FLAG_INSENSITIVE,
    FLAG_NO_CONTACT,
    FLAG_NOT_MEASURED,
    FLAG_NOT_POSITIVE,
    FLAG_SEVERAL_CROSSINGS,
    MIN_SENSITIVITY,
    flag_names,
    invert_contact_resonance,
)

KAPPA = np.array([0.3, 3.0, 30.0, 300.0, 3000.0])
GLOBAL = Cantilever((1.0e5, 6.3e5, 17.4e5), 10.0)
MODEWISE = Cantilever((1.0e5, 6.3e5, 17.4e5), 10.0, normalisation="modewise")
SPRINGS = [
    {},
    {"tilt": 11.0},
    {"lateral_ratio": 0.8, "tip_height": 0.05, "tilt": 12.0},
    {"lateral_ratio": 0.5, "tip_height": 0.03},
]


@pytest.mark.parametrize("lever", [GLOBAL, MODEWISE])
@pytest.mark.parametrize("springs", SPRINGS)
def test_round_trip_tip_position_known(lever, springs):
    f = contact_frequencies(lever, KAPPA, 0.9, **springs)
    res = invert_contact_resonance(lever, f, 0.9, **springs)
    assert np.max(np.abs(res.kappa_modes / KAPPA[:, None] - 1)) < 1e-8  # measured <= 1e-9
    assert np.array_equal(res.k_star, res.kappa * 10.0, equal_nan=True)
    assert np.all(np.isnan(res.kappa) | (np.abs(res.kappa / KAPPA - 1) < 1e-8))
    assert res.normalisation == lever.normalisation
    assert np.all(np.isnan(res.sigma))


@pytest.mark.parametrize("lever", [GLOBAL, MODEWISE])
@pytest.mark.parametrize("springs", SPRINGS[:3])
def test_round_trip_two_modes(lever, springs):
    r = np.array([0.7, 0.85, 0.95, 1.0])[:, None]
    f = contact_frequencies(lever, KAPPA[None, :4], r, modes=(1, 2), **springs)
    res = invert_contact_resonance(lever, f, **springs)
    # The true r is always one of the crossings, with its κ ...
    hit = np.abs(res.candidates - r[..., None]) < 1e-9
    assert np.all(hit.sum(-1) == 1)
    k_hit = np.where(hit, res.candidate_kappa, 0.0).sum(-1)
    assert np.max(np.abs(k_hit / KAPPA[:4] - 1)) < 1e-8
    # ... and the chosen one is the largest in [0.5, 1]: right for r >= 0.85 here; at r = 0.7
    # a second crossing near 0.88 exists (measured), so the pixel is flagged as ambiguous.
    win = np.where((res.candidates >= 0.5) & (res.candidates <= 1), res.candidates, -1)
    assert np.array_equal(res.tip_position, win.max(-1))
    assert np.max(np.abs(res.tip_position[1:] - r[1:])) < 1e-9
    assert np.max(np.abs(res.kappa[1:] / KAPPA[:4] - 1)) < 1e-8
    assert np.all(res.flags[0] & FLAG_SEVERAL_CROSSINGS)
    several = np.sum((res.candidates >= 0.5) & (res.candidates <= 1), -1) > 1
    assert np.array_equal(several, (res.flags & FLAG_SEVERAL_CROSSINGS) != 0)


def test_damped_round_trip_and_lossless_contact_gives_zero_sigma():
    lever = Cantilever((1.0e5, 6.3e5, 17.4e5), 10.0, "modewise", free_q_factors=(200, 300, 400))
    kappa = KAPPA * (1 + 0.05j)
    for springs in SPRINGS[:3]:
        f = contact_frequencies(lever, kappa, 0.9, **springs)
        q = f.real / (2 * f.imag)
        res = invert_contact_resonance(lever, f.real, 0.9, q_factors=q, **springs)
        # κ_c = κ′ + iκ″ at ω(1 + i/(2Q)) is the Kelvin-Voigt contact k* + iωσ at that complex
        # ω: its spring is κ′ + κ″/(2Q) (test_cantilever_damping.py checks it independently)
        spring = KAPPA[:, None] * (1 + 0.05 / (2 * q))
        assert np.max(np.abs(res.kappa_modes / spring - 1)) < 1e-8
        sigma = 10.0 * 0.05 * KAPPA[:, None] / (2 * np.pi * f.real)
        assert np.max(np.abs(res.sigma_modes / sigma - 1)) < 1e-7
        f0 = contact_frequencies(lever, KAPPA, 0.9, **springs)  # lossless contact
        res0 = invert_contact_resonance(lever, f0.real, 0.9, q_factors=f0.real / (2 * f0.imag))
        if not springs:
            assert np.max(np.abs(res0.sigma_modes) / (10.0 / (2 * np.pi * f0.real))) < 1e-9


def test_global_and_modewise_differ_for_a_real_lever():
    f = contact_frequencies(MODEWISE, 30.0, 0.9)
    assert abs(invert_contact_resonance(MODEWISE, f, 0.9).kappa / 30.0 - 1) < 1e-9
    assert abs(invert_contact_resonance(GLOBAL, f, 0.9).kappa_modes[1] / 30.0 - 1) > 1e-3


def test_flags():
    f1 = 1e5
    pinned_1 = f1 * (3.9266 / FREE_ROOTS[0]) ** 2
    f = np.array([[0.99 * f1], [1.01 * pinned_1], [np.nan], [1.00001 * f1], [1.3 * f1]])
    res = invert_contact_resonance(GLOBAL, f, 1.0)
    assert res.flags[0] & FLAG_BELOW_FREE and res.flags[0] & FLAG_NOT_POSITIVE
    assert res.kappa[0] < 0 or np.isnan(res.kappa[0])
    assert res.flags[1] & FLAG_ABOVE_PINNED and np.isnan(res.kappa[1])
    assert res.flags[2] & FLAG_NOT_MEASURED
    # 1e-5 above the free frequency, beyond FREE_TOLERANCE (1e-6): κ ~ 1e-5, a contact that
    # barely shifts the mode
    assert res.flags[3] & FLAG_INSENSITIVE and not res.flags[3] & FLAG_NO_CONTACT
    assert res.flags[4] == 0 and flag_names(res.flags[4]) == []
    assert flag_names(FLAG_ABOVE_PINNED | FLAG_NOT_POSITIVE) == ["not_positive", "above_pinned"]


def test_node_of_mode_is_insensitive():
    # Mode 2 of the free lever has a node at ξ ≈ 0.774: a tip there hardly moves f2 (measured
    # d ln f / d ln κ = 6e-5 at κ = 3), while at the free end the same contact gives 0.04.
    r = np.array([0.774, 1.0])
    f = contact_frequencies(GLOBAL, 3.0, r, modes=(2,))
    res = invert_contact_resonance(GLOBAL, f, r, modes=(2,))
    assert res.flags[0] & FLAG_INSENSITIVE and res.flags[1] == 0


def test_insensitive_flag_where_the_sensitivity_is_below_the_line():
    # s = d ln f / d ln κ = 2κ/(β dκ/dβ) written here from the forward model alone: a relative
    # step of 1e-4 in κ and the two resonances it gives (no inverse involved). Pixels across
    # modes 1-3, tips from 0.5 to 1 and κ from 1e-5 to 1e5 (saturation, nodes, the free lever);
    # the flag must be set exactly where s < MIN_SENSITIVITY, away from the line itself.
    rng = np.random.default_rng(11)
    kappa = 10.0 ** rng.uniform(-5.0, 5.0, 3000)
    r = rng.uniform(0.5, 1.0, 3000)
    f = contact_frequencies(GLOBAL, kappa, r)
    up = contact_frequencies(GLOBAL, kappa * (1 + 1e-4), r)
    down = contact_frequencies(GLOBAL, kappa * (1 - 1e-4), r)
    s = np.log(up / down) / np.log((1 + 1e-4) / (1 - 1e-4))
    for damped in (False, True):
        # a Q of 1e8: the closed form at a complex β, the same contact (the damping is nil)
        q = np.full(f.shape, 1e8) if damped else None
        res = invert_contact_resonance(GLOBAL, f, r, q_factors=q)
        clear = np.isfinite(res.kappa_modes) & (np.abs(s / MIN_SENSITIVITY - 1.0) > 1e-2)
        clear &= res.flags_modes != FLAG_NO_CONTACT  # κ < 1e-6-ish: the free lever, κ = 0
        assert clear.sum() > 6000 and (s[clear] < MIN_SENSITIVITY).sum() > 500
        weak = (res.flags_modes & FLAG_INSENSITIVE) != 0
        assert np.array_equal(weak[clear], s[clear] < MIN_SENSITIVITY)


def test_a_damped_mode_at_its_free_root_is_flagged_and_left_out():
    # A pixel of the forward model at k* = 0.277 N/m (κ = 0.0277 at r = 0.718) with 1e-4
    # frequency noise and measured Q's (a reviewer's probe of 20 000 such pixels): mode 2's
    # Re β lands 5.4e-7 above its free root, where its κ is the damping's alone (κ ≈ 5.5 + 27i).
    # It must be flagged and left out of k*; a closed-form slope alone missed it (k* = 31 N/m).
    f = np.array([[100500.38836404978, 626609.2891110958, 1754939.2675117375]])
    q = np.array([[238.40215019817356, 22.02922002056324, 155.1198631084366]])
    res = invert_contact_resonance(GLOBAL, f, 0.718390828771496, q_factors=q)
    assert res.flags_modes[0, 1] & FLAG_INSENSITIVE
    assert abs(res.k_star[0] / 0.277 - 1.0) < 0.03


def test_shapes_broadcast_over_pixels():
    f = contact_frequencies(GLOBAL, np.full((3, 4), 20.0), 0.9, modes=(1,))
    res = invert_contact_resonance(GLOBAL, f, np.full((3, 4), 0.9))
    assert res.kappa.shape == (3, 4) and res.flags.shape == (3, 4)
    assert np.allclose(res.kappa, 20.0, rtol=1e-9)


def test_validation():
    with pytest.raises(ValueError, match="frequencies"):
        invert_contact_resonance(GLOBAL, [[-1.0]], 0.9)
    with pytest.raises(ValueError, match="tip_position"):
        invert_contact_resonance(GLOBAL, [[1.2e5]], 1.5)
    with pytest.raises(ValueError, match="two measured modes"):
        invert_contact_resonance(GLOBAL, [[1.2e5]])


def test_a_third_mode_rejects_the_spurious_crossing_of_the_first_two():
    # At r = 0.7 modes 1 and 2 also cross near r = 0.88 (above): the two-mode rule takes the
    # larger r and flags the pixel; mode 3 measured too picks the true crossing, unflagged.
    kappa = KAPPA[1:4]
    f = contact_frequencies(GLOBAL, kappa, 0.7, modes=(1, 2, 3))
    two = invert_contact_resonance(GLOBAL, f[:, :2])
    assert np.all(np.abs(two.tip_position - 0.7) > 0.1)
    assert np.all(two.flags & FLAG_SEVERAL_CROSSINGS)
    three = invert_contact_resonance(GLOBAL, f)
    assert np.max(np.abs(three.tip_position - 0.7)) < 1e-9
    assert np.max(np.abs(three.kappa / kappa - 1)) < 1e-8
    assert np.all(three.flags == 0)
    assert np.all(three.mode_spread < 1e-9)  # exact data: the modes agree
    assert np.all(np.isnan(two.mode_spread))  # two modes, r solved: nothing left to check


def test_mode_spread_is_the_third_modes_own_kappa_and_flags_beyond_the_tolerance():
    kappa = np.array([3.0, 30.0, 300.0])
    f = contact_frequencies(GLOBAL, kappa, 0.9, modes=(1, 2, 3))
    f[:, 2] *= 1.002  # a 0.2 % error in mode 3 only
    # Independent of the check: mode 3 alone inverted at r = 0.9 (and modes 1-2 alone).
    k3 = invert_contact_resonance(GLOBAL, f[:, 2:], 0.9, modes=(3,)).kappa
    k12 = invert_contact_resonance(GLOBAL, f[:, :2], 0.9).kappa
    res = invert_contact_resonance(GLOBAL, f, 0.9)
    mean = (2 * k12 + k3) / 3
    expected = np.abs(k3 - k12) / mean  # the relative range of the per-mode κ
    assert np.max(np.abs(res.mode_spread / expected - 1)) < 1e-9
    flagged = (res.flags & FLAG_INCONSISTENT_MODES) != 0
    assert np.array_equal(flagged, expected > 0.05) and flagged.any() and not flagged.all()
    loose = invert_contact_resonance(GLOBAL, f, 0.9, mode_tolerance=10.0)
    assert not np.any(loose.flags & FLAG_INCONSISTENT_MODES)
    single = invert_contact_resonance(GLOBAL, f[:, :1], 0.9)
    assert np.all(np.isnan(single.mode_spread))  # one mode: no check
    with pytest.raises(ValueError, match="mode_tolerance"):
        invert_contact_resonance(GLOBAL, f, 0.9, mode_tolerance=0)


def test_a_third_mode_above_its_pinned_limit_contradicts_the_crossing():
    # A crossing built explicitly: modes 1 and 2 of one contact (κ = 300 at r = 0.8, a clean
    # sign change of κ_a - κ_b, the only crossing of the pair), and a mode 3 measured 10 % above
    # its pinned limit at that r (the κ -> ∞ limit of the forward model), which no κ > 0 gives.
    # That r is contradicted, not unchecked: flagged, with an infinite spread (found by review:
    # such a crossing was returned unflagged). Built this way the outcome does not depend on
    # where the scan's grid points fall (the earlier version relied on the scan missing a
    # crossing of a saturated mode, which it finds on some machines).
    r0, kappa0 = 0.8, 300.0
    f = contact_frequencies(GLOBAL, np.array([kappa0]), r0, modes=(1, 2, 3))
    pinned_3 = contact_frequencies(GLOBAL, np.array([1e11]), r0, modes=(3,))[0, 0]
    free_4 = 1e5 * (FREE_ROOTS[3] / FREE_ROOTS[0]) ** 2
    f[0, 2] = 1.1 * pinned_3
    assert f[0, 2] < free_4  # still on mode 3's side of the free mode 4
    # Independent of the check: mode 3 alone at r0 is above its pinned limit.
    alone = invert_contact_resonance(GLOBAL, f[:, 2:], r0, modes=(3,))
    assert alone.flags[0] & FLAG_ABOVE_PINNED
    res = invert_contact_resonance(GLOBAL, f)
    assert abs(res.tip_position[0] - r0) < 1e-9 and abs(res.kappa[0] / kappa0 - 1) < 1e-8
    assert np.array_equal(res.flags_modes[0, :2], [0, 0])  # the crossing itself is sound
    assert res.flags_modes[0, 2] & FLAG_ABOVE_PINNED
    assert res.flags[0] & FLAG_INCONSISTENT_MODES and np.isinf(res.mode_spread[0])


def test_the_mean_over_eight_modes_is_numpys_pairwise_sum():
    # From 8 terms numpy's sum runs by pairs (eight partial sums), not in order: the inversion's
    # mean over 8 averaged modes must still be numpy's, bit for bit (review R24a: 266 of 2,000
    # pixels differed in their last bits when the modes were added in order). 500 pixels
    # suffice: with the 8 modes added in order, 77 of them differ (measured).
    lever = Cantilever((1.0e5,), 10.0)
    modes = tuple(range(1, 9))
    rng = np.random.default_rng(3)
    f = contact_frequencies(lever, np.geomspace(0.05, 5e3, 500), 0.9, modes=modes)
    f = f * (1.0 + 1e-4 * rng.standard_normal(f.shape))
    res = invert_contact_resonance(lever, f, 0.9, modes=modes, mode_tolerance=1.0)
    use = res.averaged_modes
    n = use.sum(axis=-1)
    assert n.max() == 8
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(use, res.kappa_modes, 0.0).sum(axis=-1) / np.maximum(n, 1)
    assert np.array_equal(res.kappa, np.where(n > 0, mean, np.nan), equal_nan=True)


@pytest.mark.parametrize("q", [None, 80.0])
def test_mean_spread_and_flags_over_the_modes_are_numpys_reductions(q):
    # κ, σ, the spread and the flags of a pixel are reductions over its modes; the inversion
    # runs them a mode at a time: the numbers must be those of numpy's reductions over the
    # last axis, bit for bit (three modes, cells not measured, one mode off, no contact).
    rng = np.random.default_rng(11)
    f = contact_frequencies(GLOBAL, np.geomspace(0.05, 5e3, 400), 0.9)
    f = f * (1.0 + 1e-3 * rng.standard_normal(f.shape))  # modes that disagree (flagged)
    f[rng.random(f.shape) < 0.2] = np.nan
    f[:40, 0] = GLOBAL.free_frequencies[0]  # no contact: κ = 0, a value
    qs = None if q is None else np.full(f.shape, q)
    res = invert_contact_resonance(GLOBAL, f, 0.9, q_factors=qs, mode_tolerance=1e-4)
    use = res.averaged_modes
    n = use.sum(axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(use, res.kappa_modes, 0.0).sum(axis=-1) / np.maximum(n, 1)
        sigma = np.where(use, res.sigma_modes, 0.0).sum(axis=-1) / np.maximum(n, 1)
    assert np.array_equal(res.kappa, np.where(n > 0, mean, np.nan), equal_nan=True)
    if q is not None:
        assert np.array_equal(res.sigma, np.where(n > 0, sigma, np.nan), equal_nan=True)
    check = use & (n > 1)[:, None]
    hi = np.maximum(np.max(np.where(check, res.kappa_modes, -np.inf), axis=-1), res.kappa)
    lo = np.minimum(np.min(np.where(check, res.kappa_modes, np.inf), axis=-1), res.kappa)
    with np.errstate(invalid="ignore"):
        spread = np.where(check.any(axis=-1), (hi - lo) / res.kappa, np.nan)
    assert np.array_equal(res.mode_spread, spread, equal_nan=True)
    assert (res.mode_spread > 1e-4).any() and (n > 1).any() and (n == 0).any()
    measured = ~np.isnan(f)
    joined = np.bitwise_or.reduce(np.where(measured, res.flags_modes, 0), axis=-1)
    joined[~measured.any(axis=-1)] = FLAG_NOT_MEASURED | FLAG_NOT_POSITIVE
    joined |= np.where(spread > 1e-4, FLAG_INCONSISTENT_MODES, 0)
    assert np.array_equal(res.flags, joined)


def test_the_interval_test_of_the_sensitivity_flags_is_numpys_search():
    """The edge band about a free root compares a point with the two roots about the interval
    of its neighbour; numpy's binary search (``searchsorted``, NaN above every root) is the
    second algorithm, on points at, just beside and between the roots, at 0, ±inf and NaN."""
    from contactres.resonators import _cantilever_inversion as inversion

    rng = np.random.default_rng(8)
    at = np.concatenate([FREE_ROOTS, np.nextafter(FREE_ROOTS, 0), np.nextafter(FREE_ROOTS, 99)])
    points = np.concatenate(
        [at, rng.uniform(-2, FREE_ROOTS[-1] + 5, 300), [0.0, -0.0, np.inf, -np.inf, np.nan]]
    )
    b, x = (a.ravel() for a in np.meshgrid(points, points))
    n0 = np.searchsorted(FREE_ROOTS, b)
    expected = np.searchsorted(FREE_ROOTS, x) != n0
    assert 0 < expected.sum() < expected.size
    np.testing.assert_array_equal(inversion._left_interval(n0, x), expected)
    hi, lo = b * (1.0 + 1e-6), b * (1.0 - 1e-6)  # the flags' own use: the band about b
    np.testing.assert_array_equal(
        inversion._left_interval(n0, hi, lo),
        (np.searchsorted(FREE_ROOTS, hi) != n0) | (np.searchsorted(FREE_ROOTS, lo) != n0),
    )
