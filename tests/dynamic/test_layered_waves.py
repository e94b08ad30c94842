"""The layer waves tabulated in the slowness (contactres.dynamic._layered_waves) and the nodes
of the layered correction built from them for many frequencies at once (_layered_path).

Anchors: the public stack_compliance (the layer recursion solved directly at every wavenumber,
its own tests against a global boundary-value solve), and the layered punch with the table
switched off (every node solved directly).
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import LayeredMaterial, Material
from contactres.dynamic import _layered_nodes, _layered_path, _layered_waves
from contactres.dynamic._layered_path import film_reference, stack_at, stack_of
from contactres.dynamic._layered_punch import layered_punch_stiffness
from contactres.dynamic._layered_waves import (
    chebyshev_matrix,
    chebyshev_values,
    slowness_table,
    waves_at,
)
from contactres.errors import ContactresInputError
from contactres.layered import compliance_factors, stack_compliance

QUARTZ = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
PMMA = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
CU111 = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0, name="Cu").rotated((1, 1, 1))
A = 5e-6


def _stack(material, f, inplane=False):
    mats, hs = stack_of(material, f)
    film, q = film_reference(mats[0])
    return stack_at(mats, hs, film, q, f, inplane)


def _direct(st, eta, theta):
    """H of the stack (and of the film's reference half-space) by stack_compliance at real
    wavenumbers ``eta`` × directions ``theta``: the layer recursion at every point."""
    e = eta[:, None] * np.ones_like(theta)[None, :]
    th = np.broadcast_to(theta[None, :], e.shape)
    s = [sig * st.omega**2 / e**2 for sig in st.sigma]
    H = stack_compliance(st.tensors, s, [e * h for h in st.thicknesses], th)
    H_ref = stack_compliance([st.reference], s[:1], [], th)
    return H, H_ref


@pytest.mark.parametrize(
    ("material", "theta"),
    [
        (LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)]), np.zeros(1)),
        (LayeredMaterial(PMMA, [(QUARTZ.with_loss(1e-3), 0.3 * A)]), np.zeros(1)),
        (LayeredMaterial(QUARTZ, [(CU111, 0.3 * A), (PMMA, 0.1 * A)]), np.linspace(0, 3, 5)),
    ],
    ids=["soft-on-stiff", "lossy-stiff-on-soft", "cubic-111-two-layers"],
)
def test_slowness_table_gives_the_direct_solution_at_any_frequency(material, theta):
    """One table (built at one frequency) serves every frequency: the kernel difference from
    interpolated waves equals the direct recursion beyond the poles (measured: < 1e-13)."""
    st0 = _stack(material, 1e6)
    table = slowness_table(st0, theta)
    assert table is not None
    shift = st0.static_shift(theta)
    for f in (2e5, 3e7, 1.1e8):
        st = _stack(material, f)
        eta = st.pole * np.array([1.0, 1.37, 2.9, 11.0, 150.0])
        y = (st.pole / eta) ** 2
        waves = table.interpolated(chebyshev_matrix(table.size, 2 * y - 1))
        eta_h = [eta * h for h in st.thicknesses]
        got = waves.delta_g(st, eta_h, shift)
        # With the directions: the isotropic layers' exponentials in closed form.
        closed = waves.delta_g(st, eta_h, shift, theta)
        H, H_ref = _direct(st, eta, theta)
        want = H_ref[..., 2, 2] - H[..., 2, 2] - shift[None]
        scale = np.max(np.abs(H_ref[..., 2, 2]))
        assert np.max(np.abs(got - want)) < 1e-12 * scale
        assert np.max(np.abs(closed - want)) < 1e-12 * scale


def test_waves_at_complex_slowness_give_the_direct_solution():
    """On the lifted arc (complex η) the waves solved once per slowness reproduce the direct
    recursion at the arc of any frequency (measured: < 1e-14)."""
    material = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)])
    theta = np.zeros(1)
    for f in (3e6, 4e7):
        st = _stack(material, f)
        tau = np.linspace(0.05, 0.95, 7)
        z = _layered_waves.arc_fraction(tau)
        eta = st.pole * z
        waves = waves_at(st, theta, 1 / (st.pole_slowness * z) ** 2)
        eta_h = [eta * h for h in st.thicknesses]
        got = waves.delta_g(st, eta_h, st.static_shift(theta))
        closed = waves.delta_g(st, eta_h, st.static_shift(theta), theta)
        e = eta[:, None]
        s = [sig * st.omega**2 / e**2 for sig in st.sigma]
        H = stack_compliance(st.tensors, s, [e * h for h in st.thicknesses], np.zeros((7, 1)))
        H_ref = stack_compliance([st.reference], s[:1], [], np.zeros((7, 1)))
        want = H_ref[..., 2, 2] - H[..., 2, 2] - st.static_shift(theta)[None]
        assert np.max(np.abs(got - want)) < 1e-12 * np.max(np.abs(H_ref[..., 2, 2]))
        assert np.max(np.abs(closed - want)) < 1e-12 * np.max(np.abs(H_ref[..., 2, 2]))


def test_a_refused_table_solves_every_node_directly(monkeypatch):
    """Without the table (as for a stack it would not reach round-off on) the punch is the
    same to the table's accuracy (measured: < 1e-12), normal and tangential."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)])
    f = np.array([0.0, 2e6, 3e7])
    normal = layered_punch_stiffness(stack, A, f)
    tangential = layered_punch_stiffness(stack, A, f[1:], direction="tangential")
    monkeypatch.setattr(_layered_path, "slowness_table", lambda st, theta: None)
    assert np.max(np.abs(layered_punch_stiffness(stack, A, f) / normal - 1)) < 1e-11
    again = layered_punch_stiffness(stack, A, f[1:], direction="tangential")
    assert np.max(np.abs(again / tangential - 1)) < 1e-11


def test_many_frequencies_at_once_equal_one_at_a_time(monkeypatch):
    """The nodes of all frequencies are built and solved together (in chunks); each point's
    nodes are the ones it gets in a chunk of its own (measured: < 1e-14)."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.1 * A)])
    f = np.array([0.0, 1e6, 2e7, 5e7])
    together = layered_punch_stiffness(stack, A, f)
    monkeypatch.setattr(_layered_path, "_NODE_BUDGET", 1)
    np.testing.assert_allclose(layered_punch_stiffness(stack, A, f), together, rtol=1e-13)


def test_nodes_assembled_in_groups_equal_one_point_at_a_time(monkeypatch):
    """The real nodes of several points are assembled together (one panel search and one
    interpolation of Δg per group); a group of one point (``_GROUP_NODES`` = 1) gives the same
    punch to the bit, statics, a second layer and the tangential punch included. The
    tangential punch of a stack with an anisotropic film assembles each frequency's points on
    their own (nothing to group), so its case has two isotropic films."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A), (CU111, 0.1 * A)])
    cu = Material.isotropic(130e9, 0.34, density=8960.0, name="Cu isotropic")
    films = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A), (cu, 0.1 * A)])
    f = np.array([0.0, 1e6, 2e7, 5e7, 9e7])
    assemble = _layered_path.assemble_nodes
    points: list[int] = []

    def counted(res, rule, pts, shift):
        points.append(len(pts))
        return assemble(res, rule, pts, shift)

    monkeypatch.setattr(_layered_path, "assemble_nodes", counted)
    normal = layered_punch_stiffness(stack, A, f)
    assert max(points) > 1  # several points to a call: the grouping is exercised
    points.clear()
    tangential = layered_punch_stiffness(films, A, f[1:], direction="tangential")
    assert max(points) > 1
    monkeypatch.setattr(_layered_nodes, "_GROUP_NODES", 1)
    assert np.array_equal(layered_punch_stiffness(stack, A, f), normal)
    again = layered_punch_stiffness(films, A, f[1:], direction="tangential")
    assert np.array_equal(again, tangential)


