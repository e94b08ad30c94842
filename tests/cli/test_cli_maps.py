"""Tests of ``contactres maps synthetic|predict|fit`` against independent facts: the Hertz closed
form of a spherical tip, the scalar indentation modulus of each grain, the static limit of the
DCSF, Cu's tabulated constants; and one-line errors for bad input to every option."""

import hashlib
import json
import math
import os
import re
import shutil
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
from cli_checks import one_line_error, option_names, run

import contactres
from contactres import Material, indentation_modulus
from contactres.polycrystal import read_map, surface_matrices_from_euler

F, R = 1e-6, 2e-8  # static force, N; tip radius, m
TIP = ["--tip-radius", R, "--force", F]
M_TIP = 1.14e12  # diamond, E/(1 - ν²), Pa
NOISE = 0.002
SMALL = ["--shape", "96x96", "--grains", 20, "--noise", NOISE, "--crystal", "Cu", *TIP]
DATA = Path(contactres.__file__).parent / "data"
CU = Material.crystal("Cu")


def _ok(r):
    assert r.exit_code == 0, r.output
    return r


def _json_record(r):
    rows = json.loads(_ok(r).stdout)
    assert len(rows) == 1
    return rows[0]


def _hertz_rigid(M):
    """k* of a rigid sphere on a half-space of indentation modulus M: K = 2aM with
    a = (3FR/4M)^{1/3}, i.e. (6 F R M²)^{1/3} (Johnson 1985, Eq. 4.22 differentiated)."""
    return (6 * F * R * np.asarray(M) ** 2) ** (1 / 3)


def _exact_modulus(euler):
    """M of Cu whose surface frame is given by Bunge angles (rad), by the scalar routine."""
    Rm = surface_matrices_from_euler(*euler, degrees=False)
    return indentation_modulus(CU.rotated(Rm[2], Rm[0]))


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """A 96x96 labelled synthetic Cu map (20 grains, 0.2 % noise) and the exact M per grain."""
    path = tmp_path_factory.mktemp("maps") / "small.zarr"
    _ok(run("maps", "synthetic", *SMALL, "--out", path))
    ds = read_map(path)
    labels = ds["labels"].values
    euler = ds["euler"].values
    truth = {int(g): _exact_modulus(euler[labels == g][0]) for g in np.unique(labels)}
    return path, truth


def _predict(store, out, *extra):
    return run("maps", "predict", store, "--out", out, "--crystal", "Cu", *TIP, *extra)


def _per_pixel(labels, truth):
    return np.vectorize(truth.__getitem__)(labels)


# --------------------------------------------------------------------------------- synthetic


def test_synthetic_store_is_hertz_per_grain_with_the_stated_noise(small):
    path, truth = small
    ds = read_map(path)
    k, labels = ds["k_star_N_per_m"].values, ds["labels"].values
    assert k.shape == (96, 96) and len(truth) == 20
    # every pixel in one grain has that grain's orientation
    e = ds["euler"].values
    for g in truth:
        assert np.ptp(e[labels == g], axis=0).max() == 0
    sizes = {g: int((labels == g).sum()) for g in truth}
    for g in sorted(sizes, key=sizes.get)[-3:]:  # a few grains, the largest
        kg = k[labels == g]
        expected = _hertz_rigid(truth[g])
        assert abs(kg.mean() / expected - 1) < 5 * NOISE / math.sqrt(kg.size)
        assert kg.std(ddof=1) / kg.mean() == pytest.approx(NOISE, rel=0.25)
    # all pixels: the relative deviation from the grain's Hertz k* has the stated spread
    dev = k / _hertz_rigid(_per_pixel(labels, truth)) - 1
    assert abs(dev.mean()) < 5 * NOISE / math.sqrt(dev.size)
    assert dev.std() == pytest.approx(NOISE, rel=0.05)


def test_synthetic_flags_an_approximate_hertz_contact_as_predict_does(tmp_path):
    """a/R between a tenth and a half of the tip radius: the map is made, with predict's
    warning on stderr and in the store's attributes (a by hand: (3FR/4M)^(1/3) on the softest
    orientation of Cu, M(001) = 1.34e11 Pa: 4.8e-9 m on a 20 nm tip, 0.24)."""
    store = tmp_path / "s.zarr"
    m001 = indentation_modulus(CU)
    a = (3 * 1e-6 * 2e-8 / (4 * m001)) ** (1 / 3)
    r = _ok(run("maps", "synthetic", "--crystal", "Cu", "--tip-radius", "2e-8", "--force", "1e-6",
                "--shape", "8x8", "--grains", "2", "--out", store))  # fmt: skip
    assert f"a/R = {a / 2e-8:.3g} > 0.1" in r.stderr and "warning" in r.stderr
    assert f"a/R = {a / 2e-8:.3g}" in read_map(store).attrs["hertz_flag"]
    r = _ok(run("maps", "synthetic", "--crystal", "Cu", "--tip-radius", "2e-8", "--force", "1e-8",
                "--shape", "8x8", "--grains", "2", "--out", tmp_path / "t.zarr"))  # fmt: skip
    assert r.stderr == ""


