"""The flags of the particle fit (:func:`~contactres.analysis.fit_particles`, issue 28): each
name a step's ``flags`` can carry, and what it means (the table printed into particles.json)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

__all__ = ["DROPPED_FLAG", "PARTICLE_FLAGS"]

#: Flag name -> what it means (the names in :attr:`ParticleFit.flags`).
PARTICLE_FLAGS = {
    "sauerbrey-like": "a rigid contact fits as well (the particles move with the surface): "
    "only the mass coverage·m is identified, not κ and ξ",
    "inertial": "particles standing still fit as well (paper 2, Eq. 1): only coverage·κ and "
    "coverage·ξ are identified, not κ, ξ and the coverage apart",
    "wide-interval": "a value is not printed (κ, ξ, the coverage or κ_r, also named as "
    "unresolved): the fit's search found a point that fits nearly as well (Δχ² = D below the "
    "limit test's 9) farther than 1.3σ√max(D, 1) from it, so its error σ understates the "
    "interval the data allow (below the comb the χ² has two valleys); coverage·κ and "
    "coverage·ξ are printed there with their errors widened to hold such points",
    "outside-comb": "the coupled resonance lies outside the overtone comb",
    "overdamped": "a note (every value is printed): the contact's loss tangent ωξ/κ exceeds 1 "
    "at the coupled resonance, whose quality factor is then below 1 (its width exceeds its "
    "frequency): ΔΓ_n shows no peak there, and f_coupled (the resonance without damping) "
    "marks no feature of the shifts",
    "kappa-unresolved": "the contact stiffness κ (and f_coupled) is not identified by the data",
    "xi-unresolved": "the contact drag ξ is not identified by the data (at the noise level)",
    "coverage-unresolved": "the coverage is not identified by the data",
    "rocking-unresolved": "the rotational stiffness κ_r is not identified by the data (nor is "
    "f_coupled, which it sets)",
    "fit-at-bound": "a parameter ended on its bound (ξ = 0)",
    "poor-fit": "χ² far beyond what the noise allows (P < 1e-4 for a stated noise, or one "
    "pooled over the series): the fit stopped away from its minimum or the model does not fit "
    "this step (no value is reported)",
    "model-misfit": "the model's residuals are far larger than the noise of the time series "
    "(read off its step-to-step differences): the model does not fit (check the rocking "
    "choice, the particle's radius and density, the medium); no value is reported",
    "not-converged": "the least-squares fit did not converge (no value is reported)",
    "too-few-overtones": "fewer than two overtones measured at this time step (with the noise "
    "estimated from the residuals: fewer than 4 degrees of freedom, 2 × overtones − parameters)",
    "no-signal": "no particles at all (zero shifts) fit as well: the fit gains less over "
    "them than pure noise reaches in one step in 10⁴ (a Δχ² threshold of about 25 for seven "
    "overtones, growing with their number); the shifts are at the noise level and nothing is "
    "identified (no value is reported)",
    "particle-smaller-than-delta": "the particle is smaller than the penetration depth of the "
    "liquid at too many overtones to fit the rest: the hydrodynamic model does not hold "
    "(lattice Boltzmann is the tool)",
    "dropped-overtones-R<delta": "the overtones named after the colon were left out of the "
    "fit: the particle is smaller than the liquid's penetration depth there (δ is largest at "
    "the lowest overtones); the others are fitted",
}

#: The name of the flag of the overtones left out (followed by ": 1,3" in a step's flags).
DROPPED_FLAG = "dropped-overtones-R<delta"


def misfit_fields(flags, shape, fit_rocking: bool) -> dict[str, Any]:
    """The fields of a fit whose model misfits (:func:`~._particles.fit_particles`): every value
    and error left out (NaN of ``shape``) and every step's flags gaining "model-misfit" and the
    unresolved parameters; the model curves, χ² and the raw values stay (they show how it
    misfits)."""
    nan = np.full(shape, np.nan)
    unresolved: tuple[str, ...] = ("kappa-unresolved", "xi-unresolved", "coverage-unresolved")
    unresolved += ("rocking-unresolved",) if fit_rocking else ()
    values = "kappa coverage xi f_coupled kappa_r coverage_kappa coverage_xi".split()
    blank: dict[str, Any] = {name: nan for v in values for name in (v, f"{v}_err")}
    blank["flags"] = tuple(
        (*f, "model-misfit", *(u for u in unresolved if u not in f)) for f in flags
    )
    return blank


def noise_checked(fit, noise_fit, noise_series, bad: bool, fit_rocking: bool):
    """``fit`` (a :class:`~._particles.ParticleFit`) with the model's noise and the series'
    own (:func:`~._particle_input.noise_check`) recorded, and left out with every step flagged
    "model-misfit" where ``bad`` (:func:`misfit_fields`)."""
    fit = replace(fit, noise_fit=noise_fit, noise_series=noise_series)
    if not bad:
        return fit
    return replace(fit, **misfit_fields(fit.flags, np.shape(fit.kappa), fit_rocking))


def dropped_named(fit, overtones):
    """``fit`` with the overtones left out (R < δ) named on every step, as
    ``"dropped-overtones-R<delta: 1,3"`` (:data:`PARTICLE_FLAGS`: the name before the colon);
    unchanged when none was left out."""
    if len(overtones) == 0:
        return fit
    note = f"{DROPPED_FLAG}: {','.join(str(int(k)) for k in overtones)}"
    return replace(fit, flags=tuple((note, *f) for f in fit.flags))


def outside_cut(bad, rel, limits):
    """Rule 4 of :func:`~._particles.fit_particles` outside the comb: ``bad`` (κ, ξ, N, κ_r)
    with each value whose relative error ``rel`` exceeds its entry of ``limits`` (or is not
    finite) added."""
    return [b or not r <= lim for b, r, lim in zip(bad, rel, limits, strict=True)]
