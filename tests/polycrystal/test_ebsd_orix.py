""".ang/.ctf files round-trip with orix, the field's EBSD library, as the independent peer.

contactres writes, orix (``orix.io.load``) reads, and the reverse; the orientations are compared
as misorientation angles with the crystal symmetry (orix's ``Orientation.angle_with``), to
1e-6 rad. The convention is checked against orix, not against contactres: orix's
``Rotation.from_euler`` (Bunge, "lab2crystal", passive) gives the orientation matrix g of
Rowenhorst et al. (2015), and contactres' surface matrix is R = gᵀ (:mod:`.orientations`).

The IPF key against orix's TSL key (orix.plot.DirectionColorKeyTSL) is here too: the same
corner colours, a different construction inside the triangle. Every test that uses
orix lives in this one module, and imports it only when run (see ``_orix``), so that one
pytest-xdist worker (``--dist loadfile``) loads orix's numba functions.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres.polycrystal import (
    EbsdPhase,
    OrientationMap,
    ebsd_phase,
    indexed_pixels,
    ipf_colors,
    random_orientations,
    read_ang,
    read_ctf,
    symmetry_operators,
    write_ang,
    write_ctf,
)
from contactres.polycrystal._synthetic import synthetic_polycrystal

# orix is imported when this module's tests run, not when pytest collects it: every test worker
# collects every module, and orix compiles numba functions into a shared cache on its first
# import (two workers doing so at once crashed a fresh CI run with a segmentation fault).
io = CrystalMap = Phase = PhaseList = DirectionColorKeyTSL = None
Orientation = Rotation = symmetry = Vector3d = None


@pytest.fixture(scope="module", autouse=True)
def _orix():
    """The orix names this module's tests use (skipped with a reason without orix)."""
    global io, CrystalMap, Phase, PhaseList, DirectionColorKeyTSL
    global Orientation, Rotation, symmetry, Vector3d
    pytest.importorskip("orix", reason="orix (the `peers` extra) is the round-trip peer")
    from orix import io
    from orix.crystal_map import CrystalMap, Phase, PhaseList
    from orix.plot import DirectionColorKeyTSL
    from orix.quaternion import Orientation, Rotation, symmetry
    from orix.vector import Vector3d


TOL = 1e-6  # rad
POINT_GROUP = {"cubic": "Oh", "hexagonal": "D6h"}  # orix.quaternion.symmetry names


def _misorientation(xmap, m: OrientationMap, lattice: str, seed: int = 0) -> np.ndarray:
    """orix's symmetry-reduced angle between the orientations orix read and those of ``m`` (by
    pixel position), with ``m``'s matrices replaced by random symmetric equivalents R·S so that
    the comparison needs the symmetry."""
    i = np.rint(xmap.y / (m.step_y * 1e6)).astype(int)
    j = np.rint(xmap.x / (m.step_x * 1e6)).astype(int)
    R = m.surface_matrices()[i, j]
    S = symmetry_operators(lattice)
    R = R @ S[np.random.default_rng(seed).integers(len(S), size=len(R))]
    pg = getattr(symmetry, POINT_GROUP[lattice])
    ours = Orientation.from_matrix(np.swapaxes(R, -1, -2), symmetry=pg)
    return Orientation(xmap.rotations, symmetry=pg).angle_with(ours)


def test_the_euler_convention_is_orix_s_passive_bunge():
    e = np.random.default_rng(3).uniform([0, 0, 0], [2 * np.pi, np.pi, 2 * np.pi], (50, 3))
    from contactres.polycrystal import surface_matrices_from_euler

    R = surface_matrices_from_euler(e[:, 0], e[:, 1], e[:, 2], degrees=False)
    g = Rotation.from_euler(e).to_matrix()  # lab2crystal: v_crystal = g @ v_sample
    assert np.allclose(np.swapaxes(R, -1, -2), g, rtol=0, atol=1e-12)


