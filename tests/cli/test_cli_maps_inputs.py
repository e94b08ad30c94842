"""Map inputs that used to end in an internal error or a hang (issue 27, point 15): each is now
a one-line input error naming the map and what is wrong, raised before any large allocation."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_checks import one_line_error, run

from contactres.errors import ContactresInputError

pytest.importorskip("zarr", reason="the maps extra (zarr, xarray) is not installed")

from contactres.polycrystal import (
    read_ebsd,
    read_map,
    synthetic_polycrystal,
    write_map,
)

TIP = ["--tip-radius", 2e-8, "--force", 1e-6]


@pytest.fixture(scope="module")
def store(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("maps") / "small.zarr"
    r = run("maps", "synthetic", "--crystal", "Cu", *TIP, "--shape", "24x24", "--grains", 6,
            "--out", path)  # fmt: skip
    assert r.exit_code == 0, r.output
    return path


def _copy(store: Path, tmp_path: Path) -> Path:
    out = tmp_path / "copy.zarr"
    shutil.copytree(store, out)
    return out


def test_synthetic_map_beyond_the_pixel_limit_is_refused_before_allocating(tmp_path):
    r = run("maps", "synthetic", "--crystal", "Cu", *TIP, "--shape", "100000x100000",
            "--out", tmp_path / "big.zarr")  # fmt: skip
    one_line_error(r, "100000 x 100000", "pixels", "limit")
    assert not (tmp_path / "big.zarr").exists()
    with pytest.raises(ContactresInputError, match="limit"):
        synthetic_polycrystal((300, 300), 4, seed=1, max_pixels=80_000)
    assert synthetic_polycrystal((30, 30), 4, seed=1, max_pixels=900).euler.shape == (30, 30, 3)


@pytest.mark.parametrize("size", ["-1", "0.5"])
def test_pixel_size_out_of_range_names_the_pixel_size_not_a_contact_radius(tmp_path, size):
    r = run("maps", "synthetic", "--crystal", "Cu", *TIP, "--pixel-size", size,
            "--out", tmp_path / "m.zarr")  # fmt: skip
    line = one_line_error(r, "--pixel-size", "pixel size")
    assert "contact radius" not in line


def test_store_declaring_ten_billion_pixels_is_refused_from_its_metadata(store, tmp_path):
    # A small store whose metadata declares 10^5 x 10^5 pixels (its chunks absent: fill
    # values); main read it chunk by chunk for minutes.
    path = _copy(store, tmp_path)
    for meta in path.glob("*/zarr.json"):
        info = json.loads(meta.read_text())
        dims = info.get("dimension_names") or []
        info["shape"] = [
            100_000 if d in ("x", "y") else n for d, n in zip(dims, info["shape"], strict=True)
        ]
        meta.write_text(json.dumps(info))
    # Coordinates that cannot be read: refused before reading them, from the metadata alone
    # (an index built first, as xarray does by default, would end in "not readable" here).
    chunks = [f for c in ("x", "y") for f in (path / c / "c").rglob("*") if f.is_file()]
    assert len(chunks) >= 2
    for chunk in chunks:
        chunk.write_bytes(b"not a chunk")
    assert sum(f.stat().st_size for f in path.rglob("*") if f.is_file()) < 200_000
    with pytest.raises(ContactresInputError, match=r"100000 x 100000 = 1e\+10 pixels"):
        read_map(path)
    one_line_error(run("maps", "fit", path, "--out", tmp_path / "fit.json"), "copy.zarr", "limit")


@pytest.mark.parametrize(
    ("damage", "words"),
    [
        ("no-array", ("'euler'", "missing")),
        ("no-metadata", ("'euler'", "missing")),
        ("broken-json", ("not readable",)),
        ("truncated-chunk", ("'euler'", "cannot be read")),
        ("truncated-values", ("'k_star_N_per_m'", "cannot be read")),
        ("truncated-coordinate", ("not readable",)),  # read by xarray's index on opening
    ],
)
def test_half_written_store_is_one_line_naming_the_store(store, tmp_path, damage, words):
    path = _copy(store, tmp_path)
    euler = path / "euler"
    if damage == "no-array":
        shutil.rmtree(euler)
    elif damage == "no-metadata":
        (euler / "zarr.json").unlink()
    elif damage == "broken-json":
        (euler / "zarr.json").write_text("{\n")
    else:
        damaged = {"truncated-chunk": "euler", "truncated-values": "k_star_N_per_m"}
        variable = path / damaged.get(damage, "x")
        chunk = next(f for f in (variable / "c").rglob("*") if f.is_file())
        chunk.write_bytes(chunk.read_bytes()[:40])
    r = run("maps", "fit", path, "--out", tmp_path / "fit.json")
    one_line_error(r, "copy.zarr", *words)


def test_fit_of_a_map_without_contrast_says_so(store, tmp_path):
    ds = read_map(store).load()
    ds["k_star_N_per_m"][:] = 1300.0
    write_map(tmp_path / "constant.zarr", ds)
    r = run("maps", "fit", tmp_path / "constant.zarr", "--out", tmp_path / "fit.json")
    one_line_error(r, "no contrast to fit")
    ds["k_star_N_per_m"][:] = np.nan
    write_map(tmp_path / "empty.zarr", ds)
    r = run("maps", "fit", tmp_path / "empty.zarr", "--out", tmp_path / "fit.json")
    one_line_error(r, "no grain has two or more measured pixels")


def test_ebsd_points_spanning_a_huge_grid_are_refused_before_allocating(tmp_path):
    # Two points 10^5 steps apart in x and y span a grid of 10^10 pixels.
    head = "# XSTEP: 1\n# YSTEP: 1\n# NCOLS_ODD: 2\n# NCOLS_EVEN: 2\n# NROWS: 2\n"
    rows = ["0 0 0 0 0 0 1 1 0 0", "0 0 0 100000 100000 0 1 1 0 0"]
    path = tmp_path / "far.ang"
    path.write_text(head + "\n".join(rows) + "\n")
    with pytest.raises(ContactresInputError, match=r"far\.ang: the points span a grid of"):
        read_ebsd(path)


# ---- the EBSD export's phase name against the crystal given (issue 27) -----------------------


@pytest.fixture(scope="module")
def small_map():
    return synthetic_polycrystal((8, 8), 3, seed=2)


@pytest.mark.parametrize("suffix", [".ang", ".ctf"])
def test_a_map_named_as_another_crystal_is_refused_unless_overridden(small_map, tmp_path, suffix):
    from contactres.polycrystal import ebsd_phase, write_ang, write_ctf

    write = write_ang if suffix == ".ang" else write_ctf
    path = write(tmp_path / f"li{suffix}", small_map, ebsd_phase("Li"))
    out = tmp_path / "o.zarr"
    r = run("maps", "predict", path, "--crystal", "Cu", *TIP, "--out", out)
    line = one_line_error(r, f"li{suffix}", "'Li'", "Cu", "--crystal", "--ignore-phase-name")
    assert "phase 1" in line and not out.exists()
    r = run("maps", "predict", path, "--crystal", "Cu", *TIP, "--out", out, "--ignore-phase-name")
    assert r.exit_code == 0, r.output
    soft = ["--tip-radius", 2e-8, "--force", 1e-8]  # Li is soft: a Hertz contact at 10 nN
    r = run("maps", "predict", path, "--crystal", "li", *soft, "--out", tmp_path / "li.zarr")
    assert r.exit_code == 0, r.output  # the name is compared case-insensitively


@pytest.mark.parametrize(
    ("name", "crystal", "refused"),
    [
        ("Copper", "Cu", False),
        ("COPPER", "Cu", False),
        ("Iron (Alpha)", "Fe", False),
        ("Nickel", "Cu", True),
        ("lithium", "Cu", True),
        ("Phase 1", "Cu", False),  # names no built-in crystal: nothing to compare
        ("Brass", "Cu", False),
    ],
)
def test_phase_names_compare_as_symbol_or_common_name(small_map, tmp_path, name, crystal, refused):
    from dataclasses import replace

    from contactres.jobs.maps_predict import check_phase_name
    from contactres.materials import Material
    from contactres.polycrystal import ebsd_phase, write_ang

    path = write_ang(tmp_path / "m.ang", small_map, replace(ebsd_phase("Cu"), name=name))
    if refused:
        with pytest.raises(ContactresInputError, match="--ignore-phase-name"):
            check_phase_name(path, Material.crystal(crystal))
    else:
        check_phase_name(path, Material.crystal(crystal))
