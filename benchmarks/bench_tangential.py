"""Benchmark: the exact dynamic tangential stiffness of a rigid disk (issue 13).

Target: a 21-point exact tangential curve, k_s a in [0, 2], of a material never seen before
(the timed call prepares its own in-plane kernel table) under 1 s, at the default accuracy
(rtol = 1e-6). Materials: AT-cut quartz (the QCM plate; no mirror plane, the slow kernel path),
Cu(123) (no symmetry at all), Cu(001) and an isotropic glass. Also printed: the second curve
with the table prepared once, and the accuracy (largest relative deviation of K from a run
with every discretisation and the basis doubled).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import exit_code, target

from contactres import Material, at_cut_quartz
from contactres.dynamic._table import Resolution
from contactres.dynamic._tangential_galerkin import (
    TangentialSize,
    prepare_tangential,
    tangential_per_a,
    tangential_size,
)

TARGET_S = 1.0


def _best(fn, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> int:
    ka = np.linspace(0.0, 2.0, 21)
    materials = {
        "AT-cut quartz": at_cut_quartz(),
        "Cu(123)": Material.crystal("Cu").rotated((1, 2, 3)),
        "Cu(001)": Material.crystal("Cu"),
        "soda-lime glass": Material.crystal("soda-lime-glass"),
    }
    worst = 0.0
    print("21-point exact tangential curve, k_s a in [0, 2], rtol 1e-6")
    for name, m in materials.items():
        new = _best(lambda m=m: tangential_per_a(prepare_tangential(m), ka))
        table = prepare_tangential(m)
        again = _best(lambda table=table: tangential_per_a(table, ka))
        K = tangential_per_a(table, ka)
        size = tangential_size(2.0).doubled()
        fine = prepare_tangential(m, resolution=Resolution().doubled(), max_order=24)
        ref = tangential_per_a(fine, ka, TangentialSize(size.n_harmonics, size.n_radial, 2, 2, 24))
        err = np.max(np.abs(K - ref)) / np.max(np.abs(ref))
        worst = max(worst, new)
        print(
            f"  {name:16s} new material {new:.3f} s, table prepared {again:.3f} s, "
            f"deviation from doubled {err:.1e}"
        )
    results = [target("tangential exact 21 points, new material (worst)", worst, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
