"""Job ``paper1``: the numbers of paper 1's figures (dynamic contact stiffness of a sphere on a
cubic crystal, Figs. 2-5) and of the ranking of its displacement models.

Abscissa: the longitudinal wave number k_l a = ω a √(ρ/C11) of the (001) face, as in the paper;
damping Q⁻¹ = 0.02 (:data:`LOSS`). Fig. 2: the displacement N(r̄) across the contact along
[100] (:func:`contactres.dynamic.contact_displacement`); Figs. 3-5: DCSF of the displacement
models and of the exact rigid punch (:func:`contactres.dynamic.dcsf_models`); the ranking: the
largest relative error of each model against the exact punch. Inputs: none (pass None). The
figures are drawn by :mod:`contactres.apps.paper1`.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
import pandas as pd

from .._threads import one_blas_thread
from ..dynamic import contact_displacement, dcsf_models
from ..materials import Material
from ..measurements.schema import PAPER1_RANKING
from .contract import JobResult, Progress, say

__all__ = [
    "DISPLACEMENT_KLA",
    "KLA",
    "LOSS",
    "PAPER_MODELS",
    "POISSONS",
    "STEMS",
    "ZENERS",
    "Result",
    "Settings",
    "crystal_curves",
    "cubic",
    "displacement",
    "fig3_curves",
    "ranking_table",
    "run",
    "wa_with_exact",
]

#: The five displacement conditions of the paper (Fig. 3).
PAPER_MODELS = ("WA", "R0", "R1", "SA", "TP")
#: The loss factor of the paper's figures.
LOSS = 0.02
#: k_l a of the paper's DCSF curves.
KLA = np.linspace(0.0, 2.0, 81)
#: k_l a of the displacement curves of Fig. 2.
DISPLACEMENT_KLA = (0.3, 0.6, 0.9, 1.2, 1.7)
#: Zener ratios A of Fig. 4 and of the ranking.
ZENERS = (0.25, 0.5, 1.0, 2.0, 4.0)
#: Poisson ratios of Fig. 5.
POISSONS = (0.1, 0.2, 0.25, 0.3, 0.4)


def cubic(A: float, nu: float) -> Material:
    """The cubic solid of Zener ratio A and Poisson ratio ν (C44 = 1: the DCSF needs ratios)."""
    return Material.cubic_from_ratios(zener=A, poisson=nu)


def fig3_curves(kla=KLA, A: float = 0.5, nu: float = 0.25) -> dict[str, np.ndarray]:
    """Fig. 3: DCSF of the five displacement models and of the exact punch at A, ν."""
    out = dcsf_models(cubic(A, nu), kla, (*PAPER_MODELS, "exact"), loss=LOSS, warn_negative=False)
    curves = {f"{name} model": out[name] for name in PAPER_MODELS}
    curves["exact (rigid punch)"] = out["exact"]
    return curves


def wa_with_exact(cases: dict[str, Material], kla):
    """WA curves of labelled materials and each one's exact rigid-punch curve (Figs. 4, 5):
    (curves, exact), dicts label -> DCSF."""
    res = {
        label: dcsf_models(m, kla, ("WA", "exact"), loss=LOSS, warn_negative=False)
        for label, m in cases.items()
    }
    return {label: r["WA"] for label, r in res.items()}, {
        label: r["exact"] for label, r in res.items()
    }


def displacement(
    kla=DISPLACEMENT_KLA, A: float = 0.5, nu: float = 0.25
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Fig. 2: N(r̄) along [100] under the oscillating flat-punch pressure at each k_l a:
    (kla, rbar, N, ratio) with ``ratio`` = ``|N(r̄)|``/``|N(0)|``, one row per k_l a."""
    m = cubic(A, nu)
    rbar = np.linspace(0.0, 1.0, 41)
    kla = np.asarray(kla, dtype=float)
    N = contact_displacement(m, kla[:, None], rbar[None, :], 0.0, loss=LOSS)
    return kla, rbar, N, np.abs(N) / np.abs(N[:, :1])


