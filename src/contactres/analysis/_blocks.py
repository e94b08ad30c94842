"""The model choice of a load block: the ramps of one load of one experiment judged together.

The used ramps of one load of one experiment (ramps 2-4 in paper 2's protocol) measure the same
contact, so their class is chosen from all their points at once, which is far more decisive than
each sweep alone. For every class of :data:`~contactres.analysis._models.AMPLITUDE_MODELS` two
descriptions of the block compete (k parameters of the class's fit, plus the two noise levels
of Δf and ΔΓ, n the points of the block, N = 2n the residuals):

``shared``    one fit of all the block's points: the ramps share κ, ωξ and the class's own
              parameters (μ, τ0, d_c) and the noise levels,
              ``BIC = n ln(RSS_f/n) + n ln(RSS_Γ/n) + (k + 2) ln N``;
``per ramp``  each ramp its own parameters and noise levels (the per-sweep fits),
              ``BIC = Σ_r [n_r ln(RSS_f,r/n_r) + n_r ln(RSS_Γ,r/n_r)] + R (k + 2) ln N``,

so that ramp-to-ramp differences are allowed where the data demand them. The class of the
lowest of these 2 x 4 criteria wins, except that a candidate nested in it (a nested class,
:data:`~contactres.analysis._classify.NESTED`, and ``shared`` within ``per ramp``) is kept within
``delta_bic`` of the lowest, the simplest first, as for one sweep
(:mod:`contactres.analysis._classify`). The runner-up is the best candidate of another class and
``delta_bic`` its criterion minus the winner's; where no other class has a criterion (e.g. a
load whose Δf has the wrong sign for every loop) there is no runner-up, ``""``, and ``delta_bic``
is inf, as for one sweep (:func:`~contactres.analysis._classify.runner_up`). Every sweep of the
block takes the block's class; its own parameters come from its own fit of that class. The friction
law (Coulomb: Cattaneo-Mindlin or plateau; or Savkoor's constant traction) is first decided per
experiment over all its loads (:func:`_friction_law`; ``pool_experiment``). With it, the shared
criteria of the Cattaneo-Mindlin and the plateau loop weigh their μ against the friction of the
experiment's other loads (:mod:`contactres.analysis._mu_prior`), and the plateau's critical
displacement against the analysis's clear plateaus, both at once
(:mod:`contactres.analysis._plateau_prior`). Where that leaves the plateau within
:data:`PLATEAU_UNDECIDED` of the best other candidate, its shared criterion is instead the
Cattaneo-Mindlin loop's minus 2 ln B, B the Bayes factor of the plateau integrated over d_c and the
slip scale with both priors (:mod:`contactres.analysis._plateau_evidence`): in noisy data the
plateau fit often ends on a bound of d_c, where the priors at its optimum say nothing. Where the
block is ``shared``, the joint fit's parameters (μ, the Savkoor sliding force, d_c) are the block's
values that the per-load statistics use.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ._amplitude import Padded, bic, pad_sweeps
from ._classify import (
    CLASS_SOURCES,
    NESTED,
    SOURCE_MODEL,
    FieldTables,
    add_plateau_fits,
    fit_models,
    n_parameters,
    prefer,
    runner_up,
    source_rss,
    source_valid,
)
from ._drift import LOAD_OF_EXPERIMENT
from ._friction import loop_table_force
from ._loops import LoopTables
from ._models import AMPLITUDE_MODELS, fit_tables
from ._mu_prior import mu_prior_penalties, mu_prior_reference
from ._plateau_evidence import plateau_log_evidence
from ._plateau_prior import joint_prior_penalty, plateau_prior
from ._workers import WorkerPool, run_in_workers

__all__ = ["BLOCK_COLUMNS", "PLATEAU_CONTENDER", "block_codes", "choose_blocks"]

#: Columns of the block table besides the keys of :data:`LOAD_OF_EXPERIMENT`.
BLOCK_COLUMNS = (
    "block",
    "friction_law",
    "n_sweeps",
    "n_points",
    "model",
    "shared",
    "runner_up",
    "delta_bic",
)


# The joint fit's fields that the block table holds for its winner: column -> fit-table field.
_JOINT = {
    "df0_Hz": "df0",
    "df0_err_Hz": "df0_err",
    "dgamma0_Hz": "dgamma0",
    "dgamma0_err_Hz": "dgamma0_err",
}
_JOINT_LOOP = {
    "theta_per_m": "inverse_slip_scale",
    "lntheta_err": "ln_inverse_slip_scale_err",
    "cov_df0_lntheta": "cov_df0_ln_inverse_slip_scale",
    "x_max": "x_max",
}
_JOINT_PLATEAU = {"d_c_m": "critical_displacement", "d_c_err_m": "critical_displacement_err"}


#: A block whose shared plateau is within this of the best of its other candidates gets the
#: plateau loop fitted to each of its ramps too (for the per-ramp candidate and the ramps' own
#: parameters); one unit of BIC more than the default ``delta_bic``.
PLATEAU_CONTENDER = 3.0

#: A block whose shared plateau criterion at its fit's optimum (the priors by Laplace) is within
#: this of the best of its other candidates, either way, has the plateau's evidence integrated
#: over d_c instead (contactres.analysis._plateau_evidence): "very strong" evidence on the
#: Kass-Raftery scale (2 ln B > 10) is a choice that the integration does not change.
PLATEAU_UNDECIDED = 10.0


def _criteria(bf, fields, n_r, code, n, R, exact_loop: bool) -> np.ndarray:
    """(8, B): for each class of AMPLITUDE_MODELS its shared and its per-ramp criterion, from
    the field tables of the blocks' joint fits ``bf`` and of the sweeps' own fits ``fields``
    (``n_r`` points each)."""
    member = code >= 0
    B = len(n)
    lnN = np.log(2 * n)
    out = []
    for m in AMPLITUDE_MODELS:
        src = CLASS_SOURCES[exact_loop][m]
        k = n_parameters(src) + 2
        shared = bic(source_rss(bf, src), n, k)
        shared = np.where(source_valid(bf, src), shared, np.inf)
        ll = bic(source_rss(fields, src), n_r, 0)  # the per-ramp likelihood terms; penalty below
        ok = source_valid(fields, src)
        sums = np.bincount(code[member], weights=np.where(ok, ll, 0.0)[member], minlength=B)
        bad = np.bincount(code[member], weights=(~ok)[member].astype(float), minlength=B) > 0
        out += [shared, np.where(bad, np.inf, sums + R * k * lnN)]
    return np.stack(out)


def _mu_prior(sw, code, member, B, blocks, fits, crit, family):
    """What the prior on μ from the experiment's other loads
    (:func:`~contactres.analysis._mu_prior.mu_prior_penalties`) adds to the shared criterion of
    the Cattaneo-Mindlin and the plateau loop of every block (``crit``: the 2 x 4 criteria
    without it; blocks of a Savkoor experiment, ``family``, neither give nor get a prior): the
    (8, B) penalties, the prior (mean, var) of ln μ and the blocks' sensitivities P, Hz per
    N/m."""
    P = (
        pd.Series(sw["P_Hz_per_N_per_m"].to_numpy()[member], index=code[member])
        .groupby(level=0)
        .first()
        .reindex(np.arange(B))
        .to_numpy(float)
    )
    rows = {
        "cattaneo-mindlin-loop": 2 * AMPLITUDE_MODELS.index("cattaneo-mindlin"),
        "plateau-loop": 2 * AMPLITUDE_MODELS.index("plateau"),
    }
    joint = {key: fits[key].assign(bic_shared=crit[i]) for key, i in rows.items()}
    usable = np.ones(B, bool) if family is None else family != "savkoor"
    reference = mu_prior_reference(blocks, joint, P, usable)
    pen = mu_prior_penalties(blocks, joint, P, *reference)
    out = np.zeros_like(crit)
    for key, i in rows.items():
        out[i] = pen[key]
    return out, reference, P


def _plateau_reference(crit, plateau_fit: pd.DataFrame, u_max) -> tuple[np.ndarray, ...]:
    """The prior (mean, var) of ln(d_c/u_max) of every block's plateau
    (:func:`~contactres.analysis._plateau_prior.plateau_prior`; NaN: none) from the 2 x 4
    criteria so far ``crit`` and the joint plateau fits ``plateau_fit`` (``u_max`` the blocks'
    largest amplitudes, m)."""
    i = 2 * AMPLITUDE_MODELS.index("plateau")
    with np.errstate(invalid="ignore"):
        evidence = np.delete(crit, [i, i + 1], axis=0).min(axis=0) - crit[i]
    d_c = plateau_fit["critical_displacement"].to_numpy(float)
    d_c_err = plateau_fit["critical_displacement_err"].to_numpy(float)
    return plateau_prior(d_c, d_c_err, u_max, evidence)


def _plateau_penalty(
    ratio_prior, plateau_fit: pd.DataFrame, u_max, blocks, mu_prior, P
) -> np.ndarray:
    """(B,): what the priors on μ (``mu_prior``: mean and variance of ln μ, from
    :func:`_mu_prior`; ``P`` the blocks' sensitivities) and on the plateau amplitude
    (``ratio_prior``: mean and variance of ln(d_c/u_max) from :func:`_plateau_reference`)
    change together in the shared criterion of the
    plateau loop of every block (:func:`~contactres.analysis._plateau_prior.
    joint_prior_penalty`; ``plateau_fit`` the blocks' joint plateau fits, ``u_max`` their
    largest amplitudes, m, ``blocks`` with ``normal_force_N`` and ``n_points``)."""
    d_c = plateau_fit["critical_displacement"].to_numpy(float)
    d_c_err = plateau_fit["critical_displacement_err"].to_numpy(float)
    F = blocks["normal_force_N"].to_numpy(float)
    force, force_err, ok = loop_table_force(plateau_fit, P)
    df0 = plateau_fit["df0"].to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        # ln μ = ln Δf0 - ln θ - ln(P F_N): its covariance with d_c, then with ln d_c.
        cov = plateau_fit["cov_df0_critical_displacement"].to_numpy(float) / df0
        cov -= plateau_fit["cov_ln_inverse_slip_scale_critical_displacement"].to_numpy(float)
        cov /= d_c
    mu_prior = tuple(np.where(ok, m, np.nan) for m in mu_prior)
    return joint_prior_penalty(
        force / F,
        force_err / F,
        mu_prior,
        d_c / u_max,
        d_c_err / u_max,
        ratio_prior,
        cov,
        blocks["n_points"].to_numpy(float),
    )


def block_codes(info: pd.DataFrame, joint: np.ndarray) -> np.ndarray:
    """The load block (0 ... B-1, in the order of the keys of :data:`LOAD_OF_EXPERIMENT`) of
    every sweep ``joint`` whose load of its experiment has two or more of them; -1 elsewhere."""
    S = len(info)
    code = np.full(S, -1)
    idx = np.flatnonzero(joint)
    if idx.size:
        code[idx] = info.iloc[idx].groupby(LOAD_OF_EXPERIMENT, sort=True).ngroup().to_numpy()
    sizes = np.bincount(code[code >= 0], minlength=max(code.max() + 1, 1))
    code = np.where((code >= 0) & (sizes[np.maximum(code, 0)] >= 2), code, -1)
    keep = np.unique(code[code >= 0])
    return np.where(code >= 0, np.searchsorted(keep, code), -1)


def _friction_law(crit, classes, blocks: pd.DataFrame, delta_bic: float) -> np.ndarray:
    """The friction law of every block's experiment: ``coulomb``, ``savkoor`` or ``""`` (open).

    Paper 2 found whole experiments (mountings) following Savkoor, others Cattaneo-Mindlin
    with occasional stick plateaus: the law of the interface belongs to the experiment, not to
    one load. So the two families are compared over all loads of an experiment at once: the
    sum over its blocks of [best Coulomb criterion (Cattaneo-Mindlin or plateau) - best Savkoor
    criterion]; beyond ``delta_bic`` either way, the other family is excluded from its blocks.
    """
    sv = crit[classes == "savkoor"].min(axis=0)
    cm = crit[np.isin(classes, ["cattaneo-mindlin", "plateau"])].min(axis=0)
    # Only where both fitted (a block with no fit, e.g. Δf of the wrong sign, has inf for
    # every class: inf − inf would warn).
    diff = np.subtract(cm, sv, out=np.zeros_like(cm), where=np.isfinite(sv) & np.isfinite(cm))
    exp = blocks.groupby(["configuration", "medium", "experiment"], sort=False).ngroup()
    total = np.bincount(exp.to_numpy(), weights=diff)[exp.to_numpy()]
    return np.where(total > delta_bic, "savkoor", np.where(total < -delta_bic, "coulomb", ""))


#: Undecided blocks per worker process below which the plateau's evidence stays in this
#: process: at ~4 ms of CPU a block (the example's blocks, one core) 200 blocks are ~0.8 s,
#: well above the pool's start-up (~0.1-0.3 s, where no stage before has started it) and the
#: sending of the blocks' points, so a small study with ``workers`` > 1 loses nothing and a
#: 10^4-sweep one (~2,000 undecided blocks) uses every worker.
EVIDENCE_ROWS_PER_WORKER = 200


def _evidence(workers: int | WorkerPool, u, df, dg, w, sigma, mu_prior, ratio_prior, to_mu, rows):
    """:func:`~contactres.analysis._plateau_evidence.plateau_log_evidence` of the blocks
    ``rows``, in up to ``workers`` processes (:func:`run_in_workers`) where they are many.

    Each block's evidence depends on its own row alone (the nodes' batches only group the
    rows' arithmetic), so the blocks split into chunks with the serial call's result bit for
    bit: chunk k holds the k-th, (k + n)-th, ... of the blocks ``rows`` (a fixed split,
    whatever the timing; interleaved so that each chunk gets a like mix of blocks), only its
    rows are sent to its worker, and its (3, b) result is put back at them.

    Parameters
    ----------
    workers : processes at most (or a :class:`~contactres.analysis._workers.WorkerPool` of
        them); n = min(processes, number of ``rows`` // :data:`EVIDENCE_ROWS_PER_WORKER`)
        chunks, in this process if n <= 1
    u, df, dg, w, sigma, mu_prior, ratio_prior, to_mu, rows : as for
        :func:`~contactres.analysis._plateau_evidence.plateau_log_evidence` (``rows`` a (B,)
        mask)

    Returns
    -------
    (3, B): 2 ln B, μ and its error as the serial call gives them (NaN outside ``rows``)
    """
    todo = np.flatnonzero(rows)
    processes = workers.processes if isinstance(workers, WorkerPool) else workers
    n = min(processes, todo.size // EVIDENCE_ROWS_PER_WORKER)
    if n <= 1:
        return plateau_log_evidence(u, df, dg, w, sigma, mu_prior, ratio_prior, to_mu, rows)
    chunks = [todo[k::n] for k in range(n)]
    sigma = np.asarray(sigma, dtype=float)
    mu_prior, ratio_prior = (
        tuple(np.asarray(a, dtype=float) for a in pair) for pair in (mu_prior, ratio_prior)
    )
    to_mu = np.asarray(to_mu, dtype=float)
    parts = run_in_workers(
        plateau_log_evidence,
        workers,
        [u[c] for c in chunks],
        [df[c] for c in chunks],
        [dg[c] for c in chunks],
        [w[c] for c in chunks],
        [sigma[:, c] for c in chunks],
        [tuple(a[c] for a in mu_prior) for c in chunks],
        [tuple(a[c] for a in ratio_prior) for c in chunks],
        [to_mu[c] for c in chunks],
    )
    out = np.full((3, len(rows)), np.nan)
    for c, part in zip(chunks, parts, strict=True):
        out[:, c] = part
    return out


def choose_blocks(
    p: Padded,
    sw: pd.DataFrame,
    fields: FieldTables,
    joint: np.ndarray,
    delta_bic: float,
    exact_loop: bool,
    tables: LoopTables | None,
    workers: int | WorkerPool = 1,
    pool_experiment: bool = True,
    code: np.ndarray | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, FieldTables, dict[str, pd.DataFrame]]:
    """Choose the class of every load block of the sweeps ``joint`` (see the module docstring).

    Parameters
    ----------
    p : the sweeps as padded arrays (the order of ``sw``)
    sw : the per-sweep fits (:func:`~contactres.analysis._classify.fit_sweeps`) with the labels
        of :data:`~contactres.analysis._drift.LOAD_OF_EXPERIMENT`; the sweeps of a block need not
        have the plateau loop fitted (it is added where the block's plateau is a contender)
    fields : the fields of the per-sweep fits, by source (from the same call), in the order
        of ``sw``
    joint : which sweeps enter their block (the used ones); blocks of one sweep are left alone
    delta_bic, exact_loop, tables, workers : as for
        :func:`~contactres.analysis._classify.fit_sweeps`; the workers also
        integrate the plateau's evidence where many blocks need it (:func:`_evidence`); a
        number of processes opens one pool for the three stages that use it
    pool_experiment : decide the friction law (Coulomb or Savkoor) once per experiment
        (:func:`_friction_law`)
    code : :func:`block_codes` of ``sw`` and ``joint`` where the caller has them (None: found
        here)

    Returns
    -------
    blocks : one row per block of two or more sweeps: the keys, :data:`BLOCK_COLUMNS`, and the
        joint fit of the winning class (``df0_Hz``, ``dgamma0_Hz``, their errors, and for a
        loop ``theta_per_m``, ``lntheta_err``, ``cov_df0_lntheta``, ``x_max``, ``edge``,
        ``d_c_m``, ``d_c_err_m``), NaN where the block is not ``shared``
    per_sweep : one row per sweep of ``sw``: ``block`` (-1: none), ``model`` (the block's class,
        else the sweep's own), ``runner_up``, ``delta_bic``, ``decided_by`` (``block`` or
        ``sweep``)
    sw, fields : ``sw`` and ``fields`` with the plateau loop fitted to the sweeps of the
        contending blocks
    joint : every model's joint fit of every block: its fit table
        (:func:`contactres.analysis._models.fit_tables`, ``block`` in place of ``sweep``, one row
        per row of ``blocks``); the Coulomb loops' with ``bic_shared``, their shared criterion
        ({} where there is no block)
    """
    if not isinstance(workers, WorkerPool):
        with WorkerPool(workers) as pool:
            args = (p, sw, fields, joint, delta_bic, exact_loop, tables, pool, pool_experiment)
            return choose_blocks(*args, code=code)
    S = len(sw)
    per_sweep = pd.DataFrame(
        {
            "block": np.full(S, -1),
            # Copies: the frame is changed below, the sweep fits must not be.
            "model": np.array(sw["model_sweep"], dtype=object),
            "runner_up": np.array(sw["runner_up"], dtype=object),
            "delta_bic": np.array(sw["delta_bic"], dtype=float),
            "decided_by": np.full(S, "sweep", dtype=object),
        }
    )
    code = block_codes(sw, joint) if code is None else code
    if code.max() < 0:
        empty = pd.DataFrame(columns=[*LOAD_OF_EXPERIMENT, *BLOCK_COLUMNS])
        return empty, per_sweep, sw, fields, {}
    B = code.max() + 1
    member = code >= 0
    # The sweeps of a block in ramp order (then by name), not in the file's: their points at one
    # amplitude keep that order in the joint fit, so shuffled rows give the same fit (issue 27).
    rows = np.flatnonzero(member)
    names = pd.factorize(sw["sweep"].astype(str), sort=True)[0]
    rows = rows[np.lexsort((names[rows], sw["ramp"].to_numpy()[rows], code[rows]))]
    u, df, dg = p.points(rows)
    points = pd.DataFrame(
        {"sweep": np.repeat(code[rows], p.n[rows]), "amplitude_m": u, "df_Hz": df, "dgamma_Hz": dg},
        copy=False,  # read once, by pad_sweeps, and dropped: no copies of the points
    )
    bp = pad_sweeps(points)
    del u, df, dg, points  # bp holds them sorted: not kept through the block fits
    # Every model's joint fit of every block; their classes are chosen below, by the block
    # criteria (fit_sweeps would choose each block's class as a sweep's, for nothing).
    bu_max, bf = fit_models(bp, exact_loop, tables, workers)
    # The blocks in order of their code (the padding keeps their order of first appearance).
    codes = np.asarray(bp.sweeps).astype(int)
    order = np.argsort(codes)
    bf = {src: table.iloc[order].reset_index(drop=True) for src, table in bf.items()}
    # Every model's joint fit of every block (its fit table, one row per block in order).
    block = codes[order]
    fits = {key: t.rename(columns={"sweep": "block"}) for key, t in fit_tables(block, bf).items()}

    # The 2 x 4 criteria of every block: (shared, per ramp) for each class.
    n_r = sw["n_points"].to_numpy(float)
    n = np.bincount(code[member], weights=n_r[member], minlength=B)
    R = np.bincount(code[member], minlength=B).astype(float)
    classes = np.repeat(np.asarray(AMPLITUDE_MODELS), 2)
    keys = sw.loc[member, LOAD_OF_EXPERIMENT].assign(block=code[member])
    blocks = keys.drop_duplicates("block").sort_values("block").reset_index(drop=True)
    blocks_n = blocks.assign(n_points=n)
    crit = _criteria(bf, fields, n_r, code, n, R, exact_loop)
    family = _friction_law(crit, classes, blocks, delta_bic) if pool_experiment else None

    def excluded(crit):  # the family the experiment's friction law rules out
        if family is None:
            return crit
        savkoor = classes == "savkoor"
        coulomb = np.isin(classes, ["cattaneo-mindlin", "plateau"])
        crit = np.where(savkoor[:, None] & (family == "coulomb")[None, :], np.inf, crit)
        return np.where(coulomb[:, None] & (family == "savkoor")[None, :], np.inf, crit)

    crit = excluded(crit)
    # The friction of the experiment's other loads as a prior on μ of each Coulomb loop's shared
    # fit (contactres.analysis._mu_prior): without it a plateau is often read as
    # Cattaneo-Mindlin with a larger μ. The same for the contenders below and the choice.
    prior = np.zeros_like(crit)
    if exact_loop and pool_experiment and "P_Hz_per_N_per_m" in sw.columns:
        prior, mu_ref, P = _mu_prior(sw, code, member, B, blocks_n, fits, crit, family)
        # With it, the plateau amplitudes of the analysis's clear plateaus as a prior on each
        # block's (contactres.analysis._plateau_prior), both priors on the shared plateau fit
        # at once: the BIC's ln N for d_c is what keeps a plateau of noisy data from beating
        # Cattaneo-Mindlin or elastic, and the fit trades μ against d_c.
        i = 2 * AMPLITUDE_MODELS.index("plateau")
        u_max = bu_max[order]
        pl = fits["plateau-loop"]
        # The amplitude prior from the clear plateaus by the criteria with the μ prior only.
        ratio_ref = _plateau_reference(crit + prior, pl, u_max)
        prior[i] = _plateau_penalty(ratio_ref, pl, u_max, blocks_n, mu_ref, P)
        # Where the amplitude prior exists and that leaves the plateau undecided, its evidence
        # against Cattaneo-Mindlin integrated over d_c (contactres.analysis._plateau_evidence)
        # replaces that penalty.
        j = 2 * AMPLITUDE_MODELS.index("cattaneo-mindlin")
        sigma = np.sqrt(source_rss(bf, "cm") / n)
        with np.errstate(divide="ignore", invalid="ignore"):
            to_mu = 1.0 / (P * blocks_n["normal_force_N"].to_numpy(float))
        best_other = np.delete(crit + prior, [i, i + 1], axis=0).min(axis=0)
        with np.errstate(invalid="ignore"):
            undecided = np.abs(crit[i] + prior[i] - best_other) < PLATEAU_UNDECIDED
        two_ln_b, mu_pl, mu_pl_err = _evidence(
            workers,
            bp.u[order],
            bp.df[order],
            bp.dg[order],
            bp.w[order],
            sigma,
            mu_ref,
            ratio_ref,
            to_mu,
            undecided,
        )
        use = ~np.isnan(two_ln_b) & np.isfinite(crit[j] + prior[j]) & np.isfinite(crit[i])
        with np.errstate(invalid="ignore"):
            prior[i] = np.where(use, crit[j] + prior[j] - two_ln_b - crit[i], prior[i])
        marginal = use & np.isfinite(mu_pl) & (mu_pl_err > 0)
        fits["plateau-loop"] = pl.assign(
            mu_marginal=np.where(marginal, mu_pl, np.nan),
            mu_marginal_err=np.where(marginal, mu_pl_err, np.nan),
        )
    crit = crit + prior
    if exact_loop:
        # The per-ramp plateau needs the plateau loop of each ramp: fitted where the block's
        # shared plateau contends (within PLATEAU_CONTENDER of the best other candidate left by
        # the friction law; a plateau nests Cattaneo-Mindlin, so it is always close to it), not
        # everywhere. A block whose shared plateau wins is always such a contender, so its
        # ramps have their own plateau fits.
        i = 2 * AMPLITUDE_MODELS.index("plateau")
        others = np.delete(crit, [i, i + 1], axis=0).min(axis=0)
        contend = crit[i] <= others + PLATEAU_CONTENDER
        sweeps = np.flatnonzero(member & contend[np.maximum(code, 0)])
        if sweeps.size:
            assert tables is not None  # the caller builds them for the exact loops
            sw, fields = add_plateau_fits(p, sw, fields, sweeps, delta_bic, tables, workers)
            crit = excluded(_criteria(bf, fields, n_r, code, n, R, exact_loop)) + prior
    # Candidate a is nested in b if its class is (NESTED) and it is shared or b is per ramp.
    per_ramp = np.arange(len(classes)) % 2 == 1
    cls = np.repeat(np.arange(len(AMPLITUDE_MODELS)), 2)
    nested = NESTED[cls][:, cls] & (~per_ramp[:, None] | per_ramp[None, :])
    pick = prefer(crit, nested, delta_bic)
    cols = np.arange(B)
    winner = classes[pick]
    others = np.where(classes[:, None] == winner[None, :], np.inf, crit)
    runner, evidence = runner_up(others, classes, crit[pick, cols])

    blocks["friction_law"] = family if family is not None else ""
    blocks["n_sweeps"] = R.astype(int)
    blocks["n_points"] = n.astype(int)
    blocks["model"] = winner
    blocks["shared"] = pick % 2 == 0
    blocks["runner_up"] = runner
    blocks["delta_bic"] = evidence
    # The joint fit of the winning class (NaN where the ramps keep their own parameters).
    for field in (*_JOINT, *_JOINT_LOOP, *_JOINT_PLATEAU):
        blocks[field] = np.nan
    blocks["edge"] = ""
    for m in AMPLITUDE_MODELS:
        src = CLASS_SOURCES[exact_loop][m]
        rows = (winner == m) & blocks["shared"].to_numpy()
        if not rows.any():
            continue
        table = fits[SOURCE_MODEL[src]]
        joint_map = {**_JOINT, **(_JOINT_LOOP if src in ("cm", "sv", "pl") else {})}
        joint_map |= _JOINT_PLATEAU if src == "pl" else {}
        for field, column in joint_map.items():
            blocks.loc[rows, field] = table[column].to_numpy(float)[rows]
        if src in ("cm", "sv", "pl"):
            blocks.loc[rows, "edge"] = table["edge"].to_numpy(object)[rows]

    # The joint exact Coulomb loops, winner or not: μ of the block is averaged over the two
    # with their BIC weights where they compete (friction.block_friction).
    if exact_loop:
        for m, key in (("cattaneo-mindlin", "cattaneo-mindlin-loop"), ("plateau", "plateau-loop")):
            fits[key] = fits[key].assign(bic_shared=crit[2 * AMPLITUDE_MODELS.index(m)])

    per_sweep.loc[member, "block"] = code[member]
    per_sweep.loc[member, "model"] = winner[code[member]]
    per_sweep.loc[member, "runner_up"] = runner[code[member]]
    per_sweep.loc[member, "delta_bic"] = evidence[code[member]]
    per_sweep.loc[member, "decided_by"] = "block"
    return blocks, per_sweep, sw, fields, fits
