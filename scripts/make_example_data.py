"""Make ``src/contactres/data/example_sweeps.csv``: synthetic QCM amplitude sweeps (paper 2).

Run ``python scripts/make_example_data.py`` (seeded: the same file every time). Every point comes
from the package's own forward model: JKR contact radius (paper 2, Eq. 9) -> Mindlin stiffness
κ = 2G*a (Eq. 7) -> tangential loop (Cattaneo-Mindlin, Eq. 6; a few Savkoor, Eq. 13-14; a few with
a stick plateau) plus a dashpot ωξ -> QCM shifts (Eqs. 4-5) -> Gaussian noise.

Parameters (SI; see ``PARAMETERS`` and ``CONFIGURATIONS`` below):

- resonator: f_F = 5 MHz, overtone 3, A_eff = 2.5e-5 m², Z_q = 8.8e6 kg m⁻² s⁻¹, tripod n_P = 3;
- two configurations, glass spheres on a silica-coated QCM, ν = 0.17 (E1 = E2 = E):
  ``SiO2_2.2mm`` (R = 1.1 mm): air E = 70 GPa, γ = 0.19 J/m²; water E = 77 GPa, γ = 0.05 J/m²;
  ``SiO2_1.2mm`` (R = 0.6 mm): air E = 61 GPa, γ = 0.03 J/m²; water E = 67 GPa, γ = 0.02 J/m²;
- loads: tripod 0.5 g plus 0, 0.5, ..., 2.5 g, F_N = m g/3 per contact (1.6 ... 9.8 mN);
- friction μ = 1.2 (F_N/1.635 mN)^-0.1 (falls slightly with load); ωξ such that ΔΓ0 = 5 Hz in
  air and 8 Hz in water at every load (load-independent, as in paper 2, Fig. 7);
- amplitudes: 13 steps 0.5-10 nm in air, 11 steps 0.3-5 nm in water; four ramps per load
  (up, down, up, down);
- experiment-to-experiment scatter: E x lognormal(3 %), γ x lognormal(20 %), μ x lognormal(5 %);
- running-in: ramp 1 has κ 6 % lower and μ 30 % lower;
- noise: σ = 0.3 Hz (air) and 0.6 Hz (water) on Δf and ΔΓ;
- about 8 % of loads have a stick plateau in ramps 2-4 (critical displacement 25-40 % of the
  largest amplitude); experiment 4 of SiO2_1.2mm in air follows Savkoor (τ0 such that full
  sliding is at twice the largest amplitude); experiment 3 of SiO2_2.2mm in air drifts by
  +1.5 Hz per ramp at the 1.0 g load.

With ``--experiments 14`` the same recipe gives the ~1,300-sweep table of the benchmark.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from contactres.tangential import kappa_jkr_mindlin
from contactres.normal.isotropic import effective_modulus, jkr_contact_radius
from contactres.resonators.qcm import QCM, shifts_from_loop
from contactres.tangential import CattaneoMindlinLoop, PlateauLoop, SavkoorLoop, with_dashpot

PARAMETERS = dict(
    fundamental_Hz=5e6,
    overtone=3,
    area_m2=2.5e-5,
    n_contacts=3,
    poisson=0.17,
    tripod_mass_kg=0.5e-3,
    added_mass_kg=(0.0, 0.5e-3, 1.0e-3, 1.5e-3, 2.0e-3, 2.5e-3),
    g=9.81,
    mu0=1.2,
    mu_exponent=-0.1,
    dgamma0_Hz={"air": 5.0, "water": 8.0},
    amplitudes_m={"air": np.linspace(0.5e-9, 10e-9, 13), "water": np.linspace(0.3e-9, 5e-9, 11)},
    noise_Hz={"air": 0.3, "water": 0.6},
    scatter={"E": 0.03, "gamma": 0.2, "mu": 0.05},
    running_in={"kappa": 0.94, "mu": 0.7},
    plateau_fraction=0.08,
    seed=20150601,
)
CONFIGURATIONS = {
    "SiO2_2.2mm": dict(radius=1.1e-3, air=(70e9, 0.19), water=(77e9, 0.05)),
    "SiO2_1.2mm": dict(radius=0.6e-3, air=(61e9, 0.03), water=(67e9, 0.02)),
}


def make_sweeps(n_experiments: int = 4, seed: int = PARAMETERS["seed"]) -> pd.DataFrame:
    """The synthetic sweep table (one row per point) described in the module docstring."""
    p = PARAMETERS
    rng = np.random.default_rng(seed)
    q = QCM(p["fundamental_Hz"], p["overtone"], p["area_m2"])
    P = q.sensitivity(p["n_contacts"])
    nu = p["poisson"]
    loads = [(p["tripod_mass_kg"] + m) * p["g"] / 3.0 for m in p["added_mass_kg"]]
    frames = []
    for config, c in CONFIGURATIONS.items():
        R = c["radius"]
        for medium in ("air", "water"):
            E0, gamma0 = c[medium]
            u_up = p["amplitudes_m"][medium]
            sigma = p["noise_Hz"][medium]
            omega_xi = p["dgamma0_Hz"][medium] / P
            for e in range(1, n_experiments + 1):
                E = E0 * rng.lognormal(0.0, p["scatter"]["E"])
                gamma = gamma0 * rng.lognormal(0.0, p["scatter"]["gamma"])
                mu_e = rng.lognormal(0.0, p["scatter"]["mu"])
                savkoor = config == "SiO2_1.2mm" and medium == "air" and e == 4
                for j, F in enumerate(loads):
                    kappa0 = kappa_jkr_mindlin(F, E, gamma, R, nu)
                    mu0 = p["mu0"] * (F / loads[0]) ** p["mu_exponent"] * mu_e
                    # A stick plateau belongs to a load of an experiment (ramps 2-4), not a ramp.
                    plateau = rng.random() < p["plateau_fraction"]
                    dc = rng.uniform(0.25, 0.4) * u_up[-1]
                    for ramp in (1, 2, 3, 4):
                        first = ramp == 1
                        kappa = kappa0 * (p["running_in"]["kappa"] if first else 1.0)
                        mu = mu0 * (p["running_in"]["mu"] if first else 1.0)
                        loop = CattaneoMindlinLoop(kappa, mu, F)
                        if savkoor:
                            a = jkr_contact_radius(effective_modulus(E, nu), R, F, gamma)
                            tau = kappa * 2.0 * u_up[-1] / (4.0 * a**2)
                            loop = SavkoorLoop(kappa, tau, a)
                        elif plateau and not first:
                            loop = PlateauLoop(loop, dc)
                        u = u_up if ramp % 2 else u_up[::-1]
                        df, dg = shifts_from_loop(
                            q, with_dashpot(loop, omega_xi / q.omega, q.omega), u, p["n_contacts"]
                        )
                        df = df + rng.normal(0.0, sigma, u.size)
                        dg = dg + rng.normal(0.0, sigma, u.size)
                        if config == "SiO2_2.2mm" and medium == "air" and e == 3 and j == 2:
                            df = df + 1.5 * (ramp - 1)
                        frames.append(
                            pd.DataFrame(
                                {
                                    "sweep": f"{config}/{medium}/e{e}/F{j}/r{ramp}",
                                    "experiment": f"e{e}",
                                    "configuration": config,
                                    "medium": medium,
                                    "ramp": ramp,
                                    "normal_force_N": F,
                                    "amplitude_m": u,
                                    "df_Hz": df,
                                    "dgamma_Hz": dg,
                                    "sphere_radius_m": R,
                                }
                            )
                        )
    table = pd.concat(frames, ignore_index=True)
    for name in ("fundamental_Hz", "overtone", "area_m2", "n_contacts", "poisson"):
        table[name] = p[name]
    return table


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = Path(__file__).resolve().parents[1]
    parser.add_argument(
        "--out", type=Path, default=here / "src" / "contactres" / "data" / "example_sweeps.csv"
    )
    parser.add_argument("--experiments", type=int, default=4)
    args = parser.parse_args(argv)
    table = make_sweeps(args.experiments)
    table.to_csv(args.out, index=False, float_format="%.7g")
    size = args.out.stat().st_size
    print(f"wrote {args.out}: {table['sweep'].nunique()} sweeps, {len(table)} points, {size} bytes")


if __name__ == "__main__":
    main()
