"""The analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion.

:func:`analyze` is a pure function of (sweep table, settings) and returns a
:class:`contactres.analysis.Results`; :mod:`contactres.analysis._steps` runs the steps, imported
by the first call (with pandas), so that the name alone costs no more than the package.
Its steps:

1. **Per sweep** (:mod:`contactres.analysis._classify`, all sweeps at once): every amplitude
   model of the registry fitted by its batched fitter (:mod:`contactres.analysis._models`; one
   fit table per model in ``Results.fits``): the exact Cattaneo-Mindlin, Savkoor and plateau
   loops, the elastic mean, and the straight line and parabola for slopes and curvatures; and
   the class of the sweep alone (lowest BIC, a nested simpler class kept within
   ``delta_bic``). Then **per load block**
   (:mod:`contactres.analysis._blocks`): the used ramps of one load of one experiment get one
   class, chosen from all their points (shared parameters, or each ramp its own where the data
   demand it); the limits Δf0, ΔΓ0 with standard errors and the critical displacement of a
   plateau come from each sweep's fit of that class.
2. **Contact stiffness** (paper 2, Eq. 2): κ = Δf0/P, ωξ = ΔΓ0/P, P = n_P/(2nπ²A_eff Z_q), and the
   loss tangent ΔΓ0/Δf0.
3. **Friction** for ``cattaneo-mindlin`` and ``plateau`` sweeps. From the slopes (Cattaneo-Mindlin
   sweeps only): μ from the Δf slope (μ = -κ²/(6F_N dK′/du0)) and from the ΔΓ slope
   (μ = 2κ²/(9πF_N dK″/du0)), paper 2, Eqs. 11-12. From a fit of an exact loop with a dashpot
   (no linearisation, so it stays unbiased when u0 nears the full-sliding displacement
   3μF_N/(2κ)): the Cattaneo-Mindlin loop for a ``cattaneo-mindlin`` sweep; for a ``plateau``
   sweep the Cattaneo-Mindlin loop behind a stick plateau (:class:`contactres.PlateauLoop`:
   linear up to the critical displacement d_c, then Cattaneo-Mindlin in the excess), with κ,
   μ, ωξ and d_c free and d_c started from the hinge that the classifier found; its Δf0, ΔΓ0 and
   d_c (``plateau_amplitude_m``) are reported too. A plateau sweep gets no slope-based μ
   (NaN, flag ``plateau-slope``): above d_c the shifts rise from the plateau as (u0 - d_c)² in
   ΔΓ and (u0 - d_c)^(5/2) in Δf, with no linear term for Eq. 11-12 to use, and treating the
   part above d_c as a Cattaneo-Mindlin sweep of amplitude u0 - d_c (as this analysis once did)
   biased μ: on noise-free sweeps with d_c = 0.2 (0.4) of the largest amplitude, μ from the Δf
   slope came out 10-20 % (50-70 %) high, from the ΔΓ slope 20-30 % low, and from a
   Cattaneo-Mindlin loop fitted to u0 - d_c ~1.5 % (25-35 %) high. The plateau-loop fit
   recovers μ, κ, ωξ and d_c to rounding (< 1e-12) on such sweeps (tests/analysis/test_analysis.py),
   and within its errors on sweeps with light noise. Limitation: where the slip signal above
   d_c is comparable to the noise (e.g. the water sweeps of the bundled example: 0.6 Hz noise,
   u0 <= 5 nm), few plateau sweeps are recognised, those that are owe their hinge partly to the
   noise, and their μ_fit reads low with an error (linearised, from the Jacobian) that is too
   small: in simulations of that recipe it reads 40-65 % low, in some sweeps by 3-7 times its
   error (the air recipe, 0.3 Hz noise and u0 <= 10 nm: unbiased, z standard deviation 1.2).
4. **Flags**: ``first-ramp`` (the first ramp of a load, by its label checked against the times,
   or without labels the first sweep of the load in time or file order, set aside as running-in
   unless ``keep_first_ramp``; never by where the rows stand when the table labels its ramps),
   ``ramp-order`` (ramp labels that disagree with the times or the amplitudes, or repeat or skip
   a number, :mod:`contactres.analysis._ramps`),
   ``few-points`` (< 4 points: not used), ``drift`` (the used ramps of one load of one experiment
   are offset from each other beyond noise: F test of per-ramp offsets on a common quadratic,
   false-alarm probability ``drift_p``),
   ``junction-growth`` (Δf rises with u0 by more than 2 standard errors), ``gross-sliding`` (the
   exact loop fits best beyond x = κu0/(μF_N) = 30; for a plateau, its excess beyond d_c),
   ``small-load`` (``|Δf|``/f > 1e-3), ``plateau-slope`` (a plateau sweep: no μ from the slopes).
5. **Per load** (configuration, medium, normal force): the used sweeps of each experiment are
   averaged, then mean and standard deviation over experiments (NaN values, e.g. the slope μ of
   plateau sweeps, are skipped; a load without any value gets NaN).
6. **Per configuration and medium** (Table 1): κ(F_N) of every experiment and load fitted with
   JKR (Eq. 9) + Mindlin (κ = 2G*a, Eq. 7, 8, 10) with E1 = E2 = E and ν fixed (column
   ``poisson``), E and γ free; standard errors from the Jacobian scaled by the residual
   variance, and a bootstrap over experiments (``bootstrap`` resamples, seeded).
7. **Curves**: the points of every sweep as fitted and its chosen model on the grids the
   report draws (:mod:`contactres.analysis._curves`; ``Results.points``, ``Results.curves``).
8. **Radiation** (only with ``sphere_material`` and ``plate_material``): the loss tangent of
   the sound the contact radiates into sphere and plate at each load's JKR contact radius and
   overtone frequency, its share of the measured ΔΓ0/Δf0, and E refitted for the dynamic
   softening of κ (:mod:`contactres.analysis._radiation`; ``Results.radiation``).
9. **Coated plate** (only with ``coating``): step 6 again with the contact mechanics of the
   coated plate (:mod:`contactres.analysis._coating`: JKR by the compliance method on the
   layered plate, Mindlin's sphere in series with the coated plate's tangential punch), started
   from the uncoated fit, which each group keeps under ``coating`` with the film's share of κ
   at each load; Fig. 5 draws the coated model. Done before step 8, which then takes the
   coated fit's contact radius of each load and the plate's dynamic tangential punch on the
   stack (compliances of sphere and coated plate in series at equal a; its module docstring).
"""