# ----------------------------------------------------------------------------------- predict


def test_predict_grains_is_the_exact_modulus_and_hertz(small, tmp_path):
    path, truth = small
    out = tmp_path / "p.zarr"
    rec = _json_record(_predict(path, out, "--format", "json"))
    assert rec["method"] == "grains"  # auto on a labelled store
    assert rec["exact_evaluations"] == 20 and rec["pixels"] == 96 * 96
    ds = read_map(out)
    M_true = _per_pixel(ds["labels"].values, truth)
    np.testing.assert_allclose(ds["M_Pa"].values, M_true, rtol=1e-9)
    np.testing.assert_allclose(ds["E_star_Pa"].values, M_true, rtol=1e-9)  # rigid tip
    np.testing.assert_allclose(ds["k_star_N_per_m"].values, _hertz_rigid(M_true), rtol=1e-9)
    a = (3 * F * R / (4 * M_true)) ** (1 / 3)
    np.testing.assert_allclose(ds["contact_radius_m"].values, a, rtol=1e-9)
    # the input's variables are kept
    np.testing.assert_array_equal(ds["euler"].values, read_map(path)["euler"].values)
    assert rec["M_min_Pa"] == pytest.approx(min(truth.values()), rel=1e-9)
    assert rec["M_max_Pa"] == pytest.approx(max(truth.values()), rel=1e-9)
    # --method grains asked for gives the same
    out2 = tmp_path / "g.zarr"
    _ok(_predict(path, out2, "--method", "grains"))
    np.testing.assert_array_equal(read_map(out2)["M_Pa"].values, ds["M_Pa"].values)


def test_predict_interpolated_is_within_its_stated_error(small, tmp_path):
    path, truth = small
    out = tmp_path / "i.zarr"
    rec = _json_record(_predict(path, out, "--method", "interpolated", "--format", "json"))
    assert rec["method"] == "interpolated"
    stated = float(rec["M_stated_error"])
    ds = read_map(out)
    assert float(ds.attrs["M_stated_error"]) == stated
    assert 0 < stated <= 1e-4  # the default --rtol
    M_true = _per_pixel(ds["labels"].values, truth)
    err = np.abs(ds["M_Pa"].values / M_true - 1)
    assert err.max() <= 2 * stated, (err.max(), stated)
    np.testing.assert_allclose(
        ds["k_star_N_per_m"].values, _hertz_rigid(ds["M_Pa"].values), rtol=1e-12
    )
    # the plain summary prints the same stated error
    r = _ok(_predict(path, tmp_path / "i2.zarr", "--method", "interpolated"))
    assert f"error {rec['M_stated_error']}" in r.stdout


def test_predict_an_unlabelled_ebsd_export_interpolates_within_its_stated_error(tmp_path):
    out = tmp_path / "ang.zarr"
    rec = _json_record(
        _predict(DATA / "example_cu_map.ang", out, "--format", "json")  # no labels: auto
    )
    assert rec["method"] == "interpolated" and rec["pixels"] == 64 * 64
    ds = read_map(out)
    euler = ds["euler"].values.reshape(-1, 3)
    distinct, which = np.unique(euler, axis=0, return_inverse=True)
    assert len(distinct) == 16  # the example's grains, one orientation each
    M_true = np.array([_exact_modulus(e) for e in distinct])[which.ravel()].reshape(64, 64)
    err = np.abs(ds["M_Pa"].values / M_true - 1)
    assert err.max() <= 2 * float(rec["M_stated_error"])


def test_predict_with_a_compliant_tip_is_hertz_with_series_moduli(small, tmp_path):
    path, truth = small
    out = tmp_path / "t.zarr"
    _ok(_predict(path, out, "--tip-modulus", M_TIP))
    ds = read_map(out)
    M = _per_pixel(ds["labels"].values, truth)
    E_star = 1 / (1 / M + 1 / M_TIP)
    a = (3 * F * R / (4 * E_star)) ** (1 / 3)
    np.testing.assert_allclose(ds["E_star_Pa"].values, E_star, rtol=1e-9)
    np.testing.assert_allclose(ds["contact_radius_m"].values, a, rtol=1e-9)
    np.testing.assert_allclose(ds["k_star_N_per_m"].values, 2 * a * E_star, rtol=1e-9)
    assert ds.attrs["tip_modulus_Pa"] == M_TIP


