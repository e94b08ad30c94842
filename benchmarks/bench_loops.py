"""Benchmark: 10^5 amplitudes of a Cattaneo-Mindlin loop through ``shifts_from_loop``.

Target: under 0.5 s on the 2-core reference machine. Prints the best of a few
timings and the accuracy reached against (a) the same quadrature with twice the nodes, (b) the
closed-form loop area (Mindlin-Deresiewicz) for ΔΓ, (c) scipy's adaptive quadrature of Eq. 4
at a few amplitudes around the onset of full sliding.

Run: ``.venv/bin/python benchmarks/bench_loops.py`` (exit status 1 if the target is missed).
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np
from _verdict import exit_code, target
from scipy.integrate import IntegrationWarning, quad

import contactres as cr
from contactres.resonators import DEFAULT_NODES, loop_stiffness

N = 100_000
TARGET_S = 0.5


def adaptive_k1(loop, u0):
    """K′ of Eq. 4 by scipy.quad in t (x = sin t), split at the kinks."""
    kinks = sorted(np.arcsin(x) for x in np.ravel(loop.kinks(u0)) if np.isfinite(x))

    def g(t):
        up, down = loop.branches(u0 * np.sin(t), u0)
        return (up + down) * np.sin(t)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        val, _ = quad(
            g, -np.pi / 2, np.pi / 2, points=kinks or None, epsabs=0, epsrel=1e-13, limit=500
        )
    return val / (np.pi * u0)


def main() -> int:
    q = cr.QCM(fundamental=5e6, overtone=3, area=1e-5)
    loop = cr.CattaneoMindlinLoop(kappa=4e5, mu=0.8, normal_force=5e-3)
    d = loop.slip_displacement
    u0 = np.linspace(0.0, 3.0 * d, N)  # through the onset of full sliding at u0 = d*

    cr.shifts_from_loop(q, loop, u0[:100], 3)  # warm-up (node tables)
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        df, dg = cr.shifts_from_loop(q, loop, u0, 3)
        times.append(time.perf_counter() - t0)
    best = min(times)

    P = q.sensitivity(3)
    ref = loop_stiffness(loop, u0, nodes=2 * DEFAULT_NODES)
    err_df = np.max(np.abs(df / (P * ref.real) - 1))
    nz = u0 > 0
    err_dg = np.max(np.abs(dg[nz] / (P * ref.imag[nz]) - 1))
    area = loop.area(u0[nz]) / (np.pi * u0[nz] ** 2)
    err_area = np.max(np.abs(dg[nz] / (P * area) - 1))
    probe = d * np.array([0.5, 1 - 1e-9, 1.0, 1 + 1e-9, 1.5, 2.9])
    k_probe = loop_stiffness(loop, probe)
    err_quad = max(
        abs(k.real / adaptive_k1(loop, u) - 1) for k, u in zip(k_probe, probe, strict=True)
    )

    print(
        f"shifts_from_loop, Cattaneo-Mindlin, {N} amplitudes in [0, 3 d*], "
        f"{DEFAULT_NODES} nodes per half-interval"
    )
    print(f"  time: best {best:.3f} s of {len(times)} (median {np.median(times):.3f} s)")
    print(f"  max relative change with doubled nodes: Δf {err_df:.1e}, ΔΓ {err_dg:.1e}")
    print(f"  ΔΓ vs closed-form loop area (Mindlin-Deresiewicz): {err_area:.1e}")
    print(f"  Δf vs scipy adaptive quadrature of Eq. 4 near u0 = d*: {err_quad:.1e}")
    results = [target(f"shifts_from_loop, {N} CM amplitudes", best, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
