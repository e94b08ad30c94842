"""Benchmark: the exact dynamic tangential stiffness of a rigid disk (issue 13).

Target: a 21-point exact tangential curve, k_s a in [0, 2], of a material never seen before
(the timed call prepares its own in-plane kernel table) under 0.1 s of CPU time (issue 31; it
was 1 s of wall time, issue 13), at the default accuracy (rtol = 1e-6); and, the work being
BLAS-bound, its CPU time as shipped within 1.2x of that with one BLAS thread (threadpoolctl's
limit, as ``OPENBLAS_NUM_THREADS=1``), both measured in this run and printed side by side.
Materials: AT-cut quartz (the QCM plate; no mirror plane, the slow kernel path),
Cu(123) (no symmetry at all), Cu(001) and an isotropic glass. Also printed: the second curve
with the table prepared once, and the accuracy (largest relative deviation of K from a run
with every discretisation and the basis doubled).
"""

from __future__ import annotations

import sys

import numpy as np
from _verdict import best_time, exit_code, target
from threadpoolctl import threadpool_limits

from contactres import Material, at_cut_quartz
from contactres.dynamic._table import Resolution
from contactres.dynamic._tangential_galerkin import (
    TangentialSize,
    prepare_tangential,
    tangential_per_a,
    tangential_size,
)

TARGET_S = 0.1
TARGET_THREADS_RATIO = 1.2


def _one_thread(fn):
    """``fn`` called with one BLAS thread, as under OPENBLAS_NUM_THREADS=1."""

    def call():
        with threadpool_limits(limits=1, user_api="blas"):
            return fn()

    return call


def main() -> int:
    ka = np.linspace(0.0, 2.0, 21)
    materials = {
        "AT-cut quartz": at_cut_quartz(),
        "Cu(123)": Material.crystal("Cu").rotated((1, 2, 3)),
        "Cu(001)": Material.crystal("Cu"),
        "soda-lime glass": Material.crystal("soda-lime-glass"),
    }
    worst = worst_ratio = 0.0
    print(
        "21-point exact tangential curve, k_s a in [0, 2], rtol 1e-6; CPU time, best of 3: "
        "as shipped | one BLAS thread"
    )
    for name, m in materials.items():

        def curve(m=m):
            return tangential_per_a(prepare_tangential(m), ka)

        new = best_time(curve)
        single = best_time(_one_thread(curve))
        table = prepare_tangential(m)
        again = best_time(lambda table=table: tangential_per_a(table, ka))
        K = tangential_per_a(table, ka)
        size = tangential_size(2.0).doubled()
        fine = prepare_tangential(m, resolution=Resolution().doubled(), max_order=24)
        ref = tangential_per_a(fine, ka, TangentialSize(size.n_harmonics, size.n_radial, 2, 2, 24))
        err = np.max(np.abs(K - ref)) / np.max(np.abs(ref))
        worst = max(worst, new)
        worst_ratio = max(worst_ratio, new / single)
        print(
            f"  {name:16s} new material {new:.3f} s | {single:.3f} s, table prepared "
            f"{again:.3f} s, deviation from doubled {err:.1e}"
        )
    results = [
        target("tangential exact 21 points, new material (worst, CPU)", worst, TARGET_S),
        target(
            "tangential exact 21 points: as shipped / one BLAS thread (worst)",
            worst_ratio,
            TARGET_THREADS_RATIO,
            unit="x",
        ),
    ]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
