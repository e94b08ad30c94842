"""Benchmark: the dynamic half-space kernel g(κ, θ) on a 512 x 512 (wave number x θ) grid.

Target (design.md / issue 5): under 1 s on the 2-core reference machine. Prints the best of a few
runs for three cases: the paper's lossy cubic crystal (Q⁻¹ = 0.02) over κ in [0.01, 5] (about a
fifth of the grid lies in the propagating range κ < 1, where the partial waves are barely damped
and the doubling algorithm needs the most steps), Cu (001) over a wider log range, and a lossless
solid in the evanescent range (κ > 1.5). These three surfaces are mirror planes of the solid
and take the block-structured doubling step; Cu (111), which has no such mirror, shows the cost
of the general 3x3 step (not part of the target). Also the static kernel on 512 directions.
"""

from __future__ import annotations

import time

import numpy as np

from contactres import Material, dynamic_kernel, static_kernel

TARGET_S = 1.0
N = 512
REPEAT = 3


def best_time(fn) -> tuple[float, float]:
    """Best wall-clock and best CPU time (s) of REPEAT runs; CPU time is the better guide when
    other jobs share the machine."""
    wall, cpu = [], []
    for _ in range(REPEAT):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu)


def main() -> None:
    theta = np.linspace(0.0, np.pi / 2, N)[None, :]
    cases = [
        (
            "A=0.5 nu=0.25 Q^-1=0.02, kappa 0.01..5",
            Material.cubic_from_ratios(0.5, 0.25).with_loss(0.02),
            np.linspace(0.01, 5.0, N)[:, None],
        ),
        (
            "Cu(001) Q^-1=0.02, kappa 0.05..20 (log)",
            Material.crystal("Cu").with_loss(0.02),
            np.geomspace(0.05, 20.0, N)[:, None],
        ),
        (
            "A=0.5 nu=0.25 lossless, kappa 1.5..5",
            Material.cubic_from_ratios(0.5, 0.25),
            np.linspace(1.5, 5.0, N)[:, None],
        ),
        (
            "Cu(111) Q^-1=0.02 (general step), 0.05..20",
            Material.crystal("Cu").rotated((1, 1, 1)).with_loss(0.02),
            np.geomspace(0.05, 20.0, N)[:, None],
        ),
    ]
    print(f"dynamic_kernel on a {N} x {N} grid (kappa x theta), best of {REPEAT}:")
    for name, m, kappa in cases:
        dynamic_kernel(m, kappa[:4], theta)  # warm-up
        t, cpu = best_time(lambda m=m, kappa=kappa: dynamic_kernel(m, kappa, theta))
        per_point = t / (N * N) * 1e6
        print(
            f"  {name:42s} {t:7.3f} s wall, {cpu:7.3f} s CPU  ({per_point:.2f} us/point, "
            f"{t / TARGET_S:.2f} x target {TARGET_S:g} s)"
        )
    th = np.linspace(0.0, 2 * np.pi, N)
    t, _ = best_time(lambda: static_kernel(Material.crystal("Cu"), th))
    print(f"static_kernel on {N} directions: {t * 1e3:.2f} ms")


if __name__ == "__main__":
    main()
