"""The modulus-map figure (contactres.report._map_figures): panels, labels, colour ranges, layout.

The colour range of the legend is checked against M evaluated independently (exact
indentation_moduli at the triangle's grid); the layout by the text boxes in display space.
"""

from __future__ import annotations

import io
import itertools
import warnings

import numpy as np
import pytest
from matplotlib.image import AxesImage
from matplotlib.text import Text

from contactres import Material
from contactres.polycrystal._ipf import ipf_triangle
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._normal_table import surface_matrices_from_normals
from contactres.polycrystal._synthetic import synthetic_polycrystal
from contactres.report._map_figures import modulus_map_figure

CU = Material.crystal("Cu")
TI = Material.hexagonal(162.4e9, 92.0e9, 69.0e9, 180.7e9, 46.7e9, density=4506.0)
GRID = 31


def exact(material):
    return lambda n: indentation_moduli(material, surface_matrices_from_normals(n))


def draw(material, lattice, **kw):
    m = synthetic_polycrystal((30, 45), 6, seed=2)
    R = m.surface_matrices()
    M = indentation_moduli(material, R.reshape(-1, 3, 3)).reshape(m.shape)
    fig = modulus_map_figure(M, R[..., 2, :], lattice, exact(material), grid_points=GRID, **kw)
    return fig, M


def visible_texts(fig):
    """(text, display box) of every drawn text: titles, axis labels, annotations, the
    suptitle and the tick labels of ticks inside the view (matplotlib keeps, undrawn, labels
    of ticks just outside it)."""
    renderer = fig.canvas.get_renderer()
    texts = list(fig.texts)  # the suptitle among them
    for ax in fig.axes:
        texts += [ax.title, *ax.texts]
        for axis in (ax.xaxis, ax.yaxis):
            texts.append(axis.label)
            lo, hi = sorted(axis.get_view_interval())
            eps = 1e-9 * max(1.0, abs(hi - lo))
            for tick in axis.get_major_ticks():
                if lo - eps <= tick.get_loc() <= hi + eps:
                    texts += [tick.label1, tick.label2]
    return [
        (t.get_text(), t.get_window_extent(renderer))
        for t in texts
        if isinstance(t, Text) and t.get_visible() and t.get_text().strip()
    ]


@pytest.mark.parametrize(("material", "lattice"), [(CU, "cubic"), (TI, "hexagonal")])
def test_panels_labels_and_colour_ranges(material, lattice):
    fig, M = draw(material, lattice, pixel_size=2e-6, material_name="Cu")
    ax_m, ax_ipf, ax_tri, ax_key, cb_m, cb_tri = fig.axes
    assert ax_m.get_title().startswith("(a)") and ax_ipf.get_title().startswith("(b)")
    assert ax_tri.get_title().startswith("(c)") and "key" in ax_key.get_title()
    for ax in (ax_m, ax_ipf):
        assert ax.get_xlabel() == "x (µm)" and ax.get_ylabel() == "y (µm)"
        # 45 pixels of 2 µm along x
        assert np.allclose(sorted(ax.get_images()[0].get_extent()[:2]), [0, 90], atol=1e-9)
    assert cb_m.get_ylabel() == "M (GPa)" and cb_tri.get_ylabel() == "M (GPa)"
    # The legend's range is min/max of M over the triangle (exact M, independent evaluation).
    tri = ipf_triangle(lattice, GRID)
    m_tri = exact(material)(tri.inside_normals) / 1e9
    (img,) = [a for a in ax_tri.get_children() if isinstance(a, AxesImage)]
    assert np.isclose(img.norm.vmin, m_tri.min(), rtol=1e-9, atol=0)
    assert np.isclose(img.norm.vmax, m_tri.max(), rtol=1e-9, atol=0)
    # The map's M lies within the range of all orientations: the same scale in (a).
    (map_img,) = ax_m.get_images()
    assert map_img.norm.vmin <= np.nanmin(M) / 1e9 + 1e-9
    assert np.isclose(map_img.norm.vmin, img.norm.vmin, rtol=1e-3, atol=0)
    # Corner labels are shown.
    fig.canvas.draw()
    texts = {t for t, _ in visible_texts(fig)}
    labels = ("[001]", "[101]", "[111]") if lattice == "cubic" else ("[0001]",)
    assert set(labels) <= texts


