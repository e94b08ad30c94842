"""The analysis of QCM amplitude sweeps (paper 2): sweeps -> loads -> JKR modulus and adhesion.

:func:`analyze` is a pure function of (sweep table, settings) and returns a
:class:`contactres.analysis.Results`. Its steps:

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

from collections.abc import Callable
from dataclasses import asdict, dataclass, replace

import numpy as np
import pandas as pd

from .._version import __version__
from ..errors import ContactresInputError
from ..measurements import SweepTable
from ..measurements.schema import SWEEP_TABLE
from ..resonators import QCM
from ..tangential import effective_shear_modulus, shear_modulus
from ..units import JUNCTION_SIGMAS, LINEAR_ONSET_X, MAX_MU, MIN_SWEEP_POINTS, SMALL_LOAD_LIMIT
from ._amplitude import pad_sweeps
from ._blocks import block_codes, choose_blocks
from ._classify import apply_models, fit_sweeps
from ._curves import CURVE_GRIDS, fitted_curves, jkr_curves, sweep_points
from ._drift import LOAD_OF_EXPERIMENT, drifting_sweeps, remove_linear_drift
from ._flags import Flag
from ._friction import block_friction, loop_friction, slope_friction
from ._jkr import fit_group
from ._loads import GROUP_KEYS, per_experiment, per_load, withhold_mu
from ._loops import X_MAX, loop_tables
from ._models import AMPLITUDE_MODELS, fit_tables
from ._ramps import check_ramps
from ._results import Results
from ._running_in import running_in

__all__ = ["AnalysisSettings", "analyze"]

#: Columns that describe a whole sweep, carried from the sweep table into the results.
INFO_COLUMNS = SWEEP_TABLE.where(level="sweep") + SWEEP_TABLE.where(level="constant")


@dataclass(frozen=True)
class AnalysisSettings:
    """Settings of :func:`analyze` (all recorded in ``summary.json``).

    Attributes
    ----------
    keep_first_ramp : use ramp 1 of every load (default: set aside as running-in)
    keep_drift : use the sweeps of loads whose ramps drift (default: left out of the means and
        fits, and listed)
    remove_drift : where the table has ``time_s``, remove a drift linear in time from the loads
        found drifting, test them again and use those that pass (flag ``drift-removed``)
    pool_experiments : decide the friction law (Coulomb or Savkoor) once per experiment from
        all its loads (:mod:`contactres.analysis._blocks`), and weigh the μ of each load
        block's Coulomb loops against the experiment's other loads in its class choice
        (:mod:`contactres.analysis._mu_prior`); False: each load block alone
    delta_bic : BIC margin within which the simpler amplitude model is kept
    drift_p : false-alarm probability of the drift test
    bootstrap : number of bootstrap resamples over experiments for E and γ (0: none)
    seed : seed of the bootstrap
    exact_loop : fit the exact Cattaneo-Mindlin loop (μ_fit), behind a stick plateau for
        ``plateau`` sweeps
    zq : shear-wave impedance of the quartz, kg m⁻² s⁻¹
    workers : processes for the per-sweep and per-block fits (1: none; more pay from ~10^4
        sweeps on; a script that passes more must be importable where processes are spawned,
        see :func:`contactres.analysis._classify.fit_sweeps`)
    sphere_material, plate_material : str or None
        Names of the two bodies for the radiation loss of the contact
        (:func:`contactres.analysis.material_by_name`: a built-in solid, e.g.
        ``"soda-lime-glass"`` or ``"glass"``; the plate also ``"quartz-AT"``, the AT-cut quartz
        of the QCM); both or neither (None: no radiation table).
    coating : (material, thickness_m) pair, a sequence of them (top first), or None
        The film(s) on the plate (:func:`contactres.analysis._coating.as_coating`; e.g.
        ``(contactres.pmma(), 250e-9)``; from text, ``"pmma:250e-9"``, with
        :func:`contactres.jobs.contact.parse_coating`): E and γ are then fitted with the coated
        plate's contact mechanics (step 9), E the Young's modulus of the sphere and of the
        plate's substrate. Thickness in (0, 1 m]. With the radiation materials, the radiation
        loss is that of the coated plate (step 8).
    """

    keep_first_ramp: bool = False
    keep_drift: bool = False
    remove_drift: bool = False
    pool_experiments: bool = True
    delta_bic: float = 2.0
    drift_p: float = 1e-3
    bootstrap: int = 200
    seed: int = 0
    exact_loop: bool = True
    zq: float = 8.8e6
    workers: int = 1
    sphere_material: str | None = None
    plate_material: str | None = None
    coating: object = None

    def __post_init__(self):
        if not self.delta_bic >= 0:
            raise ContactresInputError(f"delta_bic must be >= 0, got {self.delta_bic!r}")
        if not 0 < self.drift_p < 1:
            raise ContactresInputError(f"drift_p must lie in (0, 1), got {self.drift_p!r}")
        if int(self.bootstrap) != self.bootstrap or self.bootstrap < 0:
            raise ContactresInputError(
                f"bootstrap must be a whole number >= 0, got {self.bootstrap!r}"
            )
        if not self.zq > 0:
            raise ContactresInputError(f"zq must be > 0, got {self.zq!r}")
        if int(self.workers) != self.workers or self.workers < 1:
            raise ContactresInputError(f"workers must be a whole number >= 1, got {self.workers!r}")
        if (self.sphere_material is None) != (self.plate_material is None):
            raise ContactresInputError(
                "sphere_material and plate_material go together: give both (e.g. "
                "'soda-lime-glass' and 'quartz-AT') or neither"
            )
        if self.sphere_material is not None:
            # Imported here: an analysis without materials loads no half-space or dynamic solver.
            from ._radiation import material_by_name

            material_by_name(self.sphere_material, "sphere")  # ValueError naming the known
            material_by_name(self.plate_material, "plate")
        if self.coating is not None:
            # Imported here: an analysis without a coating loads no layered solver.
            from ._coating import as_coating

            object.__setattr__(
                self, "coating", as_coating(self.coating, "AnalysisSettings(coating=...)")
            )


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
    """``mask`` spread to every sweep of a load of an experiment where any sweep has it."""
    keys = sw[LOAD_OF_EXPERIMENT]
    hit = keys[mask].drop_duplicates()
    return (
        keys.merge(hit.assign(_hit=True), how="left", on=LOAD_OF_EXPERIMENT)["_hit"]
        .eq(True)
        .to_numpy()
    )


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


def analyze(
    table: SweepTable,
    *,
    settings: AnalysisSettings | None = None,
    progress: Callable[[str], None] | None = None,
    curve_grids: tuple[int, ...] = CURVE_GRIDS,
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
        every sweep's model: by default Fig. 4's
        (:data:`~contactres.analysis.FIGURE_POINTS`) and the page's and ``curves.csv``'s
        (:data:`~contactres.analysis.PAGE_POINTS`). Not an analysis setting (no result depends on
        it, and ``summary.json`` does not record it): a caller that draws no figure asks for
        ``(PAGE_POINTS,)`` alone, 30 of the 130 points per sweep (issue 31, point 3: at 10^5
        sweeps the figure grid cost ~18 s of CPU and 0.4 GB for a figure that draws a few).

    Returns
    -------
    contactres.analysis.Results
    """
    if not isinstance(table, SweepTable):
        raise TypeError(
            f"analyze takes a SweepTable, got {type(table).__name__}; pass a raw table through "
            "contactres.validate_sweeps(frame, constants={...}) first"
        )
    settings = settings or AnalysisSettings()
    grids = tuple(curve_grids)
    if (
        not grids
        or len(set(grids)) != len(grids)
        or not all(isinstance(n, int | np.integer) and n >= 2 for n in grids)
    ):
        raise ContactresInputError(
            f"curve_grids must be distinct whole numbers of points >= 2, got {curve_grids!r}"
        )
    say = progress or (lambda step: None)
    data = table.data

    padded = pad_sweeps(data)
    info = data.drop_duplicates("sweep", keep="first")[list(INFO_COLUMNS)].reset_index(drop=True)
    # The labels first: which sweeps are used, and which load blocks they form, decide where
    # the (costly) exact plateau loop is fitted to single sweeps.
    few = padded.n < MIN_SWEEP_POINTS
    # A sweep at one amplitude has no slope (the straight line is degenerate): say so.
    flat = padded.u_max == padded.u_min
    first_line = data.groupby("sweep", sort=False)["line"].min().reindex(info["sweep"]).to_numpy()
    # The order of the ramps comes from the times where the table has them (not the file).
    timed = bool(data["time_s"].notna().all())
    first_time = (
        data.groupby("sweep", sort=False)["time_s"].min().reindex(info["sweep"]).to_numpy()
        if timed
        else None
    )
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
            padded = pad_sweeps(data)
            again = _whole_loads(info, drifting_sweeps(info, padded, tested, settings.drift_p))
            again = again & ~few
            removed, drift = drift & ~again, again
    if not settings.keep_drift:
        used &= ~drift

    say("fitting the amplitude models of every sweep")
    tables = loop_tables() if settings.exact_loop else None
    alone = block_codes(info, used) < 0  # the sweeps judged alone get every model now
    sw, fields = fit_sweeps(
        padded, settings.delta_bic, settings.exact_loop, tables, settings.workers, plateau=alone
    )
    sw = info.merge(sw, on="sweep", how="right", validate="one_to_one")
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
        settings.workers,
        pool_experiment=settings.pool_experiments,
    )
    sw = apply_models(sw, fields, decided["model"].to_numpy(), settings.exact_loop)
    # Every model's fit of every sweep, final: the steps below read them.
    fits = fit_tables(sw["sweep"].to_numpy(), fields)
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
    for col in ("mu_df", "mu_dgamma", "mu_fit", "mu_block"):
        mu, err = sw[col].to_numpy(float), sw[f"{col}_err"].to_numpy(float)
        absurd = (mu > MAX_MU) & ~(mu - 2 * np.nan_to_num(err, nan=0.0) <= MAX_MU)
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
    for key, part in exp.groupby(GROUP_KEYS, sort=True):
        say(f"JKR fit: {key[0]}, {key[1]}")
        member = (sw["configuration"] == key[0]).to_numpy() & (sw["medium"] == key[1]).to_numpy()
        in_group = used & member
        g = fit_group(part, key, settings.bootstrap, settings.seed, sw[in_group])
        g["n_experiments"] = int(part["experiment"].nunique())
        g["n_sweeps_used"] = int(in_group.sum())
        models = sw.loc[in_group, "model"]
        g["models"] = {m: int((models == m).sum()) for m in AMPLITUDE_MODELS}
        g["P_Hz_per_N_per_m"] = float(part["P_Hz_per_N_per_m"].mean())
        later = member & ~few & ~running & ~drift
        g["running_in"] = running_in(sw[member], running[member], later[member])
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
    curves = fitted_curves(sw, padded, fits, grids, workers=settings.workers)
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
