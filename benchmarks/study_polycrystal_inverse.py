"""The inverse of a polycrystal map on real pixels: issue 16's acceptance, measured.

For each seed: a synthetic Cu polycrystal (:func:`contactres.jobs.maps.synthetic_map`: seeded
Voronoi grains, random orientations, exact M per grain, Hertz k* of a rigid 20 nm tip at 1 µN,
1 % Gaussian noise on every pixel), then the fit of C12/C11 and C44/C11
(:func:`contactres.jobs.maps.fit_measured_map`) twice: with the map's grain labels, and without
them (grains reconstructed by :func:`contactres.polycrystal.segment_grains`, 2°). Prints
per fit the relative errors of the ratios, their reported standard errors, the weak combination
and its relative error, M(111)/M(001) against the truth, and the time.

Targets (issue 16): on 2000 x 2000 pixels with 60 grains both ratios within 1 % and the weak
combination reported; on 512 x 512 the weak combination's uncertainty stated (and the truth
within 3 of it). The 1 % is ~1.6σ of C44/C11 for 60 grains (σ ≈ 0.6 %): about one noise draw in
seven misses it; the study prints how many of its seeds do.

Usage: ``python benchmarks/study_polycrystal_inverse.py [--size 2000] [--grains 60]
[--seeds 1 2 3]``; exit code 1 if a target is missed.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from contactres import Material, indentation_modulus
from contactres.jobs.maps import TipLoad, fit_measured_map, synthetic_map
from contactres.polycrystal import map_from_dataset

CU = Material.crystal("Cu")
TRUE = np.array([CU.C[0, 1] / CU.C[0, 0], CU.C[3, 3] / CU.C[0, 0]])
A111 = indentation_modulus(CU.rotated((1, 1, 1))) / indentation_modulus(CU)
TIP = TipLoad(radius=20e-9, force=1e-6)


def one(size: int, grains: int, seed: int) -> list[dict]:
    t0 = time.perf_counter()
    ds = synthetic_map(CU, "cubic", TIP, shape=(size, size), n_grains=grains, seed=seed, noise=0.01)
    omap = map_from_dataset(ds)
    k = ds["k_star_N_per_m"].values
    t_make = time.perf_counter() - t0
    rows = []
    for labelled in (True, False):
        m = omap if labelled else map_from_dataset(ds.drop_vars("labels"))
        t0 = time.perf_counter()
        res, _, _ = fit_measured_map(m, k, quantity="stiffness")
        err = np.array([res.c12_c11, res.c44_c11]) / TRUE - 1
        sig = np.array([res.c12_c11_error, res.c44_c11_error]) / TRUE
        rows.append(
            dict(
                labels="given" if labelled else "segmented",
                grains=res.n_grains,
                err=err,
                sig=sig,
                weak=res.weak_combination,
                weak_err=res.weak_error,
                weak_truth=float(np.exp(res.weak_direction @ np.log(TRUE))),
                a111=res.anisotropy_111,
                a111_err=res.anisotropy_111_error,
                seconds=time.perf_counter() - t0,
                make=t_make,
            )
        )
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=2000)
    ap.add_argument("--grains", type=int, default=60)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    args = ap.parse_args(argv)
    print(f"{args.size} x {args.size} pixels, {args.grains} grains, 1 % noise per pixel")
    print(f"truth: C12/C11 = {TRUE[0]:.5f}, C44/C11 = {TRUE[1]:.5f}, M(111)/M(001) = {A111:.5f}")
    within, fits, ok = 0, 0, True
    for seed in args.seeds:
        for r in one(args.size, args.grains, seed):
            fits += 1
            both = bool(np.all(np.abs(r["err"]) < 0.01))
            within += both
            pull = abs(np.log(r["weak"] / r["weak_truth"])) / r["weak_err"]
            print(
                f"seed {seed} labels {r['labels']:9s} {r['grains']:3d} grains: "
                f"C12/C11 {100 * r['err'][0]:+.2f} % (σ {100 * r['sig'][0]:.2f} %), "
                f"C44/C11 {100 * r['err'][1]:+.2f} % (σ {100 * r['sig'][1]:.2f} %); weak "
                f"{r['weak']:.5g} ± {100 * r['weak_err']:.2g} % (truth {r['weak_truth']:.5g}, "
                f"{pull:.2f}σ); M111/M001 {r['a111']:.5f} ± {r['a111_err']:.2g} "
                f"(truth {A111:.5f}); fit {r['seconds']:.1f} s, map {r['make']:.1f} s"
            )
            if args.size >= 2000:
                ok &= np.isfinite(r["weak"])
            else:
                ok &= bool(pull < 3)
    print(f"both ratios within 1 %: {within} of {fits} fits")
    if args.size >= 2000:
        ok &= within >= fits - 1  # one miss in a few draws is what σ ≈ 0.6 % predicts
    print("targets met" if ok else "TARGET MISSED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
