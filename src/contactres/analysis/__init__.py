"""Analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion.

``analyze`` (:mod:`.pipeline`) runs the steps; the modules hold one step each: padded arrays and
closed-form fits (:mod:`.amplitude`), the exact loops (:mod:`.loops`), the fitted models, one
module each, with their registry and batched fitters (:mod:`.models`), the model choice
(:mod:`.classify`), friction (:mod:`.friction`), drift (:mod:`.drift`), statistics per load
(:mod:`.loads`), the JKR + Mindlin fit (:mod:`.jkr`), the radiation loss of the contacts
(:mod:`.radiation`), the flags (:mod:`.flags`), the points and fitted curves the report draws
(:mod:`.curves`) and the results (:mod:`.results`).

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein J.
Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.
"""

from .flags import Flag
from .jkr import fit_jkr_mindlin
from .models import REGISTRY
from .pipeline import AnalysisSettings, analyze
from .results import Results

__all__ = [
    "REGISTRY",
    "AnalysisSettings",
    "Flag",
    "Results",
    "analyze",
    "fit_jkr_mindlin",
]