def test_panel_search_is_searchsorted_of_each_run():
    """The panel of each value in its own run of edges (geometric or not) is numpy's
    searchsorted of that run, less one, clipped to the run's panels; values on an edge, below
    the first and beyond the last included."""
    rng = np.random.default_rng(7)
    runs = [1.3 * 1.5 ** np.arange(9), np.cumsum(rng.uniform(0.1, 2.0, 6)), np.array([0.5, 4.0])]
    values, want, lo, hi = [], [], [], []
    first = np.cumsum([r.size for r in runs]) - [r.size for r in runs]
    for r, f0 in zip(runs, first, strict=True):
        v = np.concatenate([rng.uniform(0.5 * r[0], 1.5 * r[-1], 40), r, [r[0] / 3, 3 * r[-1]]])
        values.append(v)
        want.append(f0 + np.clip(np.searchsorted(r, v) - 1, 0, r.size - 2))
        lo.append(np.full(v.size, f0))
        hi.append(np.full(v.size, f0 + r.size - 2))
    edges, v = np.concatenate(runs), np.concatenate(values)
    got = _layered_nodes.panel_search(
        v, np.log(v), edges, np.log(edges), *map(np.concatenate, (lo, hi))
    )
    np.testing.assert_array_equal(got, np.concatenate(want))


