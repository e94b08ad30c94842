"""Benchmark: invert 512 x 512 single-mode contact-resonance maps in under 2 s (issue 29).

Four single-mode maps with the tip position known, each timed against the 2 s target: a
normal contact spring only (the closed form of Rabe et al. 1996), and a lateral spring at a
tip of height h on a lever tilted by 11° (α = 0.5, h/L = 0.05: the 4 x 4 determinant, a
quadratic in κ), each without and with quality factors (complex β, the Kelvin-Voigt damping).
The maps come from the forward model (:func:`contactres.contact_frequencies`, 64 values of
κ = k*/k_c from 1 to 300 at r = 0.95, mode 1, tiled, 1e-6 relative noise). Only the inversion
(:func:`contactres.invert_contact_resonance`, with its branch, pinned-limit, free-limit and
sensitivity flags) is timed, best of 3. The two-mode inversion with r unknown is timed on a
64 x 64 map for information, with its time scaled to 512 x 512 (it scans κ_a(r) − κ_b(r) on
200 tip positions per pixel: about 200 times the work of one single-mode map).

Run: ``.venv/bin/python benchmarks/bench_afm_map_inversion.py`` (exit status 1 if a target is
missed).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import best_time, exit_code, target

from contactres.resonators import Cantilever, contact_frequencies, invert_contact_resonance

TARGET_S = 2.0
SIDE = 512
SMALL = 64
LATERAL = {"lateral_ratio": 0.5, "tip_height": 0.05, "tilt": 11.0}


def _map(lever, kappa, springs, side, modes, rng):
    """A side x side map of the forward frequencies (and Q) of the κ values, tiled."""
    f = contact_frequencies(lever, kappa, 0.95, modes=modes, **springs)
    reps = side * side // kappa.size
    f = np.tile(f, (reps, 1)).reshape(side, side, len(modes))
    q = f.real / (2.0 * f.imag) if np.iscomplexobj(f) else None
    return f.real * (1.0 + 1e-6 * rng.standard_normal(f.shape)), q


def main() -> int:
    lever = Cantilever((1.6e5, 1.0e6), 40.0)
    kappa = np.geomspace(1.0, 300.0, 64)
    rng = np.random.default_rng(1)
    truth = np.tile(kappa, SIDE * SIDE // kappa.size).reshape(SIDE, SIDE)
    results = []
    print(f"contact-resonance maps: {SIDE} x {SIDE} pixels, mode 1, tip position known")
    for name, springs in (("normal spring", {}), ("lateral spring, 11° tilt", LATERAL)):
        for damped in (False, True):
            k = kappa * (1 + 0.05j) if damped else kappa
            f, q = _map(lever, k, springs, SIDE, (1,), rng)
            seconds = best_time(lambda f=f, q=q, s=springs: invert_contact_resonance(
                lever, f, 0.95, q_factors=q, **s
            ))  # fmt: skip
            res = invert_contact_resonance(lever, f, 0.95, q_factors=q, **springs)
            label = f"{name}{', with Q' if damped else ''}"
            spring = truth * (1 + 0.05 / (2 * q[..., 0])) if damped else truth
            err = np.median(np.abs(res.kappa / spring - 1))
            print(
                f"  {label}: {seconds:.3f} s ({1e9 * seconds / SIDE**2:.0f} ns per pixel), "
                f"median |κ/κ_true - 1| at 1e-6 noise {err:.2g}, "
                f"{np.count_nonzero(res.flags)} flagged"
            )
            results.append(target(f"afm map {SIDE}x{SIDE}, {label}", seconds, TARGET_S))
    for name, springs in (("normal spring", {}), ("lateral spring, 11° tilt", LATERAL)):
        f, _ = _map(lever, kappa, springs, SMALL, (1, 2), rng)
        t0 = time.perf_counter()
        res = invert_contact_resonance(lever, f, **springs)
        seconds = time.perf_counter() - t0
        scaled = seconds * (SIDE / SMALL) ** 2
        wrong = np.count_nonzero(~(np.abs(res.tip_position - 0.95) < 1e-3))
        print(
            f"  two modes, r unknown, {name}, {SMALL} x {SMALL} (information): {seconds:.3f} s, "
            f"~{scaled:.0f} s at {SIDE} x {SIDE}; pixels with r off by > 1e-3: {wrong}"
        )
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
