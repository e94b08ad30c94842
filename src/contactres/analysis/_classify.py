"""The model choice of every sweep: low-amplitude limits, slopes and the amplitude class.

Every sweep is fitted with every amplitude model of :mod:`contactres.analysis._models`. With
``exact_loop`` (the default) the four classes are represented by the exact descriptions of
paper 2, each fitted to both channels at once:

``elastic``           Δf = Δf0, ΔΓ = ΔΓ0 (Eq. 1)                                   (k = 2)
``cattaneo-mindlin``  the exact Cattaneo-Mindlin loop with a dashpot (Eqs. 4-6, 12) (k = 3)
``savkoor``           Savkoor's loop, constant sliding traction τ0 (Eqs. 13-15)    (k = 3)
``plateau``           the Cattaneo-Mindlin loop behind a stick plateau d_c          (k = 4)

(:func:`~contactres.analysis._loops.fit_cm_loops` with the Cattaneo-Mindlin and the Savkoor
tables, :func:`~contactres.analysis._plateau.fit_plateau_loops`). Without it, by their
closed-form small-amplitude forms: a straight line in u0 (Eq. 12, k = 4), in u0² (Eq. 15,
k = 4) and a hinge (flat, then straight; k = 5). The straight line and the parabola are fitted
in both cases: their slopes and curvatures are reported, and the slopes give μ by Eq. 12.

**Model choice (the stated criterion).** With separate unknown noise levels in Δf and ΔΓ, the
Bayesian information criterion of a model with k parameters is
``BIC = n ln(RSS_f/n) + n ln(RSS_Γ/n) + k ln(2n)``. The model with the lowest BIC wins, except
that a simpler model nested in it (:data:`NESTED`: elastic in every slip model, Cattaneo-Mindlin
in the plateau loop) is kept if its BIC is within ``delta_bic`` (default 2, "positive evidence"
on the Kass-Raftery scale) of the lowest: a parameter is added only on positive evidence.
Between models that are not nested (Cattaneo-Mindlin, Savkoor; Savkoor, plateau) the lower BIC
alone decides. The runner-up is the class with the lowest BIC among the others, and
``delta_bic`` (column) is its BIC minus the winner's: the evidence for the choice (negative, down
to -``delta_bic``, where a simpler nested class was kept against a slightly better one). Where no
other class has a BIC there is no runner-up (``""``) and the evidence is inf: a sweep of copies
of one amplitude, with the exact loops or their closed forms (only the elastic class's two
parameters are identified); a sweep of two points without the exact loops (the closed forms'
lines pass through both); with the exact loops, a load whose Δf has the wrong sign for every
loop (they need Δf0 > 0; flagged ``negative-stiffness`` only where Δf0 is below 0 by more than
twice its error). Where no class has one, NaN: a sweep of one point (the elastic class's two
parameters are determined by its two residuals, with none left over). One rule, with the exact
loops or without, for a sweep or a load block: a class whose k parameters outnumber the
residuals that carry information, two at each distinct amplitude (a straight line through
points at one amplitude has no slope), has no criterion (inf) and no parameters (NaN)
(:func:`~contactres.analysis._bad_rows.identified`); a class with no more residuals than
parameters, 2n <= k for n points (repeats counted: they add residuals), passes through every
point and has no criterion (inf) and no errors (NaN), but keeps its parameter values
(:func:`~contactres.analysis._bad_rows.has_residuals`).
:mod:`contactres.analysis._blocks` then makes the same choice for the ramps of one load block
together.
"""

from __future__ import annotations

from itertools import repeat

import numpy as np
import pandas as pd

from ._amplitude import Block, Padded, bic
from ._bad_rows import (
    blank_errors,
    blank_unidentified,
    distinct_amplitudes,
    has_residuals,
    identified,
    points_of,
)
from ._loops import LoopTable, LoopTables, loop_tables
from ._models import AMPLITUDE_MODELS, N_PARAMETERS, SWEEP_FITS
from ._models.base import LoopInputs
from ._models.plateau_loop import fit_plateaus, plateau_start
from ._workers import WorkerPool, lent_pool, run_in_workers

