"""Make ``src/contactres/data/example_sweeps.csv``: synthetic QCM amplitude sweeps (paper 2).

Run ``python scripts/make_example_data.py`` (seeded: the same file every time). The recipe is
:func:`contactres.measurements.studies.example_study` (its docstring lists every parameter)
with the seed ``EXAMPLE_SEED``; the points come from the package's own forward model (paper 2,
Eqs. 1-14) plus Gaussian noise. With ``--experiments 14`` the same recipe gives the ~1,300-sweep
table of ``benchmarks/bench_analyze.py``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from contactres.measurements.studies import EXAMPLE_SEED, example_study
from contactres.measurements.synthetic import synthetic_sweeps


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


if __name__ == "__main__":
    main()
