"""Synthetic QCM-D studies of attached particles (issue 28): the bundled example, the tests.

A :class:`ParticleStudy` is a time series of particles adsorbing on a sensor: the coverage
rises as N/A(t) = N_∞ (1 − exp(−t/τ)) (first-order adsorption kinetics) and the contacts stiffen
as they age, κ(t) = κ_0 + (κ_∞ − κ_0)(1 − exp(−t/τ_κ)), with the damping ξ constant. Every
point follows the package's forward model of a particle on its contact
(:func:`contactres.resonators.particle_shifts`: paper 2's small-load relation with the load of
N/A particles), then Gaussian noise of one stated standard deviation is added to Δf_n and to
ΔΓ_n. :func:`synthetic_particle_study` turns a study and a seed into the tidy table
``time_s, overtone, df_Hz, dgamma_Hz`` and the truth per time step; the random numbers are
drawn in one documented order, so a study and a seed give the same table on every run.

All quantities SI: m, kg/m³, N/m, kg/s, 1/m², Hz, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError

__all__ = ["PARTICLE_EXAMPLE_SEED", "ParticleStudy", "synthetic_particle_study"]

#: Seed of the bundled ``example_particles.csv`` (``scripts/make_example_particles.py``).
PARTICLE_EXAMPLE_SEED = 20100315


@dataclass(frozen=True)
class ParticleStudy:
    """A time series of particles adsorbing on a QCM-D sensor.

    The defaults are the bundled example: 1 µm silica spheres (R = 0.5 µm, ρ = 2200 kg/m³) in
    water on a 5 MHz crystal, overtones 1-13, free to rock about their contacts, 50 steps over
    an hour; the contact stiffens from 10 to 20 N/m, which moves the coupled resonance through
    the overtone comb (Δf_n changes sign over the overtones, as for the colloids of Olsson et
    al., Anal. Chem. 84, 4504 (2012)); noise σ = 0.1 Hz on Δf_n and ΔΓ_n.

    Parameters
    ----------
    radius : particle radius R, m
    density : particle density ρ, kg/m³ (a homogeneous sphere)
    medium : ``"air"``, ``"water"`` or None (no load of a medium)
    rocking : ``"free"`` or ``"locked"`` (:func:`contactres.resonators.particle_shifts`)
    fundamental : fundamental frequency f_F, Hz
    overtones : the odd overtone orders measured
    n_steps : time steps, evenly spaced from 0 to ``duration``
    duration : length of the run, s
    coverage : final coverage N_∞, particles per m²
    tau : time constant τ of the adsorption, s
    kappa_start, kappa_end : κ_0 and κ_∞ of one contact, N/m
    tau_kappa : time constant τ_κ of the contacts' ageing, s
    xi : damping ξ of one contact, kg/s
    noise : standard deviation σ of the Gaussian noise on Δf_n and on ΔΓ_n, Hz
    zq : acoustic impedance of AT-cut quartz, kg m^-2 s^-1
    """

    radius: float = 5e-7
    density: float = 2200.0
    medium: str | None = "water"
    rocking: str = "free"
    fundamental: float = 5e6
    overtones: tuple[int, ...] = (1, 3, 5, 7, 9, 11, 13)
    n_steps: int = 50
    duration: float = 3600.0
    coverage: float = 3e10
    tau: float = 600.0
    kappa_start: float = 10.0
    kappa_end: float = 20.0
    tau_kappa: float = 1200.0
    xi: float = 1e-8
    noise: float = 0.1
    zq: float = 8.8e6

    def __post_init__(self):
        if self.n_steps < 1 or not self.overtones:
            raise ContactresInputError("a particle study needs a time step and an overtone")
        if any(n < 1 or n % 2 == 0 for n in self.overtones):
            raise ContactresInputError(f"overtones {self.overtones} must be odd integers >= 1")
        if self.noise < 0:
            raise ContactresInputError(f"noise {self.noise!r} Hz must be >= 0")

    def times(self) -> np.ndarray:
        """The time of every step, s."""
        return np.linspace(0.0, self.duration, self.n_steps)

    def truth(self):
        """κ (N/m), ξ (kg/s) and the coverage (1/m²) of every step, as a DataFrame with the
        columns ``time_s, kappa_N_per_m, xi_kg_per_s, coverage_per_m2``."""
        import pandas as pd

        t = self.times()
        grown = 1.0 - np.exp(-t / self.tau)
        aged = 1.0 - np.exp(-t / self.tau_kappa)
        return pd.DataFrame(
            {
                "time_s": t,
                "kappa_N_per_m": self.kappa_start + (self.kappa_end - self.kappa_start) * aged,
                "xi_kg_per_s": np.full(t.size, self.xi),
                "coverage_per_m2": self.coverage * grown,
            }
        )


def synthetic_particle_study(study: ParticleStudy | None = None, seed: int = PARTICLE_EXAMPLE_SEED):
    """The tidy shift table of ``study`` and its truth.

    Parameters
    ----------
    study : ParticleStudy, optional
        The study (default: the bundled example's, ``ParticleStudy()``).
    seed : int
        Seed of :func:`numpy.random.default_rng`. The noise is drawn as one array of shape
        (steps, overtones, 2), Δf first, then ΔΓ, in the order of the table's rows.

    Returns
    -------
    shifts : DataFrame
        ``time_s, overtone, df_Hz, dgamma_Hz`` (Δf_n not divided by n; ΔΓ_n the half-bandwidth
        shift), one row per time and overtone, time-major.
    truth : DataFrame
        :meth:`ParticleStudy.truth`.
    """
    import pandas as pd

    from ..resonators import Particle, medium_named, particle_shifts

    study = ParticleStudy() if study is None else study
    truth = study.truth()
    particle = Particle.sphere(study.radius, study.density)
    medium = None if study.medium is None else medium_named(study.medium)
    n = np.asarray(study.overtones, dtype=float)
    df, dgamma = particle_shifts(
        study.fundamental,
        n[None, :],
        particle,
        truth["kappa_N_per_m"].to_numpy()[:, None],
        truth["xi_kg_per_s"].to_numpy()[:, None],
        truth["coverage_per_m2"].to_numpy()[:, None],
        rocking=study.rocking,
        medium=medium,
        zq=study.zq,
    )
    shape = (study.n_steps, n.size)
    df, dgamma = np.broadcast_to(df, shape), np.broadcast_to(dgamma, shape)
    noise = np.random.default_rng(seed).normal(0.0, study.noise, size=(*shape, 2))
    shifts = pd.DataFrame(
        {
            "time_s": np.repeat(truth["time_s"].to_numpy(), n.size),
            "overtone": np.tile(np.asarray(study.overtones, dtype=int), study.n_steps),
            "df_Hz": (df + noise[..., 0]).ravel(),
            "dgamma_Hz": (dgamma + noise[..., 1]).ravel(),
        }
    )
    return shifts, truth
