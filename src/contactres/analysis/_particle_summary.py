"""The printed summary of a particle fit (:class:`contactres.analysis.ParticleFit`).

Apart from the fit itself so that its module stays within the house's size limit.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._summary import Summarised, flagged, number, values

__all__ = ["FitSummary"]


class FitSummary(Summarised):
    """Base of :class:`~contactres.analysis.ParticleFit`: its ``repr`` and notebook view."""

    __slots__ = ()

    def _facts(self) -> list[tuple[str, str]]:
        """Steps, fitted parameters, κ (N/m), ξ (kg/s), N (/m²), f_coupled (MHz), flags and
        the noise the residuals imply (Hz) where it was estimated."""
        fit: Any = self  # a ParticleFit, whose fields these are
        facts = [
            ("steps", str(np.size(fit.kappa))),
            ("fitted", ", ".join(fit.parameters)),
            ("κ", values(fit.kappa, "N/m")),
            ("ξ", values(fit.xi, "kg/s")),
            ("N", values(fit.coverage, "/m²")),
            ("f_coupled", values(fit.f_coupled, "MHz", 1e6)),
            ("flagged", flagged(fit.flags)),
        ]
        if np.isfinite(fit.noise_fit):
            facts.append(("noise σ̂", number(fit.noise_fit, "Hz")))
        return facts