def test_predict_at_a_low_frequency_is_the_static_limit(small, tmp_path):
    path, _ = small
    out = tmp_path / "f.zarr"
    _ok(_predict(path, out, "--frequency", 1e3))  # Cu's built-in density
    ds = read_map(out)
    assert ds.attrs["frequency_Hz"] == 1e3
    assert np.all(ds["ka_l"].values > 0) and ds["ka_l"].values.max() < 1e-6
    np.testing.assert_allclose(ds["dcsf_real"].values, 1.0, atol=1e-3)
    assert np.abs(ds["dcsf_imag"].values).max() < 1e-3
    np.testing.assert_allclose(
        ds["k_dynamic_real_N_per_m"].values, ds["k_star_N_per_m"].values, rtol=1e-3
    )


def _film_modulus(name):
    """E/(1 − ν²) of an isotropic built-in solid from its C11, C12 (ν = C12/(C11 + C12))."""
    C = np.real(Material.crystal(name).C)
    nu = C[0, 1] / (C[0, 0] + C[0, 1])
    e = C[0, 0] * (1 + nu) * (1 - 2 * nu) / (1 - nu)
    return e / (1 - nu**2)


def test_predict_with_a_coating_of_the_crystals_own_material_is_the_bare_map(small, tmp_path):
    """An isotropic crystal under a film of its own material: M_coated = M, k*_coated = k*."""
    path, _ = small
    out = tmp_path / "own.zarr"
    r = _ok(
        run("maps", "predict", path, "--out", out, "--crystal", "fused-silica", *TIP,
            "--coating", "fused-silica:2e-9")
    )  # fmt: skip
    ds = read_map(out)
    np.testing.assert_allclose(ds["M_coated_Pa"].values, ds["M_Pa"].values, rtol=1e-8)
    np.testing.assert_allclose(
        ds["k_star_coated_N_per_m"].values, ds["k_star_N_per_m"].values, rtol=1e-8
    )
    assert "under fused-silica 2 nm: M_coated from" in r.output


def test_predict_under_a_thick_film_gives_the_films_modulus_everywhere(small, tmp_path):
    """Cu under 1 mm of fused silica (a ≈ 5 nm): the film's E/(1 − ν²) at every pixel (the
    substrate shows at O(a/h)), the bare variables as without --coating."""
    path, _ = small
    bare, coated = tmp_path / "bare.zarr", tmp_path / "thick.zarr"
    _ok(_predict(path, bare))
    rec = _json_record(_predict(path, coated, "--coating", "fused-silica:1e-3", "--format", "json"))
    ds, ref = read_map(coated), read_map(bare)
    M = ds["M_coated_Pa"].values
    np.testing.assert_allclose(M, _film_modulus("fused-silica"), rtol=1e-5)
    for name in ("M_Pa", "contact_radius_m", "k_star_N_per_m"):
        np.testing.assert_array_equal(ds[name].values, ref[name].values)
    assert rec["coating"] == "fused-silica 1 mm"
    assert rec["M_coated_max_Pa"] == pytest.approx(np.nanmax(M))
    assert float(rec["M_coated_stated_error"]) <= 1e-6