from __future__ import annotations

from .._threads import one_blas_thread
from ._settings import AnalysisSettings

# Read as True by mypy and pyright, False at run time: the names below only annotate, and
# importing them would load pandas with the sweep table.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    from ..measurements import SweepTable
    from ._results import Results

__all__ = ["AnalysisSettings", "analyze"]


@one_blas_thread()
def analyze(
    table: SweepTable,
    *,
    settings: AnalysisSettings | None = None,
    progress: Callable[[str], None] | None = None,
    curve_grids: Sequence[int] | None = None,
) -> Results:
    """Analyse a validated sweep table; see the module docstring.

    Parameters
    ----------
    table : a :class:`~contactres.measurements.SweepTable` from
        :func:`contactres.read_sweeps` or :func:`contactres.validate_sweeps` (the constants
        live in the table: :meth:`~contactres.measurements.SweepTable.with_constants`
        changes them)
    settings : :class:`AnalysisSettings` (defaults if None)
    progress : optional callback called with the name of each step as it starts
    curve_grids : the grids (numbers of points, each >= 2) on which ``Results.curves`` holds
        the sweeps' models; None (default): the page's and ``curves.csv``'s
        (:data:`~contactres.analysis.PAGE_POINTS`) for every sweep, and Fig. 4's
        (:data:`~contactres.analysis.FIGURE_POINTS`) for the sweeps that figure draws
        (:func:`~contactres.analysis.figure_examples`) only, their rows first. A tuple: every
        sweep on each grid it names, in its order. Not an analysis setting (no result depends
        on it, and ``summary.json`` does not record it): a caller that draws no figure asks
        for ``(PAGE_POINTS,)`` alone, one that wants Fig. 4's grid for every sweep
        ``(FIGURE_POINTS, PAGE_POINTS)`` (issue 31, point 3: at 10^5 sweeps that grid for
        every sweep held 10 of the 13 million curve rows, ~0.45 GB of the analysis' peak
        and ~10 s of CPU, for a figure that draws a few dozen sweeps).

    Returns
    -------
    contactres.analysis.Results
    """
    # The steps and the libraries they use (pandas, scipy) are imported by the first call, not
    # with the name: ``contactres.analyze`` costs no more than ``import contactres``, and a
    # script pays for the analysis where it analyses (tests/test_startup.py pins it).
    from ._steps import run

    return run(table, settings or AnalysisSettings(), progress or (lambda step: None), curve_grids)