@pytest.mark.parametrize(("writer", "suffix"), [(write_ang, "ang"), (write_ctf, "ctf")])
def test_orix_reads_what_contactres_writes(tmp_path, writer, suffix):
    m = synthetic_polycrystal((9, 13), n_grains=5, seed=5, pixel_size=0.5e-6)
    xmap = io.load(writer(tmp_path / f"ni.{suffix}", m, ebsd_phase("Ni")))
    assert xmap.shape == m.shape and (xmap.dx, xmap.dy) == (0.5, 0.5)  # µm
    assert xmap.phases[1].name == "Ni"
    assert np.allclose(xmap.phases[1].structure.lattice.abcABG(), [3.524] * 3 + [90] * 3)
    if suffix == "ctf":  # the .ang header has no space group
        assert xmap.phases[1].space_group.number == 225
    assert float(_misorientation(xmap, m, "cubic").max()) < TOL


def test_orix_reads_a_hexagonal_phase_with_its_symmetry(tmp_path):
    H, W = 4, 6
    R = random_orientations(H * W, seed=11).reshape(H, W, 3, 3)
    from contactres.polycrystal import euler_from_surface_matrices

    e = euler_from_surface_matrices(R, degrees=False)
    m = OrientationMap(e, 1e-6, 2e-6, np.ones((H, W)), np.full((H, W), 0.8), "CI")
    ti = EbsdPhase("Ti", "hexagonal", 2.95, 4.68, 194)
    for writer in (write_ang, write_ctf):
        xmap = io.load(writer(tmp_path / f"ti.{writer.__name__[-3:]}", m, ti))
        assert xmap.phases[1].point_group.laue.name == "6/mmm"
        assert np.allclose(
            xmap.phases[1].structure.lattice.abcABG(), [2.95, 2.95, 4.68, 90, 90, 120]
        )
        assert float(_misorientation(xmap, m, "hexagonal", seed=2).max()) < TOL


def _orix_map(tmp_path, not_indexed: np.ndarray):
    """An orix CrystalMap of random Cu orientations (5 x 7, steps 1.5 x 0.5 µm), saved by orix."""
    H, W = not_indexed.shape
    y, x = np.mgrid[0:H, 0:W]
    # Seeded (uniform random rotations): orix's angle_with goes through an arccos near 1 and
    # reached 1e-5 to 3e-5 rad on 3 of 640 unseeded maps, where an atan2 misorientation of the
    # same pixels is below 1e-15 rad: the peer's rounding, not the reader, so not left to chance.
    q = np.random.default_rng(17).normal(size=(H * W, 4))
    rot = Rotation(q / np.linalg.norm(q, axis=1, keepdims=True))
    ids = np.where(not_indexed.ravel(), -1, 1)
    cu = Phase("Cu", point_group="m-3m")
    xmap = CrystalMap(
        rot, phase_id=ids, x=x.ravel() * 1.5, y=y.ravel() * 0.5,
        phase_list=PhaseList(cu), prop={"ci": np.full(H * W, 0.9)}, scan_unit="um",
    )  # fmt: skip
    path = tmp_path / "orix.ang"
    io.save(path, xmap)
    return path, xmap


def test_contactres_reads_what_orix_writes(tmp_path):
    holes = np.zeros((5, 7), dtype=bool)
    holes[2, 3] = holes[4, 0] = True
    path, original = _orix_map(tmp_path, holes)
    m = read_ang(path)
    assert m.shape == (5, 7) and (m.step_x, m.step_y) == pytest.approx((1.5e-6, 0.5e-6), rel=1e-12)
    used = indexed_pixels(m)
    assert np.array_equal(~used.mask, holes) and used.not_indexed == 2
    # Same file, two readers: the same orientations to 1e-6 rad.
    xmap = io.load(path)
    angles = _misorientation(xmap[xmap.is_indexed], m, "cubic")
    assert float(angles.max()) < TOL
    # orix's writer rounds the angles to 1e-5 rad: against the map orix wrote, that is all.
    angles = _misorientation(original[original.is_indexed], m, "cubic")
    assert float(angles.max()) < 5e-5