def test_chebyshev_matrix_interpolates_polynomials_exactly():
    """The barycentric rows reproduce a polynomial of degree n − 1 from its n samples."""
    n = 9
    xc = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    coef = np.arange(1.0, n + 1)
    x = np.array([-1.0, -0.3, xc[2], 0.77, 1.0])
    got = chebyshev_matrix(n, x) @ np.polynomial.polynomial.polyval(xc, coef)
    np.testing.assert_allclose(got, np.polynomial.polynomial.polyval(x, coef), rtol=1e-13)


@pytest.mark.parametrize(
    ("shape", "axis"), [((10, 6), 0), ((6, 10), 1), ((2, 3, 10), 2), ((2, 3, 10), -1)]
)
def test_split_at_gives_the_views_np_split_gives(shape, axis):
    """The points' pieces cut by slicing are np.split's pieces (empty ones included), views
    of the same memory, along any axis."""
    a = np.arange(float(np.prod(shape))).reshape(shape)
    cuts = np.array([0, 3, 3, 7, 10])
    got = _layered_nodes.split_at(a, cuts, axis=axis)
    want = np.split(a, cuts, axis=axis)
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        assert g.shape == w.shape and np.array_equal(g, w)
        assert g.size == 0 or np.shares_memory(g, a)


def test_chebyshev_values_interpolate_each_nodes_own_polynomial():
    """Each node's value is that of the polynomial through its own row of samples (degree
    n − 1, complex, with a trailing axis), a node on a sample point and the ends included, and
    with rows shared by several nodes."""
    n = 7
    xc = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    x = np.array([-1.0, -0.41, xc[4], 0.2, 1.0])
    coef = np.arange(1.0, 2 * n * x.size + 1).reshape(x.size, 2, n) * (1 - 0.5j)
    poly = np.polynomial.polynomial.polyval
    # Node k's samples (n, 2) and value (2,) of the polynomials coef[k, r] (r = 0, 1).
    samples = np.stack([[[poly(v, c) for c in ck] for v in xc] for ck in coef])
    got = chebyshev_values(x, samples)
    want = np.array([[poly(v, c) for c in ck] for v, ck in zip(x, coef, strict=True)])
    np.testing.assert_allclose(got, want, rtol=1e-13)
    # Rows shared by several nodes (``rows``): node k reads row rows[k].
    rows = np.array([4, 0, 4, 2, 1, 3, 0])
    xs = np.linspace(-1.0, 1.0, rows.size)
    want = np.array([[poly(v, c) for c in coef[r]] for v, r in zip(xs, rows, strict=True)])
    np.testing.assert_allclose(chebyshev_values(xs, samples, rows), want, rtol=1e-13)


