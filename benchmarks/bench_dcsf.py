"""Benchmark: a 41-point DCSF curve, k_l a in [0, 2], all five models, for a new material;
and a 21-point curve of the exact rigid-punch model (Galerkin).

Targets: under 0.5 s for the five models (issue 6) and under 1 s for the exact curve (issue 7),
at the default accuracy (rtol = 1e-6). Prints, per material, the
wall-clock and CPU time of the full curve (kernel table + all models) for a material never seen
before in the process (the kernel table is built from scratch; the material-independent Bessel
and WA weights of the far-field grid are cached per process, so the very first call of a process
is timed separately), and the accuracy: the largest relative deviation of every model from a
converged run (every resolution doubled; doubling twice moves the defaults by < 1e-7 too).
"""

from __future__ import annotations

import time

import numpy as np

from contactres import Material
from contactres.dynamic.exact import exact_n, galerkin_size
from contactres.dynamic.normal_stiffness import MODELS, _model_n, shear_wavenumber_ratio
from contactres.dynamic.quadrature import functionals, kernel_table, resolution_for

TARGET_S = 0.5
TARGET_EXACT_S = 1.0
KLA_EXACT = np.linspace(0.0, 2.0, 21)
KLA = np.linspace(0.0, 2.0, 41)
# Slightly perturbed parameters so that no kernel table is reused between the timed runs.
CASES = [(0.5, 0.25), (0.25, 0.25), (1.0, 0.25), (2.0, 0.25), (3.21, 0.419), (10.0, 0.25)]


def curve(m, res):
    table = kernel_table(m, 0.02, res)
    f = functionals(table, KLA * shear_wavenumber_ratio(m))
    return {name: table.n_static / _model_n(f, name) for name in MODELS}


def timed(m, res):
    t0, c0 = time.perf_counter(), time.process_time()
    out = curve(m, res)
    return out, time.perf_counter() - t0, time.process_time() - c0


def main() -> None:
    res = resolution_for(1e-6)
    ref_res = res.doubled()
    print(f"DCSF, 41 points k_l a in [0, 2], models {', '.join(MODELS)}, Q^-1 = 0.02, rtol 1e-6")
    _, wall, cpu = timed(Material.cubic_from_ratios(0.7001, 0.2501), res)
    print(f"  first call of the process (fills the far-grid caches): {wall:.3f} s wall")
    worst = 0.0
    for k, (A, nu) in enumerate(CASES):
        m = Material.cubic_from_ratios(A * (1 + 1e-9 * (k + 1)), nu)
        out, wall, cpu = timed(m, res)
        ref = curve(m, ref_res)
        err = max(float(np.max(np.abs(out[n] / ref[n] - 1))) for n in MODELS)
        worst = max(worst, wall)
        nth = kernel_table(m, 0.02, res).theta.size
        flag = "ok" if wall < TARGET_S else "SLOW"
        print(
            f"  A={A:<5g} nu={nu:<5g} n_theta={nth:<4d} wall {wall:.3f} s  cpu {cpu:.3f} s  "
            f"max rel. error {err:.1e}  [{flag}]"
        )
    print(f"worst {worst:.3f} s (target {TARGET_S} s): ratio {worst / TARGET_S:.2f}")

    print("exact (rigid flat punch, Galerkin), 21 points k_l a in [0, 2], rtol 1e-6")
    worst = 0.0
    for k, (A, nu) in enumerate(CASES):
        m = Material.cubic_from_ratios(A * (1 + 1e-9 * (k + 11)), nu)
        ksa = KLA_EXACT * shear_wavenumber_ratio(m)
        size = galerkin_size(float(ksa.max()))
        t0, c0 = time.perf_counter(), time.process_time()
        table = kernel_table(m, 0.02, res)
        ex = table.n_static / exact_n(table, ksa, size)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        fine = kernel_table(m, 0.02, ref_res)
        ref = fine.n_static / exact_n(fine, ksa, size.doubled())
        err = float(np.max(np.abs(ex / ref - 1)))
        worst = max(worst, wall)
        flag = "ok" if wall < TARGET_EXACT_S else "SLOW"
        print(
            f"  A={A:<5g} nu={nu:<5g} terms {size.n_radial}x{2 * size.n_harmonics + 1}  "
            f"wall {wall:.3f} s  cpu {cpu:.3f} s  max rel. error {err:.1e}  [{flag}]"
        )
    print(f"worst {worst:.3f} s (target {TARGET_EXACT_S} s): ratio {worst / TARGET_EXACT_S:.2f}")


if __name__ == "__main__":
    main()