@pytest.mark.parametrize("confidence", ["CI", "MAD (degrees)"])
def test_the_indexed_pixels_survive_both_formats(tmp_path, confidence):
    """The not-indexed pixels (CI = −1 of an .ang map, phase 0 of a .ctf map) stay not indexed
    through .ang and .ctf; CI is never written as MAD nor MAD as CI."""
    shape = (3, 4)
    e = np.zeros((*shape, 3))
    if confidence == "CI":
        conf, phase = np.array([[0.9, -1, 0.5, 0.3]] * 3), np.ones(shape)
        conf[2, 0] = 0.05  # low, but indexed
    else:
        conf, phase = np.array([[0.4, 0.0, 1.2, 2.5]] * 3), np.array([[1, 0, 1, 1]] * 3)
    m = OrientationMap(e, 1e-6, 1e-6, phase, conf, confidence, source="m")
    off = indexed_pixels(m, min_confidence=0.0).not_indexed
    ang, ctf = (
        read_ang(write_ang(tmp_path / "m.ang", m)),
        read_ctf(write_ctf(tmp_path / "m.ctf", m)),
    )
    for back in (ang, ctf):
        assert indexed_pixels(back, min_confidence=0.0).not_indexed == off == 3
    if confidence == "CI":
        assert np.array_equal(ang.confidence, conf) and np.all(ctf.confidence == 0.0)
        assert indexed_pixels(ang).low_confidence == 1
    else:
        assert np.array_equal(ctf.confidence, conf)
        assert set(np.unique(ang.confidence)) == {-1.0, 1.0}
        assert np.array_equal(indexed_pixels(ctf, max_mad=1.5).mask, (conf <= 1.5) & (phase != 0))


def test_orix_reads_the_bundled_example_map():
    from importlib.resources import as_file, files

    with as_file(files("contactres") / "data" / "example_cu_map.ang") as path:
        xmap, m = io.load(path), read_ang(path)
    assert xmap.shape == m.shape == (64, 64) and xmap.phases[1].name == "Cu"
    assert float(_misorientation(xmap, m, "cubic").max()) < TOL


# ------------------------------------------------------------------ the IPF key
# Corners (red, green, blue) in crystal coordinates: [001], [101], [111]; [0001], [2-1-10] = a1,
# [10-10] (azimuth 30°).
CORNERS = {
    "cubic": ("Oh", [[0, 0, 1], [1, 0, 1], [1, 1, 1]]),
    "hexagonal": ("D6h", [[0, 0, 1], [1, 0, 0], [np.sqrt(3) / 2, 0.5, 0]]),
}


@pytest.mark.parametrize("lattice", sorted(CORNERS))
def test_the_corner_colours_are_orix_s(lattice):
    name, corners = CORNERS[lattice]
    pg = getattr(symmetry, name)
    corners = np.array(corners, dtype=float)
    theirs = DirectionColorKeyTSL(pg).direction2color(Vector3d(corners))
    ours = ipf_colors(corners, lattice)
    assert np.allclose(ours, np.eye(3), rtol=0, atol=1e-12)
    # orix's own corners are within 0.01 of pure (its sector centre and azimuth correction).
    assert np.allclose(theirs, ours, rtol=0, atol=0.01)


@pytest.mark.parametrize("lattice", sorted(CORNERS))
def test_the_interior_differs_as_the_docstring_says(lattice):
    """The bound the module docstring states (0.3 cubic, 0.5 hexagonal, rounded up to 0.35 and
    0.55 here) holds on a dense sample, and the keys do differ (a claim of equality would fail)."""
    pg = getattr(symmetry, CORNERS[lattice][0])
    v = np.random.default_rng(0).normal(size=(20000, 3))
    diff = np.abs(
        DirectionColorKeyTSL(pg).direction2color(Vector3d(v)) - ipf_colors(v, lattice)
    ).max()
    assert 0.1 < diff < {"cubic": 0.35, "hexagonal": 0.55}[lattice]