__all__ = [
    "CLASS_SOURCES",
    "LIMITS_FROM",
    "NESTED",
    "SOURCE_MODEL",
    "FieldTables",
    "add_plateau_fits",
    "apply_models",
    "choose",
    "class_criteria",
    "fit_models",
    "fit_sweeps",
    "n_parameters",
    "prefer",
    "runner_up",
    "source_rss",
    "source_valid",
]


#: Sources of each class: exact loops (``exact_loop``) or closed-form small-amplitude forms.
CLASS_SOURCES = {
    True: {"elastic": "el", "cattaneo-mindlin": "cm", "savkoor": "sv", "plateau": "pl"},
    False: {"elastic": "el", "cattaneo-mindlin": "line", "savkoor": "parabola", "plateau": "hinge"},
}
#: The registered model (:data:`~contactres.analysis.REGISTRY`) behind each source.
SOURCE_MODEL = {fit.source: fit.model for fit in SWEEP_FITS}
#: ``limits_from`` of a sweep whose limits come from each source.
LIMITS_FROM = {
    "el": "mean",
    "line": "line",
    "parabola": "parabola",
    "hinge": "plateau",
    "cm": "cm-loop",
    "sv": "savkoor-loop",
    "pl": "plateau-loop",
}


#: The fields of every per-sweep fit, by source (``el``, ``line``, ... ``pl``): one table each,
#: a row per sweep in the order of the sweep table, the columns the fitter's own field names.
FieldTables = dict[str, pd.DataFrame]


def _fit_block(
    b: Block, exact_loop: bool, tables: LoopTables | None, plateau: np.ndarray
) -> tuple[np.ndarray, dict[str, dict[str, np.ndarray]]]:
    """Every registered sweep model (:data:`~contactres.analysis._models.SWEEP_FITS`, the
    exact loops only with ``exact_loop``) fitted to one block of sweeps, in the registry's
    order: the largest amplitude of each sweep and the fields of each fit by source (arrays
    with the sweep as last axis); the plateau loop only to the sweeps ``plateau`` (the others
    get NaN)."""
    u_max = np.max(np.where(b.w > 0, b.u, 0.0), axis=1)
    inputs = LoopInputs(tables, plateau)
    done: dict[str, dict[str, np.ndarray]] = {}
    for fit in SWEEP_FITS:
        if fit.exact and not exact_loop:
            continue
        done[fit.source] = fit.fit(b, done, inputs)
    # A fit of more parameters than the sweep identifies (a straight line through points at
    # one amplitude) has neither parameters nor a criterion; one that passes through every point
    # (no more residuals than parameters: a one-point sweep's mean) keeps its parameters but has
    # no errors and no criterion. One rule for every class, here where every fit of a sweep or of
    # a load block's points is made. Applied after all the fits, so that those started from an
    # earlier one get the same inputs as before. (The exact loops also refuse such sweeps
    # themselves, by a count of distinct amplitudes of their own, _bad_rows.usable_rows: the
    # Cattaneo-Mindlin and Savkoor loops 2 for their 3 parameters, as here; the plateau loop 3
    # for its 4, stricter than the 2 here, also where add_plateau_fits fits it later.)
    distinct = distinct_amplitudes(b.u, b.w)
    points = points_of(b.w)
    for fit in SWEEP_FITS:
        if fit.source in done:
            k = N_PARAMETERS[fit.model]
            fields = blank_unidentified(done[fit.source], identified(distinct, k))
            done[fit.source] = blank_errors(fields, has_residuals(points, k))
    return u_max, done


def _plateaus_of_rows(b: Block, found, u_c, rss, theta, table: LoopTable) -> dict[str, np.ndarray]:
    """The plateau loop (:func:`~contactres.analysis._models.plateau_loop.fit_plateaus`) of
    every sweep of ``b`` (a picklable call for :func:`run_in_workers`)."""
    return fit_plateaus(b, found, u_c, rss, theta, table, np.ones(len(b.n), bool))


