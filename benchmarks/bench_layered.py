"""Benchmark: the surface Green's function of one film on a substrate against the homogeneous
half-space (contactres.surface_green), static and dynamic, on a 128 x 128 (η x θ) grid.

The layered response costs the substrate's half-space compliance, the film's at θ and θ + π,
two 3x3 exponentials and a few 3x3 products and inverses per point (contactres.layered._recursion;
a mirror-plane film, e.g. isotropic, needs the film at θ only and one exponential). The target
is at most 2.5x the time of the two homogeneous half-spaces (the substrate's and the film's,
through the same function) together, a ratio that holds however loaded the machine is. Each
figure is the best wall-clock time of a few runs; a few seconds in all.

Run: ``.venv/bin/python benchmarks/bench_layered.py`` (exit status 1 if a target is missed).
"""

from __future__ import annotations

import sys

import numpy as np
from _verdict import best_time, exit_code, target

from contactres import LayeredMaterial, Material, surface_green

N = 128
REPEAT = 3
MAX_RATIO = 2.5


def main() -> int:
    quartz = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz").with_loss(0.01)
    pmma = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA").with_loss(0.05)
    si111 = Material.crystal("Si").rotated((1, 1, 1)).with_loss(0.01)
    eta = np.geomspace(1e5, 1e8, N)[:, None]
    theta = np.linspace(0.0, 2 * np.pi, N)[None, :]
    cases = [
        ("PMMA 250 nm on quartz, static", quartz, pmma, 0.0),
        ("PMMA 250 nm on quartz, 15 MHz", quartz, pmma, 15e6),
        ("Si(111) 250 nm on quartz, 15 MHz", quartz, si111, 15e6),
    ]
    print(f"surface_green on a {N} x {N} grid (eta x theta), best of {REPEAT}:")
    results = []
    for name, sub, film, f in cases:
        stack = LayeredMaterial(sub, [(film, 250e-9)])
        surface_green(stack, eta[:2], theta, f)  # warm-up
        t_sub = best_time(lambda sub=sub, f=f: surface_green(sub, eta, theta, f), REPEAT)
        t_film = best_time(lambda film=film, f=f: surface_green(film, eta, theta, f), REPEAT)
        t_lay = best_time(lambda stack=stack, f=f: surface_green(stack, eta, theta, f), REPEAT)
        us = 1e6 / (N * N)
        print(
            f"  {name}: {t_lay * us:.2f} us/point layered; half-spaces: substrate "
            f"{t_sub * us:.2f}, film {t_film * us:.2f} us/point; "
            f"ratio {t_lay / (t_sub + t_film):.2f}"
        )
        results.append(
            target(
                f"{name} (vs {MAX_RATIO:g}x both half-spaces)", t_lay, MAX_RATIO * (t_sub + t_film)
            )
        )
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
