"""EBSD text exports: .ang (radians) and .ctf (degrees) on square grids, and their errors."""

from __future__ import annotations

import numpy as np
import pytest

from contactres.examples import example_path
from contactres.polycrystal import OrientationMap
from contactres.polycrystal._ebsd import read_ang, read_ctf, read_ebsd, write_ang, write_ctf
from contactres.polycrystal._synthetic import synthetic_polycrystal

ANG = """\
# TEM_PIXperUM          1.000000
# x-star                0.500000
# Phase 1
# MaterialName          Copper
# GRID: SqrGrid
# XSTEP: 0.500000
# YSTEP: 0.250000
# NCOLS_ODD: 3
# NCOLS_EVEN: 3
# NROWS: 2
#
  0.10000   0.20000   0.30000      0.00000      0.00000  100.0  0.900  1  0  1.1
  1.10000   1.20000   1.30000      0.50000      0.00000  100.0  0.800  1  0  1.1
  2.10000   2.20000   2.30000      1.00000      0.00000  100.0  0.700  1  0  1.1
  3.10000   0.20000   4.30000      0.00000      0.25000  100.0  0.600  1  0  1.1
  4.10000   1.20000   5.30000      0.50000      0.25000  100.0  0.500  1  0  1.1
  5.10000   2.20000   6.10000      1.00000      0.25000  100.0 -1.000  0  0  1.1
"""

CTF = """\
Channel Text File
Prj\tC:\\data\\cu.cpr
Author\t[Unknown]
JobMode\tGrid
XCells\t2
YCells\t2
XStep\t2
YStep\t2
AcqE1\t0
AcqE2\t0
AcqE3\t0
Euler angles refer to Sample Coordinate system (CS0)!\tMag\t500\tCoverage\t100\tDevice\t0\tKV\t20
Phases\t1
3.615;3.615;3.615\t90;90;90\tCopper\t11\t225
Phase\tX\tY\tBands\tError\tEuler1\tEuler2\tEuler3\tMAD\tBC\tBS
1\t0\t0\t8\t0\t90\t45\t0\t0.5\t150\t200
1\t2\t0\t8\t0\t180\t90\t270\t0.6\t150\t200
0\t0\t2\t0\t3\t0\t0\t0\t0\t0\t0
1\t2\t2\t9\t0\t10\t20\t30\t0.4\t160\t210
"""


def test_ang_fixture_reads_as_a_square_grid(tmp_path):
    p = tmp_path / "scan.ang"
    p.write_text(ANG)
    m = read_ang(p)
    assert m.shape == (2, 3)
    assert (m.step_x, m.step_y) == (0.5e-6, 0.25e-6)
    assert np.array_equal(m.euler[0, 1], [1.1, 1.2, 1.3])  # radians as written
    assert np.array_equal(m.euler[1, 2], [5.1, 2.2, 6.1])
    assert np.array_equal(m.confidence[:, 2], [0.7, -1.0])
    assert np.array_equal(m.phase, [[1, 1, 1], [1, 1, 0]])
    assert m.confidence_name == "CI"


def test_ctf_fixture_reads_degrees_as_radians(tmp_path):
    p = tmp_path / "scan.ctf"
    p.write_text(CTF)
    m = read_ebsd(p)
    assert m.shape == (2, 2) and (m.step_x, m.step_y) == (2e-6, 2e-6)
    assert np.allclose(m.euler[0, 0], np.radians([90, 45, 0]), rtol=1e-15, atol=0)
    assert np.allclose(m.euler[0, 1], [np.pi, np.pi / 2, 1.5 * np.pi], rtol=1e-15, atol=0)
    assert np.array_equal(m.phase, [[1, 1], [0, 1]])
    assert np.array_equal(m.confidence, [[0.5, 0.6], [0.0, 0.4]])


def test_rows_in_any_order_land_on_their_pixel(tmp_path):
    head, body = ANG.rsplit("#\n", 1)
    data = body.splitlines()
    p = tmp_path / "shuffled.ang"
    p.write_text(head + "#\n" + "\n".join(data[::-1]) + "\n")
    q = tmp_path / "scan.ang"
    q.write_text(ANG)
    assert np.array_equal(read_ang(p).euler, read_ang(q).euler)


@pytest.mark.parametrize(("writer", "reader"), [(write_ang, read_ang), (write_ctf, read_ctf)])
def test_writer_reader_round_trip(tmp_path, writer, reader):
    m = synthetic_polycrystal((9, 13), n_grains=4, seed=5, pixel_size=0.5e-6)
    back = reader(writer(tmp_path / f"m.{reader.__name__[-3:]}", m))
    assert back.shape == m.shape and (back.step_x, back.step_y) == (m.step_x, m.step_y)
    assert np.allclose(back.euler, m.euler, rtol=1e-15, atol=1e-15)
    if reader is read_ang:  # radians written with 17 digits: bit for bit
        assert np.array_equal(back.euler, m.euler)
    assert np.array_equal(back.phase, m.phase)


def test_hexagonal_grid_is_rejected(tmp_path):
    p = tmp_path / "hex.ang"
    p.write_text(ANG.replace("SqrGrid", "HexGrid"))
    with pytest.raises(ValueError, match=r"hex\.ang: '# GRID: HexGrid' is not supported"):
        read_ang(p)


def test_ctf_other_job_mode_is_rejected(tmp_path):
    p = tmp_path / "line.ctf"
    p.write_text(CTF.replace("JobMode\tGrid", "JobMode\tLineScan"))
    with pytest.raises(ValueError, match="JobMode 'LineScan'"):
        read_ctf(p)