def _put(out: dict[str, np.ndarray], part: dict[str, np.ndarray], rows, S: int) -> None:
    """Write the arrays of ``part`` (sweep as last axis) at the sweeps ``rows`` of ``out``
    (``S`` sweeps), making each array of ``out`` on first sight."""
    for key, v in part.items():
        if key not in out:
            dtype = object if v.dtype.kind in "OUS" else v.dtype
            out[key] = np.empty((*v.shape[:-1], S), dtype=dtype)
        out[key][..., rows] = v


def fit_models(
    p: Padded,
    exact_loop: bool = True,
    tables: LoopTables | None = None,
    workers: int | WorkerPool = 1,
    plateau: np.ndarray | None = None,
) -> tuple[np.ndarray, FieldTables]:
    """Every amplitude model fitted to every sweep of ``p``, without the choice of a class:
    the largest amplitude of each sweep (m) and the field tables of every fit, in the order of
    the sweeps (arguments as for :func:`fit_sweeps`).

    What :func:`contactres.analysis._blocks.choose_blocks` needs of the joint fits of the load
    blocks: it chooses their classes by criteria of its own, so the per-sweep choice that
    :func:`fit_sweeps` adds would be made and dropped."""
    if exact_loop and tables is None:
        tables = loop_tables()
    S = len(p.n)
    plateau = np.ones(S, bool) if plateau is None else np.asarray(plateau, bool)
    u_max: dict[str, np.ndarray] = {}
    fields: dict[str, dict[str, np.ndarray]] = {}
    groups = p.blocks()  # <= BLOCK_POINTS points each: the fits' temporaries stay at a few MB
    # Each block padded when its fit comes (in this process; a pool a few calls ahead),
    # and its fields put in place as they come, then dropped: a list of every block's results
    # held a second copy of all the fields until the last had come (~0.1 GB at 10^5 sweeps,
    # issue 31, point 3).
    blocks = (p.block(rows) for rows in groups)
    masks = (plateau[rows] for rows in groups)
    with lent_pool(workers) as pool:
        parts = pool.imap(
            _fit_block, len(groups), blocks, repeat(exact_loop), repeat(tables), masks
        )
        for rows, (top, done) in zip(groups, parts, strict=True):
            _put(u_max, {"u_max": top}, rows, S)
            for source, part in done.items():
                _put(fields.setdefault(source, {}), part, rows, S)
    return u_max["u_max"], {source: pd.DataFrame(f) for source, f in fields.items()}


def n_parameters(source: str) -> int:
    """The k of the BIC of a fit from ``source``."""
    return N_PARAMETERS[SOURCE_MODEL[source]]


def source_rss(fields: FieldTables, source: str) -> np.ndarray:
    """(2, rows): the residual sums of Δf and ΔΓ of the fits of ``source`` (its table of
    ``fields``)."""
    table = fields[source]
    return np.stack([table["rss_df"].to_numpy(float), table["rss_dgamma"]])


def source_valid(fields: FieldTables, source: str) -> np.ndarray:
    """Whether the fit of ``source`` (its table of ``fields``) exists and is physical for each
    sweep (a loop needs Pκ > 0; a hinge must have been found)."""
    table = fields[source]
    rss = table["rss_df"].to_numpy(float) + table["rss_dgamma"].to_numpy(float)
    ok = np.isfinite(rss)
    if source == "hinge":
        ok &= table["found"].to_numpy(bool)
    if source in ("cm", "sv", "pl"):
        ok &= table["df0_Hz"].to_numpy(float) > 0
    return ok


def class_criteria(fields: FieldTables, n: np.ndarray, exact_loop: bool) -> np.ndarray:
    """BIC of each class of :data:`AMPLITUDE_MODELS` for every sweep (``n`` points each) from
    the fits ``fields``, (4, S); inf where the class's fit is not valid (:func:`source_valid`)."""
    out = []
    for model in AMPLITUDE_MODELS:
        src = CLASS_SOURCES[exact_loop][model]
        crit = bic(source_rss(fields, src), n, n_parameters(src))
        out.append(np.where(source_valid(fields, src), crit, np.inf))
    return np.stack(out)


#: NESTED[i, j]: class i of AMPLITUDE_MODELS is class j with some parameters fixed (or i = j):
#: elastic is every slip model without slip, Cattaneo-Mindlin the plateau loop with d_c = 0.
NESTED = np.array(
    [
        [True, True, True, True],  # elastic
        [False, True, False, True],  # cattaneo-mindlin
        [False, False, True, False],  # savkoor
        [False, False, False, True],  # plateau
    ]
)