def test_predict_on_a_dask_cluster_equals_the_serial_run(small, tmp_path):
    distributed = pytest.importorskip("distributed", reason="dask.distributed not installed")
    path, _ = small
    common = ["--method", "interpolated", "--chunks", 32]  # 9 chunks
    _ok(_predict(path, tmp_path / "serial.zarr", *common))
    with distributed.LocalCluster(
        n_workers=1, processes=False, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        address = cluster.scheduler_address
        _ok(_predict(path, tmp_path / "cluster.zarr", *common, "--scheduler", address))
    serial = read_map(tmp_path / "serial.zarr")["M_Pa"].values
    clustered = read_map(tmp_path / "cluster.zarr")["M_Pa"].values
    assert np.isfinite(serial).all()
    assert np.array_equal(serial, clustered)


# --------------------------------------------------------------------------------------- fit


def test_cu_constants_are_the_tabulated_ones():
    C = np.asarray(CU.C)
    assert (C[0, 0], C[0, 1], C[3, 3]) == pytest.approx((168.4e9, 121.4e9, 75.4e9), rel=1e-12)


def test_fit_recovers_cu_ratios_from_a_large_synthetic_map(tmp_path):
    store, out = tmp_path / "big.zarr", tmp_path / "fit.json"
    _ok(run("maps", "synthetic", "--shape", "200x200", "--grains", 40, "--noise", NOISE,
            "--crystal", "Cu", *TIP, "--out", store))  # fmt: skip
    flat = _json_record(run("maps", "fit", store, "--out", out, "--format", "json"))
    doc = json.loads(out.read_text())
    C = np.asarray(CU.C)
    truth = {"c12_c11": C[0, 1] / C[0, 0], "c44_c11": C[3, 3] / C[0, 0]}
    for key, value in truth.items():
        sigma = doc[f"{key}_error"]
        assert 0 < sigma < 0.02, (key, sigma)  # small enough for the test to mean something
        assert abs(doc[key] - value) < 3 * sigma, (key, doc[key], value, sigma)
        assert flat[key] == doc[key]
    assert doc["n_grains"] == 40 and doc["segmented"] is False and doc["pixels"] == 200 * 200
    assert doc["strong_identified"] is True and doc["weak_identified"] is True
    assert isinstance(doc["conventions"], dict) and "null" in doc["conventions"]
    # without --tip-radius/--force the calibration, hence C11, is not determined: null
    for key in ("c11", "c12", "c44", "c11_error", "calibration"):
        assert doc[key] is None, key


def test_fit_of_the_bundled_example_reports_the_weak_combination_undetermined(
    tmp_path, monkeypatch
):
    from contactres.jobs import maps_fit

    computed: list = []
    compute = maps_fit.run

    def once(inputs, settings, progress=None):  # the second run prints the same fit as JSON
        if computed:
            assert (inputs, settings) == computed[0][0]
        else:
            computed.append(((inputs, settings), compute(inputs, settings, progress)))
        return computed[0][1]

    monkeypatch.setattr(maps_fit, "run", once)
    out = tmp_path / "ex.json"
    values = ["--values", DATA / "example_cu_kstar.csv"]
    r = _ok(run("maps", "fit", DATA / "example_cu_map.ang", *values, "--out", out))
    doc = json.loads(out.read_text())
    assert doc["segmented"] is True  # the .ang holds no labels
    assert 12 <= doc["n_grains"] <= 16  # the map was made with 16 grains
    assert doc["c12_c11"] is None and doc["c44_c11"] is None
    assert doc["weak_identified"] is False and doc["weak_combination"] is None
    assert doc["strong_identified"] is True
    for ratio in ("C12/C11", "C44/C11"):
        lines = [x for x in r.stdout.splitlines() if x.strip().startswith(ratio)]
        assert len(lines) == 1 and f"{ratio} = not determined" in lines[0], r.stdout
        assert not re.search(re.escape(ratio) + r"\s*=\s*[-+0-9.]", r.stdout), r.stdout
    truth = indentation_modulus(CU.rotated((1, 1, 1))) / indentation_modulus(CU.rotated((0, 0, 1)))
    sigma = doc["anisotropy_111_error"]
    assert 0 < sigma < 0.01
    assert abs(doc["anisotropy_111"] - truth) < 3 * sigma, (doc["anisotropy_111"], truth, sigma)
    # Issue 27: in --format csv/json the warnings (here: the weak combination undetermined)
    # were only in the JSON file; they are in the record and on stderr too.
    r = _ok(run("maps", "fit", DATA / "example_cu_map.ang", *values, "--out", out,
                "--format", "json"))  # fmt: skip
    (record,) = json.loads(r.stdout)  # one record, as a list of rows
    assert record["warnings"] == "; ".join(doc["warnings"]) and doc["warnings"]
    warned = [x for x in r.stderr.splitlines() if x.startswith("contactres: warning: ")]
    assert [x.removeprefix("contactres: warning: ") for x in warned] == doc["warnings"]


# ------------------------------------------------------------------------ output and inputs


def _digest(folder: Path) -> dict:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def test_output_replaces_atomically_and_inputs_are_untouched(small, tmp_path):
    path, _ = small
    store = tmp_path / "in.zarr"
    shutil.copytree(path, store)
    before = _digest(store)
    out = tmp_path / "p.zarr"
    _ok(_predict(store, out))
    rigid = read_map(out)["k_star_N_per_m"].values
    _ok(_predict(store, out, "--tip-modulus", M_TIP))  # an earlier store is replaced
    compliant = read_map(out)["k_star_N_per_m"].values
    assert np.all(compliant < rigid)
    # predicting onto the input itself is refused, in one line, and nothing changes
    one_line_error(_predict(store, store), str(store), "input")
    assert _digest(store) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.zarr", "p.zarr"]  # no staging
    # maps fit: the JSON may not overwrite the measured map
    np.savetxt(tmp_path / "k.csv", rigid, delimiter=",")
    one_line_error(
        run("maps", "fit", store, "--values", tmp_path / "k.csv", "--out", tmp_path / "k.csv"),
        "k.csv",
    )
    assert _digest(store) == before


def test_a_rerun_replaces_only_a_store_contactres_wrote_with_nothing_added(tmp_path):
    """Issue 27: a rerun of maps synthetic / maps predict into an existing store replaced it
    whole, deleting a notes.txt or another array inside it, or another program's store."""
    xr = pytest.importorskip("xarray")
    tiny = ["--shape", "8x8", "--grains", 2, "--crystal", "Cu", *TIP]
    store = tmp_path / "s.zarr"
    _ok(run("maps", "synthetic", *tiny, "--out", store))
    _ok(run("maps", "synthetic", *tiny, "--seed", 3, "--out", store))  # its own: replaced
    (store / "notes.txt").write_text("my notes")
    xr.Dataset({"mine": ("x", np.arange(3.0))}).to_zarr(store / "grp", consolidated=False)
    _ok(run("maps", "synthetic", *tiny, "--out", tmp_path / "in.zarr"))
    before = _digest(store)
    for r in (
        run("maps", "synthetic", *tiny, "--out", store),
        _predict(tmp_path / "in.zarr", store),
    ):
        one_line_error(r, "'" + str(store) + "'", "did not write", "(grp, notes.txt)")
        assert _digest(store) == before
    theirs = tmp_path / "theirs.zarr"
    xr.Dataset({"t": ("x", np.arange(3.0))}).to_zarr(theirs, consolidated=False)
    before = _digest(theirs)
    one_line_error(run("maps", "synthetic", *tiny, "--out", theirs), "theirs.zarr", "did not write")
    assert _digest(theirs) == before


# ---------------------------------------------------------------------------------- bad input

SYN = {"--out": "o.zarr", "--crystal": "Cu", "--tip-radius": "2e-8", "--force": "1e-6",
       "--shape": "8x8", "--grains": "2"}  # fmt: skip
SYN_BARE = {k: v for k, v in SYN.items() if k != "--crystal"}
SYN_CONST = {**SYN_BARE, "--c11": "168.4e9", "--c12": "121.4e9", "--c44": "75.4e9"}


PRE = {"map": "in.zarr", "--out": "p.zarr", "--crystal": "Cu", "--tip-radius": "2e-8",
       "--force": "1e-6"}  # fmt: skip
PRE_CONST = {**{k: v for k, v in PRE.items() if k != "--crystal"},
             "--c11": "168.4e9", "--c12": "121.4e9", "--c44": "75.4e9"}  # fmt: skip
PRE_INTERP = {**PRE, "--method": "interpolated"}
PRE_HEX = {**PRE_CONST, "--c13": "100e9", "--c33": "170e9"}
FIT = {"map": "in.zarr", "--out": "f.json"}


# (command, base, option, value, words the one line must name; None: the option and value).
# "map" is the positional MAP argument.
BAD = [
    ("synthetic", SYN, "--out", "notzarr", ("'notzarr'", "not a Zarr store")),
    ("synthetic", SYN, "--crystal", "quartz", ("--crystal", "quartz", "trigonal")),
    ("synthetic", SYN_BARE, "--c11", "168.4e9", ("missing", "--c12", "--c44")),
    ("synthetic", SYN_CONST, "--c12", "nan", None),
    ("synthetic", SYN_CONST, "--c13", "100e9", ("missing --c33",)),
    ("synthetic", SYN_CONST, "--c33", "-1e11", None),
    ("synthetic", SYN_CONST, "--c44", "75.4", ("--c44", "75.4", "gigapascals")),
    ("synthetic", SYN, "--density", "8.96", ("--density", "8.96", "g/cm^3")),
    ("synthetic", SYN, "--tip-radius", "20", None),
    ("synthetic", SYN, "--force", "-1", None),
    # 1 N on a 20 nm tip: a/R = 24 on Cu, beyond Hertz; the map was made without a word
    # (issue 27's closing campaign), as maps predict refuses it
    ("synthetic", SYN, "--force", "1", ("--force 1 N", "24.1 times the tip radius", "units")),
    ("synthetic", SYN, "--tip-modulus", "1.14e3", ("--tip-modulus", "1.14e3", "gigapascals")),
    ("synthetic", SYN, "--shape", "0x5", None),
    ("synthetic", SYN, "--grains", "0", None),
    ("synthetic", SYN, "--seed", "-1", None),
    ("synthetic", SYN, "--noise", "0.7", None),
    ("synthetic", SYN, "--pixel-size", "1e3", ("--pixel-size", "1e3", "nanometres")),
    ("predict", PRE, "map", "nosuch.zarr", ("MAP", "nosuch.zarr")),
    ("predict", PRE, "--out", "nodir/p.zarr", ("nodir",)),
    ("predict", PRE, "--crystal", "Xx", ("--crystal", "'Xx'", "unknown crystal")),
    ("predict", PRE_CONST, "--c11", "168.4", ("--c11", "168.4", "gigapascals")),
    ("predict", PRE, "--c12", "121.4e9", ("--crystal", "--c12", "not both")),
    ("predict", PRE_HEX, "--c13", "nan", None),
    ("predict", PRE_HEX, "--c33", "1e3", None),
    ("predict", PRE_CONST, "--c44", "-75.4e9", None),
    ("predict", PRE, "--density", "8.96", None),
    ("predict", PRE, "--tip-radius", "20", None),
    ("predict", PRE, "--force", "-1", None),
    ("predict", PRE, "--tip-modulus", "1.14e3", None),
    ("predict", PRE, "--method", "foo", None),
    ("predict", PRE_INTERP, "--rtol", "0.5", ("--rtol", "0.5", "0.01")),
    ("predict", PRE, "--frequency", "5", None),
    ("predict", PRE, "--model", "R1", None),
    ("predict", PRE, "--chunks", "0", None),
    ("predict", PRE, "--scheduler", "localhost:8786", None),
    ("predict", PRE, "--figure", "nodir/m.png", ("nodir",)),
    ("predict", PRE, "--format", "xml", None),
    ("predict", PRE, "--min-confidence", "2", ("--min-confidence",)),
    ("predict", PRE, "--max-mad", "0", ("--max-mad",)),
    ("predict", PRE, "--phase", "3", ("phase 3",)),
    ("predict", PRE, "--coating", "unobtainium:1e-8", ("--coating", "unobtainium")),
    # a flag takes no value: the word after it is refused as an extra argument
    ("predict", PRE, "--ignore-phase-name", "maybe", ("unexpected extra argument", "maybe")),
    ("fit", FIT, "map", "nosuch.zarr", ("MAP", "nosuch.zarr")),
    ("fit", FIT, "--out", "nodir/f.json", ("nodir",)),
    ("fit", FIT, "--values", "badcell.csv", ("badcell.csv", "row 3", "column 5", "1.3e3x")),
    ("fit", FIT, "--variable", "missing_name", ("in.zarr", "missing_name")),
    ("fit", FIT, "--quantity", "foo", None),
    ("fit", FIT, "--lattice", "triclinic", None),
    ("fit", FIT, "--tolerance-deg", "0", None),
    ("fit", FIT, "--tip-radius", "2e-8", ("--tip-radius", "--force")),
    ("fit", FIT, "--force", "-1", None),
    ("fit", FIT, "--tip-modulus", "1.14e3", None),
    ("fit", FIT, "--format", "xml", None),
    ("fit", FIT, "--min-confidence", "nan", ("--min-confidence",)),
    ("fit", FIT, "--max-mad", "-1", ("--max-mad",)),
    ("fit", FIT, "--phase", "-1", ("--phase",)),
]

# More cases: combinations and the other ways a file or an output can be wrong.
MORE = [
    ("synthetic", SYN, "--crystal", "Xx", ("--crystal", "'Xx'")),
    ("synthetic", SYN, "--out", "nodir/o.zarr", ("nodir",)),
    ("synthetic", SYN_CONST, "--c11", "100e9", ("--c11", "unstable")),  # c11 < c12
    ("predict", PRE, "--out", "notzarr", ("'notzarr'", "not a Zarr store")),
    ("predict", PRE, "--figure", "m.jpg2", ("--figure", "'m.jpg2'", ".png, .svg, .pdf")),
    ("predict", PRE, "--out", "in.zarr", ("'in.zarr'", "input")),
    ("predict", PRE, "map", "notzarr", ("notzarr", "Zarr")),
    ("predict", PRE, "map", "good.csv", ("good.csv", ".ang")),
    ("predict", PRE_CONST, "--frequency", "1e3", ("--frequency", "--density")),
    ("predict", PRE_CONST, "--c13", "100e9", ("missing --c33",)),
    ("predict", PRE, "--rtol", "0.5", ("--rtol", "0.5")),
    ("predict", PRE_INTERP, "--rtol", "1e-9", ("--rtol", "1e-09")),
    ("predict", PRE, "--coating", "pmma250e-9", ("--coating", "MATERIAL:THICKNESS")),
    (
        "predict",
        {**PRE, "--frequency": "1e3"},
        "--coating",
        "pmma:2.5e-7",
        ("--coating", "--frequency", "wave speeds", "dcsf --coating"),
    ),
    ("fit", FIT, "--values", "neg.csv", ("neg.csv", "row 6", "column 2", "-1300")),
    ("fit", FIT, "--values", "shape.csv", ("--values", "shape.csv", "96 rows x 95 columns")),
    ("fit", FIT, "--values", "nosuch.csv", ("--values", "nosuch.csv")),
    ("fit", FIT, "--values", "empty.csv", ("empty.csv",)),
    ("fit", FIT, "--tip-radius", "20", ("--tip-radius", "20")),
    ("fit", {**FIT, "--values": "good.csv"}, "--out", "good.csv", ("'good.csv'", "input")),
    ("fit", FIT, "--out", "in.zarr", ("--out", "in.zarr")),
]


def _id(case):
    values = case.values if hasattr(case, "values") else case
    return f"{values[0]}{values[2]}={values[3]}"


@pytest.fixture
def bad_inputs(small, tmp_path, monkeypatch):
    """A folder with the store in.zarr, a non-Zarr folder and measured maps good and bad."""
    monkeypatch.chdir(tmp_path)
    shutil.copytree(small[0], "in.zarr")
    os.mkdir("notzarr")
    good = np.full((96, 96), "1300", dtype=object)
    np.savetxt("good.csv", good.astype(float), delimiter=",")
    for name, (i, j, cell) in {"badcell.csv": (2, 4, "1.3e3x"), "neg.csv": (5, 1, "-1300")}.items():
        g = good.copy()
        g[i, j] = cell
        Path(name).write_text("\n".join(",".join(row) for row in g) + "\n")
    np.savetxt("shape.csv", np.full((96, 95), 1300.0), delimiter=",")
    Path("empty.csv").write_text("")
    return tmp_path


def _invoke(command, base, option, value):
    options = {**base, option: value}
    positional = [options.pop("map")] if "map" in options else []
    return run("maps", command, *positional, *[x for kv in options.items() for x in kv])


@pytest.mark.parametrize("command, base, option, value, words", BAD + MORE,
                         ids=[_id(c) for c in BAD + MORE])  # fmt: skip
def test_each_option_refuses_bad_input_in_one_line(bad_inputs, command, base, option, value,
                                                   words):  # fmt: skip
    listing = sorted(os.listdir(bad_inputs))
    r = _invoke(command, base, option, value)
    one_line_error(r, *(words or (option, value)))
    assert sorted(os.listdir(bad_inputs)) == listing  # nothing written


def test_every_option_has_a_bad_input_case():
    from contactres.cli.maps import maps_fit, maps_predict, maps_synthetic

    def cases(name):
        options = set()
        for case in BAD:
            values = case.values if hasattr(case, "values") else case
            if values[0] == name:
                options.add("map_path" if values[2] == "map" else values[2])
        return options

    assert option_names(maps_synthetic) == cases("synthetic")
    assert option_names(maps_predict) == cases("predict")
    assert option_names(maps_fit) == cases("fit")


def test_predict_per_grain_ignores_unlabelled_pixels():
    # Labels [0, 0, -1, 1]: the -1 pixel (another orientation) must not lend grain 1 its
    # orientation, and gets NaN, not an error.
    from contactres import Material, indentation_modulus
    from contactres.jobs.maps import TipLoad, predict_map
    from contactres.polycrystal._maps import OrientationMap

    euler = np.zeros((1, 4, 3))
    euler[0, :2] = (0.3, 0.9, 0.2)
    euler[0, 2] = (0.1, 0.7, 1.0)
    omap = OrientationMap(
        euler, 1e-6, 1e-6, np.ones((1, 4)), np.ones((1, 4)), labels=np.array([[0, 0, -1, 1]])
    )
    cu = Material.crystal("Cu")
    ds, info = predict_map(omap, cu, "cubic", TipLoad(2e-8, 1e-6), method="grains")
    M = ds["M_Pa"].values[0]
    assert info["method"] == "grains" and np.isnan(M[2]) and np.isnan(ds["k_star_N_per_m"][0, 2])
    assert M[3] == pytest.approx(indentation_modulus(cu), rel=1e-9)  # Euler (0, 0, 0): (001)


# ------------------------------------------------------------------ pixels that are not indexed


def _with_holes(store, tmp_path):
    """The .ang of the synthetic map with a 30x30 block not indexed (CI -1, phase 0, angles 0,
    as OIM writes such pixels) and its measured k* (the instrument measured there too)."""
    from dataclasses import replace

    from contactres.polycrystal import map_from_dataset, write_ang

    ds = read_map(store)
    omap = map_from_dataset(ds)
    hole = np.zeros(omap.shape, dtype=bool)
    hole[10:40, 20:50] = True
    euler = np.where(hole[..., None], 0.0, omap.euler)
    omap = replace(
        omap,
        euler=euler,
        labels=None,
        phase=np.where(hole, 0, 1),
        confidence=np.where(hole, -1.0, 0.9),
        confidence_name="CI",
    )
    ang = write_ang(tmp_path / "holes.ang", omap)
    values = tmp_path / "kstar.csv"
    np.savetxt(values, ds["k_star_N_per_m"].values, delimiter=",")
    return ang, values, hole


def test_unindexed_pixels_are_left_out_of_predictions_and_fits(tmp_path):
    """Issue 27: unindexed pixels (phase 0, CI -1) got a Cu modulus, and a fit on such a map
    moved the strong combination far outside its error. They are left out and counted."""
    store = tmp_path / "big.zarr"
    _ok(run("maps", "synthetic", "--shape", "120x120", "--grains", 30, "--noise", NOISE,
            "--crystal", "Cu", *TIP, "--out", store))  # fmt: skip
    ang, values, hole = _with_holes(store, tmp_path)
    r = _ok(_predict(ang, tmp_path / "p.zarr"))
    assert r.stdout.splitlines()[0] == "900 of 14400 pixels left out: 900 not indexed"
    M = read_map(tmp_path / "p.zarr")["M_Pa"].values
    assert np.isnan(M[hole]).all() and np.isfinite(M[~hole]).all()
    r = _ok(run("maps", "fit", ang, "--values", values, "--out", tmp_path / "f.json"))
    doc = json.loads((tmp_path / "f.json").read_text())
    assert doc["pixels_left_out"] == 900 and doc["pixels"] <= 14400 - 900
    # The same fit as of the map without that block (angles and values NaN: no indexing rule
    # involved), a second path through the API; with the placeholder angles kept, not.
    from dataclasses import replace

    from contactres.jobs.maps import fit_measured_map
    from contactres.polycrystal import map_from_dataset

    ds = read_map(store)
    omap = replace(map_from_dataset(ds), labels=None)
    k = ds["k_star_N_per_m"].values
    blank = replace(omap, euler=np.where(hole[..., None], np.nan, omap.euler))
    ref, _, _ = fit_measured_map(blank, np.where(hole, np.nan, k), quantity="stiffness")
    assert doc["strong_combination"] == pytest.approx(ref.strong_combination, rel=1e-12)
    assert doc["n_grains"] == ref.n_grains
    # A phase the map does not hold, and a threshold outside CI's range: one line each.
    bad = _predict(ang, tmp_path / "q.zarr", "--phase", 3)
    assert bad.exit_code == 2 and "no indexed pixel of phase 3; its phases are 1" in bad.output
    bad = _predict(ang, tmp_path / "q.zarr", "--min-confidence", 2)
    assert bad.exit_code == 2 and "--min-confidence" in bad.output


def test_pixels_without_a_measured_value_are_named(tmp_path):
    """Issue 27's closing campaign: an indexed pixel whose measured value is NaN or empty was
    left out of the fit with only the count of pixels used changing (4095 of 4096); it is
    named with the indexing rule and counted in pixels_left_out."""
    ang, kstar = contactres.example_path("example_cu_map.ang"), "example_cu_kstar.csv"
    k = np.loadtxt(contactres.example_path(kstar), delimiter=",")
    holes = [(5, 3), (17, 40), (63, 63)]
    for i, j in holes:
        k[i, j] = np.nan
    values = tmp_path / "k.csv"
    np.savetxt(values, k, delimiter=",")
    r = _ok(run("maps", "fit", ang, "--values", values, "--out", tmp_path / "f.json"))
    assert "3 of 4096 pixels left out: 3 without a measured value (NaN or empty)" in r.stdout
    doc = json.loads((tmp_path / "f.json").read_text())
    assert doc["pixels_left_out"] == 3 and doc["pixels"] == 4096 - 3


def test_predict_flags_hertz_approximate_at_a_over_r_0_3(small, tmp_path):
    """issue 30: between a/R = 0.1 and 0.5 the map is computed but flagged, as ``contact``
    flags its rows. On an isotropic solid (M = E/(1 − ν²) everywhere) under a rigid tip, the
    force that puts a/R at 0.3 follows from Hertz's a³ = 3FR/(4M) (Johnson 1985, Eq. 4.22)."""
    path, _ = small
    force = 4 * _film_modulus("fused-silica") * (0.3 * R) ** 3 / (3 * R)
    out = tmp_path / "flagged.zarr"
    args = ["maps", "predict", path, "--out", out, "--crystal", "fused-silica"]
    r = _ok(run(*args, "--tip-radius", R, "--force", force, "--format", "json"))
    warnings = [line for line in r.stderr.splitlines() if "warning" in line]
    assert len(warnings) == 1
    assert "a/R = 0.3 > 0.1 on the softest orientation" in warnings[0]
    assert "Hertz approximate" in warnings[0]
    flag = warnings[0].removeprefix("contactres: warning: ")
    assert _json_record(r)["hertz_flag"] == flag
    assert read_map(out).attrs["hertz_flag"] == flag
    # A tenth of that force (a/R = 0.14) is still flagged; a thousandth (0.03) is not.
    for scale, flagged in ((0.1, True), (1e-3, False)):
        out = tmp_path / f"f{scale}.zarr"
        r = _ok(run(*args[:4], out, *args[5:], "--tip-radius", R, "--force", force * scale))
        assert ("Hertz approximate" in r.stderr) is flagged
        assert ("hertz_flag" in read_map(out).attrs) is flagged


@pytest.mark.parametrize(
    ("command", "out", "wanted"),
    [("synthetic", "o.csv", "name it with .zarr"), ("fit", "o.csv", "name it with .json")],
)
def test_an_output_named_for_another_format_is_refused(tmp_path, monkeypatch, command, out, wanted):
    """Issue 30's review: `maps predict/synthetic --out o.csv` wrote a Zarr folder named o.csv
    and `maps fit --out o.csv` JSON into a .csv; each is now refused in one line, nothing made."""
    monkeypatch.chdir(tmp_path)
    if command == "synthetic":
        args = ["maps", "synthetic", "--crystal", "Cu", "--tip-radius", "2e-8", "--force", "5e-8"]
        args += ["--shape", "8x8", "--grains", "3", "--out", out]
    else:
        ang = files("contactres") / "data" / "example_cu_map.ang"
        kstar = files("contactres") / "data" / "example_cu_kstar.csv"
        args = ["maps", "fit", str(ang), "--values", str(kstar), "--out", out]
    r = run(*args)
    assert r.exit_code == 2 and wanted in r.stderr, r.output
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / out).exists()
