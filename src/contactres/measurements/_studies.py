"""Recipes of synthetic QCM studies: the bundled example data and the validation study.

Each recipe is a :class:`~contactres.measurements.SweepStudy` modelled on paper 2's
experiment; :func:`~contactres.measurements.synthetic_sweeps` turns it and a seed into
a sweep table.
"""

from __future__ import annotations

import numpy as np

from ..resonators import QCM
from ._synthetic import Drift, SweepGroup, SweepStudy

__all__ = ["EXAMPLE_SEED", "example_study", "validation_study"]

#: Seed of the bundled example data (``scripts/make_example_data.py``).
EXAMPLE_SEED = 20150601


def example_study(n_experiments: int = 4) -> SweepStudy:
    """The study of the bundled ``example_sweeps.csv`` (seed :data:`EXAMPLE_SEED`).

    Modelled on paper 2's experiment: glass spheres on a silica-coated 5 MHz QCM (overtone 3,
    A_eff = 2.5e-5 m², Z_q = 8.8e6 kg m⁻² s⁻¹), tripod n_P = 3, ν = 0.17 (E1 = E2 = E):

    - ``SiO2_2.2mm`` (R = 1.1 mm): air E = 70 GPa, γ = 0.19 J/m²; water E = 77 GPa,
      γ = 0.05 J/m²; ``SiO2_1.2mm`` (R = 0.6 mm): air E = 61 GPa, γ = 0.03 J/m²; water
      E = 67 GPa, γ = 0.02 J/m²;
    - loads: tripod 0.5 g plus 0, 0.5, ..., 2.5 g, F_N = m g/3 per contact (1.6 ... 9.8 mN);
    - μ = 1.2 (F_N/1.635 mN)^-0.1 (falls slightly with load); ωξ such that ΔΓ0 = 5 Hz in air
      and 8 Hz in water at every load (load-independent, as in paper 2, Fig. 7);
    - amplitudes: 13 steps 0.5-10 nm in air, 11 steps 0.3-5 nm in water; four ramps per load
      (up, down, up, down);
    - experiment-to-experiment scatter: E x lognormal(3 %), γ x lognormal(20 %),
      μ x lognormal(5 %);
    - running-in: ramp 1 has κ 6 % lower and μ 30 % lower;
    - noise: σ = 0.3 Hz (air) and 0.6 Hz (water) on Δf and ΔΓ;
    - about 8 % of loads have a stick plateau in ramps 2-4 (critical displacement 25-40 % of
      the largest amplitude); experiment 4 of SiO2_1.2mm in air follows Savkoor (τ0 such that
      full sliding is at twice the largest amplitude); experiment 3 of SiO2_2.2mm in air drifts
      by +1.5 Hz per ramp at the 1.0 g load.

    Parameters
    ----------
    n_experiments : repeated experiments per configuration and medium (14 gives the
        ~1,300-sweep table of the analysis benchmark)
    """
    q = QCM(5e6, 3, 2.5e-5)
    P = q.sensitivity(3)
    g = 9.81
    loads = tuple((0.5e-3 + m) * g / 3.0 for m in (0.0, 0.5e-3, 1.0e-3, 1.5e-3, 2.0e-3, 2.5e-3))
    # per medium: amplitudes (m), omega_xi (N/m), noise (Hz), the last fields of SweepGroup
    air = (tuple(np.linspace(0.5e-9, 10e-9, 13)), 5.0 / P, 0.3)
    water = (tuple(np.linspace(0.3e-9, 5e-9, 11)), 8.0 / P, 0.6)
    groups = (
        SweepGroup("SiO2_2.2mm", "air", 1.1e-3, 70e9, 0.19, *air),
        SweepGroup("SiO2_2.2mm", "water", 1.1e-3, 77e9, 0.05, *water),
        SweepGroup("SiO2_1.2mm", "air", 0.6e-3, 61e9, 0.03, *air),
        SweepGroup("SiO2_1.2mm", "water", 0.6e-3, 67e9, 0.02, *water),
    )
    return SweepStudy(
        groups=groups,
        normal_forces=loads,
        n_experiments=n_experiments,
        qcm=q,
        n_contacts=3,
        poisson=0.17,
        mu=1.2,
        mu_exponent=-0.1,
        scatter=(("E", 0.03), ("gamma", 0.2), ("mu", 0.05)),
        running_in_kappa=0.94,
        running_in_mu=0.7,
        random_plateau=0.08,
        savkoor_experiments=(("SiO2_1.2mm", "air", 4),),
        drifts=(Drift("SiO2_2.2mm", "air", 3, 2, 1.5),),
    )