def test_no_overlapping_text_and_png_without_warnings():
    fig, _ = draw(CU, "cubic", material_name="copper $1$ " + "x" * 80)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=80)
    assert buf.getvalue()[:8] == b"\x89PNG\r\n\x1a\n"
    fig.canvas.draw()
    boxes = visible_texts(fig)
    for (ta, a), (tb, b) in itertools.combinations(boxes, 2):
        assert not a.overlaps(b), f"text {ta!r} overlaps {tb!r}"
    fbox = fig.bbox
    for t, box in boxes:
        assert fbox.x0 - 1 <= box.x0 and box.x1 <= fbox.x1 + 1, f"{t!r} cut at the sides"
        assert fbox.y0 - 1 <= box.y0 and box.y1 <= fbox.y1 + 1, f"{t!r} cut at the top/bottom"


def test_pixels_without_data_and_pixel_axes():
    m = synthetic_polycrystal((20, 20), 4, seed=1)
    R = m.surface_matrices()
    M = indentation_moduli(CU, R.reshape(-1, 3, 3)).reshape(m.shape)
    n = R[..., 2, :].copy()
    M[0, 0], n[1, 1] = np.nan, np.nan
    fig = modulus_map_figure(M, n, "cubic", exact(CU), grid_points=GRID)
    ax_m, ax_ipf = fig.axes[:2]
    assert ax_m.get_xlabel() == "x (pixel)"
    rgba = ax_ipf.get_images()[0].get_array()
    assert rgba[1, 1, 3] == 0 and np.all(rgba[0, 0, :3] >= 0) and rgba[0, 0, 3] == 1


def test_bad_input():
    M = np.full((4, 5), 1e11)
    n = np.tile([0.0, 0.0, 1.0], (4, 5, 1))
    with pytest.raises(ValueError, match="normals must have shape"):
        modulus_map_figure(M, n[:3], "cubic", exact(CU))
    with pytest.raises(ValueError, match="moduli must be a map"):
        modulus_map_figure(M.ravel(), n, "cubic", exact(CU))
    with pytest.raises(ValueError, match="no finite"):
        modulus_map_figure(M * np.nan, n, "cubic", exact(CU))
    with pytest.raises(ValueError, match="lattice"):
        modulus_map_figure(M, n, "monoclinic", exact(CU))
    with pytest.raises(ValueError, match="pixel_size"):
        # GRID: the triangle is evaluated before pixel_size is read (81 points: 1.4 s of CPU)
        modulus_map_figure(M, n, "cubic", exact(CU), pixel_size=-1.0, grid_points=GRID)
    with pytest.raises(ValueError, match="one finite M"):
        modulus_map_figure(M, n, "cubic", lambda v: np.ones(3), grid_points=GRID)


# ------------------------------------------------------------ the legend the job computed


def _triangle_image(fig):
    ax_tri = fig.axes[2]
    (img,) = [a for a in ax_tri.get_children() if isinstance(a, AxesImage)]
    return img


def test_triangle_moduli_at_the_corners_are_the_faces_indentation_moduli():
    from contactres.normal import indentation_modulus
    from contactres.polycrystal import triangle_moduli

    tri = triangle_moduli("cubic", exact(CU), GRID)
    # [001] is the origin of the projection, <110> (written [011] in the triangle's crystal
    # coordinates) the end of its X axis: corners of the grid
    assert np.allclose(tri.triangle.normals[0, 0], [0, 0, 1])
    assert np.allclose(tri.triangle.normals[0, -1], np.array([0, 1, 1]) / np.sqrt(2))
    # an independent route: the θ integral of paper 1, Eq. 4 on the rotated crystal
    for (i, j), face in (((0, 0), (0, 0, 1)), ((0, -1), (0, 1, 1))):
        expected = indentation_modulus(CU.rotated(normal=face))
        assert tri.moduli[i, j] == pytest.approx(expected, rel=1e-7)
    assert np.isnan(tri.moduli[~tri.cells]).all() and np.isfinite(tri.moduli[tri.cells]).all()
    lo, hi = tri.inside_range
    assert lo == pytest.approx(indentation_modulus(CU.rotated(normal=(0, 0, 1))), rel=1e-7)
    assert hi == pytest.approx(indentation_modulus(CU.rotated(normal=(1, 1, 1))), rel=1e-2)


