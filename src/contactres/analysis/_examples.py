"""Which sweeps paper 2's Fig. 4 draws: per medium, the used sweeps of a typical load and of
an unusual one.

Fig. 4 of paper 2 shows Δf and ΔΓ against the amplitude u0 for a few loads only: per medium,
one load whose sweeps follow the Cattaneo-Mindlin loop (the typical shape) and one whose sweeps
end in a plateau or follow Savkoor's loop (paper 2, Eqs. 13-14): the unusual shapes. The
choice is made here, in the analysis, so that the figure
(:func:`contactres.report.figures.figure_sweeps`) and the fitted curves on its grid
(:func:`contactres.analysis._curves.fitted_curves`, :data:`~contactres.analysis.FIGURE_POINTS`
points per sweep) hold the same sweeps by construction: at 10^5 sweeps the figure's grid for
every sweep was 10 million of the 13 million curve rows, for a figure that draws a few dozen
(issue 31, point 3).

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein J.
Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["FIGURE_COLUMNS", "drawn_in_figure", "figure_examples"]

# The columns that name a load of one experiment: a load's sweeps are its ramps.
_LOAD = ["experiment", "configuration", "normal_force_N"]
# The models of the unusual shapes (paper 2, Fig. 4's second load of a medium).
_UNUSUAL = ["plateau", "savkoor"]
#: What :func:`drawn_in_figure` reads of the sweeps: a caller may pass these columns alone
#: (a test checks the choice on them equals the choice on the whole table).
FIGURE_COLUMNS = ["sweep", "medium", "used", "model", *_LOAD]


def _picks(sw: pd.DataFrame, medium: str) -> list[pd.DataFrame]:
    """The used sweeps of one typical (Cattaneo-Mindlin) load of ``medium`` and of one
    unusual (plateau or Savkoor) load, each the first of its kind in the order of ``sw``; any
    used load when the medium has neither; none when it has no used sweep."""
    part = sw[(sw["medium"] == medium) & sw["used"]]
    picks = []
    typical = part[part["model"] == "cattaneo-mindlin"]
    if len(typical):
        picks.append(part.merge(typical.iloc[[0]][_LOAD], on=_LOAD))
    unusual = part[part["model"].isin(_UNUSUAL)]
    if len(unusual):
        picks.append(part.merge(unusual.iloc[[0]][_LOAD], on=_LOAD))
    if not picks and len(part):
        picks.append(part.merge(part.iloc[[0]][_LOAD], on=_LOAD))
    return picks


def figure_examples(sweeps: pd.DataFrame) -> list[tuple[str, pd.DataFrame]]:
    """The loads paper 2's Fig. 4 draws, in the order it draws them.

    Per medium (in sorted order), the used sweeps of the first load (in the order of
    ``sweeps``) with a Cattaneo-Mindlin sweep, then those of the first load with a plateau or
    Savkoor sweep (the same load twice where its first sweeps of both kinds share it); a
    medium with neither gives its first used load; a medium without used sweeps gives none.

    Parameters
    ----------
    sweeps : the per-sweep results (:attr:`contactres.analysis.Results.sweeps`): ``sweep``,
        ``medium``, ``used``, ``model``, ``experiment``, ``configuration``,
        ``normal_force_N`` (N)

    Returns
    -------
    list of (str, DataFrame)
        (medium, the used sweeps of one load: rows of ``sweeps`` in their order, a fresh
        index), one pair per load drawn.
    """
    return [(m, sel) for m in sorted(sweeps["medium"].unique()) for sel in _picks(sweeps, m)]


def drawn_in_figure(sweeps: pd.DataFrame) -> np.ndarray:
    """Which rows of ``sweeps`` Fig. 4 draws (:func:`figure_examples`): a boolean array, one
    per row, True for each sweep of a load drawn."""
    examples = figure_examples(sweeps)
    if not examples:
        return np.zeros(len(sweeps), dtype=bool)
    ids = np.concatenate([sel["sweep"].to_numpy(dtype=object) for _, sel in examples])
    return sweeps["sweep"].isin(ids).to_numpy(dtype=bool)