def prefer(criteria: np.ndarray, nested: np.ndarray, delta_bic: float) -> np.ndarray:
    """Index of the candidate chosen from criteria (K, S): the first candidate within
    ``delta_bic`` of the lowest that is nested in the lowest (``nested[i, j]``: candidate i is
    candidate j with parameters fixed). Between candidates that are not nested the criterion
    alone decides."""
    S = criteria.shape[1]
    best = np.argmin(criteria, axis=0)
    close = criteria <= criteria[best, np.arange(S)] + delta_bic
    return np.argmax(close & nested[:, best], axis=0)


def runner_up(
    others: np.ndarray, names: np.ndarray, best: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The runner-up of a choice and the evidence for it, for each column of ``others``.

    Parameters
    ----------
    others : (K, S) the criteria of the candidates, inf for those of the winner's class (a
        class is no rival of itself) and for those without a criterion
    names : (K,) the class of each candidate
    best : (S,) the winner's criterion

    Returns
    -------
    runner_up : (S,) the class of the candidate with the lowest of ``others``; ``""`` (a text
        cell's "none") where every one of them is +inf (no criterion): a sweep of one point,
        where no class has a residual left for a criterion, or a block whose loops all failed. An
        argmin over nothing but inf would name the first class, the winner itself where that
        is ``elastic``. Ties go to the first class in ``names``' order.
    evidence : (S,) the runner-up's criterion minus ``best``: inf where there is no runner-up,
        NaN where the winner has no criterion either
    """
    S = others.shape[1]
    runner = np.argmin(others, axis=0)
    lowest = others[runner, np.arange(S)]
    with np.errstate(invalid="ignore"):
        evidence = lowest - best
    # Only +inf is "no criterion": a NaN or -inf rival (none is reached by the fits, whose BICs
    # are finite or +inf) keeps argmin's class, as before runner_up existed (review R32a).
    return np.where(lowest == np.inf, "", names[runner]), evidence


def choose(criteria: np.ndarray, delta_bic: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The class chosen from BICs (4, S) by :func:`prefer` with :data:`NESTED`.

    Returns the index of the winner, the runner-up's class (:func:`runner_up`: the lowest BIC
    among the other classes, ``""`` where none has one) and the evidence: the runner-up's BIC
    minus the winner's.
    """
    choice = prefer(criteria, NESTED, delta_bic)
    S = criteria.shape[1]
    others = criteria.copy()
    others[choice, np.arange(S)] = np.inf
    runner, evidence = runner_up(
        others, np.asarray(AMPLITUDE_MODELS), criteria[choice, np.arange(S)]
    )
    return choice, runner, evidence


def apply_models(
    sw: pd.DataFrame, fields: FieldTables, model: np.ndarray, exact_loop: bool
) -> pd.DataFrame:
    """Set the class of every sweep and take its limits, their errors and its plateau from the
    fit of that class (``model``: names from :data:`AMPLITUDE_MODELS`; the fits ``fields``, in
    the order of ``sw``). Returns a new frame."""
    sw = sw.copy()
    hinge_fit, line_fit = fields["hinge"], fields["line"]
    model = np.asarray(model, dtype=object)
    sources = CLASS_SOURCES[exact_loop]
    # Looked up once per distinct class (a hash table in C), not once per sweep in Python.
    codes, classes = pd.factorize(model)
    distinct = np.array([sources[m] for m in classes], dtype=object)
    # Whether each sweep's limits come from the hinge or the straight line (by class, then
    # spread by code: no comparison of 10^5 strings per channel).
    from_hinge = np.array([s == "hinge" for s in distinct], dtype=bool)[codes]
    from_line = np.array([s == "line" for s in distinct], dtype=bool)[codes]
    is_pl = model == "plateau"
    # Slope of the linear part: the hinge slope for a plateau, the straight line otherwise.
    hinge = is_pl & hinge_fit["found"].to_numpy(bool)
    for name in ("df", "dgamma"):
        a = np.full(len(sw), np.nan)
        err = np.full(len(sw), np.nan)
        for c, s in enumerate(distinct):
            rows = codes == c
            a[rows] = fields[s][f"{name}0_Hz"].to_numpy(float)[rows]
            err[rows] = fields[s][f"{name}0_err_Hz"].to_numpy(float)[rows]
        sw[f"{name}0_Hz"] = a
        sw[f"{name}0_err_Hz"] = err
        for col, key in (("_slope_Hz_per_m", "_b"), ("_slope_err_Hz_per_m", "_b_err")):
            sw[f"{name}{col}"] = np.where(
                hinge, hinge_fit[f"{name}{key}"].to_numpy(float), line_fit[f"{name}{key}"]
            )
        # The covariance of Δf0 and the slope is known where both come from the same fit.
        same = np.where(hinge, from_hinge, from_line)
        cov = np.where(hinge, hinge_fit[f"{name}_cov_ab"], line_fit[f"{name}_cov_ab"])
        sw[f"{name}0_slope_cov"] = np.where(same, cov, 0.0)
    if exact_loop:
        pl = fields["pl"]
        d_c, d_c_err = pl["d_c_m"].to_numpy(float), pl["d_c_err_m"].to_numpy(float)
    else:
        d_c, d_c_err = hinge_fit["u_c_m"].to_numpy(float), np.full(len(sw), np.nan)
    sw["plateau_amplitude_m"] = np.where(is_pl, d_c, np.nan)
    sw["plateau_amplitude_err_m"] = np.where(is_pl, d_c_err, np.nan)
    sw["model"] = model.astype(str)
    sw["limits_from"] = np.array([LIMITS_FROM[s] for s in distinct], dtype=object)[codes].astype(
        str
    )
    return sw


def fit_sweeps(
    p: Padded,
    delta_bic: float = 2.0,
    exact_loop: bool = True,
    tables: LoopTables | None = None,
    workers: int | WorkerPool = 1,
    plateau: np.ndarray | None = None,
) -> tuple[pd.DataFrame, FieldTables]:
    """Fit every amplitude model to every sweep and choose one (see the module docstring).

    Parameters
    ----------
    p : the sweeps as padded arrays (:func:`contactres.analysis._amplitude.pad_sweeps`)
    delta_bic : BIC margin within which the simpler model is kept
    exact_loop : the exact loops represent the classes (else their closed-form small-amplitude
        forms)
    tables : the Cattaneo-Mindlin and Savkoor loop tables
        (:func:`contactres.analysis._loops.loop_tables`; built here if None and ``exact_loop``)
    workers : processes for the fits of the blocks of sweeps (1: none, in this process), or
        the analysis's :class:`~contactres.analysis._workers.WorkerPool` (its processes, left
        running). More than one pays from ~10^4 sweeps on (both cores of a 2-core machine:
        ~1.8x faster at 10^5 sweeps); it starts a process pool, so a script calling it must be
        importable (``if __name__ == "__main__":``) where processes are spawned (Windows,
        macOS).
    plateau : (S,) which sweeps get the exact plateau loop (default all); the others have no
        ``plateau`` class until :func:`add_plateau_fits` adds it

    Returns
    -------
    sweeps : DataFrame
        One row per sweep (order of first appearance): the low-amplitude limits with standard
        errors from the chosen class (``limits_from``: ``mean``, ``cm-loop``, ``savkoor-loop``,
        ``plateau-loop``, or ``line``, ``parabola``, ``plateau`` without ``exact_loop``), the
        slopes (straight line; a found hinge for a plateau) and curvatures (parabola), the
        plateau's critical displacement, the noise levels (straight line), ``bic_<class>``,
        ``model``, ``runner_up`` and ``delta_bic`` (:func:`choose`), ``model_sweep`` (the same
        as ``model`` here; :mod:`contactres.analysis._blocks` may change ``model``).
    fields : FieldTables
        Every fit's fields by source, one row per row of ``sweeps``: ``el``, ``line``,
        ``parabola``, ``hinge`` and, with ``exact_loop``, the loop fits ``cm``, ``sv``
        (columns of :func:`~contactres.analysis._loops.fit_cm_loops`) and ``pl`` (of
        :func:`~contactres.analysis._plateau.fit_plateau_loops`); named as the fitters name
        them (:func:`contactres.analysis._models.fit_tables` gives them the registry's names).
    """
    n = p.n.astype(float)
    u_max, fields = fit_models(p, exact_loop, tables, workers, plateau)
    sw = pd.DataFrame(
        {"sweep": p.sweeps, "n_points": p.n, "direction": p.direction, "u_max_m": u_max}
    )
    line, parabola = fields["line"], fields["parabola"]
    for name in ("df", "dgamma"):
        sw[f"sigma_{name}_Hz"] = np.sqrt(line[f"rss_{name}"].to_numpy() / np.maximum(n - 2, 1))
        sw[f"{name}_curvature_Hz_per_m2"] = parabola[f"{name}_b"].to_numpy()
        sw[f"{name}_curvature_err_Hz_per_m2"] = parabola[f"{name}_b_err"].to_numpy()
    return _choose_each(sw, fields, delta_bic, exact_loop), fields


def _choose_each(
    sw: pd.DataFrame, fields: FieldTables, delta_bic: float, exact_loop: bool
) -> pd.DataFrame:
    """The class of every sweep alone from its fits (:func:`choose`, :func:`apply_models`)."""
    criteria = class_criteria(fields, sw["n_points"].to_numpy(float), exact_loop)
    for m, crit in zip(AMPLITUDE_MODELS, criteria, strict=True):
        sw[f"bic_{m}"] = crit
    choice, runner, evidence = choose(criteria, delta_bic)
    names = np.asarray(AMPLITUDE_MODELS)
    sw = apply_models(sw, fields, names[choice], exact_loop)
    sw["model_sweep"] = sw["model"]
    sw["runner_up"] = runner
    sw["delta_bic"] = evidence
    sw["decided_by"] = "sweep"
    return sw


def add_plateau_fits(
    p: Padded,
    sw: pd.DataFrame,
    fields: FieldTables,
    rows: np.ndarray,
    delta_bic: float,
    tables: LoopTables,
    workers: int | WorkerPool = 1,
) -> tuple[pd.DataFrame, FieldTables]:
    """Fit the exact plateau loop to the sweeps ``rows`` of ``sw`` (from
    :func:`fit_sweeps` with ``exact_loop``, in the order of ``p``; its fits ``fields``) that do
    not have it yet, and choose their class again with it. Returns a new frame and new fields
    (the plateau loop's table a new one, the others shared)."""
    sw = sw.copy()
    rows = np.asarray(rows, dtype=np.intp)
    rows = rows[~np.isfinite(fields["pl"]["rss_df"].to_numpy(float)[rows])]
    if rows.size == 0:
        return sw, fields
    groups = p.blocks(rows)
    hinge, line = ({c: t[c].to_numpy() for c in t} for t in (fields["hinge"], fields["line"]))
    found, u_c, rss = plateau_start(hinge, line)
    theta = fields["cm"]["theta_per_m"].to_numpy(float)
    parts = run_in_workers(
        _plateaus_of_rows,
        workers,
        [p.block(g) for g in groups],
        [found[g] for g in groups],
        [u_c[g] for g in groups],
        [rss[:, g] for g in groups],
        [theta[g] for g in groups],
        repeat(tables.cm),
    )
    pl = fields["pl"].copy()
    for g, part in zip(groups, parts, strict=True):
        for key, v in part.items():
            values = pl[key].to_numpy(copy=True)
            values[g] = v
            pl[key] = values
    fields = {**fields, "pl": pl}
    # Only the sweeps refitted can choose otherwise (each sweep's choice is its own fits'):
    # chosen again alone, their rows written into the frame; the others' are as they were.
    mine = {src: table.iloc[rows].reset_index(drop=True) for src, table in fields.items()}
    again = _choose_each(sw.iloc[rows].reset_index(drop=True), mine, delta_bic, True)
    for col in again.columns:
        values = sw[col].to_numpy(copy=True)
        values[rows] = again[col].to_numpy()
        sw[col] = values
    return sw, fields
