"""Benchmark: the indentation modulus M of 1000 random Cu orientations (issue 16, point 2).

Batched (:func:`contactres.polycrystal.indentation_moduli`: one rotation einsum, Ĝ on the
(orientation x θ) grid by the stacked doubling algorithm) against the scalar loop
``indentation_modulus(cu.rotated(normal, inplane))`` over the same orientations. Target: a
10x speed-up (the batched time under a tenth of the loop's). Also prints the largest relative
difference between the two (they must agree to 1e-10).

Run: ``.venv/bin/python benchmarks/bench_polycrystal_moduli.py`` (exit status 1 if the target is
missed).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _verdict import exit_code, target

from contactres import Material, indentation_modulus
from contactres.polycrystal import indentation_moduli

N = 1000
REPEAT = 3
SPEEDUP = 10.0


def random_rotations(n: int, seed: int = 0) -> np.ndarray:
    """n random proper rotations (QR of Gaussian matrices, signs fixed)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]
    q[np.linalg.det(q) < 0] *= -1
    return q


def main() -> int:
    cu = Material.crystal("Cu")
    R = random_rotations(N)
    indentation_moduli(cu, R[:4])  # warm-up
    batched = []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        M = indentation_moduli(cu, R)
        batched.append(time.perf_counter() - t0)
    t_batched = min(batched)
    t0 = time.perf_counter()
    ref = np.array([indentation_modulus(cu.rotated(r[2], r[0])) for r in R])
    t_scalar = time.perf_counter() - t0
    err = float(np.max(np.abs(M / ref - 1)))
    print(f"indentation modulus of {N} random Cu orientations:")
    print(f"  batched indentation_moduli: {t_batched:.3f} s ({t_batched / N * 1e6:.0f} us each)")
    print(
        f"  scalar loop (rotated + indentation_modulus): {t_scalar:.3f} s "
        f"({t_scalar / N * 1e6:.0f} us each)"
    )
    print(f"  speed-up {t_scalar / t_batched:.1f}x, max relative difference {err:.2e}")
    results = [target(f"batched M of {N} orientations", t_batched, t_scalar / SPEEDUP)]
    results.append(err <= 1e-10)
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
