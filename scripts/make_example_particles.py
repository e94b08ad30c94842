"""Make ``src/contactres/data/example_particles.csv``: a synthetic QCM-D study of attached
particles (issue 28), the bundled example of ``contactres qcm particles``.

Run ``python scripts/make_example_particles.py`` (seeded: the same file every time). The recipe
is :class:`contactres.measurements.ParticleStudy` with its defaults (its docstring lists every
parameter: 1 µm silica spheres in water on a 5 MHz crystal, overtones 1-13, 50 steps over an
hour, the coverage rising and the contacts stiffening, noise 0.1 Hz on Δf_n and ΔΓ_n) and the
seed ``PARTICLE_EXAMPLE_SEED``; the shifts come from the package's forward model
(:func:`contactres.resonators.particle_shifts`) plus Gaussian noise.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from contactres.measurements import PARTICLE_EXAMPLE_SEED, ParticleStudy, synthetic_particle_study


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = Path(__file__).resolve().parents[1]
    parser.add_argument(
        "--out", type=Path, default=here / "src" / "contactres" / "data" / "example_particles.csv"
    )
    args = parser.parse_args(argv)
    shifts, _ = synthetic_particle_study(ParticleStudy(), PARTICLE_EXAMPLE_SEED)
    # Seven significant digits: 1 mHz on the largest shifts (~1 kHz), below the 0.1 Hz noise.
    shifts.to_csv(args.out, index=False, float_format="%.7g")
    size = args.out.stat().st_size
    steps = shifts["time_s"].nunique()
    print(f"wrote {args.out}: {steps} time steps, {len(shifts)} rows, {size} bytes")


if __name__ == "__main__":
    main()
