"""``jkr-mindlin``: the load dependence κ(F_N) = 2G*a with the JKR contact radius a (paper 2,
Eqs. 7-10; E1 = E2 = E, ν fixed).

Fitted per configuration and medium by :func:`contactres.analysis.fit_jkr_mindlin` (not
per sweep: no :class:`~contactres.analysis._models.base.SweepFit`).
"""

from __future__ import annotations

from ...fitting import Model, Parameter
from ...tangential import kappa_jkr_mindlin
from ...units import POISSON_OPEN_RANGE

__all__ = ["MODEL"]

MODEL = Model(
    "jkr-mindlin",
    "JKR + Mindlin tangential stiffness",
    (
        Parameter("E", "Young's modulus E", "Pa", "E_Pa", (1e6, 1e13), scale=1e10),
        Parameter("gamma", "energy of adhesion γ", "J/m^2", "gamma_J_m2", (0.0, 1e3), scale=0.1),
        Parameter("radius", "sphere radius R", "m", "sphere_radius_m", (1e-9, 1.0), True, 1e-3),
        Parameter("poisson", "Poisson ratio ν", "-", "poisson", POISSON_OPEN_RANGE, True),
    ),
    "normal_force",
    "N",
    "kappa",
    "N/m",
    "paper 2, Eqs. 7-10 and κ = 2G*a",
    kappa_jkr_mindlin,
)
