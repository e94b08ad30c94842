"""Polycrystal maps: synthetic maps, chunked evaluation (serial == dask bit for bit), Zarr IO.

The same bits from worker processes (the function and blocks pickled, uneven chunks): in
test_moduli_bits.py, on distinct orientations."""

from __future__ import annotations

import functools
import pickle
import subprocess
import sys

import numpy as np
import pytest

from contactres import Material
from contactres.polycrystal._maps import (
    MAP_CONVENTIONS,
    ExactModulus,
    OrientationMap,
    evaluate_map,
    map_from_dataset,
    map_to_dataset,
    read_map,
    write_map,
)
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._orientations import surface_matrices_from_euler
from contactres.polycrystal._synthetic import synthetic_polycrystal


def normal_z(R: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Module-level per-pixel function: the z component of the normal in crystal axes."""
    return scale * R[..., 2, 2]


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    # In-process workers (threads): starts in ~0.1 s; the same map_blocks graph and scheduler as
    # a cluster of processes (the benchmark runs processes=True).
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
    )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def cu_map():
    return synthetic_polycrystal((17, 19), n_grains=5, seed=7, pixel_size=2e-6)


# --- synthetic maps ---------------------------------------------------------------------------


def test_synthetic_map_is_seeded_and_consistent():
    a = synthetic_polycrystal((40, 50), n_grains=8, seed=3)
    b = synthetic_polycrystal((40, 50), n_grains=8, seed=3)
    c = synthetic_polycrystal((40, 50), n_grains=8, seed=4)
    assert np.array_equal(a.euler, b.euler) and np.array_equal(a.labels, b.labels)
    assert not np.array_equal(a.euler, c.euler)
    assert a.euler.shape == (40, 50, 3) and a.grain_euler.shape == (8, 3) and a.n_grains == 8
    assert np.array_equal(a.euler, a.grain_euler[a.labels])
    assert a.step_x == a.step_y == 1e-6


def test_synthetic_labels_are_the_nearest_seed():
    m = synthetic_polycrystal((31, 17), n_grains=6, seed=11, pixel_size=3e-6)
    yy, xx = np.meshgrid(np.arange(31) * 3e-6, np.arange(17) * 3e-6, indexing="ij")
    d2 = (xx[..., None] - m.seed_points[:, 0]) ** 2 + (yy[..., None] - m.seed_points[:, 1]) ** 2
    assert np.array_equal(m.labels, np.argmin(d2, axis=-1))


def test_synthetic_orientations_are_bunge_radians_in_range():
    m = synthetic_polycrystal((10, 10), n_grains=50, seed=0)
    e = m.grain_euler
    assert np.all((e[:, [0, 2]] >= 0) & (e[:, [0, 2]] < 2 * np.pi))
    assert np.all((e[:, 1] >= 0) & (e[:, 1] <= np.pi))


@pytest.mark.parametrize("kwargs", [{"shape": (0, 5)}, {"n_grains": 0}, {"pixel_size": -1.0}])
def test_synthetic_rejects_bad_parameters(kwargs):
    args = {"shape": (5, 5), "n_grains": 2, "seed": 0} | kwargs
    with pytest.raises(ValueError):
        synthetic_polycrystal(**args)


# --- evaluate_map ---------------------------------------------------------------------------


def test_serial_evaluation_is_the_function_of_every_pixel(cu_map):
    e = cu_map.euler
    R = surface_matrices_from_euler(e[..., 0], e[..., 1], e[..., 2], degrees=False)
    got = evaluate_map(normal_z, cu_map, chunks=(8, 8))
    assert np.array_equal(got, R[..., 2, 2])


def test_known_orientations_give_the_known_moduli():
    # Cube orientation (normal [001]) and normal [010] (Φ = 90°): both M{100} of Cu.
    euler = np.zeros((2, 3, 3))
    euler[1, :, 1] = np.pi / 2
    M = evaluate_map(ExactModulus(Material.crystal("Cu")), euler, chunks=(1, 2))
    ref = indentation_moduli(Material.crystal("Cu"), np.eye(3)[None])[0]
    assert np.allclose(M, ref, rtol=1e-12, atol=0)


def test_dask_path_equals_serial_bit_for_bit_exact_modulus(cu_map, client):
    f = ExactModulus(Material.crystal("Cu"))
    chunks = (10, 12)  # divides neither 17 nor 19
    serial = evaluate_map(f, cu_map, chunks=chunks)
    dask = evaluate_map(f, cu_map, chunks=chunks, client=client)
    assert serial.dtype == dask.dtype == float
    assert np.array_equal(serial, dask)
    labels = cu_map.labels
    ref = indentation_moduli(Material.crystal("Cu"), surface_matrices_from_euler(
        *cu_map.grain_euler.T, degrees=False))  # fmt: skip
    assert np.allclose(serial, ref[labels], rtol=1e-10, atol=0)


def test_dask_path_with_a_partial_and_a_dask_input(cu_map, client):
    da = pytest.importorskip("dask.array")
    f = functools.partial(normal_z, scale=2.0)
    serial = evaluate_map(f, cu_map.euler, chunks=(7, 9))
    lazy = da.from_array(cu_map.euler, chunks=(5, 5, 3))  # rechunked to (7, 9) inside
    assert np.array_equal(serial, evaluate_map(f, lazy, chunks=(7, 9), client=client))
    assert np.array_equal(serial, evaluate_map(f, lazy, chunks=(7, 9)))


def test_scheduler_address_runs_the_same_code(cu_map, client):
    serial = evaluate_map(normal_z, cu_map, chunks=(16, 16))
    remote = evaluate_map(normal_z, cu_map, chunks=(16, 16), scheduler=client.scheduler.address)
    assert np.array_equal(serial, remote)


@pytest.mark.parametrize("use_client", [False, True])
def test_progress_counts_every_chunk(cu_map, client, use_client):
    calls = []
    evaluate_map(
        normal_z, cu_map, chunks=(6, 7), client=client if use_client else None,
        progress=lambda done, total: calls.append((done, total)),
    )  # fmt: skip
    assert calls == [(k, 9) for k in range(1, 10)]  # 3 x 3 chunks of a 17 x 19 map


def test_exact_modulus_function_pickles():
    f = ExactModulus(Material.crystal("Cu"))
    g = pickle.loads(pickle.dumps(f))
    R = surface_matrices_from_euler([0.3, 1.0], [0.5, 2.0], [0.7, 3.0], degrees=False)
    assert np.array_equal(f(R), g(R))


def test_bad_arguments_are_rejected(cu_map, client):
    with pytest.raises(ValueError, match="shape"):
        evaluate_map(normal_z, np.zeros((4, 4)))
    with pytest.raises(ValueError, match="chunks"):
        evaluate_map(normal_z, cu_map, chunks=(0, 4))
    with pytest.raises(ValueError, match="not both"):
        evaluate_map(normal_z, cu_map, client=client, scheduler="tcp://127.0.0.1:1")
    with pytest.raises(ValueError, match="per-pixel function"):
        evaluate_map(lambda R: R[..., 0, :], cu_map)


# --- the container and Zarr IO ---------------------------------------------------------------


def test_container_checks_shapes():
    with pytest.raises(ValueError, match="euler"):
        OrientationMap(np.zeros((3, 3)), 1e-6, 1e-6, np.zeros((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="phase"):
        OrientationMap(np.zeros((3, 3, 3)), 1e-6, 1e-6, np.zeros((3, 2)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="step_x"):
        OrientationMap(np.zeros((3, 3, 3)), 0.0, 1e-6, np.zeros((3, 3)), np.zeros((3, 3)))


def test_zarr_round_trip_keeps_values_and_conventions(cu_map, tmp_path):
    path = write_map(tmp_path / "map.zarr", map_to_dataset(cu_map), chunks=(8, 16))
    ds = read_map(path)
    for key, value in MAP_CONVENTIONS.items():
        assert ds.attrs[key] == value
    assert ds.attrs["euler_convention"] == "Bunge ZXZ, passive, radians"
    assert ds.attrs["sample_frame"] == "x=RD, y=TD, z=ND inward normal"
    assert ds["euler"].attrs["units"] == "rad" and ds["x"].attrs["units"] == "m"
    assert ds["euler"].data.chunksize == (8, 16, 3)  # read lazily, chunk by chunk
    back = map_from_dataset(ds)
    assert np.array_equal(back.euler, cu_map.euler)
    assert np.array_equal(back.labels, cu_map.labels)
    assert np.array_equal(back.phase, cu_map.phase)
    assert (back.step_x, back.step_y, back.source) == (2e-6, 2e-6, cu_map.source)
    assert np.allclose(ds["x"].values[1], 2e-6, rtol=1e-15, atol=0)


def test_write_map_replaces_a_store_and_leaves_nothing_beside(cu_map, tmp_path):
    target = tmp_path / "map.zarr"
    write_map(target, cu_map)
    other = synthetic_polycrystal((5, 6), n_grains=2, seed=1)
    write_map(target, other)
    assert np.array_equal(map_from_dataset(read_map(target)).euler, other.euler)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.zarr"]


def test_a_written_store_opens_in_xarray_without_a_warning(cu_map, tmp_path):
    """The store carries consolidated metadata: xarray's default open finds it and does not
    warn (issue 30: every open of a contactres store warned); writing warns nothing either."""
    import warnings

    xr = pytest.importorskip("xarray", reason="the maps extra (xarray, zarr) is not installed")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_map(tmp_path / "map.zarr", cu_map)
        with xr.open_zarr(tmp_path / "map.zarr") as ds:
            assert np.array_equal(ds["euler"].values, map_to_dataset(cu_map)["euler"].values)


def test_write_map_refuses_to_overwrite_other_files(cu_map, tmp_path):
    (tmp_path / "data.zarr").write_text("not a store")
    with pytest.raises(ValueError, match="not a Zarr store"):
        write_map(tmp_path / "data.zarr", cu_map)
    assert (tmp_path / "data.zarr").read_text() == "not a store"
    with pytest.raises(FileNotFoundError):
        read_map(tmp_path / "missing.zarr")


def test_the_package_does_not_import_dask_xarray_or_zarr():
    code = (
        "import sys, contactres.polycrystal, contactres.polycrystal._maps, "
        "contactres.polycrystal._ebsd, contactres.polycrystal._synthetic; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('dask', 'distributed', 'xarray', 'zarr')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