def test_non_numeric_value_names_file_row_column_value_and_rule(tmp_path):
    p = tmp_path / "bad.ang"
    p.write_text(ANG.replace("0.800", "0.8x0"))
    with pytest.raises(ValueError) as err:
        read_ang(p)
    msg = str(err.value)
    for part in ("bad.ang", "data row 2", "line 13", "'CI'", "'0.8x0'", "finite number"):
        assert part in msg


def test_missing_value_is_reported(tmp_path):
    p = tmp_path / "short.ctf"
    lines = CTF.splitlines()
    lines[-2] = "0\t0\t2\t0\t3\t0\t\t0\t0\t0\t0"  # Euler2 empty
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"short\.ctf: data row 3 \(line 18\), column 'Euler2'"):
        read_ctf(p)


def test_too_few_columns_is_reported(tmp_path):
    p = tmp_path / "narrow.ang"
    text = "\n".join(" ".join(r.split()[:6]) if not r.startswith("#") else r
                     for r in ANG.splitlines())  # fmt: skip
    p.write_text(text + "\n")
    with pytest.raises(ValueError, match=r"narrow\.ang: data row 1 .*column 'CI'.*8 columns"):
        read_ang(p)


def test_missing_ctf_column_and_not_a_grid(tmp_path):
    p = tmp_path / "nomad.ctf"
    p.write_text(CTF.replace("\tMAD\t", "\tMAX\t"))
    with pytest.raises(ValueError, match=r"lacks the columns \['MAD'\]"):
        read_ctf(p)
    q = tmp_path / "hole.ang"
    q.write_text("\n".join(ANG.splitlines()[:-1]) + "\n")  # the last point missing
    with pytest.raises(ValueError, match="has no data row"):
        read_ang(q)
    r = tmp_path / "off.ang"
    r.write_text(ANG.replace("1.00000      0.25000", "1.10000      0.25000"))
    with pytest.raises(ValueError, match=r"data row 6 .*column 'x'.*not on the square grid"):
        read_ang(r)


def test_angle_beyond_two_turns_and_unknown_suffix(tmp_path):
    p = tmp_path / "deg.ang"
    p.write_text(ANG.replace("2.10000   2.20000", "210.0000   2.20000"))
    with pytest.raises(ValueError, match=r"column 'phi1': value '210\.0'.*two turns"):
        read_ang(p)
    with pytest.raises(ValueError, match="unknown EBSD export"):
        read_ebsd(tmp_path / "scan.txt")


def test_the_writers_name_the_phase_they_are_given(tmp_path):
    from contactres.polycrystal import EbsdPhase, ebsd_phase

    m = synthetic_polycrystal((3, 4), n_grains=2, seed=1, pixel_size=1e-6)
    ang = write_ang(tmp_path / "ni.ang", m, ebsd_phase("Ni")).read_text()
    assert "# MaterialName Ni\n" in ang and "# Symmetry 43\n" in ang  # 432: cubic, EDAX code
    assert "# LatticeConstants 3.5240 3.5240 3.5240 90.0000 90.0000 90.0000\n" in ang
    ctf = write_ctf(tmp_path / "ti.ctf", m, EbsdPhase("Ti", "hexagonal", 2.95, 4.68, 194))
    assert "2.9500;2.9500;4.6800\t90.0000;90.0000;120.0000\tTi\t9\t194\n" in ctf.read_text()
    assert "Copper" not in write_ctf(tmp_path / "any.ctf", m).read_text()  # unnamed: "unknown"


def test_bad_phases_and_maps_of_several_phases_are_refused(tmp_path):
    from contactres.polycrystal import EbsdPhase, OrientationMap, ebsd_phase

    with pytest.raises(ValueError, match="needs c"):
        EbsdPhase("Ti", "hexagonal", 2.95)
    with pytest.raises(ValueError, match="lattice 'tetragonal'"):
        EbsdPhase("Sn", "tetragonal", 5.8)
    with pytest.raises(ValueError, match="no lattice constants known for 'quartz'"):
        ebsd_phase("quartz")
    two = OrientationMap(np.zeros((1, 3, 3)), 1e-6, 1e-6, [[1, 2, 0]], [[0.5, 0.5, 0.5]], "CI")
    for writer in (write_ang, write_ctf):
        with pytest.raises(ValueError, match="holds phases 0, 1, 2: the writers describe one"):
            writer(tmp_path / "two.txt", two)
        with pytest.raises(ValueError, match="phase must be an EbsdPhase"):
            writer(tmp_path / "one.txt", two, "Ni")


def test_a_map_prints_compactly_and_renders_in_notebooks():
    """issue 30: repr of the bundled 64 x 64 map was 2,388 characters of raw arrays."""
    m = read_ebsd(example_path("example_cu_map.ang"))
    text = repr(m)
    assert len(text) < 200 and "array(" not in text and "\n" not in text
    assert "64 x 64 of 1 x 1 µm" in text and "grains: not labelled" in text
    assert "example_cu_map.ang" in text and "CI:" in text
    s = synthetic_polycrystal((9, 13), n_grains=4, seed=5, pixel_size=0.5e-6)
    assert repr(s).startswith("SyntheticPolycrystal(pixels: 9 x 13 of 0.5 x 0.5 µm")
    assert f"grains: {len(np.unique(s.labels))};" in repr(s) and "array(" not in repr(s)
    page = OrientationMap(s.euler, 1e-6, 1e-6, s.phase, s.confidence, source="<a & b>")
    assert "<table>" in page._repr_html_() and "&lt;a &amp; b&gt;" in page._repr_html_()
