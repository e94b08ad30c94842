"""Make ``src/contactres/data/example_sweeps.csv``: synthetic QCM amplitude sweeps (paper 2), and
``example_spectra.csv``: the admittance spectra of a part of them (issue 14).

Run ``python scripts/make_example_data.py`` (seeded: the same file every time). The recipe is
:func:`contactres.measurements.example_study` (its docstring lists every parameter)
with the seed ``EXAMPLE_SEED``; the points come from the package's own forward model (paper 2,
Eqs. 1-14) plus Gaussian noise. With ``--experiments 14`` the same recipe gives the ~1,300-sweep
table of ``benchmarks/bench_analyze.py``. The spectra: configuration SiO2_1.2mm in air,
experiment e1, ramps 2 and 3 (every load), 40 points per spectrum, from
:func:`contactres.measurements.spectra_from_sweeps` (BVD resonator, peak
signal-to-noise 1000, two reference spectra), seed ``EXAMPLE_SEED``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from contactres.measurements import (
    EXAMPLE_SEED,
    example_study,
    spectra_from_sweeps,
    synthetic_sweeps,
)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = Path(__file__).resolve().parents[1]
    parser.add_argument(
        "--out", type=Path, default=here / "src" / "contactres" / "data" / "example_sweeps.csv"
    )
    parser.add_argument("--experiments", type=int, default=4)
    args = parser.parse_args(argv)
    table = synthetic_sweeps(example_study(args.experiments), EXAMPLE_SEED, constants=True)
    # Seven significant digits: below the noise, and a small file for the package.
    table.to_csv(args.out, index=False, float_format="%.7g")
    size = args.out.stat().st_size
    print(f"wrote {args.out}: {table['sweep'].nunique()} sweeps, {len(table)} points, {size} bytes")
    if args.experiments != 4:
        return
    part = table[
        (table["configuration"] == "SiO2_1.2mm")
        & (table["medium"] == "air")
        & (table["experiment"] == "e1")
        & table["ramp"].isin([2, 3])
    ]
    spectra = spectra_from_sweeps(part, n_points=40, seed=EXAMPLE_SEED)
    target = args.out.with_name("example_spectra.csv")
    # Frequencies to 0.01 Hz (the shifts are ~0.1-100 Hz), G and B to 7 digits (noise 1e-3).
    spectra["frequency_Hz"] = spectra["frequency_Hz"].map(lambda v: f"{v:.2f}")
    spectra.to_csv(target, index=False, float_format="%.7g")
    n_spec = spectra["spectrum"].nunique()
    print(f"wrote {target}: {n_spec} spectra, {len(spectra)} points, {target.stat().st_size} bytes")


if __name__ == "__main__":
    main()