@pytest.mark.parametrize("eta_h", [0.5, np.inf])
def test_the_probes_beyond_the_decay_of_the_film_change_nothing(monkeypatch, eta_h):
    """The edges beyond η h₁ = 50 under a film that is its own reference are probed only where
    Δg has not decayed yet: probing every edge (η h₁ = ∞) or stopping at 0.5 (where Δg has not
    decayed, so the rest is probed after all) gives the same punch (measured: < 1e-15)."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)])
    f = np.array([0.0, 2e6, 3e7])
    want = layered_punch_stiffness(stack, A, f)
    monkeypatch.setattr(_layered_path, "_PROBE_ETA_H", eta_h)
    np.testing.assert_allclose(layered_punch_stiffness(stack, A, f), want, rtol=1e-13)


def test_a_film_beyond_the_nodes_reach_is_refused():
    """A film so thin (h/a = 1e-7) that Δg has not decayed by η a = 1e6 is refused with the
    reason, not integrated on a truncated path."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 1e-7 * A)])
    with pytest.raises(ContactresInputError, match="out of reach"):
        layered_punch_stiffness(stack, A, 1e6)


def test_panel_waves_are_each_points_own_interpolation():
    """The waves at the real samples of the geometric panels, interpolated once for points of
    every frequency (y = (S₁/s)² is the same sequence at each), equal each point's waves
    interpolated at its own samples s (``real_all``) to round-off, on a film over a substrate
    and under a second layer."""
    res = _layered_nodes.PunchResolution()
    xc = np.cos(np.pi * (np.arange(res.n_cheb) + 0.5) / res.n_cheb)
    u = np.arange(9) * np.log(res.ratio)
    uc = (0.5 * (u[:-1, None] + u[1:, None]) + 0.5 * (u[1:, None] - u[:-1, None]) * xc).ravel()
    for stack in (
        LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)]),
        LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A), (CU111, 0.1 * A)]),
    ):
        stacks = [_stack(stack, f) for f in (1e6, 2e7, 9e7)]
        theta = np.linspace(0.0, np.pi, 4, endpoint=False)
        shared = _layered_path._SharedWaves(stacks[0], theta, res, stacks)
        counts = [96, 24, 60]
        items = [
            (st, A, st.pole * A * np.exp(uc[:n])) for st, n in zip(stacks, counts, strict=True)
        ]
        got = shared.panel_waves(counts, res.ratio, res.n_cheb).arrays()
        want = shared.real_all(items).arrays()
        for g, w in zip(got, want, strict=True):
            assert np.max(np.abs(g - w)) <= 1e-13 * np.max(np.abs(w))


# Stacks of isotropic layers the sagittal recursion serves: a film (its own reference) and two
# lossy layers.
SAGITTAL_STACKS = [
    LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)]),
    LayeredMaterial(PMMA, [(QUARTZ.with_loss(1e-3), 0.3 * A), (PMMA, 0.1 * A)]),
]


@pytest.mark.parametrize(
    "material",
    SAGITTAL_STACKS,
    ids=["film", "two-lossy-layers"],
)
def test_the_sagittal_recursion_is_the_three_by_three_one(monkeypatch, material):
    """Isotropic layers of an axisymmetric stack at θ = 0: H_33 from the 2x2 recursion on the
    sagittal block equals the 3x3 recursion (compliance_factors with the same closed-form
    exponentials, H = P Q⁻¹ by numpy) to round-off on the real axis, on the lifted arc and in
    statics; the layer recursion of stack_compliance (general exponentials) agrees to 1e-12;
    off θ = 0 the 3x3 recursion serves."""
    theta = np.zeros(1)
    for f in (0.0, 3e6, 4e7):
        st = _stack(material, f)
        if f > 0:
            eta = st.pole * np.concatenate(
                [[1.0, 1.9, 7.0, 60.0], _layered_waves.arc_fraction(np.linspace(0.05, 0.95, 5))]
            )
        else:
            eta = np.array([0.3, 2.0, 11.0]) / A
        waves = waves_at(st, theta, st.omega**2 / eta**2)
        eta_h = [eta * h for h in st.thicknesses]
        shift = st.static_shift(theta)
        sagittal = waves.delta_g(st, eta_h, shift, theta)
        # The 3x3 recursion with the same closed-form exponentials, H = P Q⁻¹ by numpy.
        layers = [(w.reshape(4, 3, 3, -1), m) for w, m in waves.layers]
        eh = [np.asarray(x, dtype=complex) for x in eta_h]
        zeros = [np.zeros(eta.size)] * len(layers)
        P, Q = compliance_factors(layers, eh, waves.substrate.reshape(3, 3, -1), zeros)
        H3 = np.moveaxis(P, -1, 0) @ np.linalg.inv(np.moveaxis(Q, -1, 0))
        ref = np.linalg.inv(np.moveaxis(waves.reference.reshape(3, 3, -1), -1, 0))
        general = (ref[:, 2, 2] - H3[:, 2, 2])[:, None] - shift[None]
        e = eta[:, None]
        s = [sig * st.omega**2 / e**2 for sig in st.sigma]
        th = np.zeros(e.shape)
        H = stack_compliance(st.tensors, s, [e * h for h in st.thicknesses], th)
        H_ref = stack_compliance([st.reference], s[:1], [], th)
        scale = np.max(np.abs(H_ref[..., 2, 2]))
        # Round-off of the largest |Δg| (~14 under quartz layers; measured: < 6e-15).
        assert np.max(np.abs(sagittal - general)) < 1e-13 * np.max(np.abs(general))
        want = H_ref[..., 2, 2] - H[..., 2, 2] - shift[None]
        assert np.max(np.abs(sagittal - want)) < 1e-12 * scale
    # A direction off θ = 0 keeps the 3x3 recursion.
    monkeypatch.setattr(_layered_waves, "sagittal_h33", _sagittal_refused)
    off = waves.delta_g(st, eta_h, shift, theta + 0.3)
    assert np.all(np.isfinite(off))


