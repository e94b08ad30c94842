"""Benchmark: invert a 512 x 512 single-mode contact-resonance map (contact-resonance AFM).

Target: under 5 s on the 2-core reference machine. The map is made by the forward model
(:func:`contactres.contact_frequencies` on 64 values of κ = k*/k_c from 1 to 300, tip at
r = 0.95, mode 1, tiled to 512 x 512 with 1e-6 relative noise), then inverted pixel by pixel with
the tip position known (:func:`contactres.invert_contact_resonance`: the closed form of Rabe et
al. 1996 for κ, plus the branch, pinned-limit and sensitivity flags). Only the inversion is
timed; the two-mode inversion (tip position unknown) of a 64 x 64 map is timed for information.

Run: ``.venv/bin/python benchmarks/bench_afm_map.py`` (exit status 1 if the target is missed).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import exit_code, target

from contactres.resonators import Cantilever, contact_frequencies, invert_contact_resonance

TARGET_S = 5.0
SIDE = 512


def main() -> int:
    lever = Cantilever((1.6e5, 1.0e6), 40.0)
    kappa = np.geomspace(1.0, 300.0, 64)
    f = contact_frequencies(lever, kappa, 0.95, modes=(1, 2))
    rng = np.random.default_rng(1)
    reps = SIDE * SIDE // kappa.size
    f1 = np.tile(f[:, :1], (reps, 1)).reshape(SIDE, SIDE, 1)
    f1 = f1 * (1.0 + 1e-6 * rng.standard_normal(f1.shape))

    t0 = time.perf_counter()
    res = invert_contact_resonance(lever, f1, 0.95)
    t_map = time.perf_counter() - t0

    f2 = np.tile(f, (64 * 64 // kappa.size, 1)).reshape(64, 64, 2)
    t0 = time.perf_counter()
    res2 = invert_contact_resonance(lever, f2)
    t_two = time.perf_counter() - t0

    truth = np.tile(kappa, reps).reshape(SIDE, SIDE)
    print(f"contact-resonance map: {SIDE} x {SIDE} pixels, mode 1, tip position known")
    print(f"  invert:           {t_map:.3f} s ({1e9 * t_map / SIDE**2:.0f} ns per pixel)")
    err = np.median(abs(res.kappa / truth - 1))
    print(f"  median |κ/κ_true - 1| at 1e-6 frequency noise: {err:.2g}")
    print(f"  flagged pixels:   {np.count_nonzero(res.flags)}")
    print(
        f"  two modes, tip position unknown, 64 x 64 (information): {t_two:.3f} s, "
        f"max |r - 0.95| = {np.nanmax(abs(res2.tip_position - 0.95)):.2g}"
    )
    results = [target(f"afm map, {SIDE}x{SIDE} single-mode inversion", t_map, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
