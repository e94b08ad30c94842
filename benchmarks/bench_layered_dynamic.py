"""Benchmark: the dynamic flat punch on one film (contactres.dynamic.layered_punch_stiffness)
against the homogeneous exact curve (contactres.dcsf, model "exact"), 41 points, k_s a in [0, 2].

The layered curve costs the film's kernel table and exact Galerkin matrices (what the
homogeneous curve costs) plus, per point, the correction of the stack: the layered surface
response at ~100-300 wavenumbers on the lifted path and its Bessel products. The target
(issue 26, point 6) is at most 3x the homogeneous exact curve of the film with its table (both
prepared within the timed call). Each figure is the best wall-clock time of a few runs. The
tangential punch on the same stacks is timed too, against the homogeneous exact tangential curve
(printed only: no target yet).

Run: ``.venv/bin/python benchmarks/bench_layered_dynamic.py`` (exit status 1 if the target is
missed).
"""

from __future__ import annotations

import sys

import numpy as np
from _verdict import best_time, exit_code, target

from contactres import LayeredMaterial, Material, dcsf, tangential_dcsf
from contactres.dynamic import layered_punch_stiffness

N = 41
REPEAT = 3
MAX_RATIO = 3.0


def main() -> int:
    quartz = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
    pmma = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
    a = 5e-6
    ksa = np.linspace(0.0, 2.0, N)
    f = ksa * np.sqrt(np.real(pmma.C[3, 3]) / pmma.density) / (2 * np.pi * a)
    print(f"{N}-point curve, k_s a (film) in [0, 2], a = 5 um, best of {REPEAT}:")
    t_hom = best_time(lambda: dcsf(pmma, ksa, model="exact", wavenumber="shear"), REPEAT)
    print(f"  homogeneous exact (PMMA half-space): {t_hom:.3f} s")
    results = []
    for h in (250e-9, 1e-6):
        stack = LayeredMaterial(quartz, [(pmma, h)])
        t_lay = best_time(lambda stack=stack: layered_punch_stiffness(stack, a, f), REPEAT)
        print(f"  PMMA {h * 1e9:.0f} nm on quartz: {t_lay:.3f} s, ratio {t_lay / t_hom:.2f}")
        name = f"PMMA {h * 1e9:.0f} nm on quartz (vs {MAX_RATIO:g}x homogeneous exact)"
        results.append(target(name, t_lay, MAX_RATIO * t_hom))
    # The tangential punch (no target yet: printed only), against the homogeneous exact
    # tangential curve of the film.
    t_hom_t = best_time(lambda: tangential_dcsf(pmma, ksa), REPEAT)
    print(f"  tangential, homogeneous exact (PMMA half-space): {t_hom_t:.3f} s")
    for h in (250e-9, 1e-6):
        stack = LayeredMaterial(quartz, [(pmma, h)])
        t_lay = best_time(
            lambda stack=stack: layered_punch_stiffness(stack, a, f, direction="tangential"),
            REPEAT,
        )
        print(
            f"  tangential, PMMA {h * 1e9:.0f} nm on quartz: {t_lay:.3f} s, "
            f"ratio {t_lay / t_hom_t:.2f}"
        )
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
