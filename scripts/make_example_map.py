"""Make ``src/contactres/data/example_cu_map.ang`` (an EBSD-style orientation map of a synthetic
Cu polycrystal) and ``example_cu_kstar.csv`` (its 'measured' contact-stiffness map, N/m).

Run ``python scripts/make_example_map.py`` (seeded: the same files every time). The recipe:
:func:`contactres.jobs.maps.synthetic_map` with Cu (built-in constants), 64 x 64 pixels of
1 µm, 16 Voronoi grains with random orientations (seed 7), a rigid tip of R = 20 nm at
F = 1 µN (Hertz, k* = 2aM), and 1 % Gaussian noise per pixel. The .ang names the phase Cu
(lattice and space group of :func:`contactres.polycrystal.ebsd_phase`, so that orix reads it)
and holds no grain labels
(``contactres maps fit`` reconstructs the grains); the CSV has one line per row y, one value
per column x, six significant digits.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contactres.jobs.maps import TipLoad, synthetic_map
from contactres.materials import Material
from contactres.polycrystal import ebsd_phase, map_from_dataset, write_ang

SHAPE, GRAINS, SEED, NOISE = (64, 64), 16, 7, 0.01
TIP = TipLoad(radius=20e-9, force=1e-6)


def main() -> None:
    data = Path(__file__).resolve().parents[1] / "src" / "contactres" / "data"
    ds = synthetic_map(
        Material.crystal("Cu"), "cubic", TIP, shape=SHAPE, n_grains=GRAINS, seed=SEED, noise=NOISE
    )
    omap = map_from_dataset(ds.drop_vars("labels"))
    ang = write_ang(data / "example_cu_map.ang", omap, ebsd_phase("Cu"))  # Cu's name, lattice
    csv = data / "example_cu_kstar.csv"
    np.savetxt(csv, ds["k_star_N_per_m"].values, fmt="%.6g", delimiter=",")
    for path in (ang, csv):
        print(f"wrote {path}: {path.stat().st_size} bytes")


if __name__ == "__main__":
    main()
