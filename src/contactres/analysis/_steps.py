"""The steps of :func:`contactres.analysis.analyze` (paper 2), run on the first call.

:mod:`contactres.analysis._pipeline` documents the steps and holds the public function and its
settings; this module does the work, and imports the modules of every step (and with them
pandas) at the top, so that only a call of :func:`~contactres.analysis.analyze` loads them.
A plain analysis imports no scipy (its distribution functions and fits are the package's own);
the paths that need scipy, such as a coating, import it where they use it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, replace
from itertools import repeat

import numpy as np
import pandas as pd

from .._version import __version__
from ..errors import ContactresInputError
from ..measurements import SweepTable
from ..measurements.schema import SWEEP_TABLE
from ..numerics import factorize_runs
from ..resonators import QCM
from ..tangential import effective_shear_modulus, shear_modulus
from ..units import JUNCTION_SIGMAS, LINEAR_ONSET_X, MIN_SWEEP_POINTS, SMALL_LOAD_LIMIT
from ._amplitude import pad_sweeps
from ._blocks import block_codes, choose_blocks
from ._classify import apply_models, fit_sweeps
from ._curves import CURVE_GRIDS, FIGURE_POINTS, fitted_curves, jkr_curves, sweep_points
from ._drift import LOAD_OF_EXPERIMENT, drifting_sweeps, remove_linear_drift
from ._examples import FIGURE_COLUMNS, drawn_in_figure
from ._flags import Flag, negative_stiffness
from ._friction import block_friction, loop_friction, mu_out_of_range, slope_friction
from ._jkr import fit_group
from ._loads import GROUP_KEYS, per_experiment, per_load, withhold_mu
from ._loops import X_MAX, loop_tables
from ._models import AMPLITUDE_MODELS, fit_tables
from ._ramps import check_ramps
from ._results import Results
from ._running_in import QUANTITIES as RUNNING_IN_QUANTITIES
from ._running_in import running_in
from ._settings import AnalysisSettings
from ._workers import WorkerPool

__all__ = ["run"]

#: Columns that describe a whole sweep, carried from the sweep table into the results.
INFO_COLUMNS = SWEEP_TABLE.where(level="sweep") + SWEEP_TABLE.where(level="constant")
#: What :func:`~contactres.analysis._jkr.fit_group` reads of a group's points and of its used
#: sweeps: only these go to the worker processes.
JKR_POINT_COLUMNS = ["experiment", "normal_force_N", "kappa_N_per_m", "sphere_radius_m", "poisson"]
JKR_SWEEP_COLUMNS = ["sweep", "normal_force_N", "kappa_N_per_m"]


def _sensitivity(info: pd.DataFrame, zq: float) -> np.ndarray:
    """P = n_P/(2nπ²A_eff Z_q) of every sweep, Hz per N/m (paper 2, Eq. 1)."""
    keys = ["fundamental_Hz", "overtone", "area_m2", "n_contacts"]
    P = np.empty(len(info))
    # pandas-stubs type these keys Hashable: grouped by a list of columns, each is a tuple
    for key, idx in info.groupby(keys, sort=False).indices.items():
        q = QCM(fundamental=key[0], overtone=int(key[1]), area=key[2], zq=zq)  # type: ignore[index]
        P[idx] = q.sensitivity(int(key[3]))  # type: ignore[index]
    return P


def _whole_loads(sw: pd.DataFrame, mask: np.ndarray) -> np.ndarray:
    """``mask`` spread to every sweep of a load of an experiment where any sweep has it.

    By the loads' codes (one hash of the keys; gaps a load of their own, as a merge matches
    them): half the time of a merge on the four key columns (14 ms against 26 ms at 10^5
    sweeps)."""
    load = sw.groupby(LOAD_OF_EXPERIMENT, sort=False, dropna=False).ngroup().to_numpy()
    hit = np.zeros(int(load.max(initial=-1)) + 1, bool)
    hit[load[mask]] = True
    return hit[load]


def _with_info(info: pd.DataFrame, sw: pd.DataFrame) -> pd.DataFrame:
    """The columns of ``info`` (one row per sweep) put before those of ``sw``, row by row of
    ``sw``: a right merge on ``sweep``, one to one.

    Both list the sweeps in their order of first appearance in the table, so they are side by
    side, row for row, and the frames are put together as they are (a merge hashed every name
    again, ~0.35 s at 10^5 sweeps). That order is checked, and a mismatch is an internal
    error, not realigned: the steps' positional arrays (``used``, the block codes, ...) are in
    ``info``'s order, and a merge would move ``sw``'s rows without them."""
    # By value: a SweepTable built by hand may hold its ids as objects or categories, the fits
    # as str (Series.equals would compare the dtypes too).
    same = len(sw) == len(info) and np.array_equal(
        sw["sweep"].to_numpy(object), info["sweep"].to_numpy(object)
    )
    if not same:
        raise RuntimeError("the per-sweep fits are not in the order of the sweep table")
    return pd.concat([info, sw.drop(columns="sweep")], axis=1)


def _savkoor_traction(sw: pd.DataFrame, member: np.ndarray, group: dict) -> None:
    """τ0 = F_s/(πa²) of the Savkoor sweeps of one group, in place (``tau0_Pa``, with error).

    The contact radius a = κ/(2G*) (paper 2, below Eq. 6) needs G*, i.e. the group's E from
    the JKR fit (Eqs. 7-8 with ν): where E is withheld, τ0 is not given. The error combines
    those of F_s, κ and E (independent; relative: F_s + 2 κ + 2 E).
    """
    rows = member & (sw["model"] == "savkoor").to_numpy()
    E, E_err = group["E_Pa"], group["E_err_Pa"]
    if not rows.any() or not np.isfinite(E):
        return
    G_star = effective_shear_modulus(shear_modulus(E, group["poisson"]), group["poisson"])
    kappa = sw.loc[rows, "kappa_N_per_m"].to_numpy(float)
    kappa_err = sw.loc[rows, "df0_err_Hz"].to_numpy(float) / sw.loc[rows, "P_Hz_per_N_per_m"]
    F, F_err = (sw.loc[rows, c].to_numpy(float) for c in ("sliding_force_N", "sliding_force_err_N"))
    with np.errstate(divide="ignore", invalid="ignore"):
        a = kappa / (2.0 * G_star)
        tau = F / (np.pi * a**2)
        rel = np.sqrt((F_err / F) ** 2 + 4 * (kappa_err / kappa) ** 2 + 4 * (E_err / E) ** 2)
    sw.loc[rows, "tau0_Pa"] = np.where(a > 0, tau, np.nan)
    sw.loc[rows, "tau0_err_Pa"] = np.where(a > 0, np.abs(tau) * rel, np.nan)


def _flag(mask: np.ndarray, flag: Flag) -> np.ndarray:
    return np.where(mask, int(flag), 0).astype(np.int64)


def run(
    table: SweepTable,
    settings: AnalysisSettings,
    say: Callable[[str], None],
    curve_grids: Sequence[int] | None = None,
) -> Results:
    """:func:`contactres.analysis.analyze` of ``table`` with ``settings``, telling ``say``
    the name of each step as it starts, the fitted curves of every sweep on each grid of
    ``curve_grids`` (None: the page's grid, and Fig. 4's for the sweeps it draws; see
    :mod:`contactres.analysis._pipeline`)."""
    if not isinstance(table, SweepTable):
        raise TypeError(
            f"analyze takes a SweepTable, got {type(table).__name__}; pass a raw table through "
            "contactres.validate_sweeps(frame, constants={...}) first"
        )
    # A tuple or list of whole numbers first: tuple(30) or set() of nested lists would raise a
    # bare TypeError, which the CLI shows as an internal error.
    grids = CURVE_GRIDS if curve_grids is None else curve_grids
    if (
        not isinstance(grids, tuple | list)
        or not grids
        or not all(isinstance(n, int | np.integer) and not isinstance(n, bool) for n in grids)
        or len(set(grids)) != len(grids)
        or not all(n >= 2 for n in grids)
    ):
        raise ContactresInputError(
            f"curve_grids must be distinct whole numbers of points >= 2, got {curve_grids!r}"
        )
    # One pool of worker processes for every stage (started by the first that has tasks for
    # it), shut down however the analysis ends.
    with WorkerPool(settings.workers) as pool:
        return _run(table, settings, say, tuple(grids), pool, curve_grids is None)


def _run(
    table: SweepTable,
    settings: AnalysisSettings,
    say: Callable[[str], None],
    grids: tuple[int, ...],
    pool: WorkerPool,
    figure_only: bool = False,
) -> Results:
    """The steps of :func:`run` (its arguments checked), their worker processes ``pool``;
    ``figure_only``: Fig. 4's grid holds only the sweeps that figure draws."""
    data = table.data

    # Each sweep's code, numbering the sweeps by first appearance: a sweep's first row starts
    # one of the runs of its rows, and only those rows are hashed (all of them where the ids
    # are Arrow strings, which pandas hashes faster than they are compared as Python strings).
    # Once for every step: the padding (again after a drift's removal, which keeps the rows
    # and their ids) and the sweeps' first rows.
    sweep, ids = factorize_runs(data["sweep"], use_na_sentinel=False)
    if pd.isna(ids).any():
        # (validate_sweeps refuses a missing id; a SweepTable built around a frame by hand
        # would otherwise reach the fits and fail there as if the package were at fault)
        raise ContactresInputError(
            "the sweep table has rows without a sweep id: a SweepTable holds a validated "
            "table: build it with read_sweeps() or validate_sweeps(frame, constants={...})"
        )
    padded = pad_sweeps(data, (sweep, ids))
    # A sweep's first row is where the codes seen so far reach a new one (a new code is the
    # largest so far plus one): its info is that row's, as drop_duplicates("sweep") keeps it.
    seen = np.maximum.accumulate(sweep)
    first_rows = np.flatnonzero(np.diff(seen, prepend=-1))
    info = data.iloc[first_rows][list(INFO_COLUMNS)].reset_index(drop=True)
    # The labels first: which sweeps are used, and which load blocks they form, decide where
    # the (costly) exact plateau loop is fitted to single sweeps.
    few = padded.n < MIN_SWEEP_POINTS
    # A sweep at one amplitude has no slope (the straight line is degenerate): say so.
    flat = padded.u_max == padded.u_min
    # The order of the ramps comes from the times where the table has them (not the file).
    timed = bool(data["time_s"].notna().all())
    # Both minima by one grouping of the sweeps' codes, in the order of ``info`` (both by first
    # appearance): grouping by the names hashed 10^6 texts again (~0.1 s at 10^5 sweeps).
    firsts = data[["line", "time_s"] if timed else ["line"]].groupby(sweep, sort=False).min()
    first_line = firsts["line"].to_numpy()
    first_time = firsts["time_s"].to_numpy() if timed else None
    ramps = check_ramps(info, first_line, padded.direction, first_time)
    running = ramps.first  # the running-in sweep of each load, as measured
    first = running & (not settings.keep_first_ramp)
    used = ~few & ~first
    # Drift is tested on the ramps after the first: ramp 1's running-in offset is not drift.
    tested = ~few & ~running
    drift = drifting_sweeps(info, padded, tested, settings.drift_p)
    # A drifting load loses all its sweeps (its ramp 1 too, when ramp 1 is used).
    drift = _whole_loads(info, drift) & ~few
    removed = np.zeros(len(info), bool)
    drift_removed = pd.DataFrame(columns=[*LOAD_OF_EXPERIMENT, "drift_df_Hz_per_s"])
    messages = list(ramps.messages)
    if settings.remove_drift and drift.any():
        if data["time_s"].isna().any():
            messages.append(
                "drift: the table has no time_s column (or not in every row), so the drifting "
                "loads are left out instead of corrected"
            )
        else:
            # The drift is estimated on the ramps it was found in, removed from the whole load,
            # and the load tested again: corrected loads are used (flag drift-removed).
            est = info[drift & tested].groupby(LOAD_OF_EXPERIMENT, sort=True)["sweep"]
            loads = est.agg(list).rename("sweeps").reset_index()
            data, drift_removed = remove_linear_drift(data, loads)
            padded = pad_sweeps(data, (sweep, ids))
            again = _whole_loads(info, drifting_sweeps(info, padded, tested, settings.drift_p))
            again = again & ~few
            removed, drift = drift & ~again, again
    if not settings.keep_drift:
        used &= ~drift

    say("fitting the amplitude models of every sweep")
    tables = loop_tables() if settings.exact_loop else None
    code = block_codes(info, used)
    alone = code < 0  # the sweeps judged alone get every model now
    sw, fields = fit_sweeps(
        padded, settings.delta_bic, settings.exact_loop, tables, pool, plateau=alone
    )
    sw = _with_info(info, sw)
    P = _sensitivity(sw, settings.zq)
    sw["P_Hz_per_N_per_m"] = P
    sw["used"] = used

    say("choosing the model of every load block")
    blocks, decided, sw, fields, block_fits = choose_blocks(
        padded,
        sw,
        fields,
        used,
        settings.delta_bic,
        settings.exact_loop,
        tables,
        pool,
        pool_experiment=settings.pool_experiments,
        code=code,
    )
    sw = apply_models(sw, fields, decided["model"].to_numpy(), settings.exact_loop)
    # Every model's fit of every sweep, final: the steps below read them.
    fits = fit_tables(sw["sweep"].to_numpy(), fields)
    del fields  # copied into ``fits``: not kept twice to the end (~70 MB at 10^5 sweeps)
    for col in ("block", "runner_up", "delta_bic", "decided_by"):
        sw[col] = decided[col].to_numpy()
    for col in ("df_slope_Hz_per_m", "dgamma_slope_Hz_per_m"):
        sw.loc[flat, [col, col.replace("_Hz_per_m", "_err_Hz_per_m")]] = np.nan
    rises = (
        sw["df_slope_Hz_per_m"].to_numpy()
        > JUNCTION_SIGMAS * sw["df_slope_err_Hz_per_m"].to_numpy()
    )
    rises &= sw["model"].to_numpy() != "elastic"
    f_res = sw["fundamental_Hz"].to_numpy() * sw["overtone"].to_numpy()
    big = np.abs(sw["df0_Hz"].to_numpy()) > SMALL_LOAD_LIMIT * f_res
    flags = (
        _flag(first, Flag.FIRST_RAMP)
        | _flag(few, Flag.FEW_POINTS)
        | _flag(rises, Flag.JUNCTION_GROWTH)
        | _flag(big, Flag.SMALL_LOAD)
        | _flag((sw["model"] == "plateau").to_numpy(), Flag.PLATEAU_SLOPE)
        | _flag(ramps.suspect, Flag.RAMP_ORDER)
        | _flag(flat, Flag.FLAT_AMPLITUDE)
        | _flag(drift, Flag.DRIFT)
        | _flag(removed, Flag.DRIFT_REMOVED)
    )

    say("contact stiffness and friction")
    sw["kappa_N_per_m"] = sw["df0_Hz"] / P
    # A negative κ is no contact stiffness but a Δf of the wrong sign: said where it is, with
    # the input to check (the JKR fit leaves such points out, and only said so per group).
    flags |= _flag(negative_stiffness(sw["df0_Hz"], sw["df0_err_Hz"]), Flag.NEGATIVE_STIFFNESS)
    sw["omega_xi_N_per_m"] = sw["dgamma0_Hz"] / P
    with np.errstate(divide="ignore", invalid="ignore"):
        sw["loss_tangent"] = sw["dgamma0_Hz"] / sw["df0_Hz"]
    slopes = slope_friction(sw, P)
    sw["mu_df"] = np.where(rises, np.nan, slopes.mu_df)
    sw["mu_df_err"] = np.where(rises, np.nan, slopes.mu_df_err)
    sw["mu_dgamma"] = slopes.mu_dgamma
    sw["mu_dgamma_err"] = slopes.mu_dgamma_err
    sw["mu_block"] = np.nan
    sw["mu_block_err"] = np.nan
    if settings.exact_loop:
        say("friction from the exact loops")
        loops = loop_friction(sw, fits, P)
        sw["mu_fit"] = loops.mu_fit
        sw["mu_fit_err"] = loops.mu_fit_err
        sw["x_max"] = loops.x_max
        sw["sliding_force_N"] = loops.sliding_force
        sw["sliding_force_err_N"] = loops.sliding_force_err
        flags |= _flag(loops.gross_sliding, Flag.GROSS_SLIDING)
        cm = (sw["model"] == "cattaneo-mindlin").to_numpy()
        flags |= _flag(cm & (loops.x_max > LINEAR_ONSET_X), Flag.BEYOND_ONSET)
        # A plateau sweep whose own loop fit ends on d_c = 0: a value at its bound, which the
        # sweep does not resolve, is flagged and not printed (its error is NaN already).
        at_bound = (sw["model"] == "plateau") & (sw["plateau_amplitude_m"] == 0.0)
        flags |= _flag(at_bound.to_numpy(), Flag.PLATEAU_AT_BOUND)
        sw.loc[at_bound, "plateau_amplitude_m"] = np.nan
        blocks = block_friction(blocks, block_fits, sw)
        member = sw["block"].to_numpy() >= 0
        for col in ("mu_block", "mu_block_err"):
            values = blocks[col.replace("_block", "")].to_numpy(float)
            sw.loc[member, col] = np.asarray(values)[sw["block"].to_numpy()[member]]
    else:
        for col in ("mu_fit", "mu_fit_err", "x_max", "sliding_force_N", "sliding_force_err_N"):
            sw[col] = np.nan
    # A μ beyond any friction coefficient by more than twice its error is a wrong input, not a
    # result: withheld and flagged. A noisy estimate (μ = 12 ± 60 from a flat ΔΓ slope in
    # water) is kept: censoring it would bias the statistics per load.
    # A block's μ from the plateau loop's marginal μ has a log-normal error (its bound in ln μ).
    lognormal = np.zeros(len(sw), bool)
    pl = block_fits.get("plateau-loop")
    if settings.exact_loop and pl is not None and "mu_marginal" in pl.columns:
        member = sw["block"].to_numpy() >= 0
        marginal = np.isfinite(pl["mu_marginal"].to_numpy(float))
        lognormal[member] = marginal[sw["block"].to_numpy()[member]]
    for col in ("mu_df", "mu_dgamma", "mu_fit", "mu_block"):
        mu, err = sw[col].to_numpy(float), sw[f"{col}_err"].to_numpy(float)
        absurd = mu_out_of_range(mu, err, lognormal & (col == "mu_block"))
        if absurd.any():
            sw.loc[absurd, [col, f"{col}_err"]] = np.nan
            flags |= _flag(absurd, Flag.MU_OUT_OF_RANGE)
    sw["flags"] = flags

    sw["tau0_Pa"] = np.nan
    sw["tau0_err_Pa"] = np.nan

    say("statistics per load")
    exp = per_experiment(sw)
    loads = per_load(exp, sw)

    groups = []
    grouped = list(exp.groupby(GROUP_KEYS, sort=True))
    members = [
        (sw["configuration"] == key[0]).to_numpy() & (sw["medium"] == key[1]).to_numpy()
        for key, _ in grouped
    ]
    # The groups' JKR fits (at scale their bootstraps are the cost) in the worker processes,
    # each from its own group's points alone; taken in order, each after its step is said.
    jkr_fits = pool.imap(
        fit_group,
        len(grouped),
        [part[JKR_POINT_COLUMNS] for _, part in grouped],
        [key for key, _ in grouped],
        repeat(settings.bootstrap),
        repeat(settings.seed),
        [sw.loc[used & member, JKR_SWEEP_COLUMNS] for member in members],
    )
    # What running_in reads of the sweeps (the loads' keys and its quantities), taken once:
    # each group's rows of the whole frame (~80 columns) were copied for it (issue 31, point 3).
    ramps_of = sw[list(dict.fromkeys([*LOAD_OF_EXPERIMENT, *RUNNING_IN_QUANTITIES]))]
    for (key, part), member in zip(grouped, members, strict=True):
        say(f"JKR fit: {key[0]}, {key[1]}")
        in_group = used & member
        g = next(jkr_fits)
        g["n_experiments"] = int(part["experiment"].nunique())
        g["n_sweeps_used"] = int(in_group.sum())
        models = sw.loc[in_group, "model"]
        g["models"] = {m: int((models == m).sum()) for m in AMPLITUDE_MODELS}
        g["P_Hz_per_N_per_m"] = float(part["P_Hz_per_N_per_m"].mean())
        later = member & ~few & ~running & ~drift
        g["running_in"] = running_in(ramps_of[member], running[member], later[member])
        drifting = sw[member & drift].drop_duplicates(["experiment", "normal_force_N"])
        g["drifting_loads"] = [
            {"experiment": e, "normal_force_N": f}
            for e, f in zip(drifting["experiment"], drifting["normal_force_N"], strict=True)
        ]
        mine = (drift_removed["configuration"] == key[0]) & (drift_removed["medium"] == key[1])
        g["drift_removed"] = (
            drift_removed[mine].drop(columns=["configuration", "medium"]).to_dict(orient="records")
        )
        groups.append(g)
        _savkoor_traction(sw, member, g)

    laws = None
    coating = settings.coating  # a Coating: __post_init__ made it one
    if coating is not None:
        from ._coating import Coating, apply_coating

        assert isinstance(coating, Coating)
        laws = apply_coating(groups, exp, sw[used], coating, settings.bootstrap, settings.seed, say)

    # After the coating's refit, which may change a group's checks.
    loads = withhold_mu(loads, groups)

    say("the fitted curves of every sweep")
    # Fig. 4's sweeps are picked from sw as Results.sweeps holds it (the same frame, final
    # here), so the figure finds its grid for each sweep it draws.
    # Only the columns the choice reads (figure_examples): its selections and merges copied
    # every column of the used sweeps of each medium.
    held = {FIGURE_POINTS: drawn_in_figure(sw[FIGURE_COLUMNS])} if figure_only else None
    curves = fitted_curves(sw, padded, fits, grids, workers=pool, held=held)
    jkr = jkr_curves(groups, loads, laws=laws)

    radiation = None
    if settings.sphere_material is not None and settings.plate_material is not None:
        say("radiation loss of the contacts")
        from ._radiation import load_frequencies, radiation_loss

        radiation = radiation_loss(
            loads,
            groups,
            settings.sphere_material,
            settings.plate_material,
            frequency_Hz=load_frequencies(sw, loads),
            experiments=exp,
            coating=coating,
        )

    record = asdict(replace(settings, coating=None))
    # The coating's record (names and thicknesses), and none at all without one.
    del record["coating"]
    if coating is not None:
        record["coating"] = coating.record()
    record["x_max_table"] = X_MAX
    # The user's sweep table holds the named columns; each fit's fields are in its own table.
    return Results(
        sweeps=sw,
        fits=fits,
        loads=loads,
        experiments=exp,
        groups=groups,
        settings=record,
        version=__version__,
        table=table,
        points=sweep_points(padded),
        curves=curves,
        blocks=blocks,
        block_fits=block_fits,
        messages=tuple(messages),
        radiation=radiation,
        jkr=jkr,
    )
