"""Benchmark: the static indentation modulus M(a) of a coated substrate, 50 contact radii.

Target: under 0.5 s of CPU time (issue 31) on the 2-core reference machine (issue 26, point 6:
"a static M(a) curve of 50 contact radii in well under a second"). One isotropic film (250 nm
of PMMA, E = 5 GPa, ν = 0.35) on fused quartz (72 GPa, 0.17), contact radii from 0.01 h to 10 h
(:func:`contactres.indentation_modulus_at`: the axisymmetric Galerkin on the layered kernel,
accurate to < 1e-9). For information: the same curve out to a = 100 h (the basis grows like a/h),
and the sphere's contact for 20 forces (:func:`contactres.sphere_contact`).

Run: ``.venv/bin/python benchmarks/bench_layered_contact.py`` (exit status 1 if the target is
missed).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import exit_code, target

from contactres import LayeredMaterial, Material, indentation_modulus_at, sphere_contact

TARGET_S = 0.5
H = 250e-9


def main() -> int:
    quartz = Material.isotropic(72e9, 0.17, name="quartz")
    pmma = Material.isotropic(5e9, 0.35, name="PMMA")
    coated = LayeredMaterial(quartz, [(pmma, H)])
    a = np.geomspace(0.01, 10, 50) * H
    indentation_modulus_at(coated, a[:2])  # first-call imports, not timed

    t0 = time.process_time()
    M = indentation_modulus_at(coated, a)
    t_curve = time.process_time() - t0

    wide = np.geomspace(0.01, 100, 50) * H
    t0 = time.process_time()
    indentation_modulus_at(coated, wide)
    t_wide = time.process_time() - t0

    forces = np.geomspace(1e-7, 1e-2, 20)
    t0 = time.process_time()
    c = sphere_contact(coated, 10e-6, forces)
    t_sphere = time.process_time() - t0

    print(f"M(a) of {coated.name}, 50 contact radii, a/h = 0.01-10")
    print(
        f"  curve:            {t_curve:.3f} s CPU (M from {M[0] / 1e9:.2f} to "
        f"{M[-1] / 1e9:.2f} GPa)"
    )
    print(f"  a/h = 0.01-100 (information): {t_wide:.3f} s")
    print(
        f"  sphere R = 10 um, 20 forces 1e-7-1e-2 N (information): {t_sphere:.3f} s, "
        f"a/h = {c.contact_radius[0] / H:.2f}-{c.contact_radius[-1] / H:.2f}"
    )
    results = [target("layered M(a), 50 radii (CPU)", t_curve, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