def _sagittal_refused(*args):
    raise AssertionError("the sagittal recursion must not serve off θ = 0")


@pytest.mark.parametrize(
    "static_at", [None, 0, 1, 3], ids=["all-dynamic", "first", "middle", "last"]
)
def test_edge_waves_are_each_points_own_interpolation(static_at):
    """The waves at the panel edges e_i = S₁ ratio^i, interpolated once for every dynamic point
    (y = ratio^(−2i) at each) and cut into each point's rows lo..hi − 1, equal each point's own
    interpolation (``real_all``) to round-off; a static point (f = 0) among them, first, in the
    middle or last, takes the static waves in its place (review R22a)."""
    res = _layered_nodes.PunchResolution()
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.05 * A)])
    freqs = [1e6, 2e7, 9e7, 4e7]
    if static_at is not None:
        freqs[static_at] = 0.0
    stacks = [_stack(stack, f) for f in freqs]
    theta = np.linspace(0.0, np.pi, 4, endpoint=False)
    shared = _layered_path._SharedWaves(stacks[0], theta, res, stacks)
    ranges = [(0, 7), (2, 9), (0, 3), (4, 12)]
    scale = [st.pole if st.omega > 0 else 1.0 for st in stacks]
    items = [
        (st, A, p * A * res.ratio ** np.arange(lo, hi, dtype=float))
        for st, p, (lo, hi) in zip(stacks, scale, ranges, strict=True)
    ]
    got = shared.edge_waves(items, ranges, res.ratio).arrays()
    want = shared.real_all(items).arrays()
    for g, w in zip(got, want, strict=True):
        assert g.shape == w.shape
        assert np.max(np.abs(g - w)) <= 1e-13 * np.max(np.abs(w))


