"""Analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion."""

from ..tangential import kappa_jkr_mindlin
from .pipeline import AnalysisSettings, analyze, fit_jkr_mindlin

__all__ = ["AnalysisSettings", "analyze", "fit_jkr_mindlin", "kappa_jkr_mindlin"]
