"""The settings of the sweep analysis, :class:`AnalysisSettings` (paper 2).

A module of their own, light to import (no pandas or scipy): :func:`contactres.analyze` takes
them, and the steps it runs on the first call (:mod:`contactres.analysis._steps`) read them.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ContactresInputError

__all__ = ["AnalysisSettings"]


@dataclass(frozen=True)
class AnalysisSettings:
    """Settings of :func:`analyze` (all recorded in ``summary.json``).

    Attributes
    ----------
    keep_first_ramp : use ramp 1 of every load (default: set aside as running-in)
    keep_drift : use the sweeps of loads whose ramps drift (default: left out of the means and
        fits, and listed)
    remove_drift : where the table has ``time_s``, remove a drift linear in time from the loads
        found drifting, test them again and use those that pass (flag ``drift-removed``)
    pool_experiments : decide the friction law (Coulomb or Savkoor) once per experiment from
        all its loads (:mod:`contactres.analysis._blocks`), and weigh the μ of each load
        block's Coulomb loops against the experiment's other loads in its class choice
        (:mod:`contactres.analysis._mu_prior`); False: each load block alone
    delta_bic : BIC margin within which the simpler amplitude model is kept
    drift_p : false-alarm probability of the drift test
    bootstrap : number of bootstrap resamples over experiments for E and γ (0: none)
    seed : seed of the bootstrap
    exact_loop : fit the exact Cattaneo-Mindlin loop (μ_fit), behind a stick plateau for
        ``plateau`` sweeps
    zq : shear-wave impedance of the quartz, kg m⁻² s⁻¹
    workers : processes for the per-sweep and per-block fits, the plateau's evidence, the
        fitted curves and the groups' JKR fits, started once for the whole analysis
        (:mod:`contactres.analysis._workers`; 1: none; more pay from ~10^4 sweeps on; a script
        that passes more must be importable where processes are spawned, see
        :func:`contactres.analysis._classify.fit_sweeps`)
    sphere_material, plate_material : str or None
        Names of the two bodies for the radiation loss of the contact
        (:func:`contactres.analysis.material_by_name`: a built-in solid, e.g.
        ``"soda-lime-glass"`` or ``"glass"``; the plate also ``"quartz-AT"``, the AT-cut quartz
        of the QCM); both or neither (None: no radiation table).
    coating : (material, thickness_m) pair, a sequence of them (top first), or None
        The film(s) on the plate (:func:`contactres.analysis._coating.as_coating`; e.g.
        ``(contactres.pmma(), 250e-9)``; from text, ``"pmma:250e-9"``, with
        :func:`contactres.jobs.contact.parse_coating`): E and γ are then fitted with the coated
        plate's contact mechanics (step 9), E the Young's modulus of the sphere and of the
        plate's substrate. Thickness in (0, 1 m]. With the radiation materials, the radiation
        loss is that of the coated plate (step 8).
    """

    keep_first_ramp: bool = False
    keep_drift: bool = False
    remove_drift: bool = False
    pool_experiments: bool = True
    delta_bic: float = 2.0
    drift_p: float = 1e-3
    bootstrap: int = 200
    seed: int = 0
    exact_loop: bool = True
    zq: float = 8.8e6
    workers: int = 1
    sphere_material: str | None = None
    plate_material: str | None = None
    coating: object = None

    def __post_init__(self):
        if not self.delta_bic >= 0:
            raise ContactresInputError(f"delta_bic must be >= 0, got {self.delta_bic!r}")
        if not 0 < self.drift_p < 1:
            raise ContactresInputError(f"drift_p must lie in (0, 1), got {self.drift_p!r}")
        if int(self.bootstrap) != self.bootstrap or self.bootstrap < 0:
            raise ContactresInputError(
                f"bootstrap must be a whole number >= 0, got {self.bootstrap!r}"
            )
        if not self.zq > 0:
            raise ContactresInputError(f"zq must be > 0, got {self.zq!r}")
        if int(self.workers) != self.workers or self.workers < 1:
            raise ContactresInputError(f"workers must be a whole number >= 1, got {self.workers!r}")
        if (self.sphere_material is None) != (self.plate_material is None):
            raise ContactresInputError(
                "sphere_material and plate_material go together: give both (e.g. "
                "'soda-lime-glass' and 'quartz-AT') or neither"
            )
        if self.sphere_material is not None:
            # Imported here: an analysis without materials loads no half-space or dynamic solver.
            from ._radiation import material_by_name

            material_by_name(self.sphere_material, "sphere")  # ValueError naming the known
            material_by_name(self.plate_material, "plate")
        if self.coating is not None:
            # Imported here: an analysis without a coating loads no layered solver.
            from ._coating import as_coating

            object.__setattr__(
                self, "coating", as_coating(self.coating, "AnalysisSettings(coating=...)")
            )