def crystal_curves(names=("RbI", "KCl", "W", "Cu", "Li"), kla=KLA, model: str = "WA"):
    """DCSF of built-in crystals on their (001) faces, labelled with their Zener ratio."""
    curves = {}
    for name in names:
        m = Material.crystal(name)
        curve = dcsf_models(m, kla, (model,), loss=LOSS, warn_negative=False)[model]
        curves[f"{name} (A = {m.zener_ratio:.2f})"] = curve
    return curves


def ranking_table(kla=KLA, zeners=ZENERS, nu: float = 0.25) -> pd.DataFrame:
    """For each A: the largest relative error ``|DCSF_model/DCSF_exact − 1|`` of each model over
    k_l a <= 1 and over k_l a <= 2; columns zener, model, max_rel_error_kla_le_1,
    max_rel_error_kla_le_2, rank_kla_le_1 (1 = closest to exact)."""
    kla = np.asarray(kla, dtype=float)
    names = (*PAPER_MODELS, "WA2D")
    rows = []
    for A in zeners:
        out = dcsf_models(cubic(A, nu), kla, (*names, "exact"), loss=LOSS, warn_negative=False)
        ex = out["exact"]
        errs = {n: np.abs(out[n] / ex - 1) for n in names}
        e1 = {n: float(np.max(e[kla <= 1 + 1e-12])) for n, e in errs.items()}
        order = sorted(names, key=lambda n: e1[n])
        for n in names:
            rows.append(
                {
                    "zener": A,
                    "model": n,
                    "max_rel_error_kla_le_1": e1[n],
                    "max_rel_error_kla_le_2": float(np.max(errs[n])),
                    "rank_kla_le_1": order.index(n) + 1,
                }
            )
    return pd.DataFrame(rows)


@dataclass(frozen=True)
class Settings:
    """The grids of the figures (None: the paper's, the module's constants at run time)."""

    kla: np.ndarray | None = None
    displacement_kla: tuple[float, ...] | None = None
    zeners: tuple[float, ...] | None = None
    poissons: tuple[float, ...] | None = None


@dataclass(frozen=True)
class Result(JobResult):
    """The curves of every figure: ``fig2`` (kla, rbar, N, ratio), ``fig3`` (label -> DCSF),
    ``fig4`` and ``fig5`` ((WA curves, exact curves)), ``ranking`` (table:
    :data:`contactres.measurements.schema.PAPER1_RANKING`), on the grid
    ``kla``; the grids of Figs. 4, 5 (``zeners``, ``poissons``)."""

    SCHEMAS = MappingProxyType({"ranking": PAPER1_RANKING})
    NOT_VALUES = ("fig2", "fig3", "fig4", "fig5", "kla", "warnings")

    kla: np.ndarray
    fig2: tuple
    fig3: dict
    fig4: tuple
    fig5: tuple
    ranking: pd.DataFrame
    zeners: tuple[float, ...]
    poissons: tuple[float, ...]


#: The figures in the order computed: (file stem, progress label).
STEMS = (
    "paper1_fig2_displacement",
    "paper1_fig3_models",
    "paper1_fig4_anisotropy",
    "paper1_fig5_poisson",
    "paper1_model_ranking",
)


@one_blas_thread()
def run(inputs: None = None, settings: Settings | None = None, progress: Progress | None = None):
    """The numbers of paper 1's figures; ``progress`` gets "[i/5] stem" before each."""
    s = settings or Settings()
    kla = KLA if s.kla is None else s.kla
    zeners = ZENERS if s.zeners is None else s.zeners
    poissons = POISSONS if s.poissons is None else s.poissons

    def stage(i: int) -> None:
        say(progress, f"[{i + 1}/{len(STEMS)}] {STEMS[i]}")

    stage(0)
    fig2 = displacement(DISPLACEMENT_KLA if s.displacement_kla is None else s.displacement_kla)
    stage(1)
    fig3 = fig3_curves(kla)
    stage(2)
    fig4 = wa_with_exact({f"A = {A:g}": cubic(A, 0.25) for A in zeners}, kla)
    stage(3)
    fig5 = wa_with_exact({f"ν = {nu:g}": cubic(2.0, nu) for nu in poissons}, kla)
    stage(4)
    ranking = ranking_table(kla, zeners)
    return Result(kla, fig2, fig3, fig4, fig5, ranking, tuple(zeners), tuple(poissons))