@pytest.mark.parametrize(
    "material",
    SAGITTAL_STACKS,
    ids=["film-own-reference", "two-lossy-layers"],
)
def test_the_sagittal_form_gives_the_direct_solution(material):
    """The sagittal form of the waves (the {x, z} rows alone, kept by the normal punch's sets
    of isotropic layers at θ = 0): Δg solved directly, interpolated from the slowness table,
    joined and sliced, equals stack_compliance's at every node (to 1e-12 of the largest
    ``|H_ref|``, as the 3x3 recursion's test above), and the 3x3 arrays' own Δg to the bit
    where no interpolation is involved (the same arithmetic on the same numbers; a misplaced
    row or sign is off by O(1))."""
    theta = np.zeros(1)
    res = _layered_nodes.PunchResolution()
    for f in (0.0, 3e6, 4e7):
        st = _stack(material, f)
        shift = st.static_shift(theta)
        shared = _layered_path._SharedWaves(st, theta, res, [st])
        assert shared.sagittal
        if f > 0:
            eta = st.pole * np.array([1.0, 1.3, 1.9, 7.0, 60.0])
        else:
            eta = np.array([0.3, 2.0, 11.0]) / A
        eta_h = [eta * h for h in st.thicknesses]
        full = waves_at(st, theta, st.omega**2 / eta**2)
        red = full.sagittal_form()
        assert red.sagittal and red.size == eta.size
        got = red.delta_g(st, eta_h, shift, theta)
        assert np.array_equal(got, full.delta_g(st, eta_h, shift, theta))
        H, H_ref = _direct(st, eta, theta)
        want = H_ref[..., 2, 2] - H[..., 2, 2] - shift[None]
        scale = np.max(np.abs(H_ref[..., 2, 2]))
        assert np.max(np.abs(got - want)) < 1e-12 * scale
        if f == 0:
            continue
        # From the table, in the set's form (as _SharedWaves keeps it), joined with the
        # direct ones and sliced back out: the same values node by node.
        assert shared.table is not None and shared.table.sagittal
        y = (st.pole / eta) ** 2
        inter = shared.table.interpolated(chebyshev_matrix(shared.table.size, 2 * y - 1))
        both = _layered_waves.StackWaves.combined([red, inter, red])
        n = eta.size
        values = both.delta_g(st, [np.tile(e, 3) for e in eta_h], shift, theta)
        assert np.array_equal(values[:n], got) and np.array_equal(values[2 * n :], got)
        assert np.max(np.abs(values[n : 2 * n] - want)) < 1e-12 * scale
        middle = both._with([w[..., n : 2 * n, :] for w in both.arrays()])
        assert np.array_equal(middle.delta_g(st, eta_h, shift, theta), values[n : 2 * n])
    # Off θ = 0, and for the in-plane kernel, the sets keep the 3x3 arrays.
    st = _stack(material, 3e6)
    assert not _layered_path._SharedWaves(st, np.full(1, 0.4), res, [st]).sagittal
    st = _stack(material, 3e6, inplane=True)
    assert not _layered_path._SharedWaves(st, theta, res, [st]).sagittal


def test_a_stack_made_or_replaced_with_other_materials_has_its_own_key():
    """A stack's grouping key (the stacks of one key share their layer waves) is its material
    set's: formed from its own fields whether made by stack_at, by hand, or replaced with other
    materials; kept across frequencies (review R31e: a key given or kept from another set
    grouped two sets' stacks, and Δg of the second was 3 % off)."""
    import dataclasses

    from contactres.dynamic._layered_path import Stack

    glass = Material.isotropic(160e9, 0.22, density=2330.0)

    def at(h, f, sub=QUARTZ):
        mats, hs = stack_of(LayeredMaterial(sub, [(PMMA, h)]), f)
        film, q = film_reference(mats[0])
        return stack_at(mats, hs, film, q, f, False, {})

    s1, s2 = at(250e-9, 2e7), at(1e-6, 2e7, glass)
    assert s1.key != s2.key and at(250e-9, 3e7).key == s1.key
    init = [f.name for f in dataclasses.fields(Stack) if f.init]
    by_hand = Stack(**{name: getattr(s2, name) for name in init})
    assert by_hand.key == s2.key and by_hand.needs_correction == s2.needs_correction
    other = {n: getattr(s2, n) for n in ("tensors", "sigma", "thicknesses", "pole_slowness")}
    assert dataclasses.replace(s1, **other).key == s2.key
    # Independent of the key's recipe: the stacks of two sets give each its own Δg, as each
    # solved alone does.
    res = _layered_nodes.punch_resolution(1e-6)
    theta = np.zeros(1)
    from contactres.dynamic._table import prepare

    gref = float(np.max(np.abs(prepare(film_reference(PMMA)[0], 0.0, 1e-6).ginf)))
    pair = _layered_path.correction_nodes([s1, by_hand], np.array([A, A]), theta, res, gref)
    alone = _layered_path.correction_nodes([s2], np.array([A]), theta, res, gref)
    np.testing.assert_allclose(pair[1].delta_g, alone[0].delta_g, rtol=1e-12, atol=0)