def test_the_figure_draws_the_triangle_it_is_given_without_evaluating_m():
    from contactres.polycrystal import triangle_moduli

    def fake(n):  # any function of the normal: the figure must draw exactly these values
        return 1e11 * (1.0 + n[:, 0] + 2.0 * n[:, 1])

    given = triangle_moduli("cubic", fake, GRID)
    m = synthetic_polycrystal((10, 12), 3, seed=4)
    R = m.surface_matrices()
    M = np.full(m.shape, 1.2e11)
    fig = modulus_map_figure(M, R[..., 2, :], "cubic", given)
    img = _triangle_image(fig)
    drawn = np.ma.filled(img.get_array().astype(float), np.nan)
    np.testing.assert_array_equal(np.isnan(drawn), np.isnan(given.moduli))
    ok = np.isfinite(drawn)
    np.testing.assert_allclose(drawn[ok], given.moduli[ok] / 1e9, rtol=1e-15)
    assert img.norm.vmin == pytest.approx(given.inside_range[0] / 1e9, rel=1e-15)
    with pytest.raises(ValueError, match="hexagonal lattice"):
        modulus_map_figure(M, R[..., 2, :], "cubic", triangle_moduli("hexagonal", fake, GRID))


@pytest.fixture(scope="module")
def predicted():
    """``maps predict`` of the bundled Cu map with its legend (exact M over the triangle's
    grid, ~1.5 s of CPU): computed once for the two tests that draw it."""
    from importlib.resources import as_file, files

    from contactres.jobs import maps_predict
    from contactres.jobs.maps import TipLoad

    settings = maps_predict.Settings(CU, "cubic", TipLoad(radius=20e-9, force=1e-6))
    with as_file(files("contactres") / "data" / "example_cu_map.ang") as ang:
        return maps_predict.run(ang, settings)


def test_prediction_figure_draws_the_triangle_of_the_maps_predict_result(predicted):
    import dataclasses

    from contactres.jobs import maps_predict
    from contactres.polycrystal import triangle_moduli
    from contactres.report import prediction_figure

    result = predicted
    # the job's legend is exact M over the triangle
    assert result.triangle.moduli.shape == (maps_predict.TRIANGLE_GRID,) * 2
    ok = result.triangle.cells
    n = result.triangle.normals
    np.testing.assert_allclose(result.triangle.moduli[ok], exact(CU)(n), rtol=1e-12)
    # the figure draws the result's values: swap them for others and see those drawn
    other = triangle_moduli("cubic", lambda v: 1e11 + 1e10 * v[:, 2], maps_predict.TRIANGLE_GRID)
    fig = prediction_figure(dataclasses.replace(result, triangle=other))
    drawn = np.ma.filled(_triangle_image(fig).get_array().astype(float), np.nan)
    np.testing.assert_allclose(drawn[other.cells], other.moduli[other.cells] / 1e9, rtol=1e-15)


def test_the_legend_is_optional_and_the_report_draws_the_map(predicted, tmp_path):
    import dataclasses
    from importlib.resources import as_file, files

    from contactres.errors import ContactresInputError
    from contactres.jobs import maps_predict
    from contactres.jobs.maps import TipLoad
    from contactres.report import prediction_figure, write_report

    settings = maps_predict.Settings(CU, "cubic", TipLoad(20e-9, 1e-6), legend=False)
    with as_file(files("contactres") / "data" / "example_cu_map.ang") as ang:
        bare = maps_predict.run(ang, settings)
    assert bare.triangle is None
    with pytest.raises(ContactresInputError, match="legend=True"):
        prediction_figure(bare)
    write_report(bare, tmp_path / "bare", ("json", "png"))
    assert not (tmp_path / "bare" / "M_map.png").exists()
    # the legend of the same map and settings, computed with legend=True (the test above
    # checks it against exact M at its grid)
    legend = predicted.triangle
    assert legend is not None
    write_report(dataclasses.replace(bare, triangle=legend), tmp_path / "full", ("json", "png"))
    assert (tmp_path / "full" / "M_map.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
