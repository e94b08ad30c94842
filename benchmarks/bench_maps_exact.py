"""Benchmark: the exact indentation modulus M of every pixel of a 512 x 512 grain map.

Target (issue 31, point 5): at most 5 s of CPU (the per-pixel evaluation took 34 s). A map of
grains has one orientation per grain; :func:`contactres.polycrystal.indentation_moduli`
evaluates each distinct orientation once, chunk by chunk of
:func:`~contactres.polycrystal.evaluate_map` (256 x 256 pixels). The map is a seeded Voronoi
polycrystal of 60 Cu grains (:func:`~contactres.polycrystal.synthetic_polycrystal`). Printed:
CPU time (``time.process_time``) of the best of 3 runs (as shipped and with one BLAS thread,
alternating) and the number of distinct orientations; a per-pixel map (every pixel its own
orientation, as a scattered EBSD scan) is timed on 64 x 64 and scaled to 512 x 512 for
comparison (the work then is per pixel: ~0.1-0.5 ms each).

The same call is timed with one BLAS thread (threadpoolctl's limit) and the ratio of the two
CPU times is judged (issue 31, point 1: as shipped within 1.2x of one thread).

Run: ``.venv/bin/python benchmarks/bench_maps_exact.py``.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import exit_code, shipped_and_one_thread, target, thread_ratio

from contactres import Material
from contactres.polycrystal import ExactModulus, evaluate_map, synthetic_polycrystal

SIDE = 512
SMALL = 64
N_GRAINS = 60
SEED = 31
TARGET_S = 5.0


def cpu_best(fn, repeat: int = 2) -> float:
    """The smallest CPU time (s) of ``repeat`` runs of ``fn()``."""
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return min(times)


def main() -> int:
    exact = ExactModulus(Material.crystal("Cu"))
    grains = synthetic_polycrystal((SIDE, SIDE), N_GRAINS, seed=SEED, pixel_size=1e-6)
    distinct = np.unique(grains.euler.reshape(-1, 3), axis=0).shape[0]
    t_map, t_one = shipped_and_one_thread(lambda: evaluate_map(exact, grains.euler), repeat=3)
    print(f"exact M, {SIDE} x {SIDE} map of {N_GRAINS} Cu grains ({distinct} orientations):")
    print(f"  {t_map:.2f} s CPU as shipped | {t_one:.2f} s with one BLAS thread")
    rng = np.random.default_rng(SEED)
    scattered = grains.euler[:SMALL, :SMALL] + 1e-3 * rng.standard_normal((SMALL, SMALL, 3))
    t_small = cpu_best(lambda: evaluate_map(exact, scattered), repeat=1)
    scale = (SIDE / SMALL) ** 2
    print(
        f"  per pixel (every pixel its own orientation), {SMALL} x {SMALL}: {t_small:.2f} s CPU, "
        f"{t_small * scale:.1f} s scaled to {SIDE} x {SIDE}"
    )
    return exit_code(
        [
            target(f"exact M of a {SIDE} x {SIDE} grain map (CPU)", t_map, TARGET_S),
            thread_ratio(f"exact M of a {SIDE} x {SIDE} grain map", t_map, t_one),
        ]
    )


if __name__ == "__main__":
    sys.exit(main())
