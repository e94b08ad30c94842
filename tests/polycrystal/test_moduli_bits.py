"""Exact M is the same to the bit in every process (issue 27, point 10): the rotation of the
stiffness runs through numpy's own loops, not BLAS, whose rounding depends on its threads."""

import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from contactres import Material
from contactres.materials import rotate_tensor, voigt_to_tensor
from contactres.polycrystal import ExactModulus, evaluate_map
from contactres.polycrystal._moduli import _rotated

CU = Material.crystal("Cu")


def _random_euler(shape, seed):
    """Bunge angles of orientations uniform on SO(3), one per pixel (no two pixels alike)."""
    rng = np.random.default_rng(seed)
    return np.stack(
        [
            rng.uniform(0, 2 * np.pi, shape),
            np.arccos(rng.uniform(-1, 1, shape)),
            rng.uniform(0, 2 * np.pi, shape),
        ],
        axis=-1,
    )


def test_rotation_of_the_stiffness_is_the_tensor_rule():
    # Against materials.rotate_tensor, one rotation at a time (its own einsum).
    R = Rotation.random(25, random_state=3).as_matrix()
    c = voigt_to_tensor(np.asarray(CU.C, dtype=float))
    got = _rotated(R, c)
    for n in range(R.shape[0]):
        np.testing.assert_allclose(got[n], rotate_tensor(c, R[n]), rtol=0, atol=1e-12 * 168.4e9)


def test_blas_threads_do_not_change_a_bit():
    # The same 400 orientations in two fresh processes with 1 and 2 BLAS threads.
    code = (
        "import sys, numpy as np\n"
        "from contactres import Material\n"
        "from contactres.polycrystal import ExactModulus, evaluate_map\n"
        "rng = np.random.default_rng(11)\n"
        "e = np.stack([rng.uniform(0, 6.28, (20, 20)), np.arccos(rng.uniform(-1, 1, (20, 20))),"
        " rng.uniform(0, 6.28, (20, 20))], axis=-1)\n"
        "M = evaluate_map(ExactModulus(Material.crystal('Cu')), e, chunks=(10, 10))\n"
        "sys.stdout.write(M.tobytes().hex())\n"
    )
    out = []
    for threads in ("1", "2"):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS=threads,
                   MKL_NUM_THREADS=threads)  # fmt: skip
        run = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300
        )
        assert run.returncode == 0, run.stderr
        out.append(run.stdout)
    assert out[0] == out[1]


def test_two_worker_processes_give_the_serial_bits_on_distinct_orientations():
    distributed = pytest.importorskip("distributed", reason="dask.distributed not installed")
    # The function and the blocks pickled to 2 separate worker processes. 1200 distinct
    # orientations in chunks that divide neither side (blocks of 16 and 14 rows, 25 and 15
    # columns): the bits do not depend on the process nor on the shape of a block.
    euler = _random_euler((30, 40), seed=5)
    f = ExactModulus(CU)
    serial = evaluate_map(f, euler, chunks=(16, 25))
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        clustered = evaluate_map(f, euler, chunks=(16, 25), client=client)
    assert np.isfinite(serial).all()
    assert np.array_equal(serial, clustered)
