"""``contactres afm map`` on instrument files written at test time in the real layouts (an Asylum
DART .ibw, a BGlib SHO fit .h5, a NetCDF grid): the lever's forward model
(contactres.contact_frequencies) at the k* written out gives back the resonance in the file; the
reference calibration gives the reference's modulus back; bad files are one line."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from cli_checks import figures_not_drawn, one_line_error, run

import contactres as cr

xr = pytest.importorskip("xarray", reason="xarray (the extra 'maps') holds the map Dataset")
MEASUREMENTS = Path(__file__).resolve().parents[1] / "measurements"
F_FREE, R_TIP = 90e3, 0.95  # Hz, L1/L


def _module(name):
    """A helper module of the reader tests (the DART and BGlib writers), loaded by its path."""
    spec = importlib.util.spec_from_file_location(f"_c3_{name}", MEASUREMENTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def fixtures():
    return _module("afm_file_fixtures")


def _ok(r):
    assert r.exit_code == 0, r.output
    return r


def _forward(ds, k_c):
    """The lever's mode-1 resonance (Hz) and Q at the k* and σ of the map, by the forward model:
    the Kelvin-Voigt contact at the complex frequency ω_c = ω(1 + i/(2Q)) of the map's f and Q,
    κ_c = (k* + iω_c σ)/k_c, on a lever without free damping."""
    lever = cr.Cantilever((F_FREE,), k_c)
    f, q = ds["frequency_Hz"].values, ds["q_factor"].values
    omega_c = 2 * np.pi * f * (1 + 0.5j / q)
    kappa = (ds["k_star_N_per_m"].values + 1j * omega_c * ds["sigma_N_s_per_m"].values) / k_c
    fc = cr.contact_frequencies(lever, kappa, R_TIP, modes=(1,))[..., 0]
    return fc.real, fc.real / (2 * fc.imag)


def test_dart_image_to_maps_report_and_reference_calibration(fixtures, tmp_path):
    path = tmp_path / "dart.ibw"
    _, truth = fixtures.write_dart_ibw(path, points=24, lines=16)
    out = tmp_path / "out"
    options = ["--free-frequency", F_FREE, "--tip-position", R_TIP]
    ref = ["--reference", "0:3,0:3", "--reference-modulus", 3e9]
    r = _ok(run("afm", "map", path, "--out", out, *options, *ref))
    assert "384 with k*" in r.output and "wrote" in r.output
    assert {p.name for p in out.iterdir()} >= {
        "afm_map.json", "afm_map.nc", "afm_maps.png", "afm_histograms.png"
    }  # fmt: skip
    ds = xr.load_dataset(out / "afm_map.nc")
    f0, q = truth["f0"].T, truth["q"].T  # the fixture is (points, lines): x first
    # float32 layers: the reconstruction is as good as the data (~1e-7 relative).
    np.testing.assert_allclose(ds["frequency_Hz"], f0, rtol=1e-6)
    np.testing.assert_allclose(ds["q_factor"], q, rtol=1e-3)
    f_back, q_back = _forward(ds, fixtures.SPRING_CONSTANT)
    np.testing.assert_allclose(f_back, f0, rtol=1e-6)
    np.testing.assert_allclose(q_back, q, rtol=1e-3)
    # The reference region (matrix) has 3 GPa; the inclusion follows (k*/k*_ref)^1.5.
    k = ds["k_star_N_per_m"].values
    k_ref = np.median(k[:3, :3])
    np.testing.assert_allclose(ds["M_Pa"], 3e9 * (k / k_ref) ** 1.5, rtol=1e-10)
    record = json.loads((out / "afm_map.json").read_text())
    lever = record["conventions"]["lever"]["spring_constant_N_per_m"]
    assert lever == {"option": None, "note": fixtures.SPRING_CONSTANT, "note_key": "SpringConstant",
                     "used": fixtures.SPRING_CONSTANT}  # fmt: skip
    assert record["conventions"]["dart"]["phase_sign"] == "lag"
    assert ds["x"].attrs["units"] == "m"
    np.testing.assert_allclose(ds["x"].values[1], fixtures.SCAN_SIZE / 24, rtol=1e-6)


def test_bglib_sho_fit_inverts_as_the_direct_inversion(tmp_path, monkeypatch):
    """Done when of issue 29: a BGlib-style SHO table gives the k* of the direct inversion."""
    monkeypatch.syspath_prepend(str(MEASUREMENTS))  # the reader tests import their fixtures
    be = _module("test_afm_maps")
    path = tmp_path / "be.h5"
    truth = be.write_bglib(path, rows=4, cols=6)
    out = tmp_path / "be"
    lever = ["--spring-constant", 3.0, "--free-frequency", F_FREE, "--tip-position", R_TIP]
    figures_not_drawn(monkeypatch)  # the maps' numbers and files, not their pixels
    _ok(run("afm", "map", path, "--out", out, *lever, "--map-name", "be.zarr"))
    ds = xr.open_zarr(out / "be.zarr", consolidated=False).load()
    f = truth["Frequency [Hz]"][..., 0].astype(np.float32).astype(float)
    q = truth["Quality Factor"][..., 0].astype(np.float32).astype(float)
    direct = cr.invert_contact_resonance(
        cr.Cantilever((F_FREE,), 3.0), f[..., None], R_TIP, q_factors=q[..., None]
    )
    np.testing.assert_allclose(ds["k_star_N_per_m"], direct.k_star, rtol=1e-12)
    np.testing.assert_allclose(ds["sigma_N_s_per_m"], direct.sigma, rtol=1e-12)


def test_a_netcdf_grid_of_frequency_and_q(tmp_path, kelvin_voigt, monkeypatch):
    lever = cr.Cantilever((F_FREE,), 2.0)
    k_true = np.linspace(40.0, 120.0, 6).reshape(2, 3)  # N/m
    f, q = kelvin_voigt(lever, k_true, 0.05, R_TIP)
    grid = xr.Dataset({"frequency_Hz": (("y", "x"), f), "q_factor": (("y", "x"), q)})
    grid.to_netcdf(tmp_path / "grid.nc")
    out = tmp_path / "g"
    lever = ["--spring-constant", 2.0, "--free-frequency", F_FREE, "--tip-position", R_TIP]
    figures_not_drawn(monkeypatch)  # the maps' numbers and files, not their pixels
    _ok(run("afm", "map", tmp_path / "grid.nc", "--out", out, *lever, "--punch-radius", 5e-9))
    ds = xr.load_dataset(out / "afm_map.nc")
    np.testing.assert_allclose(ds["k_star_N_per_m"], k_true, rtol=1e-9)
    np.testing.assert_allclose(ds["tan_delta"], 0.05, rtol=1e-8)
    np.testing.assert_allclose(ds["E_star_Pa"], k_true / 1e-8, rtol=1e-9)


def test_bad_files_and_options_are_one_line(fixtures, tmp_path):
    base = ["--free-frequency", F_FREE, "--tip-position", R_TIP, "--out", tmp_path / "o"]
    missing = tmp_path / "no_phase2.ibw"
    labels = tuple(x if x != "Phase2Retrace" else "ZSensorRetrace" for x in fixtures.DART_LABELS)
    fixtures.write_dart_ibw(missing, points=8, lines=6, labels=labels)
    one_line_error(run("afm", "map", missing, *base), "Phase2", "layers present")
    no_k = tmp_path / "no_k.ibw"
    fixtures.write_dart_ibw(no_k, points=8, lines=6, SpringConstant=None)
    one_line_error(run("afm", "map", no_k, *base), "SpringConstant", "--spring-constant")
    no_width = tmp_path / "no_width.ibw"
    fixtures.write_dart_ibw(no_width, points=8, lines=6, DFRTFrequencyWidth=None)
    one_line_error(run("afm", "map", no_width, *base), "--frequency-width")
    good = tmp_path / "good.ibw"
    fixtures.write_dart_ibw(good, points=8, lines=6)
    one_line_error(
        run("afm", "map", good, *base, "--reference", "0:7,0:3", "--reference-modulus", 3e9),
        "not inside",
    )
    one_line_error(run("afm", "map", good, *base, "--reference", "0-3"), "Y0:Y1,X0:X1")
    empty = ["--reference", "5:5,0:3", "--reference-modulus", 3e9]
    one_line_error(run("afm", "map", good, *base, *empty), "5:5", "is empty")
    one_line_error(run("afm", "map", good, *base, "--phase-sign", "lead"), "--phase-sign")
    # A lever's constant is checked as a lever's (1e5 N/m is a contact's k*, not a lever's).
    one_line_error(
        run("afm", "map", good, *base, "--spring-constant", 1e5),
        "--spring-constant",
        "cantilever spring constant",
    )
    # A negative tilt (free end farther from the sample) is not modelled: refused as an option.
    r = run("afm", "map", good, *base, "--tilt", -5)
    assert r.exit_code == 2 and "--tilt" in r.output and "0<=x<=45" in r.output, r.output
    one_line_error(run("afm", "map", good, *base, "--map-name", "maps.h5"), ".nc", ".zarr")
    (tmp_path / "again").mkdir()
    twin = tmp_path / "again" / "good.ibw"
    twin.write_bytes(good.read_bytes())
    one_line_error(run("afm", "map", good, twin, *base), "good", "twice")
    one_line_error(
        run("afm", "map", good, *base, "--tip-radius", 2e-8, "--punch-radius", 5e-9),
        "one way to the modulus",
    )
    zeros = tmp_path / "zeros.nc"
    xr.Dataset(
        {"frequency_Hz": (("y", "x"), np.zeros((3, 3))), "q_factor": (("y", "x"), np.ones((3, 3)))}
    ).to_netcdf(zeros)
    r = run("afm", "map", zeros, *base, "--spring-constant", 2.0)
    one_line_error(r, "zeros.nc", "no frequency")


def test_a_series_calibrates_each_map_against_its_reference(tmp_path, kelvin_voigt, monkeypatch):
    """Two maps of one sample (a 3 GPa reference in columns 0-1, 9 GPa beside it), the second
    with a worn, blunter tip: each map's own reference region gives the same moduli, and the
    reference stiffness of each map shows the wear (Killgore et al. 2011)."""
    lever = cr.Cantilever((F_FREE,), 2.0)
    e = np.full((3, 5), 9e9)
    e[:, :2] = 3e9
    files = []
    for name, radius in (("sharp", 10e-9), ("worn", 30e-9)):
        a = (3 * 50e-9 * radius / (4 * e)) ** (1 / 3)  # Hertz at 50 nN, a rigid tip
        f, q = kelvin_voigt(lever, 2 * a * e, 0.02, R_TIP)
        path = tmp_path / f"{name}.nc"
        xr.Dataset({"frequency_Hz": (("y", "x"), f), "q_factor": (("y", "x"), q)}).to_netcdf(path)
        files.append(path)
    lever_options = ["--spring-constant", 2.0, "--free-frequency", F_FREE, "--tip-position", R_TIP]
    ref = ["--reference", "0:3,0:2", "--reference-modulus", 3e9]
    out = tmp_path / "series"
    figures_not_drawn(monkeypatch)  # the maps' numbers and files, not their pixels
    r = _ok(run("afm", "map", *files, "--out", out, *lever_options, *ref))
    assert r.output.count("wrote") == 2
    k_ref = []
    for name in ("sharp", "worn"):
        ds = xr.load_dataset(out / name / "afm_map.nc")
        np.testing.assert_allclose(ds["M_Pa"], e, rtol=1e-8)
        record = json.loads((out / name / "afm_map.json").read_text())
        k_ref.append(record["conventions"]["modulus"]["reference_k_star_N_per_m"])
    assert k_ref[1] / k_ref[0] == pytest.approx(3 ** (1 / 3), rel=1e-8)  # k* ∝ R^(1/3)


def test_scale_bar_is_a_round_length_near_a_fifth_of_the_width():
    from contactres.report._cr_map_figures import scale_bar_length

    assert scale_bar_length(2e-6) == pytest.approx(2e-7)
    assert scale_bar_length(5e-6) == pytest.approx(1e-6)
    assert scale_bar_length(3.3e-6) == pytest.approx(5e-7)
    assert scale_bar_length(1e-7) == pytest.approx(2e-8)


def test_a_series_on_a_dask_cluster_equals_the_serial_run(fixtures, tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed", reason="dask.distributed not installed")
    files = []
    for name in ("a", "b"):
        files.append(tmp_path / f"{name}.ibw")
        fixtures.write_dart_ibw(files[-1], points=12, lines=8)
    options = ["--free-frequency", F_FREE, "--tip-position", R_TIP]
    figures_not_drawn(monkeypatch)  # the maps' numbers and files, not their pixels
    _ok(run("afm", "map", *files, "--out", tmp_path / "serial", *options))
    with distributed.LocalCluster(
        n_workers=1, processes=False, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        address = cluster.scheduler_address
        _ok(run("afm", "map", *files, "--out", tmp_path / "dask", *options, "--scheduler", address))
    for name in ("a", "b"):
        serial = xr.load_dataset(tmp_path / "serial" / name / "afm_map.nc")
        clustered = xr.load_dataset(tmp_path / "dask" / name / "afm_map.nc")
        assert np.isfinite(serial["k_star_N_per_m"]).all()
        assert serial.equals(clustered)


def test_flagged_damping_and_a_failing_modulus_are_counted_and_warned(
    fixtures, tmp_path, monkeypatch
):
    path = tmp_path / "dart.ibw"
    fixtures.write_dart_ibw(path, points=8, lines=6)
    base = ["--free-frequency", F_FREE, "--tip-position", R_TIP, "--out", tmp_path / "o"]
    # 50 N on a 20 nm tip: no Hertz contact anywhere, M NaN on all 48 pixels.
    figures_not_drawn(monkeypatch)  # the maps' numbers and files, not their pixels
    r = _ok(run("afm", "map", path, *base, "--force", 50, "--tip-radius", 2e-8))
    assert "48 modulus-flagged" in r.output
    warned = [
        line for line in r.output.splitlines() if line.startswith("contactres: warning: M is NaN")
    ]
    assert len(warned) == 1 and "48 pixels" in warned[0] and "--force/--tip-radius" in warned[0]
    record = json.loads((tmp_path / "o" / "afm_map.json").read_text())
    assert "not_hertzian" in record["conventions"]["flags_present"]
    # A free Q far below the contact's Q: σ < 0 everywhere, σ and tan δ NaN, one warning.
    r = _ok(run("afm", "map", path, *base, "--free-q", 1.0))
    assert "48 flagged" in r.output and "tan δ median" not in r.output
    warned = [line for line in r.output.splitlines() if "negative_damping" in line]
    assert len(warned) == 1 and warned[0].startswith("contactres: warning: 48 pixels")


def test_files_contactres_did_not_write_are_refused_before_the_work(
    fixtures, tmp_path, monkeypatch
):
    """Issue 27: an afm_map.json of the user's in --out, or a Zarr store another program wrote
    at --map-name, is refused in one line before the map is computed; nothing changes."""
    from contactres.jobs import afm_map

    path = tmp_path / "dart.ibw"
    fixtures.write_dart_ibw(path, points=8, lines=6)
    out = tmp_path / "o"
    out.mkdir()
    (out / "afm_map.json").write_text("my notes")

    def never(*args, **kwargs):
        raise AssertionError("the work started before the folder was checked")

    monkeypatch.setattr(afm_map, "series", never)
    base = ["--free-frequency", F_FREE, "--tip-position", R_TIP, "--out", out]
    one_line_error(run("afm", "map", path, *base), "(afm_map.json)", "did not write")
    (out / "afm_map.json").unlink()
    xr.Dataset({"t": ("x", np.arange(3.0))}).to_zarr(out / "m.zarr", consolidated=False)
    before = sorted(str(p.relative_to(out)) for p in out.rglob("*"))
    r = run("afm", "map", path, *base, "--map-name", "m.zarr")
    one_line_error(r, "m.zarr", "did not write")
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == before