def validation_study(n_experiments: int = 4) -> SweepStudy:
    """The study that the QCM analysis is validated on (``benchmarks/study_qcm_trust.py``).

    Harder than :func:`example_study`, in the spirit of paper 2's experiment: three
    configurations (glass spheres R = 1.1 mm and 0.6 mm on silica, and R = 1.1 mm on a PMMA
    coating, taken as E1 = E2 = E, driven to 60 nm so that its softer
    contact reaches slip), air and water, six loads, ``n_experiments`` repeated
    experiments, four ramps (up, down, up, down), and:

    - noise σ = 0.3 Hz in air and 0.6 Hz in water (as in :func:`example_study`);
    - 15 % of the loads of an experiment show a stick plateau in ramps 2-4 (critical
      displacement 20-45 % of the largest amplitude);
    - one experiment per medium follows Savkoor (SiO2_1.2mm e4 in air, SiO2_2.2mm e2 in water;
      full sliding at twice the largest amplitude);
    - running-in: ramp 1 has κ 6 % lower and μ 30 % lower;
    - drift of Δf in three loads (+1.5, +2, -2 Hz per ramp);
    - scatter between experiments: E lognormal 3 %, γ 20 %, μ 5 %; μ = 1.2 (F_N/F_1)^-0.1.

    Truths: E and γ of each group as listed in the groups, μ from ``mu``, ``mu_exponent``
    and the scatter (``synthetic_sweeps(..., truth=True)`` gives them per sweep).
    """
    base = example_study(n_experiments)
    # The glass groups of the example, as they are (same media, same sphere materials).
    air = {k: getattr(base.groups[0], k) for k in ("amplitudes", "omega_xi", "noise")}
    water = {k: getattr(base.groups[1], k) for k in ("amplitudes", "omega_xi", "noise")}
    soft_air = dict(air, amplitudes=tuple(np.linspace(3e-9, 60e-9, 13)))
    soft_water = dict(water, amplitudes=tuple(np.linspace(3e-9, 60e-9, 11)))
    groups = (
        *base.groups,
        # The soft contact slips later: the drive is raised until it does (x = κu0/(μF_N) ~ 0.5-1).
        SweepGroup("PMMA_2.2mm", "air", 1.1e-3, 5e9, 0.04, **soft_air),
        SweepGroup("PMMA_2.2mm", "water", 1.1e-3, 4.5e9, 0.03, **soft_water),
    )
    return SweepStudy(
        groups=groups,
        normal_forces=base.normal_forces,
        n_experiments=n_experiments,
        qcm=base.qcm,
        n_contacts=base.n_contacts,
        poisson=base.poisson,
        mu=base.mu,
        mu_exponent=base.mu_exponent,
        scatter=base.scatter,
        running_in_kappa=base.running_in_kappa,
        running_in_mu=base.running_in_mu,
        random_plateau=0.15,
        random_plateau_range=(0.2, 0.45),
        savkoor_experiments=(("SiO2_1.2mm", "air", 4), ("SiO2_2.2mm", "water", 2)),
        drifts=(
            Drift("SiO2_2.2mm", "air", 3, 2, 1.5),
            Drift("SiO2_1.2mm", "water", 1, 4, 2.0),
            Drift("PMMA_2.2mm", "air", 2, 1, -2.0),
        ),
    )
